// Commands that FISH runs: from a function's `command` block, from a file a function calls, from
// a 'whilestepping' function and from a FISH history while the model cycles. Each command does
// there what it does at the prompt, or is refused with a located error naming why; the running
// function, the cycle and every index stay valid (these tests also run under the sanitizers).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "fish/runtime.h"
#include "test_util.h"

using odec::test::Session;

namespace {

double number(Session& s, const std::string& name) {
    const odec::fish::Symbol* sym = s.interp.fish().find(name);
    EXPECT_NE(sym, nullptr) << name;
    return sym ? sym->value.number() : -1;
}

// A scratch directory, the working directory while it lives.
struct ScratchDir {
    std::string dir, old;
    ScratchDir() {
        char tmpl[] = "/tmp/odec-fish-commands-XXXXXX";
        dir = mkdtemp(tmpl);
        char buf[4096];
        old = getcwd(buf, sizeof buf);
        EXPECT_EQ(chdir(dir.c_str()), 0);
    }
    ~ScratchDir() {
        EXPECT_EQ(chdir(old.c_str()), 0);
        std::system(("rm -rf '" + dir + "'").c_str());
    }
};

// Two half-metre blocks, the lower one fixed, on a joint, under gravity.
const char* kTwoBlocks = "poly brick 0 1 0 1 0 0.5\n"
                         "poly brick 0 1 0 1 0.5 1\n"
                         "prop mat=1 dens=2000\n"
                         "prop jmat=1 jkn=1e9 jks=1e9 jfric=30\n"
                         "fix range z 0 0.5\n"
                         "grav 0 0 -10\n";

} // namespace

// A parametric study: each case starts with 'new' inside the function's loop. The function,
// its loop variable and the results it keeps survive every 'new'; the model is each case's own.
TEST(FishCommands, NewInsideAFunctionKeepsTheRunningFunction) {
    Session s;
    ASSERT_TRUE(s.run("def study\n"
                      "  total = 0\n"
                      "  loop k (1,20)\n"
                      "    command\n"
                      "      new\n"
                      "      prop mat=1 dens=2000\n"
                      "      poly brick 0 1 0 1 0 @k\n"
                      "    endcommand\n"
                      "    total = total + nblock\n"
                      "    last = b_vol(block_head)\n"
                      "  endloop\n"
                      "end\n"
                      "@study\n"))
        << s.error();
    EXPECT_EQ(number(s, "total"), 20);    // one block in each case, never more
    EXPECT_DOUBLE_EQ(number(s, "last"), 20.0); // the last case's 1 x 1 x 20 block
    EXPECT_EQ(s.model.blocks.size(), 1);
    // At the prompt 'new' forgets FISH as before.
    ASSERT_TRUE(s.run("new\n")) << s.error();
    EXPECT_EQ(s.interp.fish().find("study"), nullptr);
}

// The same through a file the function calls, and with 'restore' of a case saved before.
TEST(FishCommands, NewAndRestoreFromACalledFile) {
    ScratchDir d;
    {
        std::ofstream f("case.dat");
        f << "new\nprop mat=1 dens=2000\npoly brick 0 1 0 1 0 @h\n";
    }
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 2 0 2 0 2\nprop mat=1 dens=1000\nsave 'base'\n"
                      "def study\n"
                      "  loop k (1,3)\n"
                      "    h = k * 0.5\n"
                      "    command\n"
                      "      call 'case.dat'\n"
                      "    endcommand\n"
                      "    v = v + b_vol(block_head)\n"
                      "  endloop\n"
                      "  command\n"
                      "    restore 'base'\n"
                      "  endcommand\n"
                      "  vb = b_vol(block_head)\n"
                      "end\n"
                      "@study\n"))
        << s.error();
    EXPECT_DOUBLE_EQ(number(s, "v"), 0.5 + 1.0 + 1.5);
    EXPECT_DOUBLE_EQ(number(s, "vb"), 8.0);
    EXPECT_EQ(s.model.blocks.size(), 1);
}

// A pointer taken before 'new' names a block that no longer exists: a FISH error, not a read
// of freed memory.
TEST(FishCommands, PointersTakenBeforeNewAreRefused) {
    Session s;
    EXPECT_FALSE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\n"
                       "def f\n"
                       "  b = block_head\n"
                       "  command\n"
                       "    new\n"
                       "  endcommand\n"
                       "  x = b_vol(b)\n"
                       "end\n"
                       "@f\n"));
    EXPECT_NE(s.error().find("no longer exists"), std::string::npos) << s.error();
}

