// The contact update's per-contact set-up, batch by batch (contact_axes.h).
#include "engine/contact_axes.h"

#include <cmath>

#include "engine/normal_code.h"
#include "engine/simd.h"
#include "engine/stages.h"

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

using simd::load4;
using simd::M4;
using simd::splat;
using simd::store4;
using simd::V4;

// The plain sub-contacts of lanes [0, count) (step_plain_subs), four lanes at a time (lanes past
// count are made of whatever the batch holds there, and not read). Written with vectors, not for
// the compiler to find: every operation is the scalar law's, lane by lane.
[[gnu::always_inline]] inline void plain_lanes(const ContactAxesBatch& A, ContactSubBatch& S, int count) {
    static_assert(ContactSubBatch::kSize % 4 == 0, "whole vectors");
    const V4 zero = splat(0.0), one = splat(1.0);
    for (int l = 0; l < count; l += 4) {
        const V4 kn = load4(&S.kn[l]), ks = load4(&S.ks[l]);
        const V4 coh_intact = load4(&S.coh[l]), ten_intact = load4(&S.ten[l]);
        const V4 tan_intact = load4(&S.tan_phi[l]), tan_res = load4(&S.tan_res[l]);
        const M4 joined = load4(&S.joined[l]) != zero;
        const V4 n = load4(&S.n_subs[l]);
        V4 to_a[9], to_b[9], dt_ax[9], cab_ax[3], du0[3];
        for (int i = 0; i < 9; ++i) {
            to_a[i] = load4(&A.to[0][i][l]);
            to_b[i] = load4(&A.to[1][i][l]);
            dt_ax[i] = load4(&A.dt_ax[i][l]);
        }
        for (int i = 0; i < 3; ++i) {
            cab_ax[i] = load4(&A.cab_ax[i][l]);
            du0[i] = load4(&A.du0[i][l]);
        }
        V4 f0 = zero, f1 = zero, f2 = zero, m0 = zero, m1 = zero, m2 = zero, scale = zero;
        M4 slow = {0, 0, 0, 0};
        for (int j = 0; j < ContactSubBatch::kMaxSubs; ++j) {
            const M4 active = splat(j) < n;
            if (!(active[0] | active[1] | active[2] | active[3])) break; // (no lane has more)
            // Its lever from a's centroid, on the axes (rigid_contact): both sides' made, one kept.
            const M4 of_b = load4(&S.of_b[j][l]) != zero;
            const V4 l0 = load4(&S.local[j][0][l]), l1 = load4(&S.local[j][1][l]), l2 = load4(&S.local[j][2][l]);
            V4 r[3];
            for (int i = 0; i < 3; ++i) {
                const V4 ra = zero + (to_a[3 * i] * l0 + to_a[3 * i + 1] * l1 + to_a[3 * i + 2] * l2);
                const V4 rb = cab_ax[i] + (to_b[3 * i] * l0 + to_b[3 * i + 1] * l1 + to_b[3 * i + 2] * l2);
                r[i] = of_b ? rb : ra;
            }
            V4 du[3];
            for (int i = 0; i < 3; ++i) du[i] = du0[i] + (dt_ax[3 * i] * r[0] + dt_ax[3 * i + 1] * r[1] + dt_ax[3 * i + 2] * r[2]);
            // The joint law's plain case (joint_step_on_axes).
            const V4 un = load4(&S.un[j][l]) - du[0];
            const V4 ss1 = load4(&S.ss[j][0][l]) - ks * du[1], ss2 = load4(&S.ss[j][1][l]) - ks * du[2];
            const M4 failed = load4(&S.failed[j][l]) != zero;
            const V4 coh = failed ? zero : coh_intact;
            const V4 ten = failed ? zero : ten_intact;
            const V4 tan_phi = failed ? tan_res : tan_intact;
            const V4 sn = joined ? kn * un : kn * (un + load4(&S.dil[j][l]));
            const M4 open = (sn < -ten) | ((sn <= zero) & (ten <= zero));
            const V4 limit = coh + sn * tan_phi;
            const V4 tmax = zero < limit ? limit : zero; // std::max(0.0, limit)
            const M4 slip = ss1 * ss1 + ss2 * ss2 > tmax * tmax;
            slow |= active & ~joined & (open | slip);
            store4(&S.un_new[j][l], un);
            store4(&S.dus[j][0][l], du[1]);
            store4(&S.dus[j][1][l], du[2]);
            store4(&S.ss_new[j][0][l], ss1);
            store4(&S.ss_new[j][1][l], ss2);
            const V4 area = load4(&S.area[j][l]);
            const V4 fn = area * sn, fs1 = area * ss1, fs2 = area * ss2;
            // The sums, in the sub-contacts' order (rigid_contact).
            f0 = active ? f0 + fn : f0;
            f1 = active ? f1 + fs1 : f1;
            f2 = active ? f2 + fs2 : f2;
            m0 = active ? m0 + (r[1] * fs2 - r[2] * fs1) : m0;
            m1 = active ? m1 + (r[2] * fn - r[0] * fs2) : m1;
            m2 = active ? m2 + (r[0] * fs1 - r[1] * fn) : m2;
            const V4 mag2 = fn * fn + fs1 * fs1 + fs2 * fs2;
            V4 mag;
            for (int i = 0; i < 4; ++i) mag[i] = std::sqrt(mag2[i]);
            scale = active ? scale + mag : scale;
        }
        // Back on the world axes (ax^T f, as Eigen sums it), and b's moment about its centroid.
        V4 ax[3][3];
        for (int i = 0; i < 3; ++i) {
            ax[0][i] = load4(&A.n[i][l]);
            ax[1][i] = load4(&A.e1[i][l]);
            ax[2][i] = load4(&A.e2[i][l]);
        }
        V4 fb[3], ma[3];
        for (int i = 0; i < 3; ++i) {
            fb[i] = simd::sum3(ax[0][i] * f0, ax[1][i] * f1, ax[2][i] * f2);
            ma[i] = simd::sum3(ax[0][i] * m0, ax[1][i] * m1, ax[2][i] * m2);
        }
        const V4 c0 = load4(&A.cab[0][l]), c1 = load4(&A.cab[1][l]), c2 = load4(&A.cab[2][l]);
        const V4 cross[3] = {c1 * fb[2] - c2 * fb[1], c2 * fb[0] - c0 * fb[2], c0 * fb[1] - c1 * fb[0]};
        for (int i = 0; i < 3; ++i) {
            store4(&S.fb[i][l], fb[i]);
            store4(&S.ma[i][l], ma[i]);
            store4(&S.mb[i][l], ma[i] - cross[i]);
        }
        store4(&S.scale[l], scale);
        store4(&S.slow[l], slow ? one : zero);
    }
}

} // namespace

