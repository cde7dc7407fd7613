// Scripts run end to end through the interpreter, checked against the physics they model.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "engine/blocks.h"
#include "lang/help.h"
#include "test_util.h"

using odec::test::Session;

namespace {
const std::string kSource = ODEC_SOURCE_DIR;
}

// Verification problem 1: central differences with constant gravity are exact up to round-off.
TEST(FreeFall, TutorialMatchesTheAnalyticAnswer) {
    Session s;
    ASSERT_TRUE(s.interp.run_file(kSource + "/examples/tutorial/free-fall.dat")) << s.error();
    const odec::Model& m = s.model;
    ASSERT_EQ(m.blocks.size(), 1);
    const double t = m.time, g = 10.0, z0 = 10.5;
    EXPECT_NEAR(t, 1.0, 1e-12);
    const double z_exact = z0 - g * t * t / 2;
    EXPECT_NEAR(m.blocks.centroid[0].z(), z_exact, 1e-6 * std::abs(z_exact));
    EXPECT_NEAR(m.blocks.disp[0].z(), -5.0, 1e-6 * 5.0);
    EXPECT_NEAR(odec::velocity_at_t(m, 0).z(), -10.0, 1e-6 * 10.0);
    // The histories saw the same: last zdis sample -5, last zvel sample -10.
    ASSERT_EQ(m.histories.items.size(), 3u);
    EXPECT_NEAR(m.histories.items[1].values.back(), -5.0, 5e-6);
    EXPECT_NEAR(m.histories.items[2].values.back(), -10.0, 1e-5);
}

TEST(FreeFall, LocalDampingLeavesAFifthOfGravity) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 10 11\nprop mat=1 dens=2000\ngrav 0 0 -10\nset dt 1e-3\n"
                      "hist ncyc 1\nhist zvel 0.5 0.5 10.5\nstep 1000"))
        << s.error();
    const auto& v = s.model.histories.items[0].values;
    ASSERT_EQ(v.size(), 1000u);
    // Acceleration between 0.5 s and 1 s, well after the first step.
    const double a = (v[999] - v[499]) / 0.5;
    EXPECT_NEAR(a, -0.2 * 10.0, 1e-9);
}

TEST(FreeFall, InitialVelocityIsIntegratedExactly) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=1000\ngrav 0 0 -10\ndamp off\nset dt 1e-3\n"
                      "ini zvel 5 xvel 1\nstep 1000"));
    // z = v0 t - g t^2 / 2 = 0 after 1 s; x = 1.
    EXPECT_NEAR(s.model.blocks.disp[0].z(), 0.0, 1e-9);
    EXPECT_NEAR(s.model.blocks.disp[0].x(), 1.0, 1e-9);
}

TEST(Commands, FixHoldsBlocksAndFreeReleasesThem) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1 region 1\npoly brick 0 1 0 1 5 6 region 2\nprop mat=1 dens=1000\n"
                      "grav 0 0 -10\ndamp off\nset dt 1e-3\nfix range region 1\nstep 100"));
    EXPECT_EQ(s.model.blocks.disp[0].norm(), 0.0);
    EXPECT_LT(s.model.blocks.disp[1].z(), 0.0);
    ASSERT_TRUE(s.run("free range z -1 2\nstep 100"));
    EXPECT_LT(s.model.blocks.disp[0].z(), 0.0);
}

TEST(Commands, RangeSelectsByGroupIdSphereAndNot) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1 group 'a'\npoly brick 2 3 0 1 0 1 group 'b'\n"
                      "poly brick 4 5 0 1 0 1\nfix range not group 'a'"));
    EXPECT_FALSE(s.model.blocks.flags[0] & odec::kFixed);
    EXPECT_TRUE(s.model.blocks.flags[1] & odec::kFixed);
    EXPECT_TRUE(s.model.blocks.flags[2] & odec::kFixed);
    ASSERT_TRUE(s.run("free\nfix range id 2 3 sphere 4.5,0.5,0.5 0.1"));
    EXPECT_FALSE(s.model.blocks.flags[1] & odec::kFixed);
    EXPECT_TRUE(s.model.blocks.flags[2] & odec::kFixed);
    ASSERT_TRUE(s.run("free\nfix range plane dip 90 dd 90 origin 1.5,0,0 below"));
    EXPECT_TRUE(s.model.blocks.flags[0] & odec::kFixed);
    EXPECT_FALSE(s.model.blocks.flags[1] & odec::kFixed);
}