// Geometry commands run by a 'whilestepping' function change the blocks while the model
// cycles: the cycle takes the new blocks at once (contacts, masses, timestep, checks), with no
// false verdict and no read past an array.
TEST(FishCommands, GeometryCommandsWhileStepping) {
    Session s;
    ASSERT_TRUE(s.run(std::string(kTwoBlocks) +
                      "def cut\n"
                      "  whilestepping\n"
                      "  if step = 5 then\n"
                      "    command\n"
                      "      jset dip 45 dd 90 origin 0.5,0.5,0.75\n"
                      "    endcommand\n"
                      "  endif\n"
                      "  if step = 10 then\n"
                      "    command\n"
                      "      poly brick 3 4 0 1 0 1\n"
                      "    endcommand\n"
                      "  endif\n"
                      "end\n"
                      "step 20\n"))
        << s.error();
    EXPECT_EQ(s.model.step, 20);
    EXPECT_GE(s.model.blocks.size(), 5); // both bricks cut, and one more brick
    for (const auto& v : s.model.blocks.vel) EXPECT_TRUE(v.allFinite());
}

// ... and a block deleted by a FISH history (sampled after each step) is not read afterwards.
TEST(FishCommands, DeleteFromAFishHistory) {
    Session s;
    ASSERT_TRUE(s.run(std::string(kTwoBlocks) +
                      "poly brick 3 4 0 1 0 1\n"
                      "def h\n"
                      "  h = nblock\n"
                      "  if step = 6 then\n"
                      "    command\n"
                      "      delete range x 3 4\n"
                      "    endcommand\n"
                      "  endif\n"
                      "end\n"
                      "hist ncyc 2\n"
                      "hist @h\n"
                      "step 12\n"))
        << s.error();
    EXPECT_EQ(s.model.blocks.size(), 2);
    EXPECT_EQ(s.model.step, 12);
}

// What would replace the model that cycles, or cycle it again, is refused where FISH runs it,
// with the reason; the step stops there and the model is the one that was cycling.
TEST(FishCommands, NewRestoreAndStepRefusedWhileCycling) {
    for (const std::string cmd : {"new", "restore 'x'", "step 5", "solve", "cycle 3"}) {
        Session s;
        const bool ok = s.run(std::string(kTwoBlocks) +
                              "def f\n"
                              "  whilestepping\n"
                              "  command\n"
                              "    " + cmd + "\n"
                              "  endcommand\n"
                              "end\n"
                              "step 10\n");
        EXPECT_FALSE(ok) << cmd;
        EXPECT_NE(s.error().find("t.dat:10:5: error: '"), std::string::npos) << s.error();
        EXPECT_NE(s.error().find("cannot run while the model cycles"), std::string::npos) << s.error();
        EXPECT_EQ(s.model.blocks.size(), 2) << cmd;
        EXPECT_EQ(s.model.step, 0) << cmd; // refused in the first step, before it moved
    }
}

// The same commands are refused from a FISH history during cycling (the history records, the
// model is kept).
TEST(FishCommands, NewRefusedFromAFishHistory) {
    Session s;
    EXPECT_FALSE(s.run(std::string(kTwoBlocks) +
                       "def h\n"
                       "  h = nblock\n"
                       "  command\n"
                       "    new\n"
                       "  endcommand\n"
                       "end\n"
                       "hist @h\n"
                       "step 20\n"));
    // The history fails at its first sample, and the run stops there with both reasons.
    EXPECT_NE(s.error().find("history 1 (@h) failed at step 10"), std::string::npos) << s.error();
    EXPECT_NE(s.error().find("'new' cannot run while the model cycles"), std::string::npos) << s.error();
    EXPECT_EQ(s.model.blocks.size(), 2);
    EXPECT_EQ(s.model.step, 10);
    EXPECT_TRUE(s.model.histories.sample_steps.empty());
}

