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

using odec::test::read_bytes;
using odec::test::Session;
using odec::test::write_bytes;

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

// A deformable cube of Mohr-Coulomb zones on a held base, under its weight and a vertical
// stress on its top near its strength, so that zones yield; histories of a gridpoint's
// displacement, a zone's stress and the reaction of the base.
const char* kZonedCube =
    "poly brick 0 1 0 1 0 1\n"
    "prop mat=1 dens=2500 ymod=10e9 prat=0.25 coh=3e5 fric=30 ten=1e5\n"
    "change cons=2\n"
    "gen edge 0.25\n"
    "grav 0 0 -10\n"
    "bound zvel 0 range z -0.001 0.001\n"
    "fix range x -0.001 0.001 z -0.001 0.001\n"
    "bound stress 0 0 -1.2e6 0 0 0 range z 0.999 1.001\n"
    "hist ncyc 5\n"
    "hist zdis 0.5 0.5 1\n"
    "hist xvel 1 1 1\n"
    "hist szz 0.5 0.5 0.5\n"
    "hist zreaction range z -0.001 0.001\n";


// The bytes of a model's save file, with the wall-clock profile left out (it is the one
// part of the state that differs between two runs of the same steps).
std::string state_bytes(const odec::Model& m, const std::string& path) {
    odec::Model copy = m;
    copy.profile = odec::Profile();
    std::string error;
    EXPECT_TRUE(odec::save_model_unchecked(copy, path, error)) << error;
    return read_bytes(path);
}

template <class V>
bool same_bits(const V& a, const V& b) {
    using T = typename V::value_type;
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
        EXPECT_TRUE(same_bits(x.contacts.sub_un, y.contacts.sub_un));
        EXPECT_TRUE(same_bits(x.contacts.sub_ss, y.contacts.sub_ss));
        EXPECT_TRUE(same_bits(x.contacts.normal_code, y.contacts.normal_code));
        EXPECT_EQ(std::memcmp(&x.time, &y.time, sizeof x.time), 0);
        EXPECT_EQ(std::memcmp(&x.damping.auto_coefficient, &y.damping.auto_coefficient, sizeof(double)), 0);
        ASSERT_EQ(x.histories.items.size(), 2u);
        EXPECT_TRUE(same_bits(x.histories.items[0].values, y.histories.items[0].values));
        // And everything else too: the two states save to the same bytes.
        EXPECT_EQ(state_bytes(x, at("x.check")), state_bytes(y, at("y.check")));
    }
}

TEST_F(Save, OpenContactsKeptByReferenceGoOnBitForBit) {
    // Two stacks 2 cm apart, in dynamic mode; the top brick of one thrown at the other, saved on
    // its way across the gap (its side sub-contacts open, their closures kept by reference and
    // the contacts left alone by the update: contact.h), and again after it struck and pushed the
    // other top brick along (whose corners, sliding off those of the brick below, press in
    // where no sub-contact is: a file without the contacts' free motion (format 18) had the
    // restored model rebuild that contact at once, where the model saved did so later).
    const std::string scene =
        "config dyn\npoly brick -1 3.04 -1 2 -1 0\n"
        "poly brick 0 1 0 1 0.001 1.001\npoly brick 0 1 0 1 1.002 2.002\n"
        "poly brick 1.02 2.02 0 1 0.001 1.001\npoly brick 1.02 2.02 0 1 1.002 2.002\n"
        "prop mat=1 dens=2700\nprop jmat=1 jkn=1e9 jks=1e9 jfric=30\n"
        "grav 0 0 -10\nfix range z -1 0\nset dt 2.5e-5\nstep 200\n"
        "ini xvel 1 range x 0 1 z 1.002 2.002\nstep 300\n";
    for (int after : {0, 1000}) {
        SCOPED_TRACE(after);
        Session a;
        ASSERT_TRUE(a.run(scene + "step " + std::to_string(after + 1) + "\nsave '" + at("mid") + "'\nstep 1500")) << a.error();
        Session b;
        ASSERT_TRUE(b.run("rest '" + at("mid") + "'\nstep 1500")) << b.error();
        const odec::Model& x = a.model;
        const odec::Model& y = b.model;
        EXPECT_TRUE(same_bits(x.blocks.centroid, y.blocks.centroid));
        EXPECT_TRUE(same_bits(x.blocks.vel, y.blocks.vel));
        EXPECT_TRUE(same_bits(x.contacts.sub_un, y.contacts.sub_un));
        EXPECT_TRUE(same_bits(x.contacts.sub_ss, y.contacts.sub_ss));
        EXPECT_EQ(state_bytes(x, at("x.check")), state_bytes(y, at("y.check")));
        // The thrown brick went across and pushed the other stack's top brick.
        EXPECT_GT(x.blocks.centroid[4].x(), 1.52 + 1e-4);
    }
}

