// Every model odec saves can be read back, and the files odec reads and writes cannot hang it,
// exhaust its memory or fail silently:
// - save refuses, writing nothing, a model that restore would refuse (the two share one
//   validation); histories added during a run, whose first samples are NaN, round-trip;
// - the step counter and the model time stop with an error before they overflow;
// - save streams through a small buffer: its memory does not grow with the file, and it works
//   after running out of memory; restore holds the model, not the file too;
// - temporary files of saves killed part way are removed by the next save and at start-up;
// - save does not replace a read-only file or one that is not a regular file;
// - restore, table read, FISH open() and export vtk refuse named pipes and devices at once;
// - a full disk is reported by the log and by FISH write().
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <dirent.h>
#include <fcntl.h>
#include <malloc.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <new>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "fish/runtime.h"
#include "io/save.h"
#include "../sanitizers.h"
#include "test_util.h"

using odec::test::read_bytes;
using odec::test::Session;
using odec::test::write_bytes;

namespace {


bool exists(const std::string& path) {
    struct stat st;
    return ::lstat(path.c_str(), &st) == 0;
}

std::set<std::string> files_in(const std::string& dir) {
    std::set<std::string> out;
    if (DIR* d = opendir(dir.c_str())) {
        while (dirent* e = readdir(d)) {
            const std::string n = e->d_name;
            if (n != "." && n != "..") out.insert(n);
        }
        closedir(d);
    }
    return out;
}

// A file's modification time set `seconds` into the past.
void age(const std::string& path, int seconds) {
    struct timeval tv[2];
    gettimeofday(&tv[0], nullptr);
    tv[0].tv_sec -= seconds;
    tv[1] = tv[0];
    ASSERT_EQ(utimes(path.c_str(), tv), 0) << path;
}

// The model's state as bytes, as it is (the wall-clock profile left out).
std::string state_bytes(const odec::Model& m, const std::string& path) {
    odec::Model copy = m;
    copy.profile = odec::Profile();
    std::string error;
    EXPECT_TRUE(odec::save_model_unchecked(copy, path, error)) << error;
    const std::string bytes = read_bytes(path);
    std::remove(path.c_str());
    return bytes;
}

enum class Outcome { Ok, Failed, Hung };

// Runs f in a child process, which must end within `seconds`: a call that waits on a named
// pipe shows as Hung instead of stopping the tests.
Outcome in_child(const std::function<bool()>& f, int seconds = 20) {
    std::fflush(nullptr);
    const pid_t pid = fork();
    if (pid == 0) {
        const bool ok = f();
        std::fflush(nullptr);
        _exit(ok ? 0 : 1);
    }
    if (pid < 0) return Outcome::Failed;
    for (int k = 0; k < seconds * 100; ++k) {
        int status = 0;
        if (waitpid(pid, &status, WNOHANG) == pid) {
            return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? Outcome::Ok : Outcome::Failed;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    kill(pid, SIGKILL);
    waitpid(pid, nullptr, 0);
    return Outcome::Hung;
}

// A process id that is not in use: that of a child that has ended.
pid_t dead_pid() {
    const pid_t pid = fork();
    if (pid == 0) _exit(0);
    waitpid(pid, nullptr, 0);
    return pid;
}

// A number from /proc/self/status ("VmRSS", "VmHWM"), in kB; -1 when absent.
long status_kb(const std::string& key) {
    std::ifstream f("/proc/self/status");
    std::string line;
    while (std::getline(f, line)) {
        if (line.rfind(key + ":", 0) == 0) return std::atol(line.c_str() + key.size() + 1);
    }
    return -1;
}

// Resets the peak resident size (VmHWM) to the current one; false where the kernel cannot.
bool reset_peak_memory() {
    std::ofstream f("/proc/self/clear_refs");
    f << "5";
    f.flush();
    return static_cast<bool>(f);
}

// A model whose save file is about `mb` MiB, nearly all of it one history's samples, made
// directly (building as large a model by commands would take minutes).
odec::Model large_model(int mb) {
    Session s;
    EXPECT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\ngrav 0 0 -10\nset dt 1e-3\n"
                      "hist ncyc 1\nhist zdis 0.5 0.5 0.5\nstep 3"))
        << s.error();
    odec::Model m = s.model;
    const size_t n = static_cast<size_t>(mb) << 16; // 16 bytes a sample: its step and its value
    m.histories.sample_steps.resize(n);
    m.histories.items[0].values.resize(n);
    for (size_t k = 0; k < n; ++k) {
        m.histories.sample_steps[k] = static_cast<long>(k);
        m.histories.items[0].values[k] = -0.5 * 10 * 1e-6 * static_cast<double>(k * k);
    }
    m.step = static_cast<long>(n);
    return m;
}

class SaveFiles : public ::testing::Test {
protected:
    std::string dir;
    void SetUp() override {
        char tmpl[] = "/tmp/odec-save-files-XXXXXX";
        ASSERT_NE(mkdtemp(tmpl), nullptr);
        dir = tmpl;
    }
    void TearDown() override {
        for (const std::string& f : files_in(dir)) {
            const std::string p = at(f);
            chmod(p.c_str(), 0600);
            if (std::remove(p.c_str()) != 0) rmdir(p.c_str());
        }
        rmdir(dir.c_str());
    }
    std::string at(const std::string& name) const { return dir + "/" + name; }

