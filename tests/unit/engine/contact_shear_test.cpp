// Verification problem 5: direct shear of a joint under constant normal stress.
// sigma_n = 1 MPa, phi = 30, c = 0, kn = ks = 1e10 Pa/m. A 1 x 1 m block is pushed along
// x at a constant slow velocity over a longer fixed block, under a constant normal load.
// The specimen is 2 mm thick, so the moment of the shear force about its centroid (which a
// shear box would take) tilts the normal stress by only 0.1 %.
#include <gtest/gtest.h>

#include <cmath>

#include "contact_test_util.h"

using namespace odec;
using namespace odec::test;

namespace {

struct ShearRun {
    double peak = 0;      // Pa, largest mean shear stress
    double peak_us = 0;   // m, shear displacement at the peak
    double final_tau = 0; // Pa
    double final_sn = 0;  // Pa
    double rise = 0;      // m, upward displacement of the top block
    double slid = 0;      // m, shear displacement at the end
};

ShearRun direct_shear(int jcons, double res_friction, double dilation, double zdil, double cohesion, double u_end) {
    Model m;
    set_material(m, 1, 2000);
    JointMaterial& j = set_joint(m, 1, 1e10, 1e10, 30);
    j.res_friction = res_friction;
    j.dilation = dilation;
    j.zdilation = zdil;
    j.cohesion = cohesion;
    m.settings.default_jcons = jcons;
    add_fixed(m, make_brick(-0.5, 2.0, -0.5, 1.5, -1, 0));
    const double sn = 1e6;
    const int top = add_block(m, make_brick(0, 1, 0, 1, -sn / 1e10, 0.002 - sn / 1e10), 0, -1, 1);
    m.blocks.loads[top].push_back(BlockLoad{LoadKind::Point, 0, Vec3::Zero(), Vec3(0, 0, -sn), Vec3::Zero()});
    m.blocks.vel_bc[top] = 1;
    m.blocks.vel_bc_value[top] = Vec3(0.01, 0, 0);
    ShearRun r;
    EXPECT_EQ(prepare_cycle(m), "");
    const int c = contact_between(m, 0, top);
    EXPECT_GE(c, 0);
    while (m.blocks.disp[top].x() < u_end) {
        run_steps(m, 10);
        const ContactInfo info = contact_info(m, contact_between(m, 0, top));
        if (info.shear_stress > r.peak) {
            r.peak = info.shear_stress;
            r.peak_us = info.shear_disp;
        }
        r.final_tau = info.shear_stress;
        r.final_sn = info.normal_stress;
        r.slid = info.shear_disp;
    }
    r.rise = m.blocks.disp[top].z();
    return r;
}

} // namespace

TEST(ContactShear, PeakAndResidual) {
    const ShearRun r = direct_shear(2, 20, 0, 0, 0, 300e-6);
    const double peak = 1e6 * std::tan(30 * M_PI / 180);
    const double residual = 1e6 * std::tan(20 * M_PI / 180);
    EXPECT_NEAR(r.peak, peak, 0.01 * peak);
    EXPECT_NEAR(r.peak_us, peak / 1e10, 0.05 * peak / 1e10);
    EXPECT_NEAR(r.final_tau, residual, 0.01 * residual);
    EXPECT_NEAR(r.final_sn, 1e6, 0.01 * 1e6);
    std::printf("direct shear: peak %.4f MPa at %.2f um (analytic %.4f at %.2f), residual %.4f MPa (analytic %.4f)\n",
                r.peak / 1e6, r.peak_us * 1e6, peak / 1e6, peak / 1e10 * 1e6, r.final_tau / 1e6, residual / 1e6);
}

TEST(ContactShear, CohesionLostOnFailure) {
    // Model 1 with cohesion: peak c + sn tan(phi), then sn tan(phi) once failed.
    const ShearRun r = direct_shear(1, 0, 0, 0, 0.2e6, 300e-6);
    const double peak = 0.2e6 + 1e6 * std::tan(30 * M_PI / 180);
    const double residual = 1e6 * std::tan(30 * M_PI / 180);
    EXPECT_NEAR(r.peak, peak, 0.01 * peak);
    EXPECT_NEAR(r.final_tau, residual, 0.01 * residual);
}