// Four lanes per instruction where the machine has AVX2, two elsewhere (simd.h).
ODEC_SIMD_CLONES
void make_contact_axes(ContactAxesBatch& batch, int count) { axes_lanes<ContactAxesBatch::kSize>(batch, count); }


ODEC_SIMD_CLONES
void step_plain_subs(const ContactAxesBatch& axes, ContactSubBatch& subs, int count) { plain_lanes(axes, subs, count); }

namespace {

// One block's turn, as update_contacts made it block by block.
[[gnu::always_inline]] inline void block_turn(const Eigen::Vector3d& w_now, bool still, double dt, bool dynamic,
                                              Eigen::Vector3d& axis, double& sin, double& cos1) {
    const Eigen::Vector3d w = still ? Eigen::Vector3d(Eigen::Vector3d::Zero()) : w_now;
    const double angle = w.norm() * dt;
    axis = angle > 0 ? Eigen::Vector3d(w / w.norm()) : Eigen::Vector3d(Eigen::Vector3d::Zero());
    double sin_h = 0, cos_h = 1;
    if (angle > 0) {
        half_turn(angle * angle, sin_h, cos_h);
        sin_h *= angle;
    }
    sin = dynamic ? 2.0 * sin_h * cos_h : angle;
    cos1 = dynamic ? 2.0 * sin_h * sin_h : 0.0;
}

} // namespace

ODEC_SIMD_CLONES
void make_block_turns(const Eigen::Vector3d* ang_vel, const std::uint8_t* still, int b0, int b1, double dt, bool dynamic,
                      Eigen::Vector3d* axis, double* sin, double* cos1) {
    const V4 zero = splat(0.0), one = splat(1.0), two = splat(2.0);
    int b = b0;
    for (; b + 4 <= b1; b += 4) {
        V4 w[3];
        simd::load_xyz4(ang_vel[b].data(), w[0], w[1], w[2]);
        const M4 moving = V4{double(still[b]), double(still[b + 1]), double(still[b + 2]), double(still[b + 3])} == zero;
        for (int i = 0; i < 3; ++i) w[i] = moving ? w[i] : zero;
        const V4 sq = w[0] * w[0] + (w[1] * w[1] + w[2] * w[2]);
        V4 norm;
        for (int l = 0; l < 4; ++l) norm[l] = std::sqrt(sq[l]);
        const V4 angle = norm * splat(dt);
        const M4 turns = angle > zero;
        V4 ax[3];
        for (int i = 0; i < 3; ++i) ax[i] = turns ? w[i] / norm : zero;
        simd::store_xyz4(axis[b].data(), ax[0], ax[1], ax[2]);
        // half_turn's series below h2 = 1e-6, its library functions above (lane by lane).
        const V4 h2 = splat(0.25) * (angle * angle);
        const V4 sixth = splat(1.0 / 6), twelfth = splat(1.0 / 12), twentieth = splat(1.0 / 20), half = splat(0.5);
        V4 sin_h = half * (one - h2 * sixth * (one - h2 * twentieth));
        V4 cos_h = one - h2 * half * (one - h2 * twelfth);
        const M4 series = h2 < splat(1e-6);
        for (int l = 0; l < 4; ++l) {
            if (!turns[l]) {
                sin_h[l] = 0;
                cos_h[l] = 1;
            } else if (!series[l]) {
                double sl, cl; // (a vector's lane is no reference's)
                half_turn(angle[l] * angle[l], sl, cl);
                sin_h[l] = sl;
                cos_h[l] = cl;
            }
        }
        sin_h = turns ? sin_h * angle : sin_h;
        const V4 s = dynamic ? two * sin_h * cos_h : angle;
        const V4 c1 = dynamic ? two * sin_h * sin_h : zero;
        simd::store4(sin + b, s);
        simd::store4(cos1 + b, c1);
    }
    for (; b < b1; ++b) block_turn(ang_vel[b], still[b] != 0, dt, dynamic, axis[b], sin[b], cos1[b]);
}

} // namespace odec