    // A block falling freely for 10 steps.
    static void falling(Session& s) {
        ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\ngrav 0 0 -10\nset dt 1e-3\n"
                          "hist ncyc 2\nhist zdis 0.5 0.5 0.5\nstep 10"))
            << s.error();
    }
};

} // namespace

// ---- 1. save and restore share one validation ---------------------------------------------

TEST_F(SaveFiles, AModelRestoreWouldRefuseIsNotSavedAndNothingIsWritten) {
    Session s;
    falling(s);
    ASSERT_TRUE(s.run("save '" + at("keep") + "'")) << s.error();
    const std::string old_bytes = read_bytes(at("keep.sav"));
    ASSERT_GT(old_bytes.size(), 100u);
    // What a run that ran away can leave: numbers that are no longer finite.
    s.check_save_at_end = false;
    const odec::Model good = s.model;
    struct Case {
        std::function<void(odec::Model&)> spoil;
        std::string why;
    };
    const double inf = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::vector<Case> cases = {
        {[&](odec::Model& m) { m.blocks.vel[0].z() = -inf; }, "block 1: the velocity is not a finite number"},
        {[&](odec::Model& m) { m.blocks.force[0].x() = nan; }, "block 1: the force is not a finite number"},
        {[&](odec::Model& m) { m.time = inf; }, "the model time is not a finite number"},
        {[&](odec::Model& m) { m.histories.items[0].values.back() = nan; }, "history 1: a value is not a finite number"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.why);
        s.model = good;
        c.spoil(s.model);
        const std::string before = state_bytes(s.model, at("state.check"));
        const std::string err_before = s.error();
        EXPECT_FALSE(s.run("save '" + at("keep") + "'"));
        const std::string quoted = "'" + at("keep") + "'";
        EXPECT_EQ(s.error().substr(err_before.size()),
                  "t.dat:1:6: error: the model cannot be saved to '" + at("keep.sav") + "': " + c.why +
                      "; nothing was written\n"
                      "    save " + quoted + "\n"
                      "         ^" + std::string(quoted.size() - 1, '~') + "\n"
                      "  see 'help save'\n");
        EXPECT_FALSE(s.run("save '" + at("fresh") + "'"));
        EXPECT_EQ(read_bytes(at("keep.sav")), old_bytes) << "the old file was changed";
        EXPECT_EQ(files_in(dir), std::set<std::string>{"keep.sav"}) << "something was written";
        EXPECT_EQ(state_bytes(s.model, at("state.check")), before) << "the model was changed";
        EXPECT_NE(odec::save_problem(s.model).find(c.why), std::string::npos);
    }
    // The unspoiled model saves again.
    s.model = good;
    EXPECT_TRUE(s.run("save '" + at("keep") + "'")) << s.error();
}