TEST_F(Save, AZonedModelGoesOnBitForBit) {
    for (const char* strain : {"", "set small\n"}) {
    SCOPED_TRACE(strain);
    Session a;
    ASSERT_TRUE(a.run(std::string(kZonedCube) + strain + "step 150")) << a.error();
    ASSERT_GT(a.model.zones.size(), 20);
    ASSERT_GT(a.model.stress_boundary.faces.size(), 0u);
    ASSERT_TRUE(a.run("save '" + at("zoned") + "'")) << a.error();
    ASSERT_TRUE(a.run("step 150")) << a.error();

    Session b;
    ASSERT_TRUE(b.run("poly brick 5 6 5 6 5 6\nrest '" + at("zoned") + "'\nstep 150")) << b.error();

    const odec::Model& x = a.model;
    const odec::Model& y = b.model;
    EXPECT_EQ(y.step, 300);
    // The zones did yield (the Mohr-Coulomb state is carried too) and the top moved down.
    int yielded = 0;
    for (std::uint8_t st : x.zones.state) yielded += (st & odec::kShearPast) ? 1 : 0;
    EXPECT_GT(yielded, 0);
    ASSERT_EQ(x.histories.items.size(), 4u);
    EXPECT_LT(x.histories.items[0].values.back(), 0);
    EXPECT_LT(x.histories.items[3].values.back(), 0); // the load on the base, downwards
    EXPECT_TRUE(same_bits(x.gridpoints.pos, y.gridpoints.pos));
    EXPECT_TRUE(same_bits(x.gridpoints.vel, y.gridpoints.vel));
    EXPECT_TRUE(same_bits(x.gridpoints.disp, y.gridpoints.disp));
    EXPECT_TRUE(same_bits(x.gridpoints.force, y.gridpoints.force));
    EXPECT_TRUE(same_bits(x.zones.stress, y.zones.stress));
    EXPECT_EQ(x.zones.state, y.zones.state);
    EXPECT_TRUE(same_bits(x.blocks.world_vertices, y.blocks.world_vertices));
    for (size_t k = 0; k < x.histories.items.size(); ++k) {
        SCOPED_TRACE(k);
        EXPECT_EQ(x.histories.items[k].values.size(), 60u);
        EXPECT_TRUE(same_bits(x.histories.items[k].values, y.histories.items[k].values));
    }
    EXPECT_EQ(std::memcmp(&x.time, &y.time, sizeof x.time), 0);
    EXPECT_EQ(state_bytes(x, at("x.check")), state_bytes(y, at("y.check")));
    }
}

