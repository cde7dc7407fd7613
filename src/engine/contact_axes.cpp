// The contact update's per-contact set-up, batch by batch (contact_axes.h).
#include "engine/contact_axes.h"

#include <cmath>

#include "engine/normal_code.h"

namespace odec {

namespace {

// A three-term sum in the order Eigen's fixed-size products and dot products add it.
inline double sum3(double a0, double a1, double a2) { return a0 + (a1 + a2); }

// The lanes [0, count) of the batch, each on its own. Written lane by lane over the batch's
// arrays, with selects instead of branches, so that the compiler takes several lanes per vector
// instruction (-ffp-contract=off keeps each product and sum as written, whatever the width).
template <int kSize>
[[gnu::always_inline]] inline void axes_lanes(ContactAxesBatch& B, int count) {
    const double scale = normal_code_detail::kScale;
#pragma omp simd
    for (int l = 0; l < count; ++l) {
        // The unit normal of the code (decode_normal).
        const double u0 = B.nu[l] / scale, v0 = B.nv[l] / scale;
        // (A code's coordinates are never -0: copysign gives sign_of's -1 or 1.)
        const double au = std::fabs(u0), av = std::fabs(v0);
        const double z = 1 - au - av;
        const double fu = (1 - av) * std::copysign(1.0, u0), fv = (1 - au) * std::copysign(1.0, v0);
        const double p0 = z < 0 ? fu : u0, p1 = z < 0 ? fv : v0, p2 = z;
        const double r = 1 / std::sqrt(sum3(p0 * p0, p1 * p1, p2 * p2));
        const double n0 = p0 * r, n1 = p1 * r, n2 = p2 * r;
        // The shear axes (shear_axes).
        const bool x_ref = std::fabs(n0) < 0.6;
        const double q0 = x_ref ? 1.0 : 0.0, q1 = x_ref ? 0.0 : 1.0, q2 = 0.0;
        const double d = sum3(q0 * n0, q1 * n1, q2 * n2);
        const double g0 = q0 - d * n0, g1 = q1 - d * n1, g2 = q2 - d * n2;
        const double gg = sum3(g0 * g0, g1 * g1, g2 * g2);
        const double root = std::sqrt(gg);
        // (Divided in every lane, kept where gg > 0: no branch in the lane's path.)
        const double h0 = g0 / root, h1 = g1 / root, h2 = g2 / root;
        const double a10 = gg > 0 ? h0 : g0, a11 = gg > 0 ? h1 : g1, a12 = gg > 0 ? h2 : g2;
        const double a20 = n1 * a12 - n2 * a11, a21 = n2 * a10 - n0 * a12, a22 = n0 * a11 - n1 * a10;
        const double ax[3][3] = {{n0, n1, n2}, {a10, a11, a12}, {a20, a21, a22}};
        // Each block's turn matrix T = cos1 (I - k k^T) + sin [k]x (turn_matrix).
        double t[2][3][3];
        for (int s = 0; s < 2; ++s) {
            const double k0 = B.k[s][0][l], k1 = B.k[s][1][l], k2 = B.k[s][2][l];
            const double c1 = B.cos1[s][l], sn = B.sin[s][l], m = -c1;
            const double kk[3] = {k0, k1, k2};
            for (int i = 0; i < 3; ++i) {
                for (int j = 0; j < 3; ++j) t[s][i][j] = (m * kk[i]) * kk[j]; // (Eigen's outer product takes the factor so)
            }
            for (int i = 0; i < 3; ++i) t[s][i][i] += c1;
            t[s][0][1] -= sn * k2;
            t[s][0][2] += sn * k1;
            t[s][1][0] += sn * k2;
            t[s][1][2] -= sn * k0;
            t[s][2][0] -= sn * k1;
            t[s][2][1] += sn * k0;
        }
        double cab[3];
        for (int i = 0; i < 3; ++i) cab[i] = B.centroid[1][i][l] - B.centroid[0][i][l];
        // du0 = ax (d_b - d_a - T_b cab).
        double w[3];
        for (int i = 0; i < 3; ++i) {
            const double tc = sum3(t[1][i][0] * cab[0], t[1][i][1] * cab[1], t[1][i][2] * cab[2]);
            w[i] = (B.disp[1][i][l] - B.disp[0][i][l]) - tc;
        }
        for (int i = 0; i < 3; ++i) {
            B.du0[i][l] = sum3(ax[i][0] * w[0], ax[i][1] * w[1], ax[i][2] * w[2]);
            B.cab_ax[i][l] = sum3(ax[i][0] * cab[0], ax[i][1] * cab[1], ax[i][2] * cab[2]);
            B.cab[i][l] = cab[i];
            B.n[i][l] = ax[0][i];
            B.e1[i][l] = ax[1][i];
            B.e2[i][l] = ax[2][i];
        }
        // dt_ax = (ax (T_b - T_a)) ax^T.
        double pm[3][3];
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                pm[i][j] = sum3(ax[i][0] * (t[1][0][j] - t[0][0][j]), ax[i][1] * (t[1][1][j] - t[0][1][j]),
                                ax[i][2] * (t[1][2][j] - t[0][2][j]));
            }
        }
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                B.dt_ax[3 * i + j][l] = sum3(pm[i][0] * ax[j][0], pm[i][1] * ax[j][1], pm[i][2] * ax[j][2]);
            }
        }
        // to_X = ax R_X (R column-major).
        for (int s = 0; s < 2; ++s) {
            for (int i = 0; i < 3; ++i) {
                for (int j = 0; j < 3; ++j) {
                    B.to[s][3 * i + j][l] = sum3(ax[i][0] * B.rot[s][3 * j][l], ax[i][1] * B.rot[s][3 * j + 1][l],
                                                 ax[i][2] * B.rot[s][3 * j + 2][l]);
                }
            }
        }
    }
}

} // namespace

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
// Four lanes per instruction where the machine has AVX2, two elsewhere: the same operations
// either way (no fused multiply-add: AVX2 alone does not bring it, and -ffp-contract=off).
__attribute__((target_clones("avx2", "default")))
#endif
void make_contact_axes(ContactAxesBatch& batch, int count) { axes_lanes<ContactAxesBatch::kSize>(batch, count); }

} // namespace odec
