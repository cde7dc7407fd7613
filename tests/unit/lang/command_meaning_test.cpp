// Commands mean what a 3DEC user expects: a driven fixed base moves, point histories follow
// the material point, joint materials must exist, 'solve time' runs for that time, and a
// range that selects nothing is said.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "engine/blocks.h"
#include "test_util.h"

using odec::test::Session;

TEST(CommandMeaning, FixedBlockFollowsItsBoundaryVelocity) {
    // The fixed base of a shake table is driven by 'bound xvel': it moves, and carries the
    // block resting on it by friction.
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 4 0 4 -1 0\npoly brick 1 2 1 2 0 1\nprop mat=1 dens=2000\n"
                      "prop jmat=1 jkn=1e9 jks=1e9 jfric=40\ngrav 0 0 -10\nfix range z -1 0\nsolve ratio 1e-6\n"
                      "reset disp\ndamp off\nbound xvel 0.1 range z -1 0\nset dt 1e-5\nstep 10000"))
        << s.error();
    const odec::Model& m = s.model;
    EXPECT_NEAR(m.blocks.disp[0].x(), 0.1 * 10000 * 1e-5, 1e-12); // 0.01 m
    EXPECT_EQ(m.blocks.disp[0].y(), 0);
    EXPECT_EQ(m.blocks.disp[0].z(), 0);
    EXPECT_NEAR(odec::velocity_at_t(m, 0).x(), 0.1, 1e-12);
    // The block on top goes with it (undamped, it swings about the base by its elastic shear).
    EXPECT_NEAR(m.blocks.disp[1].x(), 0.01, 1e-3);
}

TEST(CommandMeaning, FixedBlockDrivenByATable) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\nfix\ntable 1 0 0 1 1\n"
                      "bound yvel 2 hist table 1\nset dt 1e-3\nstep 1000"))
        << s.error();
    // v = 2 t for 1 s: y = t^2 = 1 m (a rectangle rule over the table, so to a step).
    EXPECT_NEAR(s.model.blocks.disp[0].y(), 1.0, 3e-3);
}

TEST(CommandMeaning, PointHistoriesFollowTheMaterialPoint) {
    // A block spun about z: a point 1 m from its centroid moves on a circle, the centroid not at all.
    Session s;
    ASSERT_TRUE(s.run("poly brick -1 1 -1 1 -1 1\nprop mat=1 dens=1000\ndamp off\nset dt 1e-4\n"
                      "hist ncyc 1\nhist xvel 1,0,0\nhist yvel 1,0,0\nhist ydis 1,0,0\nhist yvel 0,0,0"))
        << s.error();
    // Give it a spin of 1 rad/s about z.
    s.model.blocks.ang_vel[0] = Eigen::Vector3d(0, 0, 1);
    s.model.blocks.half_kick[0] = 1;
    ASSERT_TRUE(s.run("step 100")) << s.error();
    const auto& h = s.model.histories.items;
    const double t = s.model.time, w = 1.0;
    EXPECT_NEAR(h[1].values.back(), w * std::cos(w * t), 1e-6); // yvel of the point at (1,0,0)
    EXPECT_NEAR(h[0].values.back(), -w * std::sin(w * t), 1e-6); // xvel
    EXPECT_NEAR(h[2].values.back(), std::sin(w * t), 1e-12);    // ydis, exact for the turn
    EXPECT_NEAR(h[3].values.back(), 0.0, 1e-12);                // the centroid stays
    EXPECT_NE(h[0].label.find("block 1"), std::string::npos) << h[0].label;
}

TEST(CommandMeaning, UndefinedJointMaterialIsAnError) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\npoly brick 0 1 0 1 1 2\nprop mat=1 dens=2000\n"
                      "prop jmat=1 jkn=1e9 jks=1e9 jfric=30"));
    // As in 3DEC, a joint material may be assigned before its properties are given: said, and
    // refused when the model would cycle without them.
    EXPECT_TRUE(s.run("change jmat=2")) << s.error();
    EXPECT_NE(s.error().find("t.dat:1:8: warning: joint material 2 has no properties yet"), std::string::npos) << s.error();
    for (int c = 0; c < s.model.contacts.size(); ++c) EXPECT_EQ(s.model.contacts.jmat(c), 2);
    EXPECT_FALSE(s.run("step 1"));
    EXPECT_NE(s.error().find("has joint material 2, which has no properties"), std::string::npos) << s.error();
    EXPECT_EQ(s.model.step, 0);
    EXPECT_FALSE(s.run("set jmat 3"));
    EXPECT_NE(s.error().find("joint material 3 has no properties"), std::string::npos) << s.error();
    EXPECT_EQ(s.model.settings.default_jmat, 1);
    EXPECT_TRUE(s.run("prop jmat=2 jkn=2e9 jks=1e9 jfric=20\nchange jmat=2\nset jmat 2")) << s.error();
}

TEST(CommandMeaning, SolveTimeRunsForThatTime) {
    // A block at rest on a base is in equilibrium at once: 'solve time' must still run on.
    Session q;
    ASSERT_TRUE(q.run("poly brick 0 1 0 1 -1 0\npoly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\n"
                      "prop jmat=1 jkn=1e9 jks=1e9 jfric=30\ngrav 0 0 -10\nfix range z -1 0\nset dt 1e-4\n"
                      "solve time 0.05"))
        << q.error();
    EXPECT_NEAR(q.model.time, 0.05, 1e-4 * 1.001);
    EXPECT_GE(q.model.time, 0.05 * (1 - 1e-12));
    // With a ratio too, whichever comes first: equilibrium long before 10 s.
    Session r;
    ASSERT_TRUE(r.run("poly brick 0 1 0 1 -1 0\npoly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\n"
                      "prop jmat=1 jkn=1e9 jks=1e9 jfric=30\ngrav 0 0 -10\nfix range z -1 0\nset dt 1e-4\n"
                      "solve ratio 1e-4 time 10"))
        << r.error();
    EXPECT_LT(r.model.time, 10.0);
}

