// Loads on rigid blocks: forces at a point of the block and couples (their moment about the
// centroid), 'bound stress' on a rigid block's faces, and loads that follow a table of time;
// checked against hand-computed forces and moments and the analytic motion of free blocks.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/blocks.h"
#include "engine/stages.h"
#include "test_util.h"

using odec::test::Session;

namespace {

using odec::Vec3;

bool same_loads(const std::vector<std::vector<odec::BlockLoad>>& a, const std::vector<std::vector<odec::BlockLoad>>& b) {
    if (a.size() != b.size()) return false;
    for (size_t k = 0; k < a.size(); ++k) {
        if (a[k].size() != b[k].size()) return false;
        for (size_t i = 0; i < a[k].size(); ++i) {
            const odec::BlockLoad &x = a[k][i], &y = b[k][i];
            if (x.kind != y.kind || x.table != y.table || x.lever != y.lever || x.force != y.force || x.couple != y.couple) {
                return false;
            }
        }
    }
    return true;
}

// The loads on block index b at the model's time: force, N, and moment about the centroid, N m.
void loads_on(const odec::Model& m, int b, Vec3& force, Vec3& moment) {
    odec::block_applied_load(m, b, m.time, force, moment);
}

// A free brick 0..2 x 0..1 x 0..1 of density 1000 (mass 2000 kg), in a dynamic analysis
// without gravity or damping, stepped at 1e-4 s.
const char* kFreeBrick = "config dyn\npoly brick 0 2 0 1 0 1\nprop mat=1 dens=1000\ndamp off\nset dt 1e-4\n";
constexpr double kMass = 2000;
constexpr double kIxx = kMass * (1 + 1) / 12.0; // kg m^2 about the centroid
constexpr double kIyy = kMass * (4 + 1) / 12.0;
constexpr double kIzz = kMass * (4 + 1) / 12.0;

} // namespace

TEST(Loads, AnOffCentreLoadOnAFreeBlockTurnsItAtMOverI) {
    Session s;
    ASSERT_TRUE(s.run(kFreeBrick)) << s.error();
    // Force (100, 200, 300) N at (2, 1, 0.75): lever (1, 0.5, 0.25) from the centroid (1, 0.5, 0.5).
    ASSERT_TRUE(s.run("bound xload 100 yload 200 zload 300 point 2,1,0.75")) << s.error();
    const Vec3 f(100, 200, 300), r(1, 0.5, 0.25);
    const Vec3 mo = r.cross(f);
    ASSERT_TRUE(s.run("step 1")) << s.error();
    const odec::BlockSet& b = s.model.blocks;
    // Linear acceleration F/m, angular M/I (the brick's principal axes are the world axes).
    EXPECT_NEAR(b.accel[0].x(), f.x() / kMass, 1e-12);
    EXPECT_NEAR(b.accel[0].y(), f.y() / kMass, 1e-12);
    EXPECT_NEAR(b.accel[0].z(), f.z() / kMass, 1e-12);
    EXPECT_NEAR(b.ang_accel[0].x(), mo.x() / kIxx, 1e-12);
    EXPECT_NEAR(b.ang_accel[0].y(), mo.y() / kIyy, 1e-12);
    EXPECT_NEAR(b.ang_accel[0].z(), mo.z() / kIzz, 1e-12);
    // A couple turns the block without moving its centroid.
    Session c;
    ASSERT_TRUE(c.run(kFreeBrick)) << c.error();
    ASSERT_TRUE(c.run("bound ymoment -1000\nstep 1")) << c.error();
    EXPECT_EQ(c.model.blocks.accel[0], Vec3::Zero());
    EXPECT_NEAR(c.model.blocks.ang_accel[0].y(), -1000 / kIyy, 1e-12);
    EXPECT_EQ(c.model.blocks.ang_accel[0].x(), 0);
    EXPECT_EQ(c.model.blocks.ang_accel[0].z(), 0);
}

