// Verification problem 7 of the reference: one deformable block under uniaxial stress
// (elastic) and loaded to Mohr-Coulomb yield with and without confinement, each run from its
// example script through the real interpreter and compared with the analytic answer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/contact.h"
#include "engine/model.h"
#include "engine/zones.h"
#include "test_util.h"

using odec::test::Session;

namespace {

const std::string kDir = std::string(ODEC_SOURCE_DIR) + "/examples/verification/";

void run_script(Session& s, const std::string& name) {
    ASSERT_TRUE(s.interp.run_file(kDir + name)) << s.error();
}

const std::vector<double>& hist(const Session& s, int n) { return s.model.histories.items.at(n - 1).values; }

void report(const char* what, double computed, double analytic, const char* unit) {
    std::printf("[verification] %-44s computed %12.6g  analytic %12.6g %s  (%+.3f %%)\n", what, computed, analytic, unit,
                100.0 * (computed - analytic) / analytic);
}

// Mean of the samples after the axial strain passed `from` (the plastic plateau).
double plateau(const std::vector<double>& force, const std::vector<double>& top, double from) {
    double sum = 0;
    int n = 0;
    for (size_t k = 0; k < force.size(); ++k) {
        if (top[k] < -from) {
            sum += force[k];
            ++n;
        }
    }
    return n > 0 ? sum / n : 0.0;
}

} // namespace

TEST(Verification, ZoneUniaxialElastic) {
    Session s;
    run_script(s, "zone-uniaxial.dat");
    const double ez = hist(s, 1).back(), ex = hist(s, 2).back(), szz = hist(s, 3).back();
    report("7 uniaxial: vertical strain s/E", ez, -1e-4, "");
    report("7 uniaxial: lateral strain -nu s/E", ex, 2.5e-5, "");
    report("7 uniaxial: zone szz", szz, -1e6, "Pa");
    EXPECT_NEAR(ez, -1e-4, 0.005 * 1e-4);
    EXPECT_NEAR(ex, 2.5e-5, 0.005 * 2.5e-5);
    EXPECT_NEAR(szz, -1e6, 0.005 * 1e6);
    // Every zone carries the applied stress; the base carries the load.
    for (const auto& st : s.model.zones.stress) ASSERT_NEAR(st[2], -1e6, 0.005 * 1e6);
    EXPECT_NEAR(hist(s, 4).back(), -1e6, 0.005 * 1e6);
}

TEST(Verification, ZoneTriaxialMohrCoulomb) {
    Session s;
    run_script(s, "zone-triaxial.dat");
    const double n_phi = 3.0, c = 1e6, s3 = -2e6;
    const double s1 = s3 * n_phi - 2 * c * std::sqrt(n_phi);
    // Axial stress = -(reaction at the top) / (1 m^2), on the plateau past twice the yield strain.
    const double axial = -plateau(hist(s, 1), hist(s, 2), 1.0e-3);
    report("7 triaxial Mohr-Coulomb: s1 at yield", axial, s1, "Pa");
    EXPECT_NEAR(axial, s1, 0.005 * std::abs(s1));
    // Before yield the response is elastic: the first samples are below the yield stress.
    EXPECT_GT(-hist(s, 1).front(), s1 * 0.5);
    // The zones have yielded in shear.
    int yielded = 0;
    for (auto st : s.model.zones.state) yielded += (st & 4) != 0;
    EXPECT_EQ(yielded, s.model.zones.size());
}

TEST(Verification, ZoneUnconfinedMohrCoulomb) {
    Session s;
    run_script(s, "zone-unconfined.dat");
    const double ucs = 2 * 1e6 * std::sqrt(3.0);
    const double axial = plateau(hist(s, 1), hist(s, 2), 0.8e-3);
    report("7 unconfined Mohr-Coulomb: strength 2c sqrt(N)", axial, ucs, "Pa");
    EXPECT_NEAR(axial, ucs, 0.005 * ucs);
}

