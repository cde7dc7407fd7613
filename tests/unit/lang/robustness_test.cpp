// Inputs that used to crash odec or hang it: each must fail as an ordinary located error (or
// work), and the session must go on.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>
#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "lang/decl.h"
#include "../time_scale.h"
#include "test_util.h"

using odec::test::Session;

namespace {

std::string temp_path(const std::string& name) { return testing::TempDir() + "odec-robust-" + name; }

void write_file(const std::string& path, const std::string& text) {
    std::ofstream f(path, std::ios::trunc);
    f << text;
}

std::string error_of(const std::string& text) {
    Session s;
    EXPECT_FALSE(s.run(text)) << text;
    return s.error();
}

} // namespace

// --- call nesting -------------------------------------------------------------------------

TEST(Robustness, DeepCallChainStopsWithALocatedError) {
    // c1.dat calls c2.dat ... calls c200.dat: thousands of levels used to overflow the C++ stack.
    const int n = 200;
    for (int k = 1; k <= n; ++k) {
        write_file(temp_path("c" + std::to_string(k) + ".dat"),
                   k < n ? "call 'odec-robust-c" + std::to_string(k + 1) + ".dat'\n" : "title 'deepest'\n");
    }
    Session s;
    EXPECT_FALSE(s.run("call '" + temp_path("c1.dat") + "'"));
    const std::string dir = testing::TempDir();
    const std::string caller = dir + "odec-robust-c64.dat";
    const std::string callee = dir + "odec-robust-c65.dat";
    EXPECT_EQ(s.error(), caller + ":1:6: error: calls nest too deeply: calling '" + callee +
                             "' would make a chain of 65 files (at most 64)\n"
                             "    call 'odec-robust-c65.dat'\n"
                             "         ^~~~~~~~~~~~~~~~~~~~~\n"
                             "  the chain starts at '" + dir + "odec-robust-c1.dat'\n"
                             "  see 'help call'\n");
    EXPECT_TRUE(s.model.title.empty());
    // The session goes on, and a chain within the limit runs.
    EXPECT_TRUE(s.run("call '" + temp_path("c" + std::to_string(n - 63) + ".dat") + "'")) << s.error();
    EXPECT_EQ(s.model.title, "deepest");
}

// --- files that are not scripts -------------------------------------------------------------

TEST(Robustness, CallRefusesADirectory) {
    EXPECT_EQ(error_of("call '/tmp'"),
              "t.dat:1:6: error: cannot open '/tmp': it is a directory, not a regular file\n"
              "    call '/tmp'\n"
              "         ^~~~~~\n"
              "  see 'help call'\n");
}

TEST(Robustness, CallRefusesADeviceWithoutReadingIt) {
    // /dev/zero never ends: reading it used to fill the memory.
    EXPECT_NE(error_of("call '/dev/zero'").find("t.dat:1:6: error: cannot open '/dev/zero': it is a character device, "
                                                "not a regular file\n"),
              std::string::npos);
}

TEST(Robustness, CallRefusesANamedPipeWithoutWaiting) {
    // Opening a FIFO for reading used to wait for a writer, forever.
    const std::string path = temp_path("fifo");
    std::remove(path.c_str());
    ASSERT_EQ(mkfifo(path.c_str(), 0600), 0);
    const std::string e = error_of("call '" + path + "'");
    std::remove(path.c_str());
    EXPECT_NE(e.find("error: cannot open '" + path + "': it is a named pipe, not a regular file"), std::string::npos) << e;
}

TEST(Robustness, CallRefusesAHugeFileWithoutReadingIt) {
    const std::string path = temp_path("huge.dat");
    write_file(path, "");
    ASSERT_EQ(truncate(path.c_str(), (std::int64_t{64} << 20) + 1), 0); // sparse: no disk used
    const std::string e = error_of("call '" + path + "'");
    std::remove(path.c_str());
    EXPECT_NE(e.find("error: cannot open '" + path + "': the file is larger than 64 MiB (67108865 bytes)"),
              std::string::npos)
        << e;
}