TEST_F(Save, AModelSavedRightAfterDeleteRestoresAndGoesOn) {
    // Deleting blocks leaves the world vertices stale until the next step rebuilds them, and
    // the histories of the deleted block's gridpoint and zone marked removed (-2: they sample
    // 0): such a model saves, restores and goes on as if never saved.
    const std::string build =
        "poly brick 0 1 0 1 0 1\npoly brick 3 4 0 1 0 1\npoly brick 6 7 0 1 0 1\n"
        "prop mat=1 dens=2500 ymod=10e9 prat=0.25\ngen edge 0.5 range id 1 2\n"
        "grav 0 0 -10\nfix range z -0.001 0.001\n"
        "hist zdis 4 1 1\nhist szz 3.9 0.9 0.9\nhist zdis 0.5 0.5 1\nhist zdis 6.5 0.5 1\n"
        "step 30\ndelete range id 2\n";
    Session a;
    ASSERT_TRUE(a.run(build)) << a.error();
    ASSERT_EQ(a.model.blocks.size(), 2);
    ASSERT_EQ(a.model.histories.items[0].gridpoint, -2);
    ASSERT_EQ(a.model.histories.items[1].zone, -2);
    ASSERT_GE(a.model.histories.items[2].gridpoint, 0);
    ASSERT_TRUE(a.run("save '" + at("deleted") + "'\nstep 30")) << a.error();
    Session b;
    ASSERT_TRUE(b.run("restore '" + at("deleted") + "'\nstep 30")) << b.error();
    EXPECT_EQ(b.model.step, 60);
    EXPECT_LT(b.model.histories.items[3].values.back(), 0); // the rigid block falls
    EXPECT_EQ(state_bytes(a.model, at("x.check")), state_bytes(b.model, at("y.check")));
}

TEST_F(Save, AZonedModelRestoresEveryField) {
    Session a;
    ASSERT_TRUE(a.run(std::string(kZonedCube) + "step 20")) << a.error();
    std::string error;
    odec::Model m;
    ASSERT_TRUE(odec::save_model(a.model, at("z.sav"), error)) << error;
    ASSERT_TRUE(odec::restore_model(at("z.sav"), m, error)) << error;
    const odec::Model& x = a.model;
    EXPECT_EQ(m.blocks.cons, x.blocks.cons);
    EXPECT_EQ(m.blocks.cons[0], odec::kZoneMohrCoulomb);
    EXPECT_EQ(m.blocks.corner_gp, x.blocks.corner_gp);
    EXPECT_EQ(m.blocks.corner_gp[0].size(), 8u);
    EXPECT_EQ(m.blocks.body, x.blocks.body);
    EXPECT_EQ(m.blocks.zone_edge, x.blocks.zone_edge);
    EXPECT_EQ(m.blocks.zone_edge[0], 0.25);
    EXPECT_TRUE(m.blocks.flags[0] & odec::kDeformable);
    EXPECT_EQ(m.zones.gp, x.zones.gp);
    EXPECT_EQ(m.zones.block, x.zones.block);
    EXPECT_EQ(m.zones.model, x.zones.model);
    EXPECT_TRUE(same_bits(m.zones.volume, x.zones.volume));
    EXPECT_EQ(x.zones.grad.size(), x.zones.gp.size());
    EXPECT_TRUE(same_bits(m.zones.grad, x.zones.grad));
    EXPECT_TRUE(same_bits(m.gridpoints.ref, x.gridpoints.ref));
    EXPECT_TRUE(same_bits(m.gridpoints.traction, x.gridpoints.traction));
    EXPECT_TRUE(same_bits(m.gridpoints.mass, x.gridpoints.mass));
    EXPECT_TRUE(same_bits(m.gridpoints.stiffness, x.gridpoints.stiffness));
    EXPECT_TRUE(same_bits(m.gridpoints.nmd_rate, x.gridpoints.nmd_rate));
    EXPECT_EQ(m.gridpoints.vel_bc, x.gridpoints.vel_bc);
    EXPECT_EQ(m.gridpoints.block, x.gridpoints.block);
    EXPECT_EQ(m.gridpoints.half_kick, x.gridpoints.half_kick);
    ASSERT_EQ(m.stress_boundary.faces.size(), x.stress_boundary.faces.size());
    for (size_t k = 0; k < m.stress_boundary.faces.size(); ++k) {
        EXPECT_EQ(m.stress_boundary.faces[k].gp, x.stress_boundary.faces[k].gp);
        EXPECT_EQ(m.stress_boundary.faces[k].force, x.stress_boundary.faces[k].force);
    }
    const auto& h = m.histories.items;
    ASSERT_EQ(h.size(), 4u);
    EXPECT_EQ(h[0].gridpoint, x.histories.items[0].gridpoint);
    EXPECT_GE(h[0].gridpoint, 0);
    EXPECT_EQ(h[2].kind, odec::HistoryKind::SZZ);
    EXPECT_EQ(h[2].zone, x.histories.items[2].zone);
    EXPECT_GE(h[2].zone, 0);
    EXPECT_EQ(h[3].kind, odec::HistoryKind::ZReaction);
    EXPECT_EQ(h[3].gridpoints, x.histories.items[3].gridpoints);
    EXPECT_FALSE(h[3].gridpoints.empty());
    // And the second save is the same bytes as the first.
    ASSERT_TRUE(odec::save_model(m, at("z2.sav"), error)) << error;
    EXPECT_EQ(read_bytes(at("z.sav")), read_bytes(at("z2.sav")));
}

