// `save` and `restore`: restoring and going on gives the same bits as never having saved;
// a truncated, foreign, newer or damaged file is refused with its reason and the model kept;
// a save that fails leaves the old file as it was.
#include <gtest/gtest.h>

#include <dirent.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <type_traits>
#include <utility>
#include <vector>

#include "io/save.h"
#include "test_util.h"

using odec::test::Session;

namespace {

// A column of three unit cubes on a fixed base, the top one set sliding sideways so that
// the joints both compress and shear.
const char* kColumn =
    "poly brick -1 2 -1 2 -1 0\n"
    "poly brick 0 1 0 1 0 1\n"
    "poly brick 0 1 0 1 1 2\n"
    "poly brick 0.1 1.1 0 1 2 3\n"
    "prop mat=1 dens=2000\n"
    "prop jmat=1 jkn=1e7 jks=1e7 jfric=30\n"
    "grav 0 0 -10\n"
    "fix range z -1 0\n"
    "hist ncyc 7\n"
    "hist zdis 0.5 0.5 2.5\n"
    "hist unbal\n";

std::string read_bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

void write_bytes(const std::string& path, const std::string& bytes) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// The bytes of a model's save file, with the wall-clock profile left out (it is the one
// part of the state that differs between two runs of the same steps).
std::string state_bytes(const odec::Model& m, const std::string& path) {
    odec::Model copy = m;
    copy.profile = odec::Profile();
    std::string error;
    EXPECT_TRUE(odec::save_model(copy, path, error)) << error;
    return read_bytes(path);
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

std::vector<std::string> files_in(const std::string& dir) {
    std::vector<std::string> out;
    if (DIR* d = opendir(dir.c_str())) {
        while (dirent* e = readdir(d)) {
            const std::string n = e->d_name;
            if (n != "." && n != "..") out.push_back(n);
        }
        closedir(d);
    }
    return out;
}

class Save : public ::testing::Test {
protected:
    std::string dir;
    void SetUp() override {
        char tmpl[] = "/tmp/odec-save-test-XXXXXX";
        ASSERT_NE(mkdtemp(tmpl), nullptr);
        dir = tmpl;
    }
    void TearDown() override {
        for (const std::string& f : files_in(dir)) std::remove((dir + "/" + f).c_str());
        rmdir(dir.c_str());
    }
    std::string at(const std::string& name) const { return dir + "/" + name; }

    // A session holding the column after `steps` steps.
    void column(Session& s, int steps, const std::string& extra = "") {
        ASSERT_TRUE(s.run(std::string(kColumn) + extra + "step " + std::to_string(steps))) << s.error();
    }

    // Expect `restore` of `file` to fail with a message containing `what`, leaving the
    // session's model as it was. Returns the whole error text.
    std::string refused(const std::string& file, const std::string& what) {
        Session s;
        column(s, 10);
        const std::string before = state_bytes(s.model, at("before.check"));
        EXPECT_FALSE(s.run("restore '" + file + "'")) << file;
        EXPECT_NE(s.error().find(what), std::string::npos) << s.error();
        EXPECT_EQ(state_bytes(s.model, at("after.check")), before) << "the model changed";
        return s.error();
    }
};

} // namespace

TEST_F(Save, RestoringAndGoingOnGivesTheSameBits) {
    for (const char* damping : {"", "damp auto\n"}) {
        SCOPED_TRACE(damping);
        Session a;
        column(a, 500, damping);
        ASSERT_GT(a.model.contacts.size(), 0);
        ASSERT_TRUE(a.run("save '" + at("mid") + "'")) << a.error();
        ASSERT_TRUE(a.run("step 500")) << a.error();

        Session b;
        ASSERT_TRUE(b.run("poly brick 5 6 5 6 5 6\nrest '" + at("mid") + "'\nstep 500")) << b.error();

        const odec::Model& x = a.model;
        const odec::Model& y = b.model;
        EXPECT_EQ(x.step, 1000);
        EXPECT_EQ(y.step, 1000);
        EXPECT_TRUE(same_bits(x.blocks.centroid, y.blocks.centroid));
        EXPECT_TRUE(same_bits(x.blocks.orientation, y.blocks.orientation));
        EXPECT_TRUE(same_bits(x.blocks.vel, y.blocks.vel));
        EXPECT_TRUE(same_bits(x.blocks.ang_vel, y.blocks.ang_vel));
        EXPECT_TRUE(same_bits(x.contacts.sub_sn, y.contacts.sub_sn));
        EXPECT_TRUE(same_bits(x.contacts.sub_ss, y.contacts.sub_ss));
        EXPECT_TRUE(same_bits(x.contacts.normal, y.contacts.normal));
        EXPECT_EQ(std::memcmp(&x.time, &y.time, sizeof x.time), 0);
        EXPECT_EQ(std::memcmp(&x.damping.auto_coefficient, &y.damping.auto_coefficient, sizeof(double)), 0);
        ASSERT_EQ(x.histories.items.size(), 2u);
        EXPECT_TRUE(same_bits(x.histories.items[0].values, y.histories.items[0].values));
        // And everything else too: the two states save to the same bytes.
        EXPECT_EQ(state_bytes(x, at("x.check")), state_bytes(y, at("y.check")));
    }
}

TEST_F(Save, SaveRestoreSaveGivesTheSameFile) {
    Session a;
    column(a, 50);
    // Parts the column leaves at their defaults.
    odec::Model& x = a.model;
    x.title = "column";
    x.tables.tables[3].points = {{0, 0}, {1, 2.5}};
    x.group_names = {"base", "top"};
    x.blocks.group[0] = 0;
    x.joint_planes.push_back(odec::JointPlane{1, true, 2});
    x.damping.mode = odec::DampingMode::Rayleigh;
    x.damping.rayleigh_fraction = 0.05;
    odec::History h;
    h.kind = odec::HistoryKind::SDis;
    h.contact_id = 2;
    h.values.assign(x.histories.sample_steps.size(), 0.25);
    x.histories.items.push_back(h);
    std::string error;
    ASSERT_TRUE(odec::save_model(x, at("one.sav"), error)) << error;
    odec::Model m;
    ASSERT_TRUE(odec::restore_model(at("one.sav"), m, error)) << error;
    EXPECT_EQ(m.title, "column");
    EXPECT_EQ(m.tables.find(3)->at(0.5), 1.25);
    EXPECT_EQ(m.histories.items.back().kind, odec::HistoryKind::SDis);
    EXPECT_EQ(m.histories.items.back().contact_id, 2);
    EXPECT_EQ(m.damping.mode, odec::DampingMode::Rayleigh);
    ASSERT_TRUE(odec::save_model(m, at("two.sav"), error)) << error;
    EXPECT_EQ(read_bytes(at("one.sav")), read_bytes(at("two.sav")));
}

TEST_F(Save, AddsTheExtensionWhenThereIsNone) {
    EXPECT_EQ(odec::save_file_name("gravity"), "gravity.sav");
    EXPECT_EQ(odec::save_file_name("0_2_cyc0"), "0_2_cyc0.sav");
    EXPECT_EQ(odec::save_file_name("runs.1/model"), "runs.1/model.sav");
    EXPECT_EQ(odec::save_file_name("model.dat"), "model.dat");
    EXPECT_EQ(odec::save_file_name(".hidden"), ".hidden.sav");
    Session a;
    column(a, 5);
    ASSERT_TRUE(a.run("save '" + at("bc_grav") + "'")) << a.error();
    EXPECT_FALSE(read_bytes(at("bc_grav.sav")).empty());
    Session b;
    ASSERT_TRUE(b.run("restore '" + at("bc_grav") + "'")) << b.error();
    EXPECT_EQ(b.model.step, 5);
    EXPECT_EQ(b.model.blocks.size(), 4);
}

TEST_F(Save, MissingFileIsReported) {
    Session s;
    EXPECT_FALSE(s.run("restore nosuchfile"));
    EXPECT_EQ(s.error(),
              "t.dat:1:9: error: cannot restore 'nosuchfile.sav': No such file or directory\n"
              "    restore nosuchfile\n"
              "            ^~~~~~~~~~\n"
              "  see 'help restore'\n");
}

TEST_F(Save, TruncatedFileIsRefusedAndTheModelKept) {
    Session a;
    column(a, 100);
    ASSERT_TRUE(a.run("save '" + at("full") + "'")) << a.error();
    const std::string full = read_bytes(at("full.sav"));
    ASSERT_GT(full.size(), 200u);
    for (size_t cut : {size_t{1}, size_t{11}, size_t{12}, size_t{15}, size_t{20}, size_t{30}, size_t{40},
                       full.size() / 3, full.size() / 2, full.size() - 9, full.size() - 1}) {
        SCOPED_TRACE(cut);
        write_bytes(at("cut.sav"), full.substr(0, cut));
        refused(at("cut.sav"), "is truncated");
    }
    write_bytes(at("cut.sav"), "");
    refused(at("cut.sav"), "the file is empty");

    // The exact text, cut in the middle.
    const size_t cut = full.size() / 2;
    write_bytes(at("cut.sav"), full.substr(0, cut));
    const std::string path = at("cut.sav");
    const std::string quoted = "'" + path + "'";
    EXPECT_EQ(refused(path, "truncated"),
              "t.dat:1:9: error: cannot restore '" + path + "': the file is truncated: it has " +
                  std::to_string(cut) + " bytes, a complete save has " + std::to_string(full.size()) + "\n" +
                  "    restore " + quoted + "\n" + "            ^" + std::string(quoted.size() - 1, '~') + "\n" +
                  "  see 'help restore'\n");
    // Cut inside the header.
    write_bytes(path, full.substr(0, 14));
    EXPECT_NE(refused(path, "truncated").find("cannot restore '" + path +
                                              "': the file is truncated: it ends at byte 14, inside the header\n"),
              std::string::npos);
}

TEST_F(Save, ForeignFileIsRefused) {
    write_bytes(at("notes.sav"), "poly brick 0 1 0 1 0 1\nstep 10\n");
    const std::string e = refused(at("notes.sav"), "is not an odec save file");
    EXPECT_NE(e.find("cannot restore '" + at("notes.sav") +
                     "': it is not an odec save file (it does not begin with 'ODEC-SAVE')\n"),
              std::string::npos)
        << e;
    write_bytes(at("short.sav"), "ODX");
    refused(at("short.sav"), "is not an odec save file");
}

TEST_F(Save, NewerFormatIsRefused) {
    Session a;
    column(a, 20);
    ASSERT_TRUE(a.run("save '" + at("new") + "'")) << a.error();
    std::string bytes = read_bytes(at("new.sav"));
    const std::uint32_t newer = odec::kSaveFormatVersion + 1;
    std::memcpy(&bytes[12], &newer, 4);
    write_bytes(at("new.sav"), bytes);
    const std::string e = refused(at("new.sav"), "newer than this odec");
    EXPECT_NE(e.find("cannot restore '" + at("new.sav") + "': it was written by odec " +
                     odec::save_program_version() + " in save format " + std::to_string(newer) +
                     ", newer than this odec (" + odec::save_program_version() + ") reads (format " +
                     std::to_string(odec::kSaveFormatVersion) + " and older); restore it with a newer odec\n"),
              std::string::npos)
        << e;
}

TEST_F(Save, FlippedByteFailsTheChecksum) {
    Session a;
    column(a, 20);
    ASSERT_TRUE(a.run("save '" + at("good") + "'")) << a.error();
    const std::string good = read_bytes(at("good.sav"));
    for (size_t pos : {size_t{40}, good.size() / 2, good.size() - 20, good.size() - 1}) {
        SCOPED_TRACE(pos);
        std::string bad = good;
        bad[pos] = static_cast<char>(bad[pos] ^ 0x10);
        write_bytes(at("bad.sav"), bad);
        refused(at("bad.sav"), "the file is damaged: its checksum does not match its contents");
    }
}

TEST_F(Save, FailedSaveLeavesTheOldFileIntact) {
    Session a;
    column(a, 20);
    ASSERT_TRUE(a.run("save '" + at("keep") + "'")) << a.error();
    const std::string old_bytes = read_bytes(at("keep.sav"));
    ASSERT_TRUE(a.run("step 30")) << a.error();

    // The disk fills up halfway through writing the new one (a file size limit stands in
    // for a full disk; it works for every user, root included).
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        signal(SIGXFSZ, SIG_IGN);
        rlimit lim{static_cast<rlim_t>(old_bytes.size() / 2), static_cast<rlim_t>(old_bytes.size() / 2)};
        setrlimit(RLIMIT_FSIZE, &lim);
        std::string error;
        const bool ok = odec::save_model(a.model, at("keep.sav"), error);
        _exit(!ok && error.find("cannot save to '" + at("keep.sav") + "'") != std::string::npos &&
                      error.find("File too large") != std::string::npos
                  ? 0
                  : 1);
    }
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << "the save did not fail as expected";
    EXPECT_EQ(read_bytes(at("keep.sav")), old_bytes);
    EXPECT_EQ(files_in(dir), std::vector<std::string>{"keep.sav"}) << "a temporary file was left behind";

