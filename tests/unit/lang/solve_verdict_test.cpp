// How `solve` ends: equilibrium, a mechanism (naming the blocks that move and how fast), or a
// run stopped by its step limit while still settling (with the ratio's trend); a run stopped
// by its time limit or by Ctrl-C keeps its plain message. `print info` shows the last solve's
// criteria and verdict.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include "../time_scale.h"

#include "engine/blocks.h"
#include "engine/verdict.h"
#include "fish/runtime.h"
#include "test_util.h"
#include "verdict_text.h"

using odec::SolveOutcome;
using odec::test::Session;

namespace {

// A 1 m cube of 2000 kg resting on a fixed base under gravity 10.
const char* kResting = "poly brick 0 1 0 1 -1 0 region 1\npoly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\n"
                       "prop jmat=1 jkn=1e7 jks=1e7 jfric=30\ngrav 0 0 -10\nfix range region 1\n";

// The block of examples/verification/incline-sliding.dat (id 2) on a 40-degree incline (id 1),
// held first by a joint friction of 80 degrees.
const char* kIncline =
    "poly prism a (-10,-1,8.39099631) (20,-1,-16.78199262) (20,-1,-21.78199262) (-10,-1,3.39099631) &\n"
    "           b (-10,2,8.39099631) (20,2,-16.78199262) (20,2,-21.78199262) (-10,2,3.39099631) region 1\n"
    "poly prism a (0,0,0) (7.66044443,0,-6.42787610) (10.87438248,0,-2.59765388) (3.21393805,0,3.83022222) &\n"
    "           b (0,1,0) (7.66044443,1,-6.42787610) (10.87438248,1,-2.59765388) (3.21393805,1,3.83022222) region 2\n"
    "prop mat=1 dens=2000\nprop jmat=1 jkn=1e7 jks=1e7 jfric=80\ngrav 0 0 -10\nfix range region 1\n";

// A session that prints what solve says (Session runs quiet), without progress lines.
struct Talking : Session {
    Talking() {
        interp.quiet = false;
        interp.echo = false;
    }
    std::string said() const { return out.str(); }
};

std::string fish_text(Session& s, const std::string& name) {
    const odec::fish::Symbol* sym = s.interp.fish().find(name);
    return sym ? sym->value.s : "(no such variable)";
}

} // namespace

TEST(SolveVerdict, ABlockRestingOnAFlatJointIsInEquilibrium) {
    Talking s;
    ASSERT_TRUE(s.run(std::string(kResting) + "solve\n@v = solve_verdict\nprint info")) << s.error();
    ASSERT_TRUE(s.interp.last_solve);
    const odec::SolveVerdict& v = *s.interp.last_solve;
    EXPECT_EQ(v.outcome, SolveOutcome::Equilibrium);
    EXPECT_EQ(v.stop, odec::StopReason::Ratio);
    EXPECT_LT(v.ratio, 1e-5);
    EXPECT_TRUE(v.moving.empty());
    EXPECT_NE(s.said().find("solve: equilibrium, ratio "), std::string::npos) << s.said();
    EXPECT_NE(s.said().find(" < 1e-05 after " + std::to_string(v.steps) + " steps\n"), std::string::npos) << s.said();
    EXPECT_EQ(fish_text(s, "v"), "equilibrium");
    // print info: the criteria, then the verdict, each on its own line.
    EXPECT_NE(s.said().find("last solve: ratio limit 1e-05, step limit 200000, no time limit; ended at step " +
                            std::to_string(s.model.step) + "\n"),
              std::string::npos)
        << s.said();
    EXPECT_NE(s.said().find("verdict:    equilibrium, ratio "), std::string::npos) << s.said();
}