TEST(Robustness, TableReadRefusesWhatIsNotARegularFile) {
    EXPECT_NE(error_of("table 1 read '/dev/zero'")
                  .find("t.dat:1:14: error: cannot open '/dev/zero': it is a character device, not a regular file"),
              std::string::npos);
    EXPECT_NE(error_of("table 1 read '/tmp'").find("error: cannot open '/tmp': it is a directory, not a regular file"),
              std::string::npos);
}

TEST(Robustness, TableReadRefusesNumbersTooLargeForADouble) {
    const std::string path = temp_path("table.txt");
    write_file(path, "; t v\n0 0\n1e309 1\n");
    EXPECT_NE(error_of("table 1 read '" + path + "'").find("line 3: expected two finite numbers"), std::string::npos);
    write_file(path, "0 0\n1 -1e400\n");
    EXPECT_NE(error_of("table 1 read '" + path + "'").find("line 2: expected two finite numbers"), std::string::npos);
    write_file(path, "0 0\n1 -1e300\n");
    EXPECT_NE(error_of("table 1 read '" + path + "'").find("line 2: numbers must be of magnitude at most 1e100"),
              std::string::npos);
    std::remove(path.c_str());
}

// --- out of memory ------------------------------------------------------------------------

namespace {

// A command table with the real commands and two that run out of memory.
struct HungryTable {
    odec::CommandSpec bad_alloc{"gobble", 3, "throws std::bad_alloc"};
    odec::CommandSpec length{"lengthy", 3, "throws std::length_error"};
    odec::CommandTable table;
    HungryTable() {
        bad_alloc.positional.integer("n").optional();
        bad_alloc.handle([](odec::CommandContext&, const odec::Args&) { throw std::bad_alloc(); });
        length.handle([](odec::CommandContext&, const odec::Args&) {
            std::vector<double> v;
            v.reserve(v.max_size() + 1); // throws std::length_error
        });
        table = odec::command_table();
        table.commands.push_back(&bad_alloc);
        table.commands.push_back(&length);
    }
};

} // namespace

TEST(Robustness, OutOfMemoryFailsTheCommandAndTheSessionGoesOn) {
    HungryTable h;
    odec::Model model;
    std::ostringstream out, err;
    odec::Interpreter interp(model, h.table, out, err);
    interp.quiet = true;
    EXPECT_FALSE(interp.run_text("t.dat", "title 'before'\ngobb 5\ntitle 'not run'", false));
    EXPECT_EQ(err.str(), "t.dat:2:1: error: out of memory while running 'gobble'\n"
                         "    gobb 5\n"
                         "    ^~~~\n"
                         "  the command stopped part way: the model may keep what it had done\n"
                         "  see 'help gobble'\n");
    EXPECT_EQ(model.title, "before");
    err.str("");
    EXPECT_FALSE(interp.run_text("t.dat", "lengthy", false));
    EXPECT_NE(err.str().find("t.dat:1:1: error: out of memory while running 'lengthy'"), std::string::npos) << err.str();
    EXPECT_TRUE(interp.run_text("t.dat", "title 'after'", false));
    EXPECT_EQ(model.title, "after");
}

// --- non-finite numbers -----------------------------------------------------------------------

TEST(Robustness, NonFiniteVectorComponentsAreRefused) {
    EXPECT_EQ(error_of("grav 0 0 1e309"),
              "t.dat:1:10: error: 'gravity' components must be finite numbers (got 1e309)\n"
              "    grav 0 0 1e309\n"
              "             ^~~~~\n"
              "  see 'help gravity'\n");
    EXPECT_NE(error_of("poly brick 0 1 0 1 0 1\njset dip 30 dd 0 origin 0,0,1e309")
                  .find("t.dat:2:29: error: 'origin' components must be finite numbers (got 1e309)"),
              std::string::npos);
    EXPECT_NE(error_of("hist zdis 1e309,0,0").find("t.dat:1:11: error: 'zdisplacement' components must be finite numbers (got 1e309)"),
              std::string::npos);
    EXPECT_NE(error_of("plot view eye (-1e999,0,0)").find("error: 'view' point components must be finite numbers (got -1e999)"),
              std::string::npos);
    Session s;
    EXPECT_FALSE(s.run("grav 0 0 -1e309"));
    EXPECT_EQ(s.model.gravity, odec::Vec3::Zero());
}