    // A directory that cannot be written (for users other than root).
    if (geteuid() != 0) {
        ASSERT_EQ(chmod(dir.c_str(), 0500), 0);
        Session s;
        column(s, 5);
        EXPECT_FALSE(s.run("save '" + at("keep") + "'"));
        EXPECT_NE(s.error().find("cannot save to '" + at("keep.sav") + "': cannot create the temporary file"),
                  std::string::npos)
            << s.error();
        chmod(dir.c_str(), 0700);
        EXPECT_EQ(read_bytes(at("keep.sav")), old_bytes);
    }

    // A directory that does not exist: the error names the file.
    Session s;
    EXPECT_FALSE(s.run("save '" + at("no/such/dir/x") + "'"));
    EXPECT_NE(s.error().find("cannot save to '" + at("no/such/dir/x.sav") + "'"), std::string::npos) << s.error();
    EXPECT_NE(s.error().find("No such file or directory"), std::string::npos) << s.error();

    // And the restored old file is the model as it was then.
    Session r;
    ASSERT_TRUE(r.run("restore '" + at("keep") + "'")) << r.error();
    EXPECT_EQ(r.model.step, 20);
}

TEST_F(Save, SizesPerBlockAndContact) {
    // Columns of n cubes: the file grows by one block and one contact per cube.
    std::vector<size_t> sizes;
    std::vector<int> subs;
    for (int n : {3, 6}) {
        Session s;
        std::string text = "poly brick -1 2 -1 2 -1 0\n";
        for (int k = 0; k < n; ++k) {
            text += "poly brick 0 1 0 1 " + std::to_string(k) + " " + std::to_string(k + 1) + "\n";
        }
        text += "prop mat=1 dens=2000\nprop jmat=1 jkn=1e7 jks=1e7 jfric=30\ngrav 0 0 -10\n"
                "fix range z -1 0\nstep 10\n";
        ASSERT_TRUE(s.run(text)) << s.error();
        ASSERT_EQ(s.model.contacts.size(), n);
        sizes.push_back(state_bytes(s.model, at("size.sav")).size());
        subs.push_back(s.model.contacts.n_subs());
    }
    const double per_cube = (sizes[1] - sizes[0]) / 3.0;
    const double subs_per_cube = (subs[1] - subs[0]) / 3.0;
    std::printf("save file: %zu bytes for 3 cubes, %zu for 6: %.0f bytes per cube block with its contact "
                "(%.0f sub-contacts)\n",
                sizes[0], sizes[1], per_cube, subs_per_cube);
    EXPECT_LT(per_cube, 4000);
}