TEST(SolveVerdict, ABlockSlidingDownAnInclineIsAMechanismNamedWithItsSpeed) {
    Talking s;
    ASSERT_TRUE(s.run("config dyn\n" + std::string(kIncline) + "solve")) << s.error(); // timed: real masses
    ASSERT_EQ(s.interp.last_solve->outcome, SolveOutcome::Equilibrium);
    // Joint friction 20 < 40: the block slides. Local damping (0.8) leaves a fifth of the net
    // force, g (sin 40 - cos 40 tan 20) = 3.640 m/s^2 along the slope: 0.728 m/s^2.
    ASSERT_TRUE(s.run("prop jmat=1 jfric=20\nreset time\nsolve cycles 500\n@v = solve_verdict\nprint info")) << s.error();
    const odec::SolveVerdict& v = *s.interp.last_solve;
    EXPECT_EQ(v.outcome, SolveOutcome::Mechanism);
    EXPECT_EQ(v.stop, odec::StopReason::Steps);
    EXPECT_EQ(v.steps, 500);
    ASSERT_EQ(v.moving.size(), 1u);
    EXPECT_EQ(v.moving[0].id, 2);
    const double speed = s.model.blocks.vel[1].norm();
    EXPECT_DOUBLE_EQ(v.moving[0].speed, speed);
    EXPECT_NEAR(speed, 0.728 * s.model.time, 0.03 * 0.728 * s.model.time);
    EXPECT_GT(v.moving_growth, 1.05); // speeding up
    char fig[32];
    std::snprintf(fig, sizeof fig, "%.1f", speed); // two significant digits: 2.3
    EXPECT_NE(s.said().find("solve: mechanism at the step limit (500 steps): 1 block (id 2) still moving at up to " +
                            std::string(fig) + " m/s, speeding up over the last "),
              std::string::npos)
        << s.said();
    EXPECT_EQ(fish_text(s, "v"), "mechanism");
    EXPECT_NE(s.said().find("last solve: ratio limit 1e-05, step limit 500, no time limit"), std::string::npos);
    EXPECT_NE(s.said().find("verdict:    mechanism at the step limit"), std::string::npos) << s.said();
    // Run for a time instead, the plain line stays, and the mechanism is said after it.
    ASSERT_TRUE(s.run("solve time 0.5")) << s.error();
    EXPECT_EQ(s.interp.last_solve->outcome, SolveOutcome::Mechanism);
    EXPECT_NE(s.said().find("solve: reached the time limit, ratio "), std::string::npos) << s.said();
    EXPECT_NE(s.said().find("solve: mechanism: 1 block (id 2) still moving at up to "), std::string::npos) << s.said();
}

TEST(SolveVerdict, AStableButSlowBlockIsNotConvergedWithAFallingRatioNotAMechanism) {
    // The resting block with little damping (local 0.02) bounces on its joint and settles
    // slowly: 4000 steps are not enough to reach the ratio limit.
    Talking s;
    // Real masses: density scaling settles this block within the 4000 steps.
    ASSERT_TRUE(s.run("config dyn\n" + std::string(kResting) + "damp local 0.02\nsolve cycles 4000\n@v = solve_verdict")) << s.error();
    const odec::SolveVerdict v = *s.interp.last_solve;
    EXPECT_EQ(v.outcome, SolveOutcome::NotConverged);
    EXPECT_TRUE(v.moving.empty());
    ASSERT_TRUE(v.trend_known);
    EXPECT_LT(v.decades_per_step, 0);
    EXPECT_LT(v.ratio_to, v.ratio_from / 1.5);
    EXPECT_LT(v.speed_to, v.speed_from);
    EXPECT_GT(v.steps_to_limit, 0);
    EXPECT_GE(v.window_steps, 800); // the last fifth of the run, at least
    EXPECT_LE(v.window_steps, 1400);
    EXPECT_NE(s.said().find("solve: not converged within the step limit (4000 steps): ratio "), std::string::npos)
        << s.said();
    EXPECT_NE(s.said().find(" the ratio fell from "), std::string::npos) << s.said();
    EXPECT_NE(s.said().find(", about a decade every "), std::string::npos) << s.said();
    EXPECT_NE(s.said().find(": at this rate 1e-05 in about "), std::string::npos) << s.said();
    EXPECT_NE(s.said().find("(settling; no block moves steadily)"), std::string::npos) << s.said();
    EXPECT_EQ(s.said().find("mechanism"), std::string::npos) << s.said();
    EXPECT_EQ(fish_text(s, "v"), "not converged");
    // It was stable: solving on reaches equilibrium.
    ASSERT_TRUE(s.run("solve")) << s.error();
    EXPECT_EQ(s.interp.last_solve->outcome, SolveOutcome::Equilibrium);
}

