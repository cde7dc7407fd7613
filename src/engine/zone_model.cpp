#include "engine/zone_model.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "engine/model.h"

namespace odec {

ZoneMaterialConstants zone_constants(const Material& mat) {
    ZoneMaterialConstants c;
    c.bulk = mat.bulk;
    c.shear = mat.shear;
    c.alpha1 = mat.bulk + 4.0 * mat.shear / 3.0;
    c.alpha2 = mat.bulk - 2.0 * mat.shear / 3.0;
    c.cohesion = mat.cohesion;
    const double sphi = std::sin(mat.friction * M_PI / 180.0);
    const double spsi = std::sin(mat.dilation * M_PI / 180.0);
    c.nphi = (1 + sphi) / (1 - sphi);
    c.npsi = (1 + spsi) / (1 - spsi);
    c.sqrt_nphi = std::sqrt(c.nphi);
    c.tension = mat.tension;
    if (mat.friction > 0) {
        const double apex = mat.cohesion / std::tan(mat.friction * M_PI / 180.0);
        c.tension = std::min(c.tension, apex);
    }
    return c;
}

void elastic_increment(const ZoneMaterialConstants& c, const Sym6& de, Sym6& s) {
    const double ev = de[0] + de[1] + de[2];
    const double g2 = 2.0 * c.shear;
    const double lam = c.alpha2 * ev;
    s[0] += g2 * de[0] + lam;
    s[1] += g2 * de[1] + lam;
    s[2] += g2 * de[2] + lam;
    s[3] += g2 * de[3];
    s[4] += g2 * de[4];
    s[5] += g2 * de[5];
}

std::uint8_t mohr_coulomb_increment(const ZoneMaterialConstants& c, const Sym6& de, Sym6& s) {
    elastic_increment(c, de, s);
    // Most zones are well inside the yield surface: bound the principal stresses by the mean
    // stress p and the deviator's size (every principal deviator lies within sqrt(2/3) |dev| of
    // zero) and skip the eigen-decomposition when even the bounds satisfy both criteria.
    {
        const double p = (s[0] + s[1] + s[2]) / 3.0;
        const double dx = s[0] - p, dy = s[1] - p, dz = s[2] - p;
        const double dev2 = dx * dx + dy * dy + dz * dz + 2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
        const double r = std::sqrt(dev2 * (2.0 / 3.0)) * (1.0 + 1e-12);
        const double lo = p - r, hi = p + r;
        if (lo - hi * c.nphi + 2.0 * c.cohesion * c.sqrt_nphi > 0 && hi < c.tension) return 0;
    }
    Mat3 t;
    t << s[0], s[3], s[4], s[3], s[1], s[5], s[4], s[5], s[2];
    Eigen::SelfAdjointEigenSolver<Mat3> eig;
    eig.computeDirect(t);
    Vec3 p = eig.eigenvalues();  // ascending: p[0] = s1 (most compressive), p[2] = s3
    const double fs = p[0] - p[2] * c.nphi + 2.0 * c.cohesion * c.sqrt_nphi;
    const double ft = c.tension - p[2];
    if (fs >= 0 && ft >= 0) return 0;
    std::uint8_t now = 0;
    // Corner bisector between shear and tension surfaces.
    const double ap = std::sqrt(1.0 + c.nphi * c.nphi) + c.nphi;
    const double sp = c.tension * c.nphi - 2.0 * c.cohesion * c.sqrt_nphi;
    const double h = p[2] - c.tension + ap * (p[0] - sp);
    if (fs < 0 && h <= 0) {
        const double lam = fs / ((c.alpha1 - c.alpha2 * c.npsi) - (c.alpha2 - c.alpha1 * c.npsi) * c.nphi);
        p[0] -= lam * (c.alpha1 - c.alpha2 * c.npsi);
        p[1] -= lam * (c.alpha2 - c.alpha2 * c.npsi);
        p[2] -= lam * (c.alpha2 - c.alpha1 * c.npsi);
        now = kShearNow;
    } else {
        // Plastic flow normal to the cut-off planes that are active (associated in tension):
        // first that of s3 alone; where it leaves s2 beyond the cut-off too, the flow is normal
        // to both planes s2 = t and s3 = t, and s1 takes alpha2 times the sum of both
        // multipliers, (f2 + f3) / (alpha1 + alpha2) (clipping s2 instead would drop its
        // share of s1's correction, and s1 would climb to the cut-off step by step); where
        // even s1 ends beyond it, all three planes are active: the apex, t t t.
        const double f3 = p[2] - c.tension, f2 = p[1] - c.tension;
        const double lam = f3 / c.alpha1;
        now = kTensionNow;
        if (p[1] - lam * c.alpha2 <= c.tension) {
            p[0] -= lam * c.alpha2;
            p[1] -= lam * c.alpha2;
            p[2] = c.tension;
        } else {
            p[0] -= c.alpha2 * (f2 + f3) / (c.alpha1 + c.alpha2);
            p[1] = p[2] = c.tension;
            if (p[0] > c.tension) p[0] = c.tension;
        }
    }
    const Mat3 v = eig.eigenvectors();
    const Mat3 r = v * p.asDiagonal() * v.transpose();
    s = {r(0, 0), r(1, 1), r(2, 2), r(0, 1), r(0, 2), r(1, 2)};
    return now;
}

} // namespace odec
