// Verification problem 3: the settling column (reference/verification.md).
// n unit cubes, density 2000, kn = 1e7 Pa/m, on a fixed base, g = 10.
// The k-th joint from the top carries k * 20 kPa; the top settles 2, 12, 30 mm for
// 1, 3, 5 blocks; one block bounces on its joint with period 2 pi sqrt(rho h / kn).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "contact_test_util.h"

using namespace odec;
using namespace odec::test;

namespace {

Model column(int n) {
    Model m;
    m.settings.dyn_configured = m.settings.dynamic = true; // real masses and time: dynamics
    set_material(m, 1, 2000);
    set_joint(m, 1, 1e7, 1e7, 30);
    m.gravity = Vec3(0, 0, -10);
    add_fixed(m, make_brick(-1, 2, -1, 2, -1, 0));
    for (int k = 0; k < n; ++k) add_block(m, make_brick(0, 1, 0, 1, k, k + 1), 0, -1, 1);
    return m;
}

void check_column(int n) {
    Model m = column(n);
    CycleLimits lim;
    lim.ratio = 1e-7;
    lim.max_steps = 200000;
    const CycleResult r = cycle(m, lim);
    ASSERT_EQ(r.reason, StopReason::Ratio) << r.message;
    // Joint below block k (block index k + 1; the base is index 0).
    for (int k = 0; k < n; ++k) {
        const int c = contact_between(m, k, k + 1);
        ASSERT_GE(c, 0);
        const ContactInfo info = contact_info(m, c);
        const double expected = (n - k) * 20e3; // (n - k)-th joint from the top
        EXPECT_NEAR(info.normal_stress, expected, 0.01 * expected) << "joint " << k;
        EXPECT_NEAR(info.area, 1.0, 1e-9);
        EXPECT_NEAR(std::abs(info.normal.z()), 1.0, 1e-9);
        EXPECT_EQ(info.state, ContactState::Elastic);
    }
    const double settle = -m.blocks.disp[n].z();
    const double expected = 2e-3 * n * (n + 1) / 2.0;
    EXPECT_NEAR(settle, expected, 0.01 * expected);
    std::printf("column of %d: top settlement %.4f mm (analytic %.4f), bottom joint %.3f kPa (analytic %.3f)\n",
                n, settle * 1e3, expected * 1e3, contact_info(m, contact_between(m, 0, 1)).normal_stress / 1e3,
                n * 20.0);
}

} // namespace

TEST(ContactColumn, OneBlock) { check_column(1); }
TEST(ContactColumn, ThreeBlocks) { check_column(3); }
TEST(ContactColumn, FiveBlocks) { check_column(5); }

TEST(ContactColumn, UndampedPeriod) {
    Model m = column(1);
    m.damping.mode = DampingMode::Off;
    ASSERT_EQ(prepare_cycle(m), "");
    // Time the upward crossings of the equilibrium level (-2 mm) by linear interpolation.
    const double level = -2e-3;
    std::vector<double> crossings;
    double prev_z = 0, prev_t = 0;
    while (m.time < 0.6) {
        ASSERT_EQ(run_steps(m, 1).reason, StopReason::Steps);
        const double z = m.blocks.disp[1].z();
        if (prev_z < level && z >= level) crossings.push_back(prev_t + (level - prev_z) / (z - prev_z) * (m.time - prev_t));
        prev_z = z;
        prev_t = m.time;
    }
    ASSERT_GE(crossings.size(), 4u);
    const double period = (crossings.back() - crossings.front()) / (crossings.size() - 1);
    const double expected = 2 * M_PI * std::sqrt(2000.0 * 1.0 / 1e7);
    EXPECT_NEAR(period, expected, 0.01 * expected);
    std::printf("undamped period %.5f s (analytic %.5f), dt %.3g s\n", period, expected, m.dt);
    // No rocking: the joint is loaded evenly, so the block must not rotate.
    EXPECT_LT(rotation_since_reset(m, 1).norm(), 1e-9);
}

TEST(ContactColumn, Deterministic) {
    Model a = column(3), b = column(3);
    run_steps(a, 500);
    run_steps(b, 500);
    for (int i = 0; i < a.blocks.size(); ++i) {
        EXPECT_EQ(a.blocks.centroid[i], b.blocks.centroid[i]);
        EXPECT_EQ(a.blocks.vel[i], b.blocks.vel[i]);
    }
}
