// What the contact set keeps per sub-contact: only what it must. The side and the vertex of a
// sub-contact follow from its key and are not stored; the dilations are kept only once a joint
// can dilate. Saved files hold every field for every sub-contact, whatever memory holds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>
#include <cstdio>
#include <cstring>
#include <string>

#include "io/save.h"
#include "test_util.h"

namespace {

using odec::test::Session;

// A 1 m block pressed by 1 MPa on a fixed base and pushed along it at 0.01 m/s: its joint
// (30 degrees, no cohesion) slips after 5.8e-5 m of shear, within the first 0.01 s.
const char* kSlidingBlock =
    "poly brick -0.5 2.0 -0.5 1.5 -1 0 region 1\npoly brick 0 1 0 1 -1e-4 0.0019 region 2\n"
    "prop mat=1 dens=2000\nprop jmat=1 jkn=1e10 jks=1e10 jfric=30\nfix range region 1\n"
    "bound xvel 0.01 zload -1e6 range region 2\n";

std::string temp_path(const char* name) {
    return std::string(::testing::TempDir()) + "/odec-contact-memory-" + name;
}

TEST(ContactMemory, DilationsAreKeptOnlyOnceAJointCanDilate) {
    Session s;
    ASSERT_TRUE(s.run(std::string(kSlidingBlock) + "step time 0.01")) << s.error();
    const odec::ContactSet& cs = s.model.contacts;
    ASSERT_GT(cs.n_subs(), 0);
    bool slipped = false;
    for (int k = 0; k < cs.n_subs(); ++k) slipped = slipped || (cs.sub_flags(k) & odec::kSubSlip);
    ASSERT_TRUE(slipped);
    // Slipping on a joint that cannot dilate: no dilations held.
    EXPECT_TRUE(cs.sub_udil.empty());
    EXPECT_EQ(cs.sub_dilation(0), 0.0);

    // Saved and restored, still none; the file has them all the same (zeros).
    const std::string none = temp_path("none.sav");
    ASSERT_TRUE(s.run("save '" + none + "'")) << s.error();
    Session r;
    ASSERT_TRUE(r.run("restore '" + none + "'")) << r.error();
    EXPECT_TRUE(r.model.contacts.sub_udil.empty());
    ASSERT_EQ(r.model.contacts.n_subs(), cs.n_subs());

    // Given dilation, the joint dilates from the next step on: one entry per sub-contact.
    ASSERT_TRUE(s.run("prop jmat=1 jdil=10\nstep time 0.01")) << s.error();
    ASSERT_EQ(cs.sub_udil.size(), static_cast<size_t>(cs.n_subs()));
    double most = 0;
    for (int k = 0; k < cs.n_subs(); ++k) most = std::max(most, cs.sub_dilation(k));
    // 0.01 s of slip at 0.01 m/s, tan 10 degrees of it: about 1.8e-5 m.
    EXPECT_GT(most, 1e-5);
    EXPECT_LT(most, 2e-5);

    // Saved and restored, the same dilations, bit for bit.
    const std::string some = temp_path("some.sav");
    ASSERT_TRUE(s.run("save '" + some + "'")) << s.error();
    Session t;
    ASSERT_TRUE(t.run("restore '" + some + "'")) << t.error();
    const odec::ContactSet& ct = t.model.contacts;
    ASSERT_EQ(ct.sub_udil.size(), cs.sub_udil.size());
    EXPECT_EQ(std::memcmp(ct.sub_udil.data(), cs.sub_udil.data(), cs.sub_udil.size() * sizeof(double)), 0);
    std::remove(none.c_str());
    std::remove(some.c_str());
}

// Files of format 16 and older have each shear vector as a vector: restored, it is put on its
// contact's shear axes, and reads back as it was. The file: a 1 m block pushed along a base
// (x 0.01, y 0.004 m/s) under 1 MPa, saved by format 16 after 1,000 steps, its shear stresses
// and displacements printed then by cx_sstress and cx_sdis.
TEST(ContactMemory, ShearVectorsOfOlderFilesArePutOnTheirAxes) {
    const std::string file = std::string(ODEC_SOURCE_DIR) + "/tests/fuzz/regressions/restore/shear-v16.sav";
    Session s;
    ASSERT_TRUE(s.run("restore '" + file + "'")) << s.error();
    const odec::ContactSet& cs = s.model.contacts;
    ASSERT_EQ(cs.size(), 1);
    ASSERT_EQ(cs.n_subs(), 4);
    const double sx[4] = {-399598.55920548446, -399598.55909032165, -399598.5590442559, -399598.5591594195};
    const double sy[4] = {-159839.42368219377, -159839.42363612846, -159839.42361770253, -159839.42366376787};
    const double us[4] = {4.303808196030057e-05, 4.303808194789713e-05, 4.3038081942935805e-05, 4.303808195533925e-05};
    for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d ss = cs.sub_shear_stress(0, k);
        EXPECT_NEAR(ss.x(), sx[k], 1e-12 * 4e5);
        EXPECT_NEAR(ss.y(), sy[k], 1e-12 * 4e5);
        EXPECT_NEAR(ss.z(), 0.0, 1e-12 * 4e5);
        EXPECT_NEAR(cs.sub_shear_disp(0, k).norm(), us[k], 1e-12 * 4e-5);
    }
    // It goes on, saves as the present format and restores to the same bits.
    const std::string again = temp_path("again.sav");
    ASSERT_TRUE(s.run("step 10\nsave '" + again + "'")) << s.error();
    Session t;
    ASSERT_TRUE(t.run("restore '" + again + "'")) << t.error();
    ASSERT_EQ(t.model.contacts.n_subs(), 4);
    EXPECT_EQ(std::memcmp(t.model.contacts.sub_ss.data(), cs.sub_ss.data(), 4 * sizeof(cs.sub_ss[0])), 0);
    EXPECT_EQ(std::memcmp(t.model.contacts.sub_us.data(), cs.sub_us.data(), 4 * sizeof(cs.sub_us[0])), 0);
    std::remove(again.c_str());
}