TEST(Commands, ChangeMaterialUpdatesMass) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 2 0 1 0 1\nprop mat=1 dens=1000\nprop mat=2 dens=3000\nchange mat=2"));
    EXPECT_DOUBLE_EQ(s.model.blocks.mass[0], 6000.0);
    // Inertia about the centroid: m (b^2 + c^2) / 12.
    EXPECT_NEAR(s.model.blocks.inertia_body[0](0, 0), 6000.0 * 2 / 12, 1e-9);
}

TEST(Commands, AbbreviationsAndAliases) {
    Session s;
    ASSERT_TRUE(s.run("POLY BRICK 0 1 0 1 0 1\nproperty material=1 density=2000\nprop mat 1 dens 2500\n"
                      "gravity 0,0,-9.81\nset dt=1e-3\ncyc 10\nstep 10\nhist unbal\nhis time"));
    EXPECT_EQ(s.model.step, 20);
    EXPECT_EQ(s.model.materials[1].density, 2500);
    EXPECT_EQ(s.model.histories.items.size(), 2u);
}

TEST(Commands, HistWriteMakesACsvWithAHeader) {
    Session s;
    const std::string path = testing::TempDir() + "odec-hist.csv";
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=1000\ngrav 0 0 -10\ndamp off\nset dt 0.01\n"
                      "hist ncyc 10\nhist time\nhist zdis 0.5 0.5 0.5\nstep 100\nhist write 2 vs 1 file '" + path + "'"))
        << s.error();
    std::ifstream in(path);
    std::string header, line, last;
    std::getline(in, header);
    EXPECT_EQ(header, "\"1: time\",\"2: zdis (0.5,0.5,0.5) block 1\"");
    int rows = 0;
    while (std::getline(in, line)) {
        last = line;
        ++rows;
    }
    EXPECT_EQ(rows, 10);
    EXPECT_NEAR(std::stod(last.substr(0, last.find(','))), 1.0, 1e-12);
    EXPECT_NEAR(std::stod(last.substr(last.find(',') + 1)), -5.0, 1e-9);
}

TEST(Scripts, CallNestsWithRelativePathsAndReturn) {
    Session s;
    ASSERT_TRUE(s.interp.run_file(kSource + "/tests/scripts/call-outer.dat")) << s.error();
    // outer sets gravity, calls sub/inner.dat (relative to outer), which makes a block and returns
    // before a line that would fail; outer then goes on.
    EXPECT_EQ(s.model.blocks.size(), 1);
    EXPECT_EQ(s.model.gravity.z(), -10);
    EXPECT_EQ(s.model.title, "after the call");
}

TEST(Scripts, EchoShowsFileAndLine) {
    odec::Model model;
    std::ostringstream out, err;
    odec::Interpreter interp(model, odec::command_table(), out, err);
    ASSERT_TRUE(interp.run_text("demo.dat", "grav 0 0 -10\nset echo off\ngrav 0 0 -9", true));
    EXPECT_EQ(out.str(), "demo.dat:1> grav 0 0 -10\ndemo.dat:2> set echo off\n");
}