TEST(Verification, PrandtlFootingCollapseLoad) {
    Session s;
    run_script(s, "footing-prandtl.dat");
    // The plateau: the mean bearing pressure once the footing has settled 2 mm (about twice
    // the settlement at first yield), load over the half-footing's 1 m x 0.1 m.
    const double q = plateau(hist(s, 1), hist(s, 2), 2e-3) / 0.1;
    const double prandtl = (2 + M_PI) * 1e5;
    report("Prandtl footing: bearing pressure (2+pi) c", q, prandtl, "Pa");
    EXPECT_NEAR(q, prandtl, 0.05 * prandtl);
    // It is a collapse: the load no longer grows with settlement.
    const auto& load = hist(s, 1);
    EXPECT_LT(load.back(), 1.02 * load[load.size() * 3 / 4]);
}

namespace {

// Kirsch's solution, compression positive, p1 along z (theta from it), p2 along x.
struct Kirsch {
    double p1 = 30e6, p2 = 15e6, a = 1;
    double sr(double r, double t) const {
        const double q = a * a / (r * r);
        return (p1 + p2) / 2 * (1 - q) + (p1 - p2) / 2 * (1 - 4 * q + 3 * q * q) * std::cos(2 * t);
    }
    double st(double r, double t) const {
        const double q = a * a / (r * r);
        return (p1 + p2) / 2 * (1 + q) - (p1 - p2) / 2 * (1 + 3 * q * q) * std::cos(2 * t);
    }
};

} // namespace

TEST(Verification, KirschHole) {
    Session s;
    run_script(s, "kirsch.dat");
    const Kirsch k;
    const double g = 2.8e9, nu = 0.2103;
    const double ur0 = (k.p1 + k.p2) / (4 * g) + (k.p1 - k.p2) / (4 * g) * (4 * (1 - nu) - 1);
    const double ur90 = (k.p1 + k.p2) / (4 * g) - (k.p1 - k.p2) / (4 * g) * (4 * (1 - nu) - 1);
    const double crown = -hist(s, 1).back(), side = -hist(s, 2).back();
    report("6 Kirsch: wall displacement at the crown", crown, ur0, "m");
    report("6 Kirsch: wall displacement at the side", side, ur90, "m");
    EXPECT_NEAR(crown, ur0, 0.05 * ur0);
    EXPECT_NEAR(side, ur90, 0.05 * ur90);
    // Stresses: the mean over the zones of a window (r and theta around a point) against the
    // mean of the analytic values at their centroids, for windows from 1.2 a outwards.
    const odec::Model& m = s.model;
    struct Window {
        const char* name;
        double r0, r1, t0, t1;  // theta in degrees from the vertical
    };
    const Window windows[] = {{"r 1.2-1.4 a, side wall", 1.2, 1.4, 80, 90}, {"r 1.2-1.4 a, crown", 1.2, 1.4, 0, 10},
                              {"r 1.9-2.1 a, side wall", 1.9, 2.1, 80, 90}, {"r 1.9-2.1 a, crown", 1.9, 2.1, 0, 10},
                              {"r 1.9-2.1 a, 45 deg", 1.9, 2.1, 40, 50}};
    for (const Window& w : windows) {
        double cr = 0, ct = 0, ar = 0, at = 0;
        int n = 0;
        for (int z = 0; z < m.zones.size(); ++z) {
            if (m.blocks.flags[m.zones.block[z]] & odec::kExcavated) continue;
            const odec::Vec3 c = odec::zone_centroid(m, z);
            const double r = std::hypot(c.x(), c.z()), t = std::atan2(c.x(), c.z());
            if (r < w.r0 || r > w.r1 || t < w.t0 * M_PI / 180 || t > w.t1 * M_PI / 180) continue;
            const auto& st = m.zones.stress[z];
            const odec::Vec3 nr(std::sin(t), 0, std::cos(t)), nt(std::cos(t), 0, -std::sin(t));
            auto normal = [&](const odec::Vec3& v) {
                return v.x() * v.x() * st[0] + v.z() * v.z() * st[2] + 2 * v.x() * v.z() * st[4];
            };
            cr -= normal(nr);
            ct -= normal(nt);
            ar += k.sr(r, t);
            at += k.st(r, t);
            ++n;
        }
        ASSERT_GT(n, 3) << w.name;
        char what[96];
        std::snprintf(what, sizeof what, "6 Kirsch: hoop stress, %s", w.name);
        report(what, ct / n, at / n, "Pa");
        EXPECT_NEAR(ct / n, at / n, 0.03 * at / n) << w.name;
        std::snprintf(what, sizeof what, "6 Kirsch: radial stress, %s", w.name);
        report(what, cr / n, ar / n, "Pa");
        // The radial stress is small near the wall: 3 % of the hoop stress there.
        EXPECT_NEAR(cr / n, ar / n, 0.03 * at / n) << w.name;
    }
}

