// Verification problem 7 of the reference: one deformable block under uniaxial stress
// (elastic) and loaded to Mohr-Coulomb yield with and without confinement, each run from its
// example script through the real interpreter and compared with the analytic answer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

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