TEST(Help, ComesFromTheDeclarations) {
    Session s;
    ASSERT_TRUE(s.run("help"));
    EXPECT_NE(s.out.str().find("property          set the properties of a block material or a joint material"),
              std::string::npos);
    s.out.str("");
    ASSERT_TRUE(s.run("help prop"));
    EXPECT_NE(s.out.str().find("density rho                   mass density, kg/m^3"), std::string::npos) << s.out.str();
    s.out.str("");
    ASSERT_TRUE(s.run("help prop dens"));
    EXPECT_NE(s.out.str().find("rho: a number, > 0"), std::string::npos) << s.out.str();
    EXPECT_FALSE(s.run("help prop bogus"));
    EXPECT_NE(s.error().find("'property' has no keyword 'bogus'"), std::string::npos);
}

TEST(Manual, PagesAreGeneratedForEveryCommand) {
    const std::string page = odec::manual_page(*odec::command_table().find("property"));
    EXPECT_NE(page.find("| `density` | `den[sity]` | rho: a number, > 0 | mass density, kg/m^3 |"), std::string::npos)
        << page;
    const std::string index = odec::manual_index(odec::command_table());
    for (const odec::CommandSpec* c : odec::command_table().commands) {
        EXPECT_NE(index.find("[`" + c->name + "`](" + c->name + ".md)"), std::string::npos) << c->name;
    }
}

TEST(Commands, SetPlotKeepsPictureOptions) {
    Session s;
    ASSERT_TRUE(s.run("set plot size 640 480 view -y background black")) << s.error();
    EXPECT_EQ(s.interp.plot.width, 640);
    EXPECT_EQ(s.interp.plot.height, 480);
    EXPECT_EQ(s.interp.plot.view, "-y");
    EXPECT_EQ(s.interp.plot.background, "black");
    // Errors point into the forwarded words, and change nothing.
    EXPECT_FALSE(s.run("set plot size 10 10"));
    EXPECT_NE(s.error().find("t.dat:1:15: error: 'size' w must be 16 to 8192 (got 10)"), std::string::npos) << s.error();
    EXPECT_EQ(s.interp.plot.width, 640);
}

TEST(Commands, JsetCutsAndCountsAndRejectsBadInput) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 10 0 10 0 10\njset dip 0 dd 0 origin 0,0,5 spacing 2 number 3\n"
                      "jset dip 90 dd 90 origin 5,0,0"));
    EXPECT_EQ(s.model.blocks.size(), 8);
    EXPECT_EQ(s.model.n_joint_sets, 2);
    double volume = 0;
    for (double v : s.model.blocks.volume) volume += v;
    EXPECT_NEAR(volume, 1000.0, 1e-9);
    EXPECT_FALSE(s.run("jset dip 100 dd 0"));
    EXPECT_NE(s.error().find("error: 'dip' must be 0 to 90 (got 100)"), std::string::npos) << s.error();
    Session t;
    EXPECT_FALSE(t.run("jset dip 30 dd 0 number 3"));
    EXPECT_NE(t.error().find("error: more than one plane needs 'spacing s'"), std::string::npos) << t.error();
    EXPECT_FALSE(t.run("jset dd 30"));
    EXPECT_NE(t.error().find("error: 'jset' needs 'dip d' (and 'dd a')"), std::string::npos) << t.error();
}

TEST(Commands, ExcavateFillDeleteAndGroup) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\npoly brick 0 1 0 1 1 2\npoly brick 0 1 0 1 2 3\n"
                      "group 'top' range z 2 3\nexcavate range group 'top'"));
    EXPECT_TRUE(s.model.blocks.flags[2] & odec::kExcavated);
    ASSERT_TRUE(s.run("fill\ndelete range id 1"));
    EXPECT_FALSE(s.model.blocks.flags[1] & odec::kExcavated);
    EXPECT_EQ(s.model.blocks.size(), 2);
    EXPECT_EQ(s.model.blocks.id[0], 2); // ids are not reused or shifted
    EXPECT_FALSE(s.run("delete"));
    EXPECT_NE(s.error().find("error: 'delete' needs a range (to delete everything, use 'new')"), std::string::npos);
}