TEST(Loads, ThePointOfALoadTurnsWithTheBlock) {
    // Force (0,0,F) at lever (1,0,0) turns the brick about y: with the lever turning with it
    // (r = (cos t, 0, -sin t)), t'' = -(F/I) cos t, so from rest w^2 = -2 (F/I) sin t. A lever
    // fixed in space would give w^2 = 2 (F/I) |t| instead: 16 % more at t = -1 rad.
    Session s;
    ASSERT_TRUE(s.run(kFreeBrick)) << s.error();
    ASSERT_TRUE(s.run("bound zload 1000 point 2,0.5,0.5\nstep 14000")) << s.error();
    const odec::BlockSet& b = s.model.blocks;
    const Vec3 turned = odec::rotation_since_reset(s.model, 0);
    const double t = turned.y();
    const double w = b.ang_vel[0].y() + 0.5 * s.model.dt * b.ang_accel[0].y(); // at the time of t
    ASSERT_LT(t, -0.8) << "the brick has not turned far enough for the test to tell";
    EXPECT_NEAR(turned.x(), 0, 1e-12);
    EXPECT_NEAR(turned.z(), 0, 1e-12);
    EXPECT_NEAR(w * w, -2 * (1000 / kIyy) * std::sin(t), 1e-6 * 2 * (1000 / kIyy));
    // The moment now is that of the turned lever.
    Vec3 f, mo;
    loads_on(s.model, 0, f, mo);
    const Vec3 lever = s.model.blocks.orientation[0] * Vec3(1, 0, 0);
    EXPECT_NEAR(mo.y(), -1000 * lever.x(), 1e-9);
    EXPECT_NEAR(lever.x(), std::cos(t), 1e-9);
}

TEST(Loads, ABlockOnAJointOverturnsAtTheAnalyticLoad) {
    // A 1 x 1 x 2 m block (2000 kg/m^3) on a fixed base, pushed horizontally at the top of its
    // back face: it overturns about its front edge when F h > W b / 2, F = W b / (2 h) = W / 4.
    // The friction (40 degrees) holds it against sliding up to F = W tan 40 > W / 4.
    const double weight = 2000 * 2 * 9.81;
    const double limit = weight * 1.0 / (2 * 2.0);
    auto run = [&](double factor) {
        Session s;
        EXPECT_TRUE(s.run("poly brick -1 2 -1 2 -1 0\npoly brick 0 1 0 1 0 2\nprop mat=1 dens=2000\n"
                          "prop jmat=1 jkn=1e10 jks=1e10 jfric=40\ngrav 0 0 -9.81\nfix range id 1\nsolve"))
            << s.error();
        char cmd[128];
        std::snprintf(cmd, sizeof cmd, "bound xload %.10g point 0,0.5,2 range id 2", factor * limit);
        EXPECT_TRUE(s.run(cmd)) << s.error();
        EXPECT_TRUE(s.run("step 30000")) << s.error();
        return odec::rotation_since_reset(s.model, 1).y(); // about y: the top moves in +x
    };
    // Below the limit it stands (the joints' elastic closure turns it by a few micro-radians);
    // above it, it topples.
    EXPECT_LT(std::abs(run(0.99)), 1e-4);
    EXPECT_GT(run(1.01), 0.1);
}

TEST(Loads, StressOnARigidBrickGivesTheTractionsForceAndMoment) {
    // Brick 0..2 x 0..1 x 0..1, centroid (1, 0.5, 0.5).
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 2 0 1 0 1")) << s.error();
    // Shear sxz = 1e4 on the face x = 2 (n = (1,0,0), area 1): traction (0,0,1e4) at (2,0.5,0.5),
    // lever (1,0,0): moment (0,-1e4,0).
    ASSERT_TRUE(s.run("bound stress 0 0 0 0 1e4 0 range x 1.9 2.1")) << s.error();
    Vec3 f, mo;
    loads_on(s.model, 0, f, mo);
    EXPECT_NEAR((f - Vec3(0, 0, 1e4)).norm(), 0, 1e-9);
    EXPECT_NEAR((mo - Vec3(0, -1e4, 0)).norm(), 0, 1e-9);
    // A new stress on the face replaces the old one.
    ASSERT_TRUE(s.run("bound stress 0 0 0 0 1e4 0 range x 1.9 2.1")) << s.error();
    loads_on(s.model, 0, f, mo);
    EXPECT_NEAR(f.z(), 1e4, 1e-9);
    ASSERT_TRUE(s.run("bound free")) << s.error();
    EXPECT_TRUE(s.model.blocks.loads[0].empty());
    // szz = -1e5 + 1e4 x on the top face z = 1 (area 2): force integral over x 0..2, y 0..1 of
    // szz = (-1e5 + 1e4 * 1) * 2 = -1.8e5 in z; moment about the centroid
    // integral of (x-1, y-0.5, 0.5) x (0, 0, szz) = (0, -integral (x-1) szz, 0) = (0, -1e4 * 2/3, 0).
    ASSERT_TRUE(s.run("bound stress 0 0 -1e5 0 0 0 xgrad 0 0 1e4 0 0 0 range z 0.9 1.1")) << s.error();
    loads_on(s.model, 0, f, mo);
    EXPECT_NEAR((f - Vec3(0, 0, -1.8e5)).norm(), 0, 1e-8);
    EXPECT_NEAR((mo - Vec3(0, -1e4 * 2.0 / 3.0, 0)).norm(), 0, 1e-8);
    // A uniform pressure on every face of a lone block: no force and no moment.
    ASSERT_TRUE(s.run("bound free\nbound stress -1e6 -1e6 -1e6 0 0 0")) << s.error();
    EXPECT_EQ(s.model.blocks.loads[0].size(), 6u);
    loads_on(s.model, 0, f, mo);
    EXPECT_LT(f.norm(), 1e-9);
    EXPECT_LT(mo.norm(), 1e-9);
}