TEST_F(SaveFiles, AHistoryAddedDuringARunRoundTripsBitForBit) {
    // A history made during a run has its own samples from the next one on (older odecs kept a
    // NaN for each sample before it).
    Session a;
    ASSERT_TRUE(a.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\ngrav 0 0 -10\nset dt 1e-3\n"
                      "hist ncyc 2\nhist time\nstep 10\nhist zvel 0.5 0.5 0.5\nstep 10\n"
                      "save '" + at("mid") + "'"))
        << a.error();
    const std::vector<double>& late = a.model.histories.items[1].values;
    EXPECT_EQ(a.model.histories.sample_steps.size(), 10u);
    EXPECT_EQ(a.model.histories.items[1].first, 5);
    ASSERT_EQ(late.size(), 5u);
    for (size_t k = 0; k < 5; ++k) EXPECT_LT(late[k], 0) << k;

    Session b;
    ASSERT_TRUE(b.run("restore '" + at("mid") + "'\nsave '" + at("again") + "'")) << b.error();
    const std::vector<double>& back = b.model.histories.items[1].values;
    ASSERT_EQ(back.size(), late.size());
    EXPECT_EQ(b.model.histories.items[1].first, 5);
    EXPECT_EQ(std::memcmp(back.data(), late.data(), late.size() * sizeof(double)), 0) << "not the same bits";
    EXPECT_EQ(read_bytes(at("again.sav")), read_bytes(at("mid.sav")));
    // And both go on alike.
    ASSERT_TRUE(a.run("step 10")) << a.error();
    ASSERT_TRUE(b.run("step 10")) << b.error();
    EXPECT_EQ(state_bytes(a.model, at("a.check")), state_bytes(b.model, at("b.check")));

    // NaN anywhere in a history is refused, by save and by restore alike.
    odec::Model m = a.model;
    m.histories.items[1].values[3] = std::numeric_limits<double>::quiet_NaN();
    std::string error;
    EXPECT_FALSE(odec::save_model(m, at("bad.sav"), error));
    EXPECT_NE(error.find("history 2: a value is not a finite number"), std::string::npos) << error;
    ASSERT_TRUE(odec::save_model_unchecked(m, at("bad.sav"), error)) << error;
    odec::Model r;
    EXPECT_FALSE(odec::restore_model(at("bad.sav"), r, error));
    EXPECT_NE(error.find("history 2: a value is not a finite number"), std::string::npos) << error;
}

TEST_F(SaveFiles, ZonedBlocksInContactRoundTripRightAfterZoning) {
    // Right after 'gen' the contact between two zoned blocks still has the sub-contacts of
    // the rigid blocks (it is rebuilt before cycling): restore used to refuse such a file.
    Session a;
    ASSERT_TRUE(a.run("poly brick 0 1 0 1 0 0.5\npoly brick 0 1 0 1 0.5 1\n"
                      "prop mat=1 dens=2600 ymod=1e9 prat=0.25\nprop jmat=1 jkn=1e9 jks=1e9 jfric=40\n"
                      "gen edge 1\nsave '" + at("zoned") + "'"))
        << a.error();
    Session b;
    ASSERT_TRUE(b.run("restore '" + at("zoned") + "'\nsave '" + at("zoned2") + "'")) << b.error();
    EXPECT_EQ(read_bytes(at("zoned2.sav")), read_bytes(at("zoned.sav")));
    ASSERT_TRUE(a.run("step 10")) << a.error();
    ASSERT_TRUE(b.run("step 10")) << b.error();
    EXPECT_EQ(state_bytes(a.model, at("a.check")), state_bytes(b.model, at("b.check")));
}

TEST_F(SaveFiles, TheStepCounterStopsAtItsLargestValue) {
    // A model restored at a step near the largest a long holds used to count past it.
    Session s;
    falling(s);
    s.model.step = odec::kMaxStep - 3;
    EXPECT_FALSE(s.run("step 10"));
    EXPECT_NE(s.error().find("error: the step number has reached 1000000000000000000, the most odec counts (1e18): "
                             "the model cannot cycle further"),
              std::string::npos)
        << s.error();
    EXPECT_EQ(s.model.step, odec::kMaxStep);
    // Refused at once from there, the model unchanged; and it saves and restores.
    const std::string before = state_bytes(s.model, at("before.check"));
    EXPECT_FALSE(s.run("step 1"));
    EXPECT_EQ(state_bytes(s.model, at("after.check")), before);
    ASSERT_TRUE(s.run("save '" + at("max") + "'")) << s.error();
    Session r;
    ASSERT_TRUE(r.run("restore '" + at("max") + "'")) << r.error();
    EXPECT_EQ(r.model.step, odec::kMaxStep);
    // A file beyond it is refused.
    odec::Model beyond = s.model;
    beyond.step = odec::kMaxStep + 1;
    std::string error;
    EXPECT_FALSE(odec::save_model(beyond, at("beyond.sav"), error));
    EXPECT_NE(error.find("the step number is 1000000000000000001, outside 0 to 1e18"), std::string::npos) << error;
}