TEST(CommandMeaning, RangeThatSelectsNothingIsSaid) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nfix range z 5 6\nfree range z 5 6\nchange mat=1 range z 5 6\n"
                      "ini xvel 1 range z 5 6\nbound xvel 1 range z 5 6\nhide range z 5 6"))
        << s.error();
    const std::string e = s.error();
    for (int line = 2; line <= 7; ++line) {
        EXPECT_NE(e.find("t.dat:" + std::to_string(line) + ":1: warning: the range selects no blocks"), std::string::npos)
            << e;
    }
    EXPECT_EQ(s.model.blocks.flags[0], 0);
    EXPECT_EQ(s.model.blocks.vel_bc[0], 0);
}

TEST(CommandMeaning, FixAndFreeSayHowManyBlocksChanged) {
    Session s;
    s.interp.quiet = false;
    s.interp.echo = false;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\npoly brick 0 1 0 1 1 2\nfix range z 0 1\nfix\nfree")) << s.error();
    const std::string o = s.out.str();
    EXPECT_NE(o.find("1 blocks fixed"), std::string::npos) << o;
    EXPECT_NE(o.find("2 blocks freed"), std::string::npos) << o;
}

TEST(CommandMeaning, DilationBeyondFrictionIsRefusedAndChangesNothing) {
    Session s;
    ASSERT_TRUE(s.run("prop mat=1 dens=2000 ymod 1e9 prat 0.25 coh 1e5 fric 30")) << s.error();
    EXPECT_EQ(s.error(), "");
    EXPECT_FALSE(s.run("prop mat=1 dens=3000 dil 40"));
    EXPECT_NE(s.error().find("may not exceed the friction angle"), std::string::npos) << s.error();
    EXPECT_EQ(s.model.materials[1].density, 2000.0);
    EXPECT_EQ(s.model.materials[1].dilation, 0.0);
}

TEST(CommandMeaning, PrintTablesFitA100ColumnTerminal) {
    // Negative numbers in every column: a settled stack that was pushed about.
    Session s;
    s.interp.quiet = false;
    s.interp.echo = false;
    ASSERT_TRUE(s.run("poly brick -3 3 -3 3 -1 0\npoly brick -1 0 -1 0 0 1\npoly brick -1 0 -1 0 1 2\n"
                      "prop mat=1 dens=2000 ymod 1e9 prat 0.2\nprop jmat=1 jkn=1e9 jks=1e9 jfric=30 jcoh=1e5\n"
                      "grav 0 0 -10\nfix range z -1 0\nini xvel -1e-3 yvel -2e-4 range z 1 2\nstep 300\n"
                      "print block\nprint contact\nprint prop\nprint max"))
        << s.error();
    std::istringstream lines(s.out.str());
    std::string line;
    int n = 0;
    while (std::getline(lines, line)) {
        EXPECT_LE(line.size(), 100u) << line;
        ++n;
    }
    // Columns never run together, even for numbers that fill their width: each row of the
    // block table has its 11 fields.
    Session t;
    ASSERT_TRUE(t.run("poly brick 0 1 0 1 0 1")) << t.error();
    t.model.blocks.centroid[0] = Eigen::Vector3d(-0.000603, -1.23e-05, -1.23e+03);
    t.model.blocks.disp[0] = Eigen::Vector3d(-1.23e-05, -1.23e-05, -1.23e-05);
    t.interp.quiet = false;
    t.interp.echo = false;
    ASSERT_TRUE(t.run("print block")) << t.error();
    std::istringstream rows(t.out.str());
    std::getline(rows, line); // the header
    std::getline(rows, line);
    std::istringstream fields(line);
    int n_fields = 0;
    for (std::string f; fields >> f;) ++n_fields;
    EXPECT_EQ(n_fields, 11) << line;
    EXPECT_GT(n, 15);
    EXPECT_NE(s.out.str().find("density"), std::string::npos);
    EXPECT_NE(s.out.str().find("jcoh"), std::string::npos);
    EXPECT_NE(s.out.str().find("1e+05"), std::string::npos); // the joint cohesion, listed
}

TEST(CommandMeaning, WordsOfMissingFeaturesSayWhatIsMissing) {
    for (const char* line : {"gp"}) {
        Session s;
        EXPECT_FALSE(s.run(line));
        EXPECT_NE(s.error().find("is not available"), std::string::npos) << line << "\n" << s.error();
        EXPECT_EQ(s.error().find("unknown command"), std::string::npos) << s.error();
    }
    // A FISH definition with no 'end' says so.
    {
        Session s;
        EXPECT_FALSE(s.run("def f\n  x = 1"));
        EXPECT_NE(s.error().find("has no 'end'"), std::string::npos) << s.error();
    }
    // A plain typo is still unknown, with a suggestion.
    Session s;
    EXPECT_FALSE(s.run("stpe 10"));
    EXPECT_NE(s.error().find("unknown command 'stpe'"), std::string::npos) << s.error();
}
