// What the contact set keeps per sub-contact: only what it must. The side and the vertex of a
// sub-contact follow from its key and are not stored; the dilations are kept only once a joint
// can dilate. Saved files hold every field for every sub-contact, whatever memory holds.
#include <gtest/gtest.h>

#include <algorithm>
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
    for (int k = 0; k < cs.n_subs(); ++k) slipped = slipped || (cs.sub_flags[k] & odec::kSubSlip);
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

// The bytes every sub-contact takes in memory, array by array (the triangles of gridpoint
// sub-contacts and the dilations are kept only when some sub-contact has one). It was 114
// bytes; each field dropped or narrowed lowers it, and nothing may creep back unnoticed.
TEST(ContactMemory, ASubContactTakesFewBytes) {
    const odec::ContactSet cs;
    const size_t per_sub = sizeof(cs.sub_key[0]) + sizeof(cs.sub_area[0]) + sizeof(cs.sub_local[0]) +
                           sizeof(cs.sub_un[0]) + sizeof(cs.sub_sn[0]) + sizeof(cs.sub_us[0]) + sizeof(cs.sub_ss[0]) +
                           sizeof(cs.sub_flags[0]);
    EXPECT_LE(per_sub, 105u);
}

} // namespace