TEST(Robustness, NonFiniteScalarSaysAFiniteNumberIsExpected) {
    EXPECT_EQ(error_of("table 1 0 0 1 1e309"),
              "t.dat:1:15: error: 'table' x y must be a finite number (got 1e309)\n"
              "    table 1 0 0 1 1e309\n"
              "                  ^~~~~\n"
              "  see 'help table'\n");
    EXPECT_NE(error_of("prop mat=1 dens=1e309").find("error: 'density' must be a finite number > 0 (got 1e309)"),
              std::string::npos);
    EXPECT_NE(error_of("jset dip 1e309 dd 0").find("error: 'dip' must be 0 to 90 (got 1e309)"), std::string::npos);
}

// --- the log ------------------------------------------------------------------------------

namespace {

// A screen that takes nothing, like stdout on a full disk.
struct FullBuffer : std::streambuf {
    int overflow(int) override { return traits_type::eof(); }
    std::streamsize xsputn(const char*, std::streamsize) override { return 0; }
    int sync() override { return -1; }
};

} // namespace

TEST(Robustness, LogGoesOnWhenTheScreenFails) {
    // With stdout on a full disk the log used to stop at its first failed write (4096 bytes
    // of stdout buffer), silently.
    const std::string path = temp_path("screen.log");
    std::remove(path.c_str());
    FullBuffer full;
    std::ostream screen(&full);
    odec::Model model;
    std::ostringstream err;
    odec::Interpreter interp(model, odec::command_table(), screen, err);
    interp.quiet = true;
    std::string text = "print block\nset logfile '" + path + "'\nset log on\n";
    for (int k = 0; k < 40; ++k) text += "poly brick 0 1 0 1 " + std::to_string(k) + " " + std::to_string(k + 1) + "\n";
    text += "print block\ntitle 'last'\nprint block\nset log off\n";
    ASSERT_TRUE(interp.run_text("t.dat", text, false)) << err.str();
    std::ifstream in(path);
    const std::string log((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_GT(log.size(), 8192u);
    const size_t last = log.rfind("odec> print block");
    ASSERT_NE(last, std::string::npos) << log;
    EXPECT_NE(log.find("40 of 40 blocks", last), std::string::npos) << log.substr(last);
    std::remove(path.c_str());
}

TEST(Robustness, ABlockThatRanAwayIsNotZoned) {
    // The fuzzing campaign's hang: a block that has run away to 2.45e19 m, where neighbouring
    // doubles are kilometres apart, has all its corners at one point, and the mesher never
    // finished with it. 'gen' refuses it, naming the block, and the model stays as it was.
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2600 ymod=1e9 prat=0.25\nset dt 0.01\n"
                      "def push\n  b_yvel(block_head) = 2.45e21\nend\n@push\nstep 1\n"));
    EXPECT_FALSE(s.run("gen edge 1"));
    EXPECT_NE(s.error().find("t.dat:1:1: error: block 1 lies 2.45e+19 m from the origin, where coordinates are no "
                             "finer than 5440.09 m"),
              std::string::npos)
        << s.error();
    EXPECT_EQ(s.model.zones.size(), 0);
    EXPECT_EQ(s.model.gridpoints.size(), 0);
    // Far from the origin but resolved (a 1 m block at 2e8 m: doubles 3e-8 m apart), it is zoned.
    Session far;
    ASSERT_TRUE(far.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2600 ymod=1e9 prat=0.25\nset dt 1\n"
                        "def push\n  b_yvel(block_head) = 2e8\nend\n@push\nstep 1\ngen edge 0.5\n"))
        << far.error();
    EXPECT_GT(far.model.zones.size(), 0);
}