// A 6 m cube cut by bedding dipping 25 degrees toward a free face (east) and by two steep sets
// (examples/tutorial/jointed-block.dat with its bedding tilted): with joint friction 26 the
// slope stands, but settles slowly; with 20 it slides.
std::string jointed_slope(int friction) {
    return "poly brick 0 6 0 6 -2 6\njset dip 25 dd 90 origin 0,0,2 spacing 2 number 3\n"
           "jset dip 75 dd 90 origin 3,0,0 spacing 2 number 3\njset dip 80 dd 0 origin 0,3,0 spacing 3 number 1\n"
           "prop mat=1 dens=2600\nprop jmat=1 jkn=5e9 jks=2e9 jfric=" +
           std::to_string(friction) + " jcoh=0 jten=0\ngrav 0 0 -10\nfix range z -2 0\ndelete range x 4.5 6 z 2 6\n";
}

TEST(SolveVerdict, AStableButSlowSlopeDoesNotReadLikeAFailingOne) {
    Talking stable;
    // Real masses: density scaling brings this slope to rest within the 1000 steps. Friction 26
    // on the 25 degree bedding: at 25 the block on the bedding at the toe (block 14) is in
    // neutral equilibrium, and whether it stops or slides on at the speed it was given depends
    // on how its corners meet its neighbours, not on the verdict this test is about.
    ASSERT_TRUE(stable.run("config dyn\n" + jointed_slope(26) + "solve cycles 1000")) << stable.error();
    const odec::SolveVerdict a = *stable.interp.last_solve;
    EXPECT_EQ(a.outcome, SolveOutcome::NotConverged);
    ASSERT_TRUE(a.trend_known);
    EXPECT_LT(a.decades_per_step, 0);
    EXPECT_GT(a.steps_to_limit, 0);
    EXPECT_TRUE(a.moving.empty());
    EXPECT_NE(stable.said().find("solve: not converged within the step limit (1000 steps): ratio "), std::string::npos)
        << stable.said();
    EXPECT_NE(stable.said().find(" the ratio fell from "), std::string::npos) << stable.said();
    ASSERT_TRUE(stable.run("solve")) << stable.error();
    EXPECT_EQ(stable.interp.last_solve->outcome, SolveOutcome::Equilibrium);

    Talking failing;
    ASSERT_TRUE(failing.run(jointed_slope(20) + "solve cycles 1000")) << failing.error();
    const odec::SolveVerdict& b = *failing.interp.last_solve;
    EXPECT_EQ(b.outcome, SolveOutcome::Mechanism);
    // The blocks above the bedding plane that daylights in the free face: all but those of
    // the ground (fixed) and those held behind the steep joints.
    std::vector<int> ids;
    double fastest = 0;
    for (const odec::MovingBlock& m : b.moving) {
        ids.push_back(m.id);
        const int k = failing.model.block_index(m.id);
        ASSERT_GE(k, 0);
        EXPECT_FALSE(failing.model.blocks.flags[k] & odec::kFixed);
        EXPECT_DOUBLE_EQ(m.speed, failing.model.blocks.vel[k].norm());
        EXPECT_GT(failing.model.blocks.vel[k].x(), 0); // toward the free face
        EXPECT_LT(failing.model.blocks.vel[k].z(), 0); // and down
        fastest = std::max(fastest, m.speed);
    }
    EXPECT_EQ(b.moving_speed, fastest);
    EXPECT_GE(ids.size(), 6u);
    EXPECT_GT(b.moving_growth, 1.05);
    const std::string n = std::to_string(ids.size());
    EXPECT_NE(failing.said().find("solve: mechanism at the step limit (1000 steps): " + n + " blocks (ids " +
                                  odec::id_list(ids) + ") still moving at up to "),
              std::string::npos)
        << failing.said();
    EXPECT_EQ(failing.said().find("not converged"), std::string::npos) << failing.said();
}