// Two prisms of 40 sides, the upper one turned by half a side on the lower: their edges cross,
// and the crossing of two edges of blocks of 80 vertices has a key no four-byte code holds (its
// edges' numbers pass 4096: sub_key.h). Those keys are kept in the table, and the block comes to
// rest on the joint with its weight, saved and restored as it was.
TEST(ContactMemory, KeysOfLargeBlocksAreKeptWhole) {
    auto ring = [](double z, double turn) {
        std::string v;
        for (int i = 0; i < 40; ++i) {
            const double t = 2 * M_PI * i / 40 + turn;
            char buf[96];
            std::snprintf(buf, sizeof buf, " (%.12f,%.12f,%g)", std::cos(t), std::sin(t), z);
            v += buf;
        }
        return v;
    };
    const double half = M_PI / 40;
    const std::string script = "poly prism a" + ring(-0.5, 0) + " b" + ring(0, 0) + " region 1\n" +
                               "poly prism a" + ring(0, half) + " b" + ring(0.5, half) + " region 2\n" +
                               "prop mat=1 dens=2000\nprop jmat=1 jkn=1e10 jks=1e10 jfric=30\ngrav 0 0 -10\n"
                               "fix range region 1\nsolve\n";
    Session s;
    ASSERT_TRUE(s.run(script)) << s.error();
    const odec::ContactSet& cs = s.model.contacts;
    ASSERT_EQ(cs.size(), 1);
    int in_table = 0;
    for (int k = 0; k < cs.n_subs(); ++k) {
        in_table += odec::key_code_in_table(cs.sub_code[k]);
        EXPECT_EQ(cs.sub_side(k), odec::ContactSet::key_side(cs.sub_key(k)));
    }
    EXPECT_GT(in_table, 0);
    EXPECT_LE(cs.key_table.keys.size(), 2 * static_cast<size_t>(in_table) + 1024);
    // The joint carries the upper prism's weight (2000 kg/m^3, 0.5 m high, the 40-gon's area):
    // 10,000 Pa over its area, within the solve's ratio.
    double force = 0, area = 0;
    for (int k = 0; k < cs.n_subs(); ++k) {
        force += odec::sub_normal_stress(s.model, 0, k) * cs.sub_area[k];
        area += cs.sub_area[k];
    }
    // They touch where both are: a regular 80-gon with the 40-gons' inner radius.
    const double polygon = 0.5 * 40 * std::sin(2 * M_PI / 40);
    const double overlap = 80 * std::pow(std::cos(M_PI / 40), 2) * std::tan(M_PI / 80);
    EXPECT_NEAR(area, overlap, 1e-9);
    EXPECT_NEAR(force, 2000 * 10 * 0.5 * polygon, 1e-3 * 2000 * 10 * 0.5 * polygon);
    // Saved and restored: the same keys, and the same steps after.
    const std::string path = temp_path("large-keys.sav");
    ASSERT_TRUE(s.run("save '" + path + "'\nstep 50\n")) << s.error();
    Session r;
    ASSERT_TRUE(r.run("restore '" + path + "'\n")) << r.error();
    EXPECT_EQ(r.model.contacts.sub_keys(), std::vector<std::int64_t>(cs.sub_keys()));
    ASSERT_TRUE(r.run("step 50\n")) << r.error();
    ASSERT_EQ(r.model.contacts.n_subs(), cs.n_subs());
    EXPECT_EQ(r.model.contacts.sub_keys(), cs.sub_keys());
    for (int k = 0; k < cs.n_subs(); ++k) EXPECT_EQ(r.model.contacts.sub_un[k], cs.sub_un[k]) << k;
    std::remove(path.c_str());
}

// The bytes every sub-contact takes in memory, array by array (the triangles of gridpoint
// sub-contacts and the dilations are kept only when some sub-contact has one). It was 114
// bytes; each field dropped or narrowed lowers it, and nothing may creep back unnoticed.
TEST(ContactMemory, ASubContactTakesFewBytes) {
    const odec::ContactSet cs;
    const size_t per_sub = sizeof(cs.sub_code[0]) + sizeof(cs.sub_area[0]) + sizeof(cs.sub_point[0]) +
                           sizeof(cs.sub_un[0]) + sizeof(cs.sub_us[0]) + sizeof(cs.sub_ss[0]);
    EXPECT_LE(per_sub, 66u);
}

// The same for every contact: it was 89 bytes (the plane's point, a normal of three doubles, the
// gap and the free motion in double precision, the joint model in an int, the joint's material,
// model and glue in three arrays).
TEST(ContactMemory, AContactTakesFewBytes) {
    const odec::ContactSet cs;
    const size_t per_contact = sizeof(cs.id[0]) + sizeof(cs.block_a[0]) + sizeof(cs.block_b[0]) +
                               sizeof(cs.normal_code[0]) + sizeof(cs.gap[0]) + sizeof(cs.joint[0]) +
                               sizeof(cs.sub_offset[0]) + sizeof(cs.free_motion[0]);
    EXPECT_LE(per_contact, 34u);
}

} // namespace