TEST(Robustness, AZonedBlockFoldedByARunAwayIsNotZonedAgain) {
    // The campaign's time-out of round 9: after a run-away under a huge gravity, a zoned block's
    // corner gridpoints no longer made a convex solid, and `gen` zoning it again kept the mesher
    // busy for two minutes before it failed. `gen` refuses it at once, naming the block, and
    // the zones stay as they were.
    const std::string model = "poly brick -0.5 1.5 -0.5 1.5 -0.5 0 region 1\npoly brick 0 1 0 1 0 1 region 2\n"
                              "prop mat=1 dens=2600 ymod=1e9 prat=0.25\n"
                              "prop jmat=1 jkn=1e9 jks=1e9 jfric=40 jcoh=1e4 jten=1e3\n"
                              "grav 0 0 -10\ngen edge 1\nfix range region 1\nstep 1\n";
    Session s;
    ASSERT_TRUE(s.run(model + "gravity 0.1,-1e9,0.75\nstep 3\n")) << s.error();
    const int zones = s.model.zones.size();
    ASSERT_GT(zones, 0);
    EXPECT_FALSE(s.run("gen edge 0.4"));
    EXPECT_NE(s.error().find("t.dat:1:1: error: block 2 cannot be zoned again: its corners, where its gridpoints have "
                             "moved, no longer make a convex solid ("),
              std::string::npos)
        << s.error();
    EXPECT_EQ(s.model.zones.size(), zones);
    // Under its own weight the block deforms by far less, and is zoned again.
    Session still;
    ASSERT_TRUE(still.run(model + "step 10\ngen edge 0.4\n")) << still.error();
    EXPECT_GT(still.model.zones.size(), zones);
}

TEST(Robustness, TheMesherDiesWithTheSession) {
    // A session killed while Gmsh meshes (a time limit, a closed terminal) must not leave the
    // mesher's process running on: the campaign's time-out left one at full speed for ten
    // minutes. The mesher is a fork of odec, so it carries odec's command line, with this
    // script's unique name in it.
    const std::string script = temp_path("mesh-" + std::to_string(getpid()) + ".dat");
    write_file(script, "poly brick 0 1 0 1 0 1\ngen edge 0.012\n");
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        const int null = open("/dev/null", O_WRONLY);
        dup2(null, 1);
        dup2(null, 2);
        execl(ODEC_BINARY, ODEC_BINARY, "--quiet", script.c_str(), static_cast<char*>(nullptr));
        _exit(127);
    }
    // The processes whose command line names the script.
    auto running = [&] {
        std::vector<int> found;
        DIR* d = opendir("/proc");
        if (!d) return found;
        while (dirent* e = readdir(d)) {
            const int p = std::atoi(e->d_name);
            if (p <= 0) continue;
            std::ifstream f("/proc/" + std::string(e->d_name) + "/cmdline", std::ios::binary);
            std::string cmd;
            try {
                cmd.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
            } catch (const std::exception&) {
                continue; // the process ended while its command line was read ("No such process")
            }
            if (cmd.find(script) != std::string::npos) found.push_back(p);
        }
        closedir(d);
        return found;
    };
    // Wait until the mesher runs (two processes), then kill the session.
    bool meshing = false;
    for (int i = 0; i < 300 * odec::test::time_scale() && !meshing; ++i) {
        usleep(20000);
        meshing = running().size() >= 2;
    }
    kill(pid, SIGKILL);
    waitpid(pid, nullptr, 0);
    ASSERT_TRUE(meshing) << "the mesher never started";
    std::vector<int> left;
    for (int i = 0; i < 100; ++i) {
        left = running();
        if (left.empty()) break;
        usleep(20000);
    }
    for (int p : left) kill(p, SIGKILL); // not left running after the test
    EXPECT_TRUE(left.empty()) << left.size() << " mesher process(es) outlived the session";
    std::remove(script.c_str());
}