TEST_F(Save, DamagedZonedFilesAreRefusedAndTheModelKept) {
    Session a;
    ASSERT_TRUE(a.run(std::string(kZonedCube) + "step 10\nsave '" + at("zoned") + "'")) << a.error();
    const std::string full = read_bytes(at("zoned.sav"));
    // Where the zone and gridpoint sections begin, to damage them in particular.
    const size_t zone_at = full.find("ZONE"), grid_at = full.find("GRID"), sbnd_at = full.find("SBND");
    ASSERT_NE(zone_at, std::string::npos);
    ASSERT_NE(grid_at, std::string::npos);
    ASSERT_NE(sbnd_at, std::string::npos);
    for (size_t cut : {zone_at + 2, zone_at + 40, grid_at + 100, sbnd_at + 20, full.size() - 9}) {
        SCOPED_TRACE(cut);
        write_bytes(at("cut.sav"), full.substr(0, cut));
        refused(at("cut.sav"), "is truncated");
    }
    for (size_t pos : {zone_at + 30, (zone_at + grid_at) / 2, grid_at + 50, sbnd_at + 16}) {
        SCOPED_TRACE(pos);
        std::string bad = full;
        bad[pos] = static_cast<char>(bad[pos] ^ 0x04);
        write_bytes(at("bad.sav"), bad);
        refused(at("bad.sav"), "its checksum does not match");
    }
}