TEST(Commands, TableAndBoundaryVelocityFollowingIt) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=1000\ndamp off\nset dt 1e-3\n"
                      "table 1 0,0 1,2\nbound xvel 1 hist table 1\nstep 1000"))
        << s.error();
    // v(t) = 2 t: x = t^2 after 1 s (central differences sample the table at each step).
    EXPECT_NEAR(s.model.blocks.disp[0].x(), 1.0, 2e-3);
    EXPECT_FALSE(s.run("table 2 0,0 1"));
    EXPECT_NE(s.error().find("error: table points come in pairs x y: this x has no y"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("table 2 0,0 0,1"));
    EXPECT_NE(s.error().find("error: table x values must increase (point 2: 0 after 0)"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("bound xvel 1 hist table 7"));
    EXPECT_NE(s.error().find("error: there is no table 7"), std::string::npos) << s.error();
}

TEST(Commands, SolveStopsAtEquilibriumAndSaysWhy) {
    odec::Model model;
    std::ostringstream out, err;
    odec::Interpreter interp(model, odec::command_table(), out, err);
    ASSERT_TRUE(interp.run_text("t.dat",
                                "poly brick 0 1 0 1 -1 0 region 1\npoly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\n"
                                "prop jmat=1 jkn=1e7 jks=1e7 jfric=30\ngrav 0 0 -10\nfix range region 1\nsolve",
                                false))
        << err.str();
    EXPECT_NE(out.str().find("solve: equilibrium, ratio"), std::string::npos) << out.str();
    EXPECT_NE(out.str().find("max unbalanced force"), std::string::npos);
    // A short run prints no progress lines.
    EXPECT_EQ(out.str().find("  ... step"), std::string::npos) << out.str();
    ASSERT_TRUE(interp.run_text("t.dat", "solve cycles 3 ratio 1e-12", false));
    EXPECT_NE(out.str().find("solve: not converged within the step limit (3 steps): ratio "), std::string::npos) << out.str();
}

TEST(Commands, LongRunsShowProgress) {
    // Progress every 0 s of wall time: a line every 100 steps, with the time left when
    // the run has a known end.
    odec::Model model;
    std::ostringstream out, err;
    odec::Interpreter interp(model, odec::command_table(), out, err);
    interp.progress_seconds = 0;
    ASSERT_TRUE(interp.run_text("t.dat",
                                "poly brick 0 1 0 1 -1 0 region 1\npoly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\n"
                                "prop jmat=1 jkn=1e7 jks=1e7 jfric=30\ngrav 0 0 -10\nfix range region 1\nstep 500",
                                false))
        << err.str();
    EXPECT_NE(out.str().find("  ... step 100  time "), std::string::npos) << out.str();
    EXPECT_NE(out.str().find("20 % done, about "), std::string::npos) << out.str();
    out.str("");
    interp.echo = false; // 'set echo off' silences it
    ASSERT_TRUE(interp.run_text("t.dat", "step 500", false));
    EXPECT_EQ(out.str().find("  ... step"), std::string::npos) << out.str();
}

TEST(Commands, ContactHistoriesByPointOrId) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 -1 0 region 1\npoly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\n"
                      "prop jmat=1 jkn=1e7 jks=1e7 jfric=30\ngrav 0 0 -10\nfix range region 1\n"
                      "hist ncyc 1\nhist nstress 0.5,0.5,0\nhist ndis contact 1\nsolve"))
        << s.error();
    EXPECT_NEAR(s.model.histories.items[0].values.back(), 20000.0, 200.0);
    EXPECT_NEAR(s.model.histories.items[1].values.back(), 0.002, 2e-5);
    EXPECT_FALSE(s.run("hist sstress"));
    EXPECT_NE(s.error().find("error: 'sstress' needs a point x,y,z or 'contact id', one of them"), std::string::npos);
    EXPECT_FALSE(s.run("hist sstress contact 9"));
    EXPECT_NE(s.error().find("error: there is no contact 9"), std::string::npos) << s.error();
}

