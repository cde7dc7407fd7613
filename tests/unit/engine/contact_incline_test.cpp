// Verification problem 2: a block on an inclined plane (reference/verification.md).
// The slope is built from rotated bricks: a fixed base and a 10 m wide block on it, the
// joint at psi = 40 deg. kn = ks = 1e7 Pa/m, density 2000, g = 10.
#include <gtest/gtest.h>

#include <cmath>

#include "contact_test_util.h"

using namespace odec;
using namespace odec::test;

namespace {

constexpr double kPsi = 40.0 * M_PI / 180.0;

// Base and block, the block pressed in by its static closure so that it starts at rest
// in the normal direction. Returns the model; block index 1 is the sliding block.
Model incline(double phi_deg, double height) {
    Model m;
    m.settings.dyn_configured = m.settings.dynamic = true; // real masses and time: dynamics
    set_material(m, 1, 2000);
    set_joint(m, 1, 1e7, 1e7, phi_deg);
    m.gravity = Vec3(0, 0, -10);
    const Vec3 axis = Vec3::UnitY();
    add_fixed(m, rotated(make_brick(-20, 40, -1, 2, -2, 0), Vec3::Zero(), axis, kPsi));
    const Vec3 normal(std::sin(kPsi), 0, std::cos(kPsi));
    const double closure = 2000 * 10 * height * std::cos(kPsi) / 1e7;
    Polyhedron block = rotated(make_brick(0, 10, 0, 1, 0, height), Vec3::Zero(), axis, kPsi);
    block.translate(-closure * normal);
    add_block(m, block, 0, -1, 1);
    return m;
}

Vec3 downslope() { return Vec3(std::cos(kPsi), 0, -std::sin(kPsi)); }

// "From rest" means from equilibrium: settle the block with a friction high enough to hold
// it (the joint takes up its elastic shear), then give the joint its real friction, clear
// displacements and time, and let go. Starting with an unloaded shear spring instead would
// add the spring's own transient (about 3 % of the distance for ks = 1e7) to the answer.
void settle_then_set_friction(Model& m, double phi_deg) {
    m.joint_materials[1].friction = 80;
    m.damping.mode = DampingMode::Local;
    CycleLimits lim;
    lim.ratio = 1e-8;
    lim.max_steps = 100000;
    ASSERT_EQ(cycle(m, lim).reason, StopReason::Ratio);
    m.joint_materials[1].friction = phi_deg;
    for (int b = 0; b < m.blocks.size(); ++b) {
        m.blocks.disp[b].setZero();
        m.blocks.vel[b].setZero();
        m.blocks.ang_vel[b].setZero();
        m.blocks.half_kick[b] = 1;
    }
    m.time = 0;
}

} // namespace

TEST(ContactIncline, SlidesAtAnalyticAcceleration) {
    Model m = incline(20, 5);
    settle_then_set_friction(m, 20);
    m.damping.mode = DampingMode::Off;
    ASSERT_EQ(run_time(m, 0.5).reason, StopReason::Time);
    const double v_half = velocity_at_t(m, 1).dot(downslope());
    const double t_half = m.time;
    ASSERT_EQ(run_time(m, 1.0 - m.time).reason, StopReason::Time);
    const double v_one = velocity_at_t(m, 1).dot(downslope());
    const double accel = (v_one - v_half) / (m.time - t_half);
    const double dist = m.blocks.disp[1].dot(downslope());
    const double expected = 10 * (std::sin(kPsi) - std::cos(kPsi) * std::tan(20 * M_PI / 180));
    EXPECT_NEAR(accel, expected, 0.01 * expected);
    EXPECT_NEAR(dist, 0.5 * expected * m.time * m.time, 0.01 * 0.5 * expected);
    std::printf("incline: acceleration %.4f m/s^2 (analytic %.4f), distance after %.3f s %.4f m (analytic %.4f)\n",
                accel, expected, m.time, dist, 0.5 * expected * m.time * m.time);
    const int c = contact_between(m, 0, 1);
    ASSERT_GE(c, 0);
    const ContactInfo info = contact_info(m, c);
    EXPECT_EQ(info.state, ContactState::Slipping);
    EXPECT_NEAR(info.area, 10.0, 1e-3); // the slope's edges are not exactly under the rotated block
    EXPECT_NEAR(info.normal.dot(Vec3(std::sin(kPsi), 0, std::cos(kPsi))), 1.0, 1e-9);
    // The block must slide flat, not rock.
    EXPECT_LT(rotation_since_reset(m, 1).norm(), 1e-3);
}

TEST(ContactIncline, StableWhenFrictionExceedsSlope) {
    Model m = incline(40.1, 10);
    settle_then_set_friction(m, 40.1);
    ASSERT_EQ(run_time(m, 3.0).reason, StopReason::Time);
    const double dist = m.blocks.disp[1].dot(downslope());
    const double speed = velocity_at_t(m, 1).norm();
    std::printf("incline phi=40.1: slide %.3g m, speed %.3g m/s after %.1f s\n", dist, speed, m.time);
    // Releasing the friction lets the lightly loaded uphill corners redistribute by a small
    // slip (0.13 mm here); that is far below the joint's elastic shear displacement (6 mm).
    EXPECT_LT(std::abs(dist), 1e-3);
    EXPECT_LT(speed, 1e-5);
    EXPECT_NE(contact_info(m, contact_between(m, 0, 1)).state, ContactState::Slipping);
}