// Verification problem 8: a P wave crossing a joint between two deformable blocks. The
// transmitted amplitude, fitted as a sine of the driving frequency over the last two cycles
// of the train (before any reflection arrives), over the 1 mm/s driven at the end, against
// |T| = 1 / sqrt(1 + (omega Z / (2 kn))^2). Tolerance 5 % (the reference's).
namespace {

// Amplitude of the best fit a sin(w t) + b cos(w t) to the samples with t in [t0, t1].
double fitted_amplitude(const Session& s, int n, double f, double t0, double t1) {
    const auto& steps = s.model.histories.sample_steps;
    const auto& v = hist(s, n);
    double ss = 0, sc = 0, cc = 0, vs = 0, vc = 0;
    for (size_t k = 0; k < v.size() && k < steps.size(); ++k) {
        const double t = steps[k] * s.model.dt; // one timestep throughout: nothing changes it
        if (t < t0 || t > t1) continue;
        const double sn = std::sin(2 * M_PI * f * t), cs = std::cos(2 * M_PI * f * t);
        ss += sn * sn; sc += sn * cs; cc += cs * cs; vs += v[k] * sn; vc += v[k] * cs;
    }
    const double d = ss * cc - sc * sc;
    if (!(d > 0)) return 0;
    return std::hypot((vs * cc - vc * sc) / d, (vc * ss - vs * sc) / d);
}

void check_wave(const char* script, double f, double joint_z, double record_past) {
    Session s;
    run_script(s, script);
    const double c = 1713.0, rho = 2600.0, kn = 1e10;
    const double t_arrive = (joint_z + record_past) / c, t_end = t_arrive + 4.0 / f;
    const double computed = fitted_amplitude(s, 1, f, t_arrive + 2.0 / f, t_end) / 1e-3;
    const double analytic = 1.0 / std::sqrt(1.0 + std::pow(2 * M_PI * f * rho * c / (2.0 * kn), 2));
    char what[64];
    std::snprintf(what, sizeof what, "8 wave across a joint, |T| at %g Hz", f);
    report(what, computed, analytic, "");
    EXPECT_NEAR(computed, analytic, 0.05 * analytic);
}

} // namespace

TEST(Verification, WaveAcrossAJointAt1000Hz) { check_wave("wave-joint-1000.dat", 1000, 5, 1); }
TEST(Verification, WaveAcrossAJointAt100Hz) { check_wave("wave-joint-100.dat", 100, 36, 5); }