TEST(Loads, StressOnATiltedFaceOfARigidBlock) {
    // A right prism over the triangle (0,0), (1,0), (0,1) in x-z, 1 m deep in y: its sloping
    // face has n = (1,0,1)/sqrt 2, area sqrt 2, centroid (0.5,0.5,0.5); the block's centroid is
    // (1/3, 0.5, 1/3), so the face's lever is (1/6, 0, 1/6).
    Session s;
    ASSERT_TRUE(s.run("poly prism a (0,0,0) (1,0,0) (0,0,1) b (0,1,0) (1,1,0) (0,1,1)")) << s.error();
    const Vec3 lever(1.0 / 6, 0, 1.0 / 6);
    // sxy = 1e5: traction sigma n = (0, 1e5/sqrt 2, 0), times the area: (0, 1e5, 0).
    ASSERT_TRUE(s.run("bound stress 0 0 0 1e5 0 0 range x 0.4 0.6 z 0.4 0.6")) << s.error();
    ASSERT_EQ(s.model.blocks.loads[0].size(), 1u);
    Vec3 f, mo;
    loads_on(s.model, 0, f, mo);
    EXPECT_NEAR((f - Vec3(0, 1e5, 0)).norm(), 0, 1e-8);
    EXPECT_NEAR((mo - lever.cross(Vec3(0, 1e5, 0))).norm(), 0, 1e-8); // (-1e5/6, 0, 1e5/6)
    // A pressure p on it: force -p n A = (-p, 0, -p), along the lever: no moment.
    ASSERT_TRUE(s.run("bound stress -2e5 -2e5 -2e5 0 0 0 range x 0.4 0.6 z 0.4 0.6")) << s.error();
    loads_on(s.model, 0, f, mo);
    EXPECT_NEAR((f - Vec3(-2e5, 0, -2e5)).norm(), 0, 1e-8);
    EXPECT_LT(mo.norm(), 1e-8);
}

TEST(Loads, AFreeBlockUnderARampedForceHasTheAnalyticVelocity) {
    // F(t) = F0 t / T with T = 1 s: v = F0 t^2 / (2 m T), x = F0 t^3 / (6 m T), and for a couple
    // M0 t / T about y, w = M0 t^2 / (2 I T).
    Session s;
    ASSERT_TRUE(s.run(kFreeBrick)) << s.error();
    ASSERT_TRUE(s.run("table 1 0,0 1,1\nbound xload 1000 hist table 1\nbound ymoment 500 hist table 1\n"
                      "step 10000")) << s.error();
    const double t = s.model.time;
    EXPECT_NEAR(t, 1.0, 1e-9);
    const Vec3 v = odec::velocity_at_t(s.model, 0);
    EXPECT_NEAR(v.x(), 1000 * t * t / (2 * kMass), 1e-6 * 0.25);
    EXPECT_NEAR(s.model.blocks.disp[0].x(), 1000 * t * t * t / (6 * kMass), 1e-6 * 1000 / (6 * kMass));
    const double w = s.model.blocks.ang_vel[0].y() + 0.5 * s.model.dt * s.model.blocks.ang_accel[0].y();
    EXPECT_NEAR(w, 500 * t * t / (2 * kIyy), 1e-6 * 500 / (2 * kIyy));
    // Beyond the table's end the force holds at F0.
    ASSERT_TRUE(s.run("step 10000")) << s.error();
    EXPECT_NEAR(odec::velocity_at_t(s.model, 0).x(), 0.25 + 1000 * 1.0 / kMass, 1e-6 * 0.75);
}