// The reason is in 'help' (and so in the manual): the declaration drives both.
TEST(FishCommands, HelpSaysWhatIsRefusedWhileCycling) {
    Session s;
    s.interp.quiet = false;
    ASSERT_TRUE(s.run("help new\n")) << s.error();
    EXPECT_NE(s.out.str().find("Not while the model cycles: it would clear the model"), std::string::npos)
        << s.out.str();
}

// Energy that a 'whilestepping' function gives a block ('ini') is not taken for a run-away.
TEST(FishCommands, VelocityGivenWhileSteppingIsNoRunAway) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\nset dt 1e-3\ndamp off\n"
                      "poly brick 5 6 0 1 0 1\n"
                      "def kick\n"
                      "  whilestepping\n"
                      "  if step = 50 then\n"
                      "    command\n"
                      "      ini xvel 20 range x 0 1\n"
                      "    endcommand\n"
                      "  endif\n"
                      "end\n"
                      "step 100\n"))
        << s.error();
    EXPECT_EQ(s.model.step, 100);
    EXPECT_DOUBLE_EQ(s.model.blocks.vel[0].x(), 20.0);
}

// 'quit' from a function that runs while the model cycles is refused: it would leave in the
// middle of a step.
TEST(FishCommands, QuitRefusedWhileCycling) {
    Session s;
    EXPECT_FALSE(s.run(std::string(kTwoBlocks) + "def f\n  whilestepping\n  command\n    quit\n  endcommand\nend\nstep 3\n"));
    EXPECT_NE(s.error().find("'quit' cannot run while the model cycles"), std::string::npos) << s.error();
    EXPECT_FALSE(s.interp.quit_requested);
}

// A command block's lines are commands: a path FISH could not read ('./part.dat') is taken when
// the block runs, as at the prompt.
TEST(FishCommands, ACommandBlockMayNameAFileByAPath) {
    ScratchDir d;
    std::ofstream("part.dat") << "poly brick 0 1 0 1 0 1\n";
    Session s;
    ASSERT_TRUE(s.run("def f\n  command\n    call ./part.dat\n  endcommand\nend\n@f\n")) << s.error();
    EXPECT_EQ(s.model.blocks.size(), 1);
    // Outside a command block the same characters are still a FISH error of the definition.
    EXPECT_FALSE(s.run("def g\n  x = ./part.dat\nend\n"));
    EXPECT_NE(s.error().find("t.dat:2:7: error: '.' has no meaning in FISH"), std::string::npos) << s.error();
}

// A FISH history whose function adds a history ('hist' in its command block) changes the list
// of histories while it is sampled: the list is taken by index, the new history starts with
// the samples it missed, and the model saves and restores (the session's end check).
TEST(FishCommands, AHistoryAddedWhileHistoriesAreSampled) {
    Session s;
    ASSERT_TRUE(s.run(std::string(kTwoBlocks) +
                      "def probe\n"
                      "  if step = 10 then\n"
                      "    command\n"
                      "      hist unbal\n"
                      "    endcommand\n"
                      "  endif\n"
                      "  probe = nblock\n"
                      "end\n"
                      "hist ncyc 5\n"
                      "hist @probe\n"
                      "step 20\n"))
        << s.error();
    const auto& h = s.model.histories;
    ASSERT_EQ(h.items.size(), 2u);
    ASSERT_EQ(h.sample_steps.size(), 4u);
    EXPECT_EQ(h.items[0].values.size(), 4u);
    EXPECT_EQ(h.items[0].values[3], 2.0);
    // Added while step 10 was sampled: its own samples start with the next one, step 15.
    EXPECT_EQ(h.items[1].first, 2);
    ASSERT_EQ(h.items[1].values.size(), 2u);
    EXPECT_EQ(h.items[1].at(1), nullptr);
    ASSERT_NE(h.items[1].at(2), nullptr);
    EXPECT_TRUE(std::isfinite(*h.items[1].at(2)));
}