// Elastic settlement of a deformable block on a rigid base through a joint: the joint carries
// the weight over the area, the zones' vertical stress grows with depth as rho g, and the top
// settles by rho g H^2 / (2E) plus the joint's closure.
TEST(Verification, DeformableBlockSettlesOnAJoint) {
    Session s;
    run_script(s, "settlement-joint.dat");
    const odec::Model& m = s.model;
    ASSERT_EQ(m.contacts.size(), 1);
    const odec::ContactInfo ci = odec::contact_info(m, 0);
    report("settlement: joint normal stress", ci.normal_stress, 50e3, "Pa");
    EXPECT_NEAR(ci.normal_stress, 50e3, 0.001 * 50e3);
    for (const double z : {0.5, 1.0, 1.5}) {
        double sum = 0, zsum = 0, vol = 0;
        for (int i = 0; i < m.zones.size(); ++i) {
            const odec::Vec3 c = odec::zone_centroid(m, i);
            if (std::abs(c.z() - z) > 0.1) continue;
            sum += m.zones.volume[i] * m.zones.stress[i][2];
            zsum += m.zones.volume[i] * c.z();
            vol += m.zones.volume[i];
        }
        ASSERT_GT(vol, 0);
        const double analytic = -2500.0 * 10.0 * (2.0 - zsum / vol);
        char what[64];
        std::snprintf(what, sizeof what, "settlement: szz, slab at z = %.1f m", z);
        report(what, sum / vol, analytic, "Pa");
        EXPECT_NEAR(sum / vol, analytic, 0.02 * std::abs(analytic)); // 2 %: tetrahedra, base friction
    }
    const double top = -hist(s, 1).back(), analytic_top = 2500.0 * 10.0 * 4.0 / (2.0 * 10e9) + 5e-7;
    report("settlement: top of the block", top, analytic_top, "m");
    EXPECT_NEAR(top, analytic_top, 0.02 * analytic_top);
}

// Tension on two principal planes at once (Mohr-Coulomb's tension cut-off): a cube pulled equally
// along x and y, held along z (K 6.667 GPa, G 4 GPa: alpha1 12 GPa, alpha2 4 GPa; ten 1 MPa,
// cohesion out of reach). Elastic until sxx = syy = ten, when szz = 2 alpha2 / (alpha1 + alpha2)
// ten = 0.5 MPa; after that the flow is normal to both planes and all further strain in x and y
// is plastic, so szz stays at 0.5 MPa. (It used to climb to the cut-off, 1 MPa, step by step:
// the second plane was clipped without its share of the correction of szz.)
TEST(Verification, ZoneTensionOnTwoPlanesHoldsTheThirdStress) {
    Session s;
    ASSERT_TRUE(s.run("set small\npoly brick 0 1 0 1 0 1\n"
                      "prop mat=1 dens=2500 k=6.667e9 g=4e9 coh=1e8 fric=30 ten=1e6 dil=0\nchange cons=2\n"
                      "gen edge 0.5\nbound zvel 0 range z -0.001 0.001\nbound zvel 0 range z 0.999 1.001\n"
                      "bound xvel 0 range x -0.001 0.001\nbound yvel 0 range y -0.001 0.001\n"
                      "bound xvel 1e-3 range x 0.999 1.001\nbound yvel 1e-3 range y 0.999 1.001\nstep 10000"))
        << s.error();
    const double szz = 2 * 4e9 / (12e9 + 4e9) * 1e6;
    // The cube's mean stress (zones by volume); every zone within 3 % (the velocity boundaries
    // leave the inner gridpoints a little behind, so the zones' strains differ slightly).
    double sum = 0, vol = 0, worst = 0;
    const odec::ZoneSet& z = s.model.zones;
    for (int i = 0; i < z.size(); ++i) {
        sum += z.stress[i][2] * z.volume[i];
        vol += z.volume[i];
        worst = std::max(worst, std::abs(z.stress[i][2] - szz));
        EXPECT_NEAR(z.stress[i][0], 1e6, 1e-3 * 1e6);
        EXPECT_NEAR(z.stress[i][1], 1e6, 1e-3 * 1e6);
    }
    report("Mohr-Coulomb tension on two planes: mean szz", sum / vol, szz, "Pa");
    EXPECT_NEAR(sum / vol, szz, 0.002 * szz);
    EXPECT_LT(worst, 0.03 * szz);
}