// A tripwire for new state: when a field is added to one of these structs, the save format
// must learn it (src/io/save.cpp, the `fields` functions; raise kSaveFormatVersion when old
// files can no longer be read as they are), and then the count here is updated. Fields are
// counted as the number of values that brace-initialize the aggregate (an array counts
// each element).
namespace {
struct AnyValue {
    template <class T>
    operator T() const;
};
template <class T, class Seq, class = void>
struct BraceInit : std::false_type {};
template <class T, size_t... I>
struct BraceInit<T, std::index_sequence<I...>, std::void_t<decltype(T{(void(I), AnyValue{})...})>>
    : std::true_type {};
template <class T, size_t N = 0>
constexpr size_t count_fields() {
    if constexpr (!BraceInit<T, std::make_index_sequence<N + 1>>::value) return N;
    else return count_fields<T, N + 1>();
}
} // namespace

TEST(SaveLayout, EveryFieldIsSaved) {
    using namespace odec;
    const char* fix = "a field was added: save and restore it in src/io/save.cpp, then update this count";
    EXPECT_EQ(count_fields<Model>(), 20u) << fix;
    EXPECT_EQ(count_fields<BlockSet>(), 28u) << fix;
    EXPECT_EQ(count_fields<ContactSet>(), 31u) << fix;
    EXPECT_EQ(count_fields<Polyhedron>(), 4u) << fix;
    EXPECT_EQ(count_fields<Material>(), 8u) << fix;
    EXPECT_EQ(count_fields<JointMaterial>(), 9u) << fix;
    EXPECT_EQ(count_fields<JointPlane>(), 3u) << fix;
    EXPECT_EQ(count_fields<History>(), 7u) << fix;
    EXPECT_EQ(count_fields<HistorySet>(), 3u) << fix;
    EXPECT_EQ(count_fields<Table>(), 1u) << fix;
    EXPECT_EQ(count_fields<TableSet>(), 1u) << fix;
    EXPECT_EQ(count_fields<Damping>(), 5u) << fix;
    EXPECT_EQ(count_fields<Settings>(), 6u) << fix;
    EXPECT_EQ(count_fields<Profile>(), 6u) << fix; // 5 stage times and the step count
}