TEST_F(Save, OlderFormatsStillRestore) {
    // A format 2 file, written by the odec before deformable blocks (a falling brick with a
    // displacement history): its blocks are rigid, with the defaults of a new block.
    const std::string two = read_bytes(std::string(ODEC_SOURCE_DIR) + "/tests/fuzz/regressions/restore/brick.sav");
    ASSERT_GT(two.size(), 100u);
    std::uint32_t format = 0;
    std::memcpy(&format, &two[12], 4);
    ASSERT_EQ(format, 2u);
    write_bytes(at("two.sav"), two);
    Session b;
    ASSERT_TRUE(b.run("restore '" + at("two.sav") + "'")) << b.error();
    const odec::Model& m = b.model;
    ASSERT_EQ(m.blocks.size(), 1);
    EXPECT_EQ(m.step, 10);
    EXPECT_EQ(m.zones.size(), 0);
    EXPECT_EQ(m.gridpoints.size(), 0);
    EXPECT_TRUE(m.stress_boundary.faces.empty());
    EXPECT_TRUE(m.insitu.empty());
    EXPECT_EQ(m.blocks.cons, std::vector<std::uint8_t>{odec::kZoneElastic});
    EXPECT_EQ(m.blocks.body, std::vector<int>{0});
    EXPECT_EQ(m.blocks.zone_edge, std::vector<double>{0.0});
    EXPECT_TRUE(m.blocks.corner_gp[0].empty());
    EXPECT_FALSE(m.blocks.flags[0] & odec::kDeformable);
    ASSERT_EQ(m.histories.items.size(), 1u);
    EXPECT_EQ(m.histories.items[0].gridpoint, -1);
    EXPECT_EQ(m.histories.items[0].zone, -1);
    EXPECT_EQ(m.profile.seconds[static_cast<int>(odec::Stage::Zones)], 0.0);
    EXPECT_EQ(m.settings.ovtol, 0.0); // format 10: older files take the automatic overlap tolerance
    const double z_before = m.blocks.centroid[0].z();
    ASSERT_TRUE(b.run("step 10")) << b.error();
    EXPECT_LT(b.model.blocks.centroid[0].z(), z_before);
    // It saves again as format 3 and restores.
    ASSERT_TRUE(b.run("save '" + at("three") + "'\nrestore '" + at("three") + "'")) << b.error();
    std::memcpy(&format, read_bytes(at("three.sav")).data() + 12, 4);
    EXPECT_EQ(format, odec::kSaveFormatVersion);
    EXPECT_EQ(b.model.step, 20);

    // Format 1 is format 2 without the material point of each history (24 bytes after its
    // values): made from the same file, with its lengths and checksum made right.
    std::string one = two;
    std::uint64_t n_version = 0;
    std::memcpy(&n_version, &one[16], 8);
    const size_t payload_length_at = 24 + n_version;
    const size_t hist = one.find("HIST", payload_length_at + 8);
    ASSERT_NE(hist, std::string::npos);
    size_t p = hist + 4 + 8;                 // the section's body
    p += 4;                                  // ncyc
    std::uint64_t n_items = 0;
    std::memcpy(&n_items, &one[p], 8);
    ASSERT_EQ(n_items, 1u);
    p += 8;
    p += 4 + 24 + 4 + 4;                     // kind, point, block id, contact id
    std::uint64_t n = 0;
    std::memcpy(&n, &one[p], 8);
    p += 8 + n;                              // label
    std::memcpy(&n, &one[p], 8);
    p += 8 + 8 * n;                          // values
    one.erase(p, 24);                        // the material point
    auto shrink = [&](size_t at) {
        std::uint64_t len = 0;
        std::memcpy(&len, &one[at], 8);
        len -= 24;
        std::memcpy(&one[at], &len, 8);
    };
    shrink(hist + 4);
    shrink(payload_length_at);
    format = 1;
    std::memcpy(&one[12], &format, 4);
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (size_t i = 0; i + 8 < one.size(); ++i) {
        h ^= static_cast<unsigned char>(one[i]);
        h *= 0x100000001b3ull;
    }
    std::memcpy(&one[one.size() - 8], &h, 8);
    write_bytes(at("one.sav"), one);
    Session c;
    ASSERT_TRUE(c.run("restore '" + at("one.sav") + "'")) << c.error();
    EXPECT_EQ(c.model.step, 10);
    EXPECT_EQ(c.model.zones.size(), 0);
    ASSERT_EQ(c.model.histories.items.size(), 1u);
    // Format 1 histories followed the centroid: the material point is taken at the point.
    const odec::History& h1 = c.model.histories.items[0];
    const odec::Vec3 expected = c.model.blocks.orientation[0].conjugate() * (h1.point - c.model.blocks.centroid[0]);
    EXPECT_EQ(h1.body_offset, expected);
    ASSERT_TRUE(c.run("step 10")) << c.error();
    EXPECT_EQ(c.model.step, 20);
}

