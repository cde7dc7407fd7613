// Numbers that are not numbers, or not sensible ones: every command either refuses them with
// a located error and leaves the model as it was, or takes them and leaves every number of
// the model finite. And a forced timestep can be given back to the automatic one.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "test_util.h"

using odec::test::Session;

namespace {

const char* kStack =
    "poly brick 0 1 0 1 -1 0\npoly brick 0 1 0 1 0 1\npoly brick 0 1 0 1 1 2\npoly brick 0 1 0 1 2 3\n"
    "prop mat=1 dens=2000\nprop jmat=1 jkn=1e9 jks=1e9\nfix range z -1 0\ngrav 0 0 -10\n";

} // namespace

TEST(Numbers, SetDtAutoGivesTheStepBackToTheAutomaticOne) {
    Session s;
    ASSERT_TRUE(s.run(std::string(kStack) + "set dt 1e-4")) << s.error();
    EXPECT_EQ(s.model.settings.dt_fixed, 1e-4);
    ASSERT_TRUE(s.run("set dt auto\nstep 10")) << s.error();
    EXPECT_EQ(s.model.settings.dt_fixed, 0);
    EXPECT_NEAR(s.model.dt, 0.1 * 2 * std::sqrt(2000 / 1e9), 1e-12);
    ASSERT_TRUE(s.run("set dt 1e-4\nset dt 0")) << s.error();
    EXPECT_EQ(s.model.settings.dt_fixed, 0);
    Session t;
    EXPECT_FALSE(t.run("set dt automatic"));
    EXPECT_NE(t.error().find("t.dat:1:8: error: 'automatic' is not a number: 'dt' expects dt (a number or 'auto')"),
              std::string::npos)
        << t.error();
}

TEST(Numbers, AForcedTimestepBeyondTheStableLimitIsRefusedByStep) {
    Session s;
    ASSERT_TRUE(s.run(std::string(kStack) + "set dt 2e-3")) << s.error();
    const odec::Vec3 top = s.model.blocks.centroid[3];
    EXPECT_FALSE(s.run("step 1000"));
    EXPECT_EQ(s.error(),
              "t.dat:1:1: error: the forced timestep 0.002 s ('set dt') is larger than the stable limit, about "
              "0.000943 s (set by block 2 on its contacts): the motion would run away. Use 'set dt auto' "
              "(0.000283 s now) or a timestep below 0.000943 s\n"
              "    step 1000\n"
              "    ^~~~\n"
              "  see 'help step'\n");
    EXPECT_EQ(s.model.step, 0);
    EXPECT_EQ(s.model.blocks.centroid[3], top);
    EXPECT_FALSE(s.run("solve"));
    ASSERT_TRUE(s.run("set dt 9e-4\nstep 1000\nset dt auto\nsolve")) << s.error();
}