TEST_F(SaveFiles, TheModelTimeStopsBeforeItIsNoLongerFinite) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\nset dt 1e100\nstep 1")) << s.error();
    // A timestep this large can no longer be typed (numbers beyond 1e100 are refused); a model
    // edited from outside can still hold one.
    s.model.settings.dt_fixed = s.model.dt = 1e307;
    s.model.time = 1.79e308;
    const std::string before = state_bytes(s.model, at("before.check"));
    EXPECT_FALSE(s.run("step 5"));
    EXPECT_NE(s.error().find("error: the model time, 1.79e+308 s, would pass the largest number odec holds"),
              std::string::npos)
        << s.error();
    EXPECT_TRUE(std::isfinite(s.model.time));
    EXPECT_EQ(state_bytes(s.model, at("after.check")), before);
}

TEST_F(SaveFiles, AFileWithHugeFiniteNumbersStepsToAModelThatRoundTripsOrIsRefused) {
    // Restore takes finite numbers, however large; the next steps may make them inf. Whatever
    // they make, save either refuses it (writing nothing) or writes what restore takes back.
    for (double v : {1e300, 1.7e308}) {
        SCOPED_TRACE(v);
        Session a;
        falling(a);
        a.check_save_at_end = false;
        a.model.blocks.vel[0].z() = -v;
        std::string error;
        ASSERT_TRUE(odec::save_model(a.model, at("huge.sav"), error)) << error;
        Session b;
        ASSERT_TRUE(b.run("restore '" + at("huge.sav") + "'")) << b.error();
        b.run("step 5");
        std::remove(at("next.sav").c_str());
        if (!odec::save_problem(b.model).empty()) {
            EXPECT_FALSE(b.run("save '" + at("next") + "'"));
            EXPECT_NE(b.error().find("; nothing was written"), std::string::npos) << b.error();
            EXPECT_FALSE(exists(at("next.sav")));
            b.check_save_at_end = false;
        } else {
            EXPECT_TRUE(odec::check_save_round_trip(b.model, dir, error)) << error;
        }
    }
}

// ---- 2. save and restore stream ---------------------------------------------------------------

TEST_F(SaveFiles, SaveAndRestoreDoNotHoldTheFileInMemory) {
    const int mb = 48;
    // In a child, so that the peak resident size measures this test alone.
    const std::string path = at("large.sav");
    const Outcome o = in_child([&] {
        odec::Model m = large_model(mb);
        malloc_trim(0);
        if (!reset_peak_memory()) return true; // this kernel cannot measure it: nothing to check
        const long before = status_kb("VmRSS");
        std::string error;
        if (!odec::save_model(m, path, error)) {
            std::printf("save failed: %s\n", error.c_str());
            return false;
        }
        const long save_growth = status_kb("VmHWM") - before;
        m = odec::Model();
        malloc_trim(0);
        reset_peak_memory();
        const long before_restore = status_kb("VmRSS");
        odec::Model r;
        if (!odec::restore_model(path, r, error)) {
            std::printf("restore failed: %s\n", error.c_str());
            return false;
        }
        const long restore_growth = status_kb("VmHWM") - before_restore;
        struct stat st;
        stat(path.c_str(), &st);
        const long file_kb = static_cast<long>(st.st_size / 1024);
        std::printf("a %ld kB save: memory grew by %ld kB while saving, by %ld kB while restoring "
                    "(the restored model itself holds about %ld kB)\n",
                    file_kb, save_growth, restore_growth, file_kb);
        // Saving: a small buffer, not the file (the file is 48 MiB). Restoring: the model, not
        // the model and the file.
        return save_growth < 8 * 1024 && restore_growth < file_kb * 3 / 2 &&
               r.histories.items[0].values.size() == (static_cast<size_t>(mb) << 16);
    }, 120);
    EXPECT_EQ(o, Outcome::Ok);
}