// A joint material that a whilestepping function gives during the first stage of
// 'solve elastic' stays when the stage gives the joints their strengths back.
TEST(FishCommands, AJointMaterialGivenDuringSolveElasticStays) {
    Session s;
    ASSERT_TRUE(s.run(std::string(kTwoBlocks) +
                      "prop jmat=1 jcoh=1e5 jten=2e4\n"
                      "def w\n"
                      "  whilestepping\n"
                      "  if step = 3 then\n"
                      "    command\n"
                      "      prop jmat=5 jkn=1e9 jks=1e9 jfric=25\n"
                      "      change jmat 5\n"
                      "    endcommand\n"
                      "  endif\n"
                      "end\n"
                      "solve elastic ratio 1e-3\n"
                      "step 10\n"))
        << s.error();
    ASSERT_GE(s.model.joint_materials.size(), 6u);
    EXPECT_TRUE(s.model.joint_materials[5].defined);
    EXPECT_EQ(s.model.joint_materials[5].friction, 25.0);
    EXPECT_EQ(s.model.joint_materials[1].cohesion, 1e5);
    EXPECT_EQ(s.model.joint_materials[1].tension, 2e4);
}

// '@name' in a command block takes what 'name' is in the function's body: its argument or
// local first, then the global.
TEST(FishCommands, ACommandBlockSeesTheFunctionsArgumentsAndLocals) {
    Session s;
    ASSERT_TRUE(s.run("@z = 99\n@h = 7\n"
                      "def brick_at(x0, z)\n"
                      "  local top = z + 0.5\n"
                      "  local x1 = x0 + 1\n"
                      "  command\n"
                      "    poly brick @x0 @x1 0 1 @z @top\n"
                      "    set seen_h = @h\n"
                      "  endcommand\n"
                      "end\n"
                      "@brick_at(2, 3)\n"
                      "@brick_at(5, -1)"))
        << s.error();
    ASSERT_EQ(s.model.blocks.size(), 2);
    EXPECT_NEAR(s.model.blocks.centroid[0].z(), 3.25, 1e-12);
    EXPECT_NEAR(s.model.blocks.centroid[1].z(), -0.75, 1e-12);
    // 'h' is no local of brick_at: the global.
    EXPECT_EQ(number(s, "seen_h"), 7);
    // Outside the block the globals are as they were.
    EXPECT_EQ(number(s, "z"), 99);
    s.out.str("");
    ASSERT_TRUE(s.run("list @z")) << s.error();
    EXPECT_EQ(s.out.str(), "z = 99\n");
}

TEST(FishCommands, ACommandBlockInsideAnotherSeesItsOwnFunctionsLocals) {
    // outer's block calls inner (through a command); inner's block sees inner's locals; back in
    // outer's block, outer's again. A bare name (UDEC style) resolves the same way; 'list' too.
    Session s;
    ASSERT_TRUE(s.run("def inner(v)\n"
                      "  local w = v * 10\n"
                      "  command\n"
                      "    set from_inner = @w\n"
                      "  endcommand\n"
                      "  inner = w\n"
                      "end\n"
                      "def outer\n"
                      "  local w = 3\n"
                      "  command\n"
                      "    set before = @w\n"
                      "    @inner(4)\n"
                      "    set after = @w\n"
                      "    set bare = w\n"
                      "    list @w\n"
                      "    @w = w + 10\n"
                      "    set statement = @w\n"
                      "  endcommand\n"
                      "end\n"
                      "@outer"))
        << s.error();
    EXPECT_EQ(number(s, "before"), 3);
    EXPECT_EQ(number(s, "from_inner"), 40);
    EXPECT_EQ(number(s, "after"), 3);
    EXPECT_EQ(number(s, "bare"), 3);
    // A FISH statement typed in the block reads and assigns the local too.
    EXPECT_EQ(number(s, "statement"), 13);
    EXPECT_NE(s.out.str().find("w = 3\n"), std::string::npos) << s.out.str();
    EXPECT_EQ(s.interp.fish().find("w"), nullptr) << "no global 'w' was made";
}

TEST(FishCommands, AHistoryOfALocalIsRefused) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\n@v = 1")) << s.error();
    EXPECT_FALSE(s.run("def record(v)\n  command\n    hist @v\n  endcommand\nend\n@record(2)"));
    EXPECT_NE(s.error().find("error: 'v' is an argument or local of 'record', gone when it returns: a history samples "
                             "a global as the model cycles"),
              std::string::npos)
        << s.error();
    EXPECT_TRUE(s.model.histories.items.empty());
    // Outside a command block '@v' is the global.
    ASSERT_TRUE(s.run("hist @v")) << s.error();
    EXPECT_EQ(s.model.histories.items.size(), 1u);
}