TEST(Loads, GridpointLoadsAndStressFollowATable) {
    // A free zoned block: the momentum the loads give is the integral of their force, whatever
    // the zones do inside: P(T) = F0 T / 2 for a ramp to F0 over T.
    Session s;
    ASSERT_TRUE(s.run("config dyn\npoly brick 0 2 0 1 0 1\nprop mat=1 dens=1000 bulk 1e8 shear 1e8\ngen edge 0.5\n"
                      "damp off\ntable 1 0,0 0.05,1\n"
                      "bound xload 10 hist table 1 range x 1.9 2.1\n"
                      "bound stress 0 -1e3 0 0 0 0 hist table 1 range y 0.9 1.1"))
        << s.error();
    const odec::GridpointSet& g = s.model.gridpoints;
    int loaded = 0;
    for (int i = 0; i < g.size(); ++i) loaded += g.applied[i].x() != 0 ? 1 : 0;
    ASSERT_GT(loaded, 0);
    for (const odec::BoundaryFace& bf : s.model.stress_boundary.faces) EXPECT_EQ(bf.table, 1);
    // No traction yet at time 0 (the faces with a table are added as the model cycles).
    for (int i = 0; i < g.size(); ++i) EXPECT_EQ(g.traction[i], Vec3::Zero());
    ASSERT_TRUE(s.run("step time 0.05")) << s.error();
    Vec3 p = Vec3::Zero();
    double mass = 0;
    for (int i = 0; i < g.size(); ++i) {
        p += g.mass[i] * odec::gridpoint_velocity_at_t(s.model, i);
        mass += g.mass[i];
    }
    const double t = s.model.time;
    ASSERT_NEAR(t, 0.05, 0.01);
    const double ramp = t >= 0.05 ? 0.05 / 2 + (t - 0.05) : t * t / (2 * 0.05); // integral of table(t)
    // x: 10 N on each loaded gridpoint; y: the stress -1e3 on the face y = 1 (area 2) pushes in -y.
    EXPECT_NEAR(p.x(), 10 * loaded * ramp, 1e-4 * 10 * loaded * ramp);
    EXPECT_NEAR(p.y(), -1e3 * 2 * ramp, 1e-4 * 1e3 * 2 * ramp);
    EXPECT_NEAR(mass, 2000, 1e-6);
}

TEST(Loads, LoadsAtAPointReplaceAndAdd) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 2 0 1 0 1\ntable 1 0,1 1,1")) << s.error();
    ASSERT_TRUE(s.run("bound xload 10 range id 1\nbound yload 5 range id 1\nbound xload 7 range id 1")) << s.error();
    ASSERT_EQ(s.model.blocks.loads[0].size(), 1u);
    EXPECT_EQ(s.model.blocks.loads[0][0].force, Vec3(7, 5, 0));
    // At another point, or with a table, a load adds.
    ASSERT_TRUE(s.run("bound zload 3 point 2,0.5,0.5\nbound xload 1 hist table 1 range id 1")) << s.error();
    EXPECT_EQ(s.model.blocks.loads[0].size(), 3u);
    Vec3 f, mo;
    loads_on(s.model, 0, f, mo);
    EXPECT_EQ(f, Vec3(8, 5, 3));
    EXPECT_NEAR((mo - Vec3(1, 0, 0).cross(Vec3(0, 0, 3))).norm(), 0, 1e-12);
    // A load set to zero goes.
    ASSERT_TRUE(s.run("bound zload 0 point 2,0.5,0.5")) << s.error();
    EXPECT_EQ(s.model.blocks.loads[0].size(), 2u);
    // Given again at the same point after the block has moved a little (here 0.1 mm and a
    // few micro-radians), a load replaces the one there.
    ASSERT_TRUE(s.run("bound free\nbound xload 100 point 2,0.5,0.5\nbound zload 100 point 0,0.5,0.5\n"
                      "prop mat=1 dens=1000\nconfig dyn\ndamp off\nset dt 1e-3\nstep 100")) << s.error();
    ASSERT_GT(s.model.blocks.disp[0].norm(), 1e-4);
    ASSERT_GT(odec::rotation_since_reset(s.model, 0).norm(), 1e-6);
    ASSERT_TRUE(s.run("bound xload 50 point 2,0.5,0.5")) << s.error();
    ASSERT_EQ(s.model.blocks.loads[0].size(), 2u);
    EXPECT_EQ(s.model.blocks.loads[0][0].force, Vec3(50, 0, 0));
}