TEST(ContactShear, DilationWhileSlipping) {
    const double psi = 10 * M_PI / 180;
    const ShearRun r = direct_shear(1, 0, 10, 0, 0, 500e-6);
    // Rise = (shear displacement beyond the elastic part) tan(psi).
    const double plastic = r.slid - 1e6 * std::tan(30 * M_PI / 180) / 1e10;
    EXPECT_NEAR(r.rise, plastic * std::tan(psi), 0.01 * plastic * std::tan(psi));
    EXPECT_NEAR(r.final_sn, 1e6, 0.01 * 1e6);
    std::printf("dilation: rise %.3f um over plastic slip %.3f um: ratio %.5f (tan psi %.5f)\n", r.rise * 1e6,
                plastic * 1e6, r.rise / plastic, std::tan(psi));
}

TEST(ContactShear, DilationStopsAtZdil) {
    const ShearRun r = direct_shear(1, 0, 10, 200e-6, 0, 500e-6);
    const double plastic_to_zdil = 200e-6 - 1e6 * std::tan(30 * M_PI / 180) / 1e10;
    EXPECT_NEAR(r.rise, plastic_to_zdil * std::tan(10 * M_PI / 180), 0.02 * plastic_to_zdil * std::tan(10 * M_PI / 180));
}

// Dilation follows the direction of shearing, as in the classical Coulomb slip joint: it grows
// while the shear increment points the way of the total shear displacement and shrinks while it
// points back. Sheared out by u and back to where it started, the specimen has slipped u - ts/ks
// forward and u - 2 ts/ks back (ts = sn tan phi, the elastic part on each side of the reversal),
// so it stands (ts/ks) tan psi above where it began, not (2u - 3 ts/ks) tan psi as when every
// slip dilates.
TEST(ContactShear, DilationReversesWithTheShear) {
    Model m;
    set_material(m, 1, 2000);
    JointMaterial& j = set_joint(m, 1, 1e10, 1e10, 30);
    j.dilation = 10;
    add_fixed(m, make_brick(-0.5, 2.0, -0.5, 1.5, -1, 0));
    const double sn = 1e6, u = 500e-6;
    const int top = add_block(m, make_brick(0, 1, 0, 1, -sn / 1e10, 0.002 - sn / 1e10), 0, -1, 1);
    m.blocks.loads[top].push_back(BlockLoad{LoadKind::Point, 0, Vec3::Zero(), Vec3(0, 0, -sn), Vec3::Zero()});
    m.blocks.vel_bc[top] = 1;
    m.blocks.vel_bc_value[top] = Vec3(0.01, 0, 0);
    ASSERT_EQ(prepare_cycle(m), "");
    while (m.blocks.disp[top].x() < u) run_steps(m, 1);
    const double out = m.blocks.disp[top].z();
    m.blocks.vel_bc_value[top] = Vec3(-0.01, 0, 0);
    while (m.blocks.disp[top].x() > 0) run_steps(m, 1);
    const double back = m.blocks.disp[top].z();
    // Settle under the load at the end of the path.
    m.blocks.vel_bc_value[top] = Vec3::Zero();
    run_steps(m, 2000);
    const double rise = m.blocks.disp[top].z(), elastic = sn * std::tan(30 * M_PI / 180) / 1e10;
    const double expected = elastic * std::tan(10 * M_PI / 180);
    std::printf("dilation reversed: rise %.3f um out, %.3f um back, %.3f um settled (analytic %.3f um)\n", out * 1e6,
                back * 1e6, rise * 1e6, expected * 1e6);
    EXPECT_NEAR(out, (u - elastic) * std::tan(10 * M_PI / 180), 0.02 * (u - elastic) * std::tan(10 * M_PI / 180));
    EXPECT_NEAR(rise, expected, 0.05 * expected);
}