TEST(SolveVerdict, AVeryShortRunIsTooShortToJudge) {
    Talking s;
    ASSERT_TRUE(s.run(std::string(kResting) + "solve cycles 3 ratio 1e-12")) << s.error();
    EXPECT_EQ(s.interp.last_solve->outcome, SolveOutcome::NotConverged);
    EXPECT_FALSE(s.interp.last_solve->trend_known);
    EXPECT_NE(s.said().find("solve: not converged within the step limit (3 steps): ratio "), std::string::npos)
        << s.said();
    EXPECT_NE(s.said().find("; too few steps to judge its trend\n"), std::string::npos) << s.said();
}

TEST(SolveVerdict, TimeLimitAndInterruptionKeepTheirMessages) {
    Talking s;
    ASSERT_TRUE(s.run(std::string(kResting) + "solve time 0.05")) << s.error();
    EXPECT_NE(s.said().find("solve: reached the time limit, ratio "), std::string::npos) << s.said();
    EXPECT_EQ(s.said().find("mechanism"), std::string::npos) << s.said();
    EXPECT_EQ(s.interp.last_solve->stop, odec::StopReason::Time);
    ASSERT_TRUE(s.run("print info")) << s.error();
    EXPECT_NE(s.said().find("last solve: no ratio limit, no step limit, time limit 0.05 s"), std::string::npos)
        << s.said();
    // Ctrl-C: each try raises the flag again and again, starting a while after the solve was
    // asked for (solve lowers the flag as it starts), while the long solve of a sliding block
    // runs. A raise that comes before the command starts stops the script before it instead:
    // then the solve is tried again, the raises starting later (a loaded machine starts late).
    Talking t;
    // Real masses: in a static analysis the sliding block's light masses would soon run it away.
    ASSERT_TRUE(t.run("config dyn\n" + std::string(kIncline) + "solve\nprop jmat=1 jfric=20")) << t.error();
    std::atomic<bool> done{false};
    std::atomic<int> wait_ms{10};
    std::atomic<long> asked{0}; // tries asked for; the thread serves each once
    std::thread ctrl_c([&] {
        long served = 0;
        while (!done) {
            if (asked == served) {
                std::this_thread::sleep_for(std::chrono::milliseconds(1));
                continue;
            }
            served = asked;
            std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms));
            while (!done && asked == served) {
                t.interp.interrupt = true;
                std::this_thread::sleep_for(std::chrono::milliseconds(1));
            }
        }
    });
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(60.0 * odec::test::time_scale());
    while (std::chrono::steady_clock::now() < deadline) {
        ++asked;
        t.interp.interrupt = false; // a raise of the try before
        t.run("solve cycles 2000000000");
        if (t.interp.last_solve && t.interp.last_solve->outcome == SolveOutcome::Interrupted) break;
        wait_ms = std::min(2000, 2 * wait_ms);
    }
    done = true;
    ctrl_c.join();
    t.interp.interrupt = false;
    ASSERT_TRUE(t.interp.last_solve);
    EXPECT_EQ(t.interp.last_solve->outcome, SolveOutcome::Interrupted);
    EXPECT_EQ(t.interp.last_solve->stop, odec::StopReason::Interrupted);
    EXPECT_NE(t.said().find("solve: interrupted after "), std::string::npos) << t.said();
    EXPECT_EQ(t.said().find("mechanism"), std::string::npos) << t.said();
}

