// The bounds of a session on unchecked input (Interpreter::Limits), which the fuzzing targets
// of tests/fuzz/ set: each refuses with a located error and leaves the model as it was.
#include <gtest/gtest.h>

#include "fish/runtime.h"
#include "test_util.h"

using odec::test::Session;

TEST(Limits, ConfinedFilesRefuseAbsoluteAndParentPaths) {
    Session s;
    s.interp.limits.confine_files = true;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1"));
    const char* refused[] = {"save '/tmp/odec-limits-test'", "restore '../x.sav'", "call '/etc/passwd'",
                             "export vtk 'a/../../b'", "plot block file '/tmp/x.png'", "table 1 read '..'",
                             "set logfile '/tmp/odec.log'", "hist zdis 0,0,0\nhist write 1 file '/tmp/h.csv'"};
    for (const char* line : refused) {
        s.err.str("");
        EXPECT_FALSE(s.run(line)) << line;
        EXPECT_NE(s.error().find("error: '"), std::string::npos) << line << ": " << s.error();
        EXPECT_NE(s.error().find("only inside its working directory"), std::string::npos) << line << ": " << s.error();
    }
    EXPECT_EQ(s.model.blocks.size(), 1);
    EXPECT_EQ(s.interp.log_path, "odec.log");
}

TEST(Limits, StepBudgetCapsStepAndSolve) {
    Session s;
    s.interp.limits.block_steps = 250;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\npoly brick 2 3 0 1 0 1\nprop mat=1 dens=1000\nset dt 1e-3"));
    ASSERT_TRUE(s.run("step 100"));
    EXPECT_EQ(s.model.step, 100);
    ASSERT_TRUE(s.run("solve time 10"));
    EXPECT_EQ(s.model.step, 125); // 250 block-steps for 2 blocks
    EXPECT_FALSE(s.run("step 1"));
    EXPECT_NE(s.error().find("t.dat:1:1: error: this session may take no more steps"), std::string::npos) << s.error();
    EXPECT_EQ(s.model.step, 125);
}

TEST(Limits, BlockLimitRefusesAJointSetBeforeCutting) {
    Session s;
    s.interp.limits.max_blocks = 50;
    ASSERT_TRUE(s.run("poly brick 0 10 0 10 0 10"));
    ASSERT_TRUE(s.run("jset dip 0 dd 0 origin 0,0,5 spacing 1 number 9")); // 10 blocks
    EXPECT_EQ(s.model.blocks.size(), 10);
    const size_t planes = s.model.joint_planes.size();
    EXPECT_FALSE(s.run("jset dip 90 dd 90 origin 5,0,0 spacing 1 number 9")); // could make 100
    EXPECT_NE(s.error().find("t.dat:1:1: error: this session allows at most 50 blocks"), std::string::npos) << s.error();
    EXPECT_EQ(s.model.blocks.size(), 10);
    EXPECT_EQ(s.model.joint_planes.size(), planes);
    EXPECT_FALSE(s.run("jset dip 90 dd 90 origin 5,0,0 spacing 1e-9 number 100000")); // planes times blocks
}

TEST(Limits, BlockLimitRefusesAPolyInAFishWalk) {
    // A walk over the blocks whose command block adds a block never reaches the end: the
    // block limit ends it.
    Session s;
    s.interp.limits.max_blocks = 30;
    EXPECT_FALSE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\n"
                       "def grow\n  local b = block_head\n  loop while b # 0\n    command\n"
                       "      poly brick 0 1 0 1 2 2.5\n    endcommand\n    b = b_next(b)\n  endloop\nend\n@grow\n"));
    EXPECT_NE(s.error().find("this session allows at most 30 blocks"), std::string::npos) << s.error();
    EXPECT_EQ(s.model.blocks.size(), 30);
}

// A cube zoned again and again by a FISH loop of 2,000 `gen`s; n counts the zonings done.
constexpr const char* kRezoneLoop = "poly brick 0 1 0 1 0 1\nprop mat=1 dens=2000 ymod=1e9 prat=0.25\n"
                                    "def rezone\n  loop k (1, 2000)\n    command\n      gen edge 0.5\n    endcommand\n"
                                    "    n = k\n  endloop\nend\n@rezone\n";

TEST(Limits, ZoneBudgetEndsALoopOfZonings) {
    Session s;
    s.interp.limits.zone_budget = 400;
    EXPECT_FALSE(s.run(kRezoneLoop));
    EXPECT_NE(s.error().find("more zones in all"), std::string::npos) << s.error();
    EXPECT_GE(s.interp.limits.zone_budget, 0);
    EXPECT_LT(s.interp.limits.zone_budget, 400);
}

TEST(Limits, EachZoningCostsAtLeastAShareOfTheBudget) {
    // Each `gen` forks the mesher: a loop of small ones (a few zones each) ends after 5000 / 250
    // of them, not after 166 (a fuzzed loop of them took 20 s an input, forking the fuzzing process).
    Session s;
    s.interp.limits.zone_budget = 5000;
    EXPECT_FALSE(s.run(kRezoneLoop));
    EXPECT_NE(s.error().find("more zones in all"), std::string::npos) << s.error();
    const odec::fish::Symbol* n = s.interp.fish().find("n");
    ASSERT_NE(n, nullptr);
    EXPECT_EQ(n->value.number(), 20);
}

TEST(Limits, CommandsRunByFishCountAgainstItsBound) {
    // 200,000 iterations of two commands each would take minutes: each command costs 50.
    Session s;
    s.interp.limits.fish_steps = 200000;
    EXPECT_FALSE(s.run("poly brick 0 1 0 1 0 1\n"
                       "def many\n  loop k (1, 200000)\n    command\n      title 'a'\n      title 'b'\n"
                       "    endcommand\n    n = k\n  endloop\nend\n@many\n"));
    EXPECT_NE(s.error().find("this session's bound on FISH work is reached"), std::string::npos) << s.error();
    const odec::fish::Symbol* n = s.interp.fish().find("n");
    ASSERT_NE(n, nullptr);
    EXPECT_LT(n->value.number(), 700); // about 200000 / (2 * (50 + 100) + 1): one block
    EXPECT_GT(n->value.number(), 600);
}

TEST(Limits, NoneByDefault) {
    Session s;
    EXPECT_FALSE(s.interp.limits.confine_files);
    EXPECT_LT(s.interp.limits.block_steps, 0);
    EXPECT_EQ(s.interp.limits.max_blocks, 0);
    EXPECT_LT(s.interp.limits.zone_budget, 0);
}