TEST_F(SaveFiles, SaveWorksAfterRunningOutOfMemory) {
#if defined(ODEC_TEST_ASAN)
    GTEST_SKIP() << "AddressSanitizer reserves more address space than the limit this test sets";
#else
    const int mb = 48;
    const std::string path = at("after-oom.sav");
    const Outcome o = in_child([&] {
        Session s;
        s.check_save_at_end = false; // the child ends by _exit: no destructors
        s.model = large_model(mb);
        malloc_trim(0);
        // No more than 16 MiB of address space beyond what the model takes: a copy of its
        // 48 MiB save file no longer fits, and a large allocation fails.
        const long size_kb = status_kb("VmSize");
        const rlim_t limit = static_cast<rlim_t>(size_kb + 16 * 1024) * 1024;
        rlimit lim{limit, limit};
        if (setrlimit(RLIMIT_AS, &lim) != 0) return false;
        bool ran_out = false;
        try {
            std::vector<char> big(size_t{256} << 20, 1);
            std::printf("%d\n", big[12345]);
        } catch (const std::bad_alloc&) {
            ran_out = true;
        }
        if (!ran_out) return false;
        const bool saved = s.run("save '" + path + "'");
        if (!saved) std::printf("%s\n", s.error().c_str());
        return saved;
    }, 120);
    EXPECT_EQ(o, Outcome::Ok);
    // What it wrote is the whole model.
    odec::Model r;
    std::string error;
    ASSERT_TRUE(odec::restore_model(path, r, error)) << error;
    EXPECT_EQ(r.histories.items[0].values.size(), static_cast<size_t>(mb) << 16);
#endif
}

// ---- 3. stale temporary files -----------------------------------------------------------------

TEST_F(SaveFiles, TemporariesOfKilledSavesAreRemovedBySaveAndAtStartUp) {
    const pid_t gone = dead_pid();
    const pid_t alive = fork();
    if (alive == 0) {
        pause();
        _exit(0);
    }
    ASSERT_GT(alive, 0);
    const std::string g = std::to_string(gone), l = std::to_string(alive);
    const std::string magic("ODEC-SAVE\r\n\x1a", 12);
    struct Temp {
        std::string name, bytes;
        int age_seconds;
        bool removed;
    };
    const std::vector<Temp> temps = {
        {"m.sav.tmp-" + g + "-0", magic + "partial", 60, true},       // its process is gone
        {"other.sav.tmp-" + g + "-3", "", 60, true},                   // killed before writing
        {"m.sav.tmp-" + l + "-5", magic + "partial", 2 * 86400, true}, // not written for two days
        {"m.sav.tmp-" + l + "-1", magic + "partial", 60, false},       // its process is alive
        {"m.sav.tmp-" + g + "-2", magic + "partial", 0, false},        // just written
        {"notes.txt.tmp-" + g + "-0", "not a save", 60, false},        // not odec's
        {"m.sav.tmp-x-0", magic, 60, false},                            // not the pattern
    };
    for (const Temp& t : temps) {
        write_bytes(at(t.name), t.bytes);
        if (t.age_seconds > 0) age(at(t.name), t.age_seconds);
    }
    Session s;
    falling(s);
    ASSERT_TRUE(s.run("save '" + at("m") + "'")) << s.error();
    std::vector<std::string> removed;
    for (const Temp& t : temps) {
        EXPECT_EQ(exists(at(t.name)), !t.removed) << t.name;
        if (t.removed) removed.push_back(at(t.name));
    }
    std::sort(removed.begin(), removed.end());
    EXPECT_EQ(s.error(), "note: removed 3 temporary files left by a save that did not finish: '" + removed[0] + "', '" +
                             removed[1] + "', '" + removed[2] + "'\n");
    // A second save has nothing to remove and says nothing.
    ASSERT_TRUE(s.run("save '" + at("m") + "'")) << s.error();
    EXPECT_EQ(s.error().find("note:", 10), std::string::npos) << s.error();

    // odec removes them from its working directory as it starts.
    const std::string stale = "x.sav.tmp-" + g + "-9";
    write_bytes(at(stale), magic);
    age(at(stale), 60);
    std::fflush(nullptr);
    const pid_t pid = fork();
    if (pid == 0) {
        if (chdir(dir.c_str()) != 0) _exit(2);
        const int fd = ::open("startup.err", O_WRONLY | O_CREAT | O_TRUNC, 0644);
        dup2(fd, 2);
        execl(ODEC_BINARY, ODEC_BINARY, "--quiet", "-c", "title 'started'", static_cast<char*>(nullptr));
        _exit(3);
    }
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    EXPECT_FALSE(exists(at(stale)));
    EXPECT_EQ(read_bytes(at("startup.err")),
              "odec: note: removed a temporary file left by a save that did not finish: '" + stale + "'\n");
    // Kept ones are still there.
    EXPECT_TRUE(exists(at("m.sav.tmp-" + l + "-1")));
    EXPECT_TRUE(exists(at("notes.txt.tmp-" + g + "-0")));
    kill(alive, SIGKILL);
    waitpid(alive, nullptr, 0);
}