TEST(SolveVerdict, ARunAwayOrARefusalKeepsItsErrorAndLeavesNoVerdict) {
    Talking s;
    s.check_save_at_end = false;
    // Dynamic mode: a static analysis chooses its masses for any forced timestep.
    ASSERT_TRUE(s.run("config dyn\n" + std::string(kResting) + "solve")) << s.error();
    ASSERT_TRUE(s.interp.last_solve);
    // A forced timestep far beyond the stable one is refused before the first step.
    EXPECT_FALSE(s.run("set dt 1\nsolve"));
    EXPECT_NE(s.error().find("larger than the stable limit"), std::string::npos) << s.error();
    EXPECT_FALSE(s.interp.last_solve);
    // An absurd load (errors_test.cpp) makes the motion run away.
    ASSERT_TRUE(s.run("set dt auto\nsolve\ndamp off\nset dt 1e-3\nbound zload -5e8 range id 2")) << s.error();
    ASSERT_TRUE(s.interp.last_solve);
    EXPECT_FALSE(s.run("solve"));
    EXPECT_NE(s.error().find("error: stopped: the motion of block 2 has run away (step "), std::string::npos)
        << s.error();
    EXPECT_FALSE(s.interp.last_solve);
    ASSERT_TRUE(s.run("print info")) << s.error();
    EXPECT_NE(s.said().find("last solve: none finished since 'new' or 'restore'"), std::string::npos) << s.said();
}

TEST(SolveVerdict, NewAndRestoreForgetTheLastSolve) {
    Session s;
    ASSERT_TRUE(s.run(std::string(kResting) + "solve")) << s.error();
    ASSERT_TRUE(s.interp.last_solve);
    ASSERT_TRUE(s.run("new")) << s.error();
    EXPECT_FALSE(s.interp.last_solve);
    const std::string dir = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    const std::string file = dir + "/odec-verdict-" + std::to_string(getpid()) + ".sav";
    ASSERT_TRUE(s.run(std::string(kResting) + "solve\nsave '" + file + "'")) << s.error();
    ASSERT_TRUE(s.interp.last_solve);
    ASSERT_TRUE(s.run("restore '" + file + "'")) << s.error();
    EXPECT_FALSE(s.interp.last_solve);
    std::remove(file.c_str());
}

TEST(SolveVerdict, BlockIdsAreListedCompactly) {
    EXPECT_EQ(odec::id_list({17, 12, 13}), "12, 13, 17");
    EXPECT_EQ(odec::id_list({1, 2, 3, 4, 9}), "1-4, 9");
    EXPECT_EQ(odec::id_list({1, 3, 5, 7}, 2), "1, 3, ...");
}

namespace {

// 'solve elastic' says whether its first stage reached equilibrium: a first stage stopped by its
// step limit says so, with the ratio, instead of announcing an equilibrium it did not reach.
TEST(SolveVerdict, SolveElasticSaysWhenItsElasticStageFellShort) {
    Session shortened;
    shortened.interp.quiet = false;
    ASSERT_TRUE(shortened.run(std::string(kResting) + "solve elastic cycles 5")) << shortened.error();
    const std::string out = shortened.out.str();
    EXPECT_EQ(out.find("equilibrium with elastic joints reached"), std::string::npos) << out;
    EXPECT_NE(out.find("solve elastic: the elastic stage stopped at its step limit after 5 steps, short of "
                       "equilibrium (ratio "),
              std::string::npos)
        << out;
    Session full;
    full.interp.quiet = false;
    ASSERT_TRUE(full.run(std::string(kResting) + "solve elastic ratio 1e-4")) << full.error();
    EXPECT_NE(full.out.str().find("solve elastic: equilibrium with elastic joints reached; now with their strengths"),
              std::string::npos)
        << full.out.str();
}

} // namespace
