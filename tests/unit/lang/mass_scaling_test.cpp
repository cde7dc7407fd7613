// Static and dynamic analysis (engine/mass_scaling.h): density scaling reaches the equilibrium
// real masses reach, in fewer steps; 'config dyn', 'set dyn', 'mscale' as in 3DEC.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "engine/zones.h"
#include "test_util.h"

namespace {

using odec::test::Session;

// An elastic column 1 x 1 x 4 m (E 1 GPa, nu 0.25, 2000 kg/m^3) on a fixed base, sides on
// rollers, under its own weight: the top settles by rho g H^2 / (2 M), M = E (1-nu) / ((1+nu)(1-2nu)).
const char* kColumn = "poly brick 0 1 0 1 0 4\nprop mat=1 dens=2000 ymod=1e9 prat=0.25\ngen edge 0.25\n"
                      "bound zvel 0 range z -0.001 0.001\nbound xvel 0 range x -0.001 0.001\n"
                      "bound xvel 0 range x 0.999 1.001\nbound yvel 0 range y -0.001 0.001\n"
                      "bound yvel 0 range y 0.999 1.001\ngrav 0 0 -10\n";

struct ColumnRun {
    long steps = 0;
    double settlement = 0;
};

ColumnRun column(bool dynamic) {
    Session s;
    EXPECT_TRUE(s.run(std::string(dynamic ? "config dyn\n" : "") + kColumn + "solve ratio 1e-6")) << s.error();
    ColumnRun r;
    r.steps = s.model.step;
    const int g = odec::find_gridpoint_near(s.model, {0.5, 0.5, 4.0});
    r.settlement = -s.model.gridpoints.disp[g].z();
    return r;
}

TEST(MassScaling, StaticReachesTheEquilibriumOfRealMassesInFewerSteps) {
    const double nu = 0.25, e = 1e9, M = e * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
    const double analytic = 2000 * 10 * 16 / (2 * M);
    const ColumnRun dyn = column(true), sta = column(false);
    std::printf("[mass scaling] column settlement: dynamic %.6g m in %ld steps, static %.6g m in %ld steps, "
                "analytic %.6g m\n",
                dyn.settlement, dyn.steps, sta.settlement, sta.steps, analytic);
    EXPECT_NEAR(dyn.settlement, analytic, 0.01 * analytic);
    EXPECT_NEAR(sta.settlement, analytic, 0.01 * analytic);
    EXPECT_NEAR(sta.settlement, dyn.settlement, 0.005 * analytic);
    EXPECT_LT(sta.steps, dyn.steps);
}

// A stack of rigid blocks of very different sizes on stiff joints: the same contact forces both
// ways, the weight of what is above.
TEST(MassScaling, RigidStackCarriesItsWeightInBothModes) {
    long steps[2];
    for (int dynamic = 0; dynamic < 2; ++dynamic) {
        Session s;
        ASSERT_TRUE(s.run(std::string(dynamic ? "config dyn\n" : "") +
                          "poly brick 0 2 0 2 -1 0\npoly brick 0 2 0 2 0 0.1\npoly brick 0 2 0 2 0.1 2.1\n"
                          "prop mat=1 dens=2500\nprop jmat=1 jkn=1e11 jks=1e11 jfric=40\nfix range z -1 0\n"
                          "grav 0 0 -10\nhist ncyc 1\nhist nstress 1,1,0.1\nsolve ratio 1e-7"))
            << s.error();
        // The joint between the thin plate and the big block carries the big block: 2500 g 2 m.
        EXPECT_NEAR(s.model.histories.items[0].values.back(), 2500 * 10 * 2.0, 0.01 * 2500 * 10 * 2.0);
        steps[dynamic] = s.model.step;
    }
    std::printf("[mass scaling] rigid stack: static %ld steps, dynamic %ld steps\n", steps[0], steps[1]);
    EXPECT_LT(steps[0], steps[1]);
}

TEST(MassScaling, ModesAsIn3dec) {
    Session s;
    EXPECT_FALSE(s.model.settings.dynamic);
    // 'set dyn on' needs 'config dyn', as in 3DEC.
    EXPECT_FALSE(s.run("set dyn on"));
    EXPECT_NE(s.error().find("dynamic analysis is not configured"), std::string::npos) << s.error();
    EXPECT_FALSE(s.model.settings.dynamic);
    ASSERT_TRUE(s.run("config dyn")) << s.error();
    EXPECT_TRUE(s.model.settings.dynamic);
    ASSERT_TRUE(s.run("set dyn off")) << s.error();
    EXPECT_FALSE(s.model.settings.dynamic);
    ASSERT_TRUE(s.run("set dyn on")) << s.error();
    EXPECT_TRUE(s.model.settings.dynamic);
    ASSERT_TRUE(s.run("new")) << s.error();
    EXPECT_FALSE(s.model.settings.dynamic);
    EXPECT_FALSE(s.model.settings.dyn_configured);
}

TEST(MassScaling, PrintInfoAndTimeSayTheMode) {
    Session s;
    s.interp.quiet = false;
    ASSERT_TRUE(s.run(std::string(kColumn) + "hist time\nstep 10\nprint info")) << s.error();
    const std::string out = s.out.str();
    EXPECT_NE(out.find("note: a history of time in a static analysis"), std::string::npos) << out;
    EXPECT_NE(out.find("static analysis: density scaling, timestep"), std::string::npos) << out;
    EXPECT_NE(out.find("analysis:   static, density scaling"), std::string::npos) << out;
    EXPECT_NE(out.find("(static: not real time)"), std::string::npos) << out;
}

// Partial density scaling: a thin plate of blocks sets the dynamic step; 'mscale' raises just
// its mass and says how much was added.
TEST(MassScaling, MscaleRaisesOnlyWhatHoldsTheStepDown) {
    Session s;
    s.interp.quiet = false;
    ASSERT_TRUE(s.run("config dyn\npoly brick 0 2 0 2 -1 0\npoly brick 0 2 0 2 0 0.02\npoly brick 0 2 0 2 0.02 2\n"
                      "prop mat=1 dens=2500\nprop jmat=1 jkn=1e10 jks=1e10 jfric=40\nfix range z -1 0\n"
                      "grav 0 0 -10\nstep 1"))
        << s.error();
    const double real_dt = s.model.dt;
    // Below the real step: nothing to scale, refused, nothing changed.
    EXPECT_FALSE(s.run("mscale " + std::to_string(real_dt / 2)));
    EXPECT_NE(s.error().find("is not above the one the model takes with real masses"), std::string::npos) << s.error();
    EXPECT_EQ(s.model.settings.mscale_dt, 0.0);
    EXPECT_FALSE(s.run("mscale fast"));
    EXPECT_FALSE(s.run("mscale -1"));
    s.out.str("");
    char target[64];
    std::snprintf(target, sizeof target, "%.17g", 5 * real_dt);
    ASSERT_TRUE(s.run(std::string("mscale ") + target + "\nstep 100")) << s.error();
    EXPECT_EQ(s.model.dt, std::strtod(target, nullptr));
    const std::string out = s.out.str();
    EXPECT_NE(out.find("mscale: 0 gridpoint and 1 block masses scaled"), std::string::npos) << out;
    // The big block keeps its real mass; the plate got more.
    const auto& b = s.model.blocks;
    EXPECT_EQ(b.inertial_mass[2], b.mass[2]);
    EXPECT_GT(b.inertial_mass[1], b.mass[1]);
    ASSERT_TRUE(s.run("mscale off\nstep 1")) << s.error();
    EXPECT_EQ(b.inertial_mass[1], b.mass[1]);
    EXPECT_NEAR(s.model.dt, real_dt, 1e-9 * real_dt);
}

// Each 'step' of a dynamic run chooses the masses again; a mass 'mscale' raised is chosen as it
// was, and its block keeps its momentum: two runs of 50 steps are one of 100, to the bit.
TEST(MassScaling, MscaleKeepsMomentumFromOneStepCommandToTheNext) {
    const std::string model = "config dyn\npoly brick 0 2 0 2 -1 0\npoly brick 0 2 0 2 0 0.02\n"
                              "poly brick 0 2 0 2 0.02 2\nprop mat=1 dens=2500\n"
                              "prop jmat=1 jkn=1e10 jks=1e10 jfric=40\nfix range z -1 0\ngrav 0 0 -10\nstep 1\n";
    Session probe;
    ASSERT_TRUE(probe.run(model)) << probe.error();
    char target[64];
    std::snprintf(target, sizeof target, "%.17g", 5 * probe.model.dt);
    const std::string scaled = model + "mscale " + target + "\nini xvel 0.5 range z 0 2\n";
    Session once, twice;
    ASSERT_TRUE(once.run(scaled + "step 100")) << once.error();
    ASSERT_TRUE(twice.run(scaled + "step 50\nstep 50")) << twice.error();
    ASSERT_GT(once.model.blocks.inertial_mass[1], once.model.blocks.mass[1]);
    for (int b = 1; b < 3; ++b) {
        EXPECT_GT(std::abs(once.model.blocks.vel[b].x()), 0.01) << "block " << b + 1;
        for (int i = 0; i < 3; ++i) {
            EXPECT_EQ(twice.model.blocks.vel[b][i], once.model.blocks.vel[b][i]) << "block " << b + 1;
            EXPECT_EQ(twice.model.blocks.centroid[b][i], once.model.blocks.centroid[b][i]) << "block " << b + 1;
        }
    }
}

// A velocity given with 'ini' is what the static masses start from, not slowed by their choice.
TEST(MassScaling, AGivenVelocityIsKept) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2000 ymod=1e9 prat=0.25\ngen edge 0.3\n"
                      "ini xvel 0.1\nstep 3"))
        << s.error();
    EXPECT_FALSE(s.model.settings.dynamic);
    for (int i = 0; i < s.model.gridpoints.size(); ++i) {
        ASSERT_NEAR(s.model.gridpoints.vel[i].x(), 0.1, 1e-12) << "gridpoint " << i + 1;
    }
}

TEST(MassScaling, MscaleOnAnEmptyModelIsRefused) {
    Session s;
    EXPECT_FALSE(s.run("mscale 1e-5"));
    EXPECT_NE(s.error().find("nothing to scale"), std::string::npos) << s.error();
}

} // namespace