// ---- 4. targets that are not replaced ---------------------------------------------------------

TEST_F(SaveFiles, AReadOnlyOrNonRegularTargetIsNotReplaced) {
    Session s;
    falling(s);
    ASSERT_TRUE(s.run("save '" + at("ro") + "'")) << s.error();
    const std::string old_bytes = read_bytes(at("ro.sav"));
    ASSERT_EQ(chmod(at("ro.sav").c_str(), 0444), 0);
    ASSERT_TRUE(s.run("step 2")) << s.error();
    EXPECT_FALSE(s.run("save '" + at("ro") + "'"));
    const std::string quoted = "'" + at("ro") + "'";
    EXPECT_NE(s.error().find("t.dat:1:6: error: '" + at("ro.sav") +
                             "' is read-only: remove it or make it writable first; nothing was written\n"
                             "    save " + quoted + "\n"),
              std::string::npos)
        << s.error();
    EXPECT_EQ(read_bytes(at("ro.sav")), old_bytes);
    // Writable by its group only is writable.
    ASSERT_EQ(chmod(at("ro.sav").c_str(), 0464), 0);
    EXPECT_TRUE(s.run("save '" + at("ro") + "'")) << s.error();
    EXPECT_NE(read_bytes(at("ro.sav")), old_bytes);

    ASSERT_EQ(mkdir(at("d.sav").c_str(), 0755), 0);
    EXPECT_FALSE(s.run("save '" + at("d") + "'"));
    EXPECT_NE(s.error().find("error: cannot save to '" + at("d.sav") +
                             "': it is a directory, not a regular file; nothing was written"),
              std::string::npos)
        << s.error();
    ASSERT_EQ(mkfifo(at("p.sav").c_str(), 0644), 0);
    const std::string pipe = at("p");
    odec::Model& m = s.model;
    const Outcome o = in_child([&] {
        Session c;
        c.check_save_at_end = false;
        c.model = m;
        return !c.run("save '" + pipe + "'") &&
               c.error().find("': it is a named pipe, not a regular file; nothing was written") != std::string::npos;
    });
    EXPECT_EQ(o, Outcome::Ok);
    struct stat st;
    ASSERT_EQ(lstat(at("p.sav").c_str(), &st), 0);
    EXPECT_TRUE(S_ISFIFO(st.st_mode)) << "the named pipe was replaced";
    ASSERT_EQ(lstat(at("d.sav").c_str(), &st), 0);
    EXPECT_TRUE(S_ISDIR(st.st_mode));
    // No temporary file was left by any of them.
    for (const std::string& f : files_in(dir)) EXPECT_EQ(f.find(".tmp-"), std::string::npos) << f;
}

// ---- 5. readers refuse what call refuses ------------------------------------------------------

TEST_F(SaveFiles, RestoreRefusesDevicesPipesAndDirectoriesWithoutReadingThem) {
    Session s;
    falling(s);
    const std::string before = state_bytes(s.model, at("before.check"));
    // /dev/zero never ends: reading it used to fill the memory.
    ASSERT_EQ(symlink("/dev/zero", at("zero.sav").c_str()), 0);
    EXPECT_FALSE(s.run("restore '" + at("zero") + "'"));
    EXPECT_NE(s.error().find("t.dat:1:9: error: cannot restore '" + at("zero.sav") +
                             "': it is a character device, not a regular file\n"),
              std::string::npos)
        << s.error();
    ASSERT_EQ(mkdir(at("d.sav").c_str(), 0755), 0);
    EXPECT_FALSE(s.run("restore '" + at("d") + "'"));
    EXPECT_NE(s.error().find("cannot restore '" + at("d.sav") + "': it is a directory, not a regular file\n"),
              std::string::npos)
        << s.error();
    EXPECT_EQ(state_bytes(s.model, at("after.check")), before);

    ASSERT_EQ(mkfifo(at("p.sav").c_str(), 0644), 0);
    const std::string pipe = at("p");
    const std::string pipe_file = at("p.sav");
    const Outcome o = in_child([&] {
        Session c;
        c.check_save_at_end = false;
        return !c.run("restore '" + pipe + "'") &&
               c.error().find("cannot restore '" + pipe_file + "': it is a named pipe, not a regular file\n") !=
                   std::string::npos;
    });
    EXPECT_EQ(o, Outcome::Ok);
}