TEST(Loads, BadLoadsAreRefusedAndChangeNothing) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\npoly brick 0 1 0 1 1 2\nbound xload 5 range id 1")) << s.error();
    const odec::Model before = s.model; // NOLINT: a copy to compare with
    auto refused = [&](const std::string& cmd, const std::string& what) {
        s.err.str("");
        EXPECT_FALSE(s.run(cmd)) << cmd;
        EXPECT_NE(s.error().find(what), std::string::npos) << cmd << "\n" << s.error();
        EXPECT_TRUE(same_loads(s.model.blocks.loads, before.blocks.loads)) << cmd;
    };
    refused("bound xload 1 point 0.5,0.5,1", "error: the point (0.5,0.5,1) lies on blocks 1, 2, where they meet");
    refused("bound xload 1 point 9,9,9", "error: no rigid block holds the point (9,9,9)");
    refused("bound xmoment 1 point 0.5,0.5,0.5", "error: 'point' goes with a load (xload, yload, zload)");
    refused("bound xload 1 hist table 4", "error: there is no table 4");
    refused("bound free hist table 1", "error: 'hist table n' goes with a velocity, a load, a moment or 'stress'");
    // A point of the block takes it without a range; one outside it is loaded with a warning.
    s.err.str("");
    ASSERT_TRUE(s.run("bound zload -1 point 0.5,0.5,0.75")) << s.error();
    EXPECT_EQ(s.model.blocks.loads[0].size(), 2u);
    EXPECT_EQ(s.model.blocks.loads[1].size(), 0u);
    ASSERT_TRUE(s.run("bound zload -1 point 3,0.5,0.5 range id 1")) << s.error();
    EXPECT_NE(s.error().find("warning: the point (3,0.5,0.5) lies outside block 1: the load acts there as through a rigid arm"),
              std::string::npos)
        << s.error();
    // Deformable blocks take no moment and no point.
    Session d;
    ASSERT_TRUE(d.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=1000 bulk 1e8 shear 1e8\ngen edge 0.5")) << d.error();
    EXPECT_FALSE(d.run("bound zmoment 1"));
    EXPECT_NE(d.error().find("error: a moment goes with rigid blocks"), std::string::npos) << d.error();
    EXPECT_FALSE(d.run("bound xload 1 point 0.5,0.5,0.5"));
    EXPECT_NE(d.error().find("error: the point (0.5,0.5,0.5) lies in deformable block 1: 'point' goes with rigid blocks"),
              std::string::npos)
        << d.error();
    // A gridpoint's load follows one table.
    ASSERT_TRUE(d.run("table 1 0,0 1,1\nbound xload 1 hist table 1 range x 0.9 1.1")) << d.error();
    EXPECT_FALSE(d.run("bound yload 1 range x 0.9 1.1"));
    EXPECT_NE(d.error().find("a gridpoint's load follows one table"), std::string::npos) << d.error();
    for (int i = 0; i < d.model.gridpoints.size(); ++i) EXPECT_EQ(d.model.gridpoints.applied[i].y(), 0);
}

TEST(Loads, CuttingALoadedBlockKeepsItsLoads) {
    // A load at a point goes to the piece holding it; one at the centroid is shared by volume.
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 2 0 1 0 1\nbound zload -10 point 1.5,0.5,1\nbound xload 4 range id 1\n"
                      "jset dip 90 dd 90 origin 0.5,0,0")) << s.error();
    ASSERT_EQ(s.model.blocks.size(), 2);
    Vec3 total_f = Vec3::Zero(), total_m = Vec3::Zero();
    const Vec3 c0(1, 0.5, 0.5); // the uncut block's centroid
    for (int b = 0; b < 2; ++b) {
        Vec3 f, mo;
        loads_on(s.model, b, f, mo);
        total_f += f;
        total_m += mo + (s.model.blocks.centroid[b] - c0).cross(f);
    }
    EXPECT_NEAR((total_f - Vec3(4, 0, -10)).norm(), 0, 1e-12);
    // About the old centroid: the point load's moment; the shared centroid load's vanishes.
    EXPECT_NEAR((total_m - Vec3(0.5, 0, 0.5).cross(Vec3(0, 0, -10))).norm(), 0, 1e-12);
}

TEST(Loads, ZoningABlockRemovesItsRigidLoadsAndSaysSo) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=1000 bulk 1e8 shear 1e8\n"
                      "bound zload 5 point 0.5,0.5,1\ngen edge 0.5")) << s.error();
    EXPECT_TRUE(s.model.blocks.loads[0].empty());
    EXPECT_NE(s.error().find("warning: the loads given to block 1 while rigid ('bound xload ...', 'bound stress') are "
                             "removed"),
              std::string::npos)
        << s.error();
}