TEST_F(Save, Format6AppliedForceRestoresAsALoadAtTheCentroid) {
    // Format 6 held one applied force per block; format 7 holds loads at points with couples
    // and tables, and a table for each gridpoint load and loaded face. A format 6 file, made
    // from a format 7 one with the same model (a block with a load at its centroid), with its
    // lengths and checksum made right.
    Session a;
    ASSERT_TRUE(a.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=1000\nbound xload 1234.5 yload -2345.25 zload 3456.125")) << a.error();
    ASSERT_TRUE(a.run("save '" + at("seven") + "'")) << a.error();
    std::string file = read_bytes(at("seven.sav"));
    std::uint32_t format = 0;
    std::memcpy(&format, &file[12], 4);
    ASSERT_EQ(format, odec::kSaveFormatVersion);
    {
        // Format 12 added the clumps: an int per block after the inertial moments, before the
        // world vertex offsets and the vertices ([1][0], then [0] [0]: none until a step).
        std::string clumps(12, '\0'), offsets(16, '\0');
        const std::uint64_t one = 1;
        std::memcpy(&clumps[0], &one, 8);
        const size_t at_clumps = file.find(clumps + offsets + "ZONE");
        ASSERT_NE(at_clumps, std::string::npos);
        file.erase(at_clumps, 12);
        std::uint64_t n_version = 0, len = 0;
        std::memcpy(&n_version, &file[16], 8);
        const size_t payload_length_at = 24 + n_version;
        const size_t blks = file.find("BLKS", payload_length_at + 8);
        for (size_t at_length : {blks + 4, payload_length_at}) {
            std::memcpy(&len, &file[at_length], 8);
            len -= 12;
            std::memcpy(&file[at_length], &len, 8);
        }
    }
    const double f[3] = {1234.5, -2345.25, 3456.125};
    const std::string force(reinterpret_cast<const char*>(f), 24);
    const size_t at_force = file.find(force);
    ASSERT_NE(at_force, std::string::npos);
    ASSERT_EQ(file.find(force, at_force + 1), std::string::npos);
    // [blocks: 1][loads of block 1: 1][kind][table][lever][force][couple] -> [blocks: 1][force]
    const size_t start = at_force - 48;
    std::uint64_t n = 0;
    std::memcpy(&n, &file[start], 8);
    ASSERT_EQ(n, 1u);
    std::memcpy(&n, &file[start + 8], 8);
    ASSERT_EQ(n, 1u);
    std::string old_loads(8, '\0');
    n = 1;
    std::memcpy(&old_loads[0], &n, 8);
    old_loads += force;
    file.replace(start, 96, old_loads);
    // Then force_scale and disp, and the orientation at the last reset (format 9), which older
    // files hold as the accumulated rotation: none for this block.
    const size_t at_reference = start + 32 + 16 + 32;
    std::memcpy(&n, &file[at_reference], 8);
    ASSERT_EQ(n, 1u);
    file.replace(at_reference + 8, 32, std::string(24, '\0'));
    // GRID ends with the gridpoint load tables (none): 8 bytes before SBND.
    std::uint64_t n_version = 0;
    std::memcpy(&n_version, &file[16], 8);
    const size_t payload_length_at = 24 + n_version;
    // Format 8 added the energy account, the last section, up to the checksum.
    const size_t enrg = file.rfind("ENRG");
    ASSERT_NE(enrg, std::string::npos);
    const size_t enrg_length = file.size() - 8 - enrg;
    file.erase(enrg, enrg_length);
    const size_t blks = file.find("BLKS", payload_length_at + 8);
    const size_t grid = file.find("GRID", blks);
    const size_t sbnd = file.find("SBND", grid);
    ASSERT_TRUE(blks < start && grid != std::string::npos && sbnd != std::string::npos);
    std::memcpy(&n, &file[sbnd - 8], 8);
    ASSERT_EQ(n, 0u);
    file.erase(sbnd - 8, 8);
    auto shrink = [&](size_t at_length, std::uint64_t by) {
        std::uint64_t len = 0;
        std::memcpy(&len, &file[at_length], 8);
        len -= by;
        std::memcpy(&file[at_length], &len, 8);
    };
    shrink(blks + 4, 64 + 8);
    shrink(grid + 4, 8);
    shrink(payload_length_at, 80 + enrg_length);
    // Format 10 added the overlap tolerance, the last of the settings: the 8 bytes before DAMP.
    const size_t sets = file.find("SETS", payload_length_at + 8);
    const size_t damp = file.find("DAMP", sets);
    ASSERT_TRUE(sets != std::string::npos && damp != std::string::npos && sets < blks);
    // Formats 15 and 16 added adaptive damping's memory of the last step and its timestep, the
    // last 24 bytes of DAMP.
    std::uint64_t damp_length = 0;
    std::memcpy(&damp_length, &file[damp + 4], 8);
    file.erase(damp + 12 + damp_length - 24, 24);
    shrink(damp + 4, 24);
    shrink(payload_length_at, 24);
    file.erase(damp - 8, 8);
    shrink(sets + 4, 8);
    shrink(payload_length_at, 8);
    // Format 11 added the cables stage of the profile, format 13 the flow stage and format 14 the
    // liners stage, the last three of its stage times (the cables, the flow and the liners
    // themselves are sections after ENRG, gone with it; the hydraulic apertures of format 13 are
    // in joint materials, which this model has none of).
    // Format 17 dropped the reference points of the contacts' planes, an array after the
    // normals: none here (no contacts), so its length alone; so for the normal stresses.
    const size_t cont = file.find("CONT", payload_length_at + 8);
    ASSERT_NE(cont, std::string::npos);
    for (size_t i = 0; i < 4; ++i) { // ids, blocks a and b, normals: empty
        std::memcpy(&n, &file[cont + 12 + 8 * i], 8);
        ASSERT_EQ(n, 0u);
    }
    file.insert(cont + 12 + 32, std::string(8, '\0'));
    // Format 19 added whether open closures are held by reference (a byte) and the contacts'
    // free motion, an array, before the offsets (after the gap, joint material and model and
    // glued): the array empty here, its length alone; both gone.
    std::memcpy(&n, &file[cont + 12 + 73], 8);
    ASSERT_EQ(n, 0u);
    file.erase(cont + 12 + 72, 9);
    // Format 18 dropped the sub-contacts' normal stresses: an empty array among the empty
    // sub-contact arrays that follow the offsets (gap, joint material and model, glued: empty;
    // the offsets: none, or one 0).
    std::memcpy(&n, &file[cont + 12 + 72], 8);
    ASSERT_LE(n, 1u);
    file.insert(cont + 12 + 80 + 4 * n, std::string(8, '\0'));
    for (size_t at_length : {cont + 4, payload_length_at}) {
        std::uint64_t len = 0;
        std::memcpy(&len, &file[at_length], 8);
        len += 7;
        std::memcpy(&file[at_length], &len, 8);
    }
    const size_t prof = file.find("PROF", payload_length_at + 8);
    ASSERT_TRUE(prof != std::string::npos && prof < blks);
    const int stages = 7;
    std::memcpy(&file[prof + 12], &stages, 4);
    file.erase(prof + 12 + 4 + 7 * 8, 24);
    shrink(prof + 4, 24);
    shrink(payload_length_at, 24);
    format = 6;
    std::memcpy(&file[12], &format, 4);
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (size_t i = 0; i + 8 < file.size(); ++i) {
        h ^= static_cast<unsigned char>(file[i]);
        h *= 0x100000001b3ull;
    }
    std::memcpy(&file[file.size() - 8], &h, 8);
    write_bytes(at("six.sav"), file);
    Session b;
    ASSERT_TRUE(b.run("restore '" + at("six.sav") + "'")) << b.error();
    ASSERT_EQ(b.model.blocks.loads.size(), 1u);
    ASSERT_EQ(b.model.blocks.loads[0].size(), 1u);
    const odec::BlockLoad& l = b.model.blocks.loads[0][0];
    EXPECT_EQ(l.kind, odec::LoadKind::Point);
    EXPECT_EQ(l.table, 0);
    EXPECT_EQ(l.lever, odec::Vec3::Zero());
    EXPECT_EQ(l.force, odec::Vec3(1234.5, -2345.25, 3456.125));
    EXPECT_EQ(l.couple, odec::Vec3::Zero());
    // The same model as the current file: it saves to the same bytes.
    ASSERT_TRUE(b.run("save '" + at("again") + "'")) << b.error();
    EXPECT_EQ(read_bytes(at("again.sav")), read_bytes(at("seven.sav")));
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
    // Model: 27 saved fields, the report of the last choice of masses (mass_scaling, said
    // by the commands once and chosen again before the next step) and edits (counts the commands
    // of this session, for the contact update's memory of open contacts).
    EXPECT_EQ(count_fields<Model>(), 30u) << fix;
    // FlowSet: 15 saved fields (settings, fluid, the nodes' positions, pressures, fixities and volumes
    // at the last step) and 22 derived ones (the nodes' sub-contacts, apertures, wetted shares,
    // volumes, links and flows, the nodes that follow others between zoned faces, and the pressure
    // forces: made again from the contacts; how often they were made and from what).
    EXPECT_EQ(count_fields<FlowSet>(), 37u) << fix;
    EXPECT_EQ(count_fields<CableSet>(), 25u) << fix;
    EXPECT_EQ(count_fields<CableMaterial>(), 8u) << fix;
    // LinerSet: 30 saved fields and 3 derived (the element stiffnesses and the nodes' bounds,
    // rebuilt from pos0 and the materials).
    EXPECT_EQ(count_fields<LinerSet>(), 33u) << fix;
    EXPECT_EQ(count_fields<LinerMaterial>(), 10u) << fix;
    // EnergyAccount: 18 saved fields and whether the cycle has the model (false between commands).
    EXPECT_EQ(count_fields<EnergyAccount>(), 19u) << fix;
    // BlockSet: format 12 added the clumps; the rotation matrices are derived with the world
    // vertices (not saved: made again before the next step), and whether those are behind
    // (only within a cycle).
    EXPECT_EQ(count_fields<BlockSet>(), 37u) << fix;
    EXPECT_EQ(count_fields<BlockLoad>(), 5u) << fix;
    // ZoneSet: 7 saved fields and the colouring (derived: rebuilt when stale).
    EXPECT_EQ(count_fields<ZoneSet>(), 10u) << fix;
    EXPECT_EQ(count_fields<GridpointSet>(), 19u) << fix;
    EXPECT_EQ(count_fields<StressBoundary>(), 1u) << fix;
    EXPECT_EQ(count_fields<BoundaryFace>(), 3u) << fix;
    // ContactSet: 27 saved fields (the keys' codes and their table are saved as the keys; the
    // points' codes hold the sub-contacts' flags, and a contact's joint word its material, model
    // and glue, which the file has apart; the file also has
    // each sub-contact's contact, side and vertex, derived from the offsets and keys; format 18
    // dropped the normal stresses, derived from the closures; format 19 added free_motion and open_by_reference) and
    // 22 derived ones (block_motion, motion_fresh: measured by each step's detection for that
    // step's contact update alone; left_open, batched: count what it left and what it stepped in
    // batches; rest, cycle_runs: its memory of the open contacts it left alone, valid within one
    // run of cycle(); least_free_motion,
    // any_touch_line, summary_revision: made again after each refresh; surface_*: rebuilt from the zones;
    // joint_k*: rebuilt every step; color_*, colored: rebuilt when the pairs in contact change;
    // revision, build_seconds, write_seconds: count the refreshes and their time in this
    // session; change_seen: a restored model's contacts are found again before they are used
    // while its geometry_changed is set).
    EXPECT_EQ(count_fields<ContactSet>(), 49u) << fix;
    EXPECT_EQ(count_fields<Polyhedron>(), 4u) << fix;
    EXPECT_EQ(count_fields<Material>(), 8u) << fix;
    EXPECT_EQ(count_fields<JointMaterial>(), 12u) << fix;
    EXPECT_EQ(count_fields<JointPlane>(), 3u) << fix;
    EXPECT_EQ(count_fields<History>(), 15u) << fix;
    // HistorySet: 3 saved fields and the reader of FISH histories (set by the session).
    EXPECT_EQ(count_fields<HistorySet>(), 4u) << fix;
    EXPECT_EQ(count_fields<Table>(), 1u) << fix;
    EXPECT_EQ(count_fields<TableSet>(), 1u) << fix;
    EXPECT_EQ(count_fields<Damping>(), 8u) << fix; // format 16: the timestep of the last step
    EXPECT_EQ(count_fields<Settings>(), 10u) << fix;
    EXPECT_EQ(count_fields<Profile>(), 11u) << fix; // 10 stage times and the step count
    EXPECT_EQ(count_fields<InsituRecord>(), 2u) << fix;
    EXPECT_EQ(count_fields<StressField>(), 4u) << fix;
    EXPECT_EQ(count_fields<Range>(), 1u) << fix;
    EXPECT_EQ(count_fields<Filter>(), 9u) << fix;
}