TEST_F(SaveFiles, RestoreComparesTheSizeWithItsHeaderBeforeReadingOn) {
    Session a;
    falling(a);
    ASSERT_TRUE(a.run("save '" + at("small") + "'")) << a.error();
    const auto size = static_cast<long long>(read_bytes(at("small.sav")).size());
    // The same file made 20 GiB long (sparse: it takes no room): refused at once, not read.
    const long long huge = 20LL << 30;
    if (truncate(at("small.sav").c_str(), huge) != 0) GTEST_SKIP() << "no sparse 20 GiB file here";
    Session s;
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_FALSE(s.run("restore '" + at("small") + "'"));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_NE(s.error().find("cannot restore '" + at("small.sav") + "': the file is damaged: it has " +
                             std::to_string(huge - size) + " bytes after the end of the save\n"),
              std::string::npos)
        << s.error();
    EXPECT_LT(seconds, 2.0);
    EXPECT_EQ(s.model.blocks.size(), 0);
}

TEST_F(SaveFiles, FishOpenAndExportRefuseNamedPipesAndDevicesWithoutWaiting) {
    ASSERT_EQ(mkfifo(at("fifo").c_str(), 0644), 0);
    const std::string fifo = at("fifo");
    struct Case {
        std::string open, why;
    };
    const std::vector<Case> cases = {
        {"open('" + fifo + "', 0, 1)", "warning: FISH open('" + fifo + "'): it is a named pipe, not a regular file\n"},
        {"open('" + fifo + "', 1, 1)", "warning: FISH open('" + fifo + "'): it is a named pipe, not a regular file\n"},
        {"open('/dev/zero', 0, 1)", "warning: FISH open('/dev/zero'): it is a character device, not a regular file\n"},
        {"open('" + dir + "', 0, 1)", "warning: FISH open('" + dir + "'): it is a directory, not a regular file\n"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.open);
        const Outcome o = in_child([&] {
            Session s;
            s.check_save_at_end = false;
            return s.run("def f\n  r = " + c.open + "\nend\n@f") && s.interp.fish().find("r")->value.number() == 1 &&
                   s.error() == c.why;
        });
        EXPECT_EQ(o, Outcome::Ok);
    }
    // A character device may be written (/dev/null takes everything).
    Session n;
    ASSERT_TRUE(n.run("def f\n  array a(1)\n  a(1) = 'x'\n  o = open('/dev/null', 1, 1)\n  w = write(a, 1)\n"
                      "  c = close\nend\n@f"))
        << n.error();
    EXPECT_EQ(n.interp.fish().find("o")->value.number(), 0);
    EXPECT_EQ(n.interp.fish().find("w")->value.number(), 0);
    EXPECT_EQ(n.error(), "");

    // export vtk adds to a collection file: a named pipe of that name is refused, not waited on,
    // and nothing is written.
    ASSERT_EQ(mkfifo(at("e.pvd").c_str(), 0644), 0);
    const std::string stem = at("e");
    const Outcome o = in_child([&] {
        Session s;
        s.check_save_at_end = false;
        return s.run("poly brick 0 1 0 1 0 1") && !s.run("export vtk '" + stem + "'") &&
               s.error().find("cannot add to the collection '" + stem + ".pvd': it is a named pipe, not a regular "
                              "file") != std::string::npos;
    });
    EXPECT_EQ(o, Outcome::Ok);
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"e.pvd", "fifo"}));
}

// ---- 6. a full disk is reported ---------------------------------------------------------------