TEST(Commands, SetLogCopiesCommandsAndOutputToTheLogFile) {
    const std::string path = testing::TempDir() + "odec-test.log";
    std::remove(path.c_str());
    Session s;
    s.interp.quiet = false;
    ASSERT_TRUE(s.run("set logfile '" + path + "'\nset log on\npoly brick 0 1 0 1 0 1\nprint block\nset log off\ngrav 0 0 -10"))
        << s.error();
    std::ifstream in(path);
    const std::string log((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(log.find("odec> poly brick 0 1 0 1 0 1"), std::string::npos) << log;
    EXPECT_NE(log.find("1 of 1 blocks"), std::string::npos) << log;
    EXPECT_EQ(log.find("grav 0 0 -10"), std::string::npos) << log;
    // The screen got the same output.
    EXPECT_NE(s.out.str().find("1 of 1 blocks"), std::string::npos);
    EXPECT_FALSE(s.run("set logfile '/nonexistent-dir/x.log' log on"));
    EXPECT_NE(s.error().find("error: cannot open the log file '/nonexistent-dir/x.log'"), std::string::npos) << s.error();
    EXPECT_EQ(s.interp.log_path, path);
}

TEST(Commands, NamedRangesAndTheirUnion) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1 region 1\npoly brick 0 1 0 1 1 2 region 2\npoly brick 0 1 0 1 2 3 region 3\n"
                      "range name low region 1\nrange name High z 2 3\nrange name ends union nrange low high\n"
                      "fix range nrange ends"))
        << s.error();
    EXPECT_TRUE(s.model.blocks.flags[0] & odec::kFixed);
    EXPECT_FALSE(s.model.blocks.flags[1] & odec::kFixed);
    EXPECT_TRUE(s.model.blocks.flags[2] & odec::kFixed);
    ASSERT_TRUE(s.run("free\nfix range nrange low high")); // in both: none
    for (int b = 0; b < 3; ++b) EXPECT_FALSE(s.model.blocks.flags[b] & odec::kFixed);
    ASSERT_TRUE(s.run("fix range not nrange ends"));
    EXPECT_TRUE(s.model.blocks.flags[1] & odec::kFixed);
    EXPECT_FALSE(s.run("change mat 2 range nrange bogus"));
    EXPECT_NE(s.error().find("t.dat:1:27: error: there is no range named 'bogus'"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("fix range union region 1"));
    EXPECT_NE(s.error().find("error: 'union' must be followed by 'nrange' and the names to join"), std::string::npos);
}

TEST(Commands, OlderJointPropertyName) {
    Session s;
    ASSERT_TRUE(s.run("prop jmat 1 jkn 2.95e9 jks 1.47e9 jfriction 35.0 jcohesion 0 jdilation 0 zdilation 0.01"));
    EXPECT_EQ(s.model.joint_materials[1].zdilation, 0.01);
    EXPECT_EQ(s.model.joint_materials[1].friction, 35.0);
}

TEST(Commands, TableReadsPointsFromAFile) {
    const std::string path = testing::TempDir() + "odec-table.txt";
    {
        std::ofstream f(path);
        f << "; time velocity\n0 0\n0.5, 1\n1\t0\n";
    }
    Session s;
    ASSERT_TRUE(s.run("table 3 read '" + path + "'")) << s.error();
    const odec::Table* t = s.model.tables.find(3);
    ASSERT_NE(t, nullptr);
    ASSERT_EQ(t->points.size(), 3u);
    EXPECT_DOUBLE_EQ(t->at(0.25), 0.5);
    EXPECT_DOUBLE_EQ(t->at(0.75), 0.5);
    EXPECT_DOUBLE_EQ(t->at(2.0), 0.0);
    EXPECT_FALSE(s.run("table 4 read 'no-such-table.txt'"));
    EXPECT_NE(s.error().find("error: cannot open 'no-such-table.txt'"), std::string::npos) << s.error();
}