TEST_F(SaveFiles, AFullDiskIsReportedByTheLogOnceAndTheLogIsClosed) {
    // /dev/full fails every write with ENOSPC, as a full disk does.
    Session s;
    ASSERT_TRUE(s.run("set logfile '/dev/full'\nset log on")) << s.error();
    EXPECT_TRUE(s.interp.log_is_on());
    ASSERT_TRUE(s.run("title 'logged'\nprint info\ngrav 0 0 -10\nprint info")) << s.error();
    const std::string line = "the log '/dev/full' cannot be written: No space left on device; the log is closed\n";
    EXPECT_NE(s.error().find(line), std::string::npos) << s.error();
    EXPECT_EQ(s.error().find(line), s.error().rfind(line)) << "said more than once: " << s.error();
    EXPECT_FALSE(s.interp.log_is_on());
    EXPECT_EQ(s.model.title, "logged"); // the commands themselves ran
    // A log that works again once another file is given.
    ASSERT_TRUE(s.run("set logfile '" + at("odec.log") + "'\nset log on\ntitle 'again'\nset log off")) << s.error();
    EXPECT_NE(read_bytes(at("odec.log")).find("odec> title 'again'"), std::string::npos);

    // A named pipe is refused as a log, without waiting for a reader.
    ASSERT_EQ(mkfifo(at("fifo.log").c_str(), 0644), 0);
    const std::string fifo = at("fifo.log");
    const Outcome o = in_child([&] {
        Session c;
        c.check_save_at_end = false;
        return !c.run("set logfile '" + fifo + "'\nset log on") &&
               c.error().find("cannot open the log file '" + fifo + "': it is a named pipe, not a regular file") !=
                   std::string::npos;
    });
    EXPECT_EQ(o, Outcome::Ok);
}

TEST_F(SaveFiles, FishWriteToAFullDiskGivesOneAndSaysSo) {
    Session s;
    ASSERT_TRUE(s.run("def f\n  array a(2)\n  a(1) = 'first'\n  a(2) = 2.5\n  o = open('/dev/full', 1, 1)\n"
                      "  w = write(a, 2)\n  c = close\nend\n@f"))
        << s.error();
    EXPECT_EQ(s.interp.fish().find("o")->value.number(), 0);
    EXPECT_EQ(s.interp.fish().find("w")->value.number(), 1);
    EXPECT_NE(s.error().find("warning: FISH write to '/dev/full': No space left on device; what was written may be "
                             "incomplete\n"),
              std::string::npos)
        << s.error();
    // A file that takes the data gives 0.
    Session t;
    ASSERT_TRUE(t.run("def f\n  array a(1)\n  a(1) = 'x'\n  o = open('" + at("w.txt") + "', 1, 1)\n"
                      "  w = write(a, 1)\n  c = close\nend\n@f"))
        << t.error();
    EXPECT_EQ(t.interp.fish().find("w")->value.number(), 0);
    EXPECT_EQ(read_bytes(at("w.txt")), "x\n");
}

// ---- 7. every model round-trips -------------------------------------------------------------

TEST_F(SaveFiles, CheckSaveRunsAfterTheScripts) {
    // odec --check-save: the example tests end with a save, a restore into a fresh model and a
    // second save that must give the same bytes.
    write_bytes(at("mid.dat"), "poly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\ngrav 0 0 -10\nset dt 1e-3\n"
                               "hist ncyc 2\nhist time\nstep 10\nhist zvel 0.5 0.5 0.5\nstep 10\n");
    auto run = [&](const std::string& tmpdir) {
        std::fflush(nullptr);
        const pid_t pid = fork();
        if (pid == 0) {
            if (chdir(dir.c_str()) != 0) _exit(2);
            const int fd = ::open(at("check.err").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            dup2(fd, 2);
            setenv("TMPDIR", tmpdir.c_str(), 1);
            execl(ODEC_BINARY, ODEC_BINARY, "--quiet", "--check-save", at("mid.dat").c_str(), static_cast<char*>(nullptr));
            _exit(3);
        }
        int status = 0;
        waitpid(pid, &status, 0);
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    };
    EXPECT_EQ(run(dir), 0) << read_bytes(at("check.err"));
    EXPECT_EQ(read_bytes(at("check.err")), "");
    // It does run: where it cannot save, it fails.
    EXPECT_EQ(run(at("no-such-dir")), 1);
    EXPECT_NE(read_bytes(at("check.err")).find("odec: --check-save: cannot make a directory"), std::string::npos)
        << read_bytes(at("check.err"));
    // Nothing is left behind.
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"mid.dat", "check.err"}));
}

TEST(SessionRoundTrip, EverySessionsModelIsCheckedAtItsEnd) {
    // The sessions of the tests (test_util.h) end by saving their model, restoring it into a
    // fresh model and saving again; a session whose commands all succeeded must hold a model
    // that saves.
    EXPECT_NONFATAL_FAILURE(
        {
            Session s;
            EXPECT_TRUE(s.run("poly brick 0 1 0 1 0 1"));
            s.model.blocks.vel[0].x() = std::numeric_limits<double>::quiet_NaN();
        },
        "every command succeeded, but the model cannot be saved: block 1: the velocity is not a finite number");
}
