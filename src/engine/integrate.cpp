// The integration stage: central differences for rigid blocks and gridpoints, under one
// damping law (see cycle.h for the law, mass_scaling.h for the masses).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

#include "engine/clump.h"
#include "engine/energy.h"
#include "engine/mass_scaling.h"
#include "engine/parallel.h"
#include "engine/simd.h"
#include "engine/stages.h"
#include "engine/table.h"

namespace odec {

namespace {

// Adaptive global damping: a viscous coefficient c (1/s, force c m v) set each step from the
// frequency of the motion the model shows, so that the slowest motion towards equilibrium,
// which dominates what still moves, is damped at a fixed fraction of critical (dynamic
// relaxation with a Rayleigh-quotient estimate of that frequency). With K the stiffness and M
// the inertial masses, the squared frequency of the velocity field v is v.K v / v.M v; the step
// shows K v through the change of the unbalanced forces, f(t) - f(t - dt) = -K v dt (loads held),
// so v.K v dt = v.f(t - dt) - v.f(t) with v the velocities between the two, and the estimate
// needs three sums over the free degrees of freedom (AutoDampingSums), one kept from the last
// step. The Rayleigh quotient is never below the lowest frequency: early on, while stiff local
// motions dominate, the damping is heavier than the slowest mode needs, and it eases off as the
// model settles into its slowest motion. A motion against no stiffness (a block sliding or
// falling freely) shows no frequency and draws the least damping, so the damping does not freeze
// a mechanism. Explicit viscous damping needs c dt < 2; c is kept within [1e-4, 0.5] / dt. An
// estimate below zero or not a number (loads changed, a contact opened between the steps)
// leaves c as it was. The fraction of critical is kAutoDampingFraction (model.h).
} // namespace

void adjust_auto_damping(Damping& d, const AutoDampingSums& s, double dt) {
    const double c_max = 0.5 / dt, c_min = 1e-4 / dt;
    if (d.auto_inertia > 0) {
        // The forces changed by the motion of the last step, made with the last step's timestep.
        const double moved = d.auto_dt > 0 ? d.auto_dt : dt;
        const double w2 = (d.auto_after - s.before) / (moved * d.auto_inertia);
        if (std::isfinite(w2) && w2 >= 0) d.auto_coefficient = std::clamp(2 * kAutoDampingFraction * std::sqrt(w2), c_min, c_max);
    }
    // Kept for the next step only when they are numbers (a model running away is stopped by the
    // checks; what it leaves here must still save).
    const bool kept = std::isfinite(s.after) && std::isfinite(s.inertia);
    d.auto_after = kept ? s.after : 0.0;
    d.auto_inertia = kept ? s.inertia : 0.0;
    d.auto_dt = dt;
}

namespace {

std::atomic<bool> g_batched_blocks{true};

using simd::abs4;
using simd::finite4;
using simd::M4;
using simd::sum3;
using simd::V4;

// sign(x) (stages.h) lane by lane: 1, -1, or 0 (for 0 and NaN).
[[gnu::always_inline]] inline V4 sign4(V4 x) {
    const V4 zero = simd::splat(0.0), one = simd::splat(1.0);
    return (x > zero ? one : zero) - (x < zero ? one : zero);
}
// damped_force (stages.h) under local damping, or none (local = 0 stands for DampingMode::Off).
[[gnu::always_inline]] inline V4 damped4(bool off, double local, V4 f, V4 v) {
    return off ? f : f - simd::splat(local) * abs4(f) * sign4(v);
}
// Steps the plain blocks list[0, count) (integrate_plain_blocks), four at a time: each lane does
// what the scalar loop of integrate() does for such a block, operation for operation. Returns
// the least of them whose motion is no longer finite, or -1.
ODEC_SIMD_CLONES
int integrate_plain_blocks(BlockSet& s, const Mat3* rotation_of, const int* list, int count, bool off, double local,
                           double dt) {
    const V4 zero = simd::splat(0.0), one = simd::splat(1.0), half = simd::splat(0.5), vdt = simd::splat(dt);
    const V4 inf = simd::splat(std::numeric_limits<double>::infinity());
    int bad = -1;
    for (int g = 0; g < count; g += 4) {
        int b[4];
        for (int l = 0; l < 4; ++l) b[l] = list[std::min(g + l, count - 1)]; // (the last repeated: written twice, the same)
        // Four blocks in a row (as most are): their vectors' coordinates by whole-vector loads.
        const bool row = g + 4 <= count && b[3] == b[0] + 3;
        auto gather = [&](auto&& get) ODEC_INLINE { return V4{get(b[0]), get(b[1]), get(b[2]), get(b[3])}; };
        auto vectors = [&](const std::vector<Vec3>& arr, V4 out[3]) ODEC_INLINE {
            if (row) {
                simd::load_xyz4(arr[b[0]].data(), out[0], out[1], out[2]);
            } else {
                for (int i = 0; i < 3; ++i) out[i] = gather([&](int x) { return arr[x][i]; });
            }
        };
        auto put_vectors = [&](std::vector<Vec3>& arr, const V4 in[3]) ODEC_INLINE {
            if (row) {
                simd::store_xyz4(arr[b[0]].data(), in[0], in[1], in[2]);
            } else {
                for (int l = 0; l < 4 && g + l < count; ++l) arr[b[l]] = Vec3(in[0][l], in[1][l], in[2][l]);
            }
        };
        const V4 mass = gather([&](int x) { return s.inertial_mass[x]; });
        const V4 real_mass = gather([&](int x) { return s.mass[x]; });
        const V4 kick = gather([&](int x) { return s.half_kick[x] ? 0.5 * dt : dt; });
        // Translation.
        V4 f[3], v0[3], v[3], a[3];
        vectors(s.force, f);
        vectors(s.vel, v0);
        for (int i = 0; i < 3; ++i) {
            a[i] = damped4(off, local, f[i], v0[i]) / mass;
            v[i] = v0[i] + a[i] * kick;
        }
        // Rotation: alpha = R I^-1 R^T M (the real inertia tensor, scaled by the mass ratio).
        V4 r[3][3], mo[3], mom[3], w0[3];
        vectors(s.moment, mo);
        vectors(s.ang_vel, w0);
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) r[i][j] = gather([&](int x) { return rotation_of[x](i, j); });
            mom[i] = damped4(off, local, mo[i], w0[i]);
        }
        auto inertia = [&](int i, int j) ODEC_INLINE { return gather([&](int x) { return s.inertia_body[x](i, j); }); };
        const V4 ib00 = inertia(0, 0), ib11 = inertia(1, 1), ib22 = inertia(2, 2);
        const V4 ib01 = inertia(0, 1), ib02 = inertia(0, 2), ib12 = inertia(1, 2);
        const M4 real = (mass == real_mass) & (mass > zero) & (mass < inf);
        // (What no lane keeps is not made: divisions are the dearest operations here.)
        auto all = [](M4 m) ODEC_INLINE { return (m[0] & m[1] & m[2] & m[3]) != 0; };
        auto none = [](M4 m) ODEC_INLINE { return (m[0] | m[1] | m[2] | m[3]) == 0; };
        V4 ratio = one;
        if (!all(real)) ratio = real ? one : mass / real_mass;
        V4 mb[3];
        for (int j = 0; j < 3; ++j) mb[j] = sum3(r[0][j] * mom[0], r[1][j] * mom[1], r[2][j] * mom[2]);
        // A brick in its own axes: the diagonal's inverse.
        const M4 brick = (ib01 == zero) & (ib02 == zero) & (ib12 == zero);
        V4 q0 = zero, q1 = zero, q2 = zero;
        if (!none(brick)) {
            q0 = mb[0] / ib00;
            q1 = mb[1] / ib11;
            q2 = mb[2] / ib22;
        }
        // Else the adjugate of the tensor scaled to a trace of 1.
        V4 x0 = zero, x1 = zero, x2 = zero;
        if (!all(brick)) {
            const V4 t = ib00 + (ib11 + ib22), u = one / t;
            const V4 i00 = ib00 * u, i11 = ib11 * u, i22 = ib22 * u;
            const V4 i01 = ib01 * u, i02 = ib02 * u, i12 = ib12 * u;
            const V4 c00 = i11 * i22 - i12 * i12, c01 = i02 * i12 - i01 * i22, c02 = i01 * i12 - i02 * i11;
            const V4 c11 = i00 * i22 - i02 * i02, c12 = i01 * i02 - i00 * i12, c22 = i00 * i11 - i01 * i01;
            const V4 det = i00 * c00 + i01 * c01 + i02 * c02;
            const V4 inv_det = one / det, inv_size = one / (ratio * t);
            x0 = ((c00 * mb[0] + c01 * mb[1] + c02 * mb[2]) * inv_det) * inv_size;
            x1 = ((c01 * mb[0] + c11 * mb[1] + c12 * mb[2]) * inv_det) * inv_size;
            x2 = ((c02 * mb[0] + c12 * mb[1] + c22 * mb[2]) * inv_det) * inv_size;
        }
        V4 alpha[3], w[3], dth[3];
        for (int i = 0; i < 3; ++i) {
            const V4 turned = sum3(r[i][0] * q0, r[i][1] * q1, r[i][2] * q2);
            const V4 general = sum3(r[i][0] * x0, r[i][1] * x1, r[i][2] * x2);
            alpha[i] = brick ? (real ? turned : turned / ratio) : general;
            w[i] = w0[i] + alpha[i] * kick;
            dth[i] = w[i] * vdt;
        }
        const V4 t2 = sum3(dth[0] * dth[0], dth[1] * dth[1], dth[2] * dth[2]);
        // half_turn's series in every lane (below h2 = 1e-6, as almost every step has it), its
        // library functions lane by lane above; no turn: 0 and 1.
        const V4 h2 = simd::splat(0.25) * t2;
        V4 sin_h = half * (one - h2 * simd::splat(1.0 / 6) * (one - h2 * simd::splat(1.0 / 20)));
        V4 cos_h = one - h2 * half * (one - h2 * simd::splat(1.0 / 12));
        const M4 turns = t2 > zero, series = h2 < simd::splat(1e-6);
        if (!all(series | ~turns)) {
            for (int l = 0; l < 4; ++l) {
                if (turns[l] && !series[l]) {
                    double sl, cl; // (a vector's lane is no reference's)
                    half_turn(t2[l], sl, cl);
                    sin_h[l] = sl;
                    cos_h[l] = cl;
                }
            }
        }
        sin_h = turns ? sin_h : zero;
        cos_h = turns ? cos_h : one;
        // The turn's quaternion times the orientation (Eigen's product, w first; a quaternion's
        // coefficients are kept x, y, z, w).
        const simd::Quat4 h{dth[0] * sin_h, dth[1] * sin_h, dth[2] * sin_h, cos_h};
        simd::Quat4 o;
        if (row) {
            o = simd::load_quats4(s.orientation[b[0]].coeffs().data());
        } else {
            o.x = gather([&](int x) { return s.orientation[x].x(); });
            o.y = gather([&](int x) { return s.orientation[x].y(); });
            o.z = gather([&](int x) { return s.orientation[x].z(); });
            o.w = gather([&](int x) { return s.orientation[x].w(); });
        }
        const simd::Quat4 q = simd::quat_product4(h, o);
        const V4 nx = q.x, ny = q.y, nz = q.z, nw = q.w;
        const V4 n2 = (nx * nx + ny * ny) + (nz * nz + nw * nw);
        const M4 near_unit = abs4(n2 - one) < simd::splat(1e-8);
        V4 scale = simd::splat(1.5) - half * n2;
        if (!all(near_unit)) {
            V4 root;
            for (int l = 0; l < 4; ++l) root[l] = std::sqrt(n2[l]);
            scale = near_unit ? scale : one / root;
        }
        // Back: velocities, accelerations, positions (c + v dt), orientations where they turned.
        put_vectors(s.vel, v);
        put_vectors(s.accel, a);
        put_vectors(s.ang_vel, w);
        put_vectors(s.ang_accel, alpha);
        V4 c[3], d[3];
        vectors(s.centroid, c);
        vectors(s.disp, d);
        for (int i = 0; i < 3; ++i) {
            const V4 dx = v[i] * vdt;
            c[i] = c[i] + dx;
            d[i] = d[i] + dx;
        }
        put_vectors(s.centroid, c);
        put_vectors(s.disp, d);
        V4 qx = nx * scale, qy = ny * scale, qz = nz * scale, qw = nw * scale;
        const M4 turned = t2 > zero;
        if (row && turned[0] && turned[1] && turned[2] && turned[3]) {
            simd::transpose4(qx, qy, qz, qw);
            simd::store4(s.orientation[b[0]].coeffs().data(), qx);
            simd::store4(s.orientation[b[1]].coeffs().data(), qy);
            simd::store4(s.orientation[b[2]].coeffs().data(), qz);
            simd::store4(s.orientation[b[3]].coeffs().data(), qw);
        } else {
            for (int l = 0; l < 4 && g + l < count; ++l) {
                if (turned[l]) s.orientation[b[l]] = Quat(qw[l], qx[l], qy[l], qz[l]);
            }
        }
        // Not finite (NaN or infinite): the integration is unstable.
        M4 finite = finite4(c[0]) & finite4(c[1]) & finite4(c[2]);
        for (int i = 0; i < 3; ++i) finite &= finite4(v[i]) & finite4(w[i]);
        for (int l = 0; l < 4 && g + l < count; ++l) {
            const int x = b[l];
            s.half_kick[x] = 0;
            if (!finite[l] && (bad < 0 || x < bad)) bad = x;
        }
    }
    return bad;
}

} // namespace

void set_batched_blocks(bool on) { g_batched_blocks = on; }
bool batched_blocks() { return g_batched_blocks; }

int integrate(Model& m, double dt, AutoDampingSums* sums) {
    BlockSet& s = m.blocks;
    // One damping law for blocks and gridpoints.
    const Damping& d = m.damping;
    const bool auto_damp = sums != nullptr;
    if (d.mode == DampingMode::Auto) {
        // A coefficient set at another timestep (`set dt`, or an excavation that changed the
        // automatic one) is brought within this one's limits: c dt >= 2 would be unstable.
        double& c = m.damping.auto_coefficient;
        c = c > 0 ? std::clamp(c, 1e-4 / dt, 0.5 / dt) : 0.02 / dt;
    }
    // Static mode: the blocks' masses follow their joints as they are this step.
    if (!m.settings.dynamic) scale_block_masses(m, true);
    // Fixed chunks of blocks, whatever the number of threads: their sums are added in order.
    constexpr int kChunk = 512;
    const int nb = s.size();
    const int n_chunks = (nb + kChunk - 1) / kChunk;
    thread_local std::vector<AutoDampingSums> chunk_sums;
    thread_local std::vector<int> chunk_bad;
    chunk_sums.assign(n_chunks, AutoDampingSums{});
    chunk_bad.assign(n_chunks, -1);
    AutoDampingSums* cp = chunk_sums.data();
    int* cb = chunk_bad.data();
    // The energy account (energy.h): each step's increments by chunk, added in order.
    const bool account = m.energy.on;
    thread_local std::vector<EnergyStep> chunk_energy;
    if (account) chunk_energy.assign(n_chunks, EnergyStep{});
    EnergyStep* ce = chunk_energy.data();
    const Vec3 grav = m.gravity;
    const Mat3* rotation_of = static_cast<int>(s.rotation.size()) == nb ? s.rotation.data() : nullptr;
#ifdef ODEC_CHECK_INVARIANTS
    // Each rigid block's rotation matrix is its orientation's (refresh_world_vertices made it,
    // and nothing has turned a block since).
    for (int b = 0; rotation_of && b < nb; ++b) {
        const Mat3 r = s.orientation[b].toRotationMatrix();
        if (is_rigid_active(s, b) && std::memcmp(r.data(), rotation_of[b].data(), sizeof(double) * 9) != 0) {
            std::fprintf(stderr, "odec: block %d's rotation matrix is not its orientation's at step %ld\n", s.id[b], m.step);
            std::abort();
        }
    }
#endif
    const int threads = thread_count();
    // The plain blocks (free, alone, with their real inertia tensor, no velocity held) step four
    // at a time (integrate_plain_blocks) under local damping or none, without the energy account
    // or the adaptive damping's sums; the others one by one below.
    const bool batch = batched_blocks() && !account && !auto_damp && rotation_of &&
                       (d.mode == DampingMode::Local || d.mode == DampingMode::Off);
    const bool off = d.mode == DampingMode::Off;
    parallel_for(n_chunks, threads, nb >= kParallelMinBlocks, [&](int chunk) {
        AutoDampingSums& sums = cp[chunk];
        int& bad = cb[chunk];
        int plain[kChunk];
        int n_plain = 0;
        for (int b = chunk * kChunk; b < std::min(nb, (chunk + 1) * kChunk); ++b) {
            // The pieces of a clump move together, after the blocks alone (clump.h).
            if (!is_rigid_active(s, b) || s.clump[b] != 0) continue;
            if (batch && !(s.flags[b] & kFixed) && !s.vel_bc[b] && !(s.inertial_moment[b] > 0)) {
                plain[n_plain++] = b;
                continue;
            }
            // The applied loads of this step, for the work they do (the loads stage's values).
            Vec3 load_f = Vec3::Zero(), load_m = Vec3::Zero();
            if (account && !s.loads[b].empty()) block_applied_load(m, b, m.time, load_f, load_m);
            if (s.flags[b] & kFixed) {
                // Held still, except for the velocity components a boundary condition drives
                // (the fixed base of a shake table moves as its table says, without turning).
                Vec3 v = Vec3::Zero();
                if (s.vel_bc[b]) {
                    const double scale = m.table_factor(m.blocks.vel_bc_table[b]);
                    for (int i = 0; i < 3; ++i) {
                        if (s.vel_bc[b] & (1 << i)) v[i] = s.vel_bc_value[b][i] * scale;
                    }
                    const Vec3 dx = v * dt;
                    s.centroid[b] += dx;
                    s.disp[b] += dx;
                    if (account) {
                        // Driven: what drives it does the work its other forces do not.
                        for (int i = 0; i < 3; ++i) {
                            if (!(s.vel_bc[b] & (1 << i))) continue;
                            energy_dof(ce[chunk], s.mass[b], s.mass[b] * grav[i], load_f[i], s.force[b][i],
                                       s.force[b][i], s.vel[b][i], v[i], true, false, dt);
                        }
                    }
                }
                s.vel[b] = v;
                s.ang_vel[b].setZero();
                s.accel[b].setZero();
                s.ang_accel[b].setZero();
                s.half_kick[b] = 0;
                continue;
            }
            const double mass = s.inertial_mass[b];
            const double kick = s.half_kick[b] ? 0.5 * dt : dt;
            // Translation.
            Vec3 a;
            for (int i = 0; i < 3; ++i) {
                a[i] = damped_force(d, s.force[b][i], s.vel[b][i], mass, dt) / mass;
            }
            Vec3 v = s.vel[b] + a * kick;
            if (s.vel_bc[b]) {
                const double scale = m.table_factor(m.blocks.vel_bc_table[b]);
                for (int i = 0; i < 3; ++i) {
                    if (s.vel_bc[b] & (1 << i)) {
                        v[i] = s.vel_bc_value[b][i] * scale;
                        a[i] = 0;
                    }
                }
            }
            if (auto_damp) {
                for (int i = 0; i < 3; ++i) {
                    if (!(s.vel_bc[b] & (1 << i))) sums.add(mass, s.force[b][i], s.vel[b][i], v[i]);
                }
            }
            if (account) {
                for (int i = 0; i < 3; ++i) {
                    const bool held = s.vel_bc[b] & (1 << i);
                    // Undamped, the force is the force (a[i] * mass may differ from it in the last bit).
                    const double fd = d.mode == DampingMode::Off ? s.force[b][i] : a[i] * mass;
                    energy_dof(ce[chunk], s.mass[b], s.mass[b] * grav[i], load_f[i], s.force[b][i], fd,
                               s.vel[b][i], v[i], held, s.half_kick[b] && !held, dt);
                }
            }
            s.vel[b] = v;
            s.accel[b] = a;
            const Vec3 dx = v * dt;
            s.centroid[b] += dx;
            s.disp[b] += dx;
            // Rotation: angular acceleration from the inertia tensor (gyroscopic term neglected,
            // as usual for quasi-static block analysis), solved in the body frame, where the
            // tensor is the block's own: alpha = R I^-1 R^T M, with I scaled by the inertial
            // mass's ratio to the mass. Static mode gives an isotropic inertia chosen from the
            // joints (mass_scaling.h).
            const double iso = s.inertial_moment[b];
            Vec3 mom, alpha, diag;
            if (iso > 0) {
                diag.setConstant(iso);
                for (int i = 0; i < 3; ++i) mom[i] = damped_force(d, s.moment[b][i], s.ang_vel[b][i], iso, dt);
                alpha = mom / iso;
            } else {
                // (The rotation matrix the last refresh of the world vertices made of this
                // orientation, which nothing has changed since: the contacts stepped with it.)
                const Mat3 r = rotation_of ? rotation_of[b] : Mat3(s.orientation[b].toRotationMatrix());
                const Mat3& ib = s.inertia_body[b];
                const bool real = real_inertia(mass, s.mass[b]);
                const double ratio = real ? 1.0 : mass / s.mass[b];
                // The world tensor's diagonal, R I R^T at (i, i): what the damping and the
                // adaptive damping's sums take as the inertia about each world axis.
                if (d.mode != DampingMode::Local || auto_damp) {
                    for (int i = 0; i < 3; ++i) diag[i] = ratio * r.row(i).dot(ib * r.row(i).transpose());
                } else {
                    diag.setZero();
                }
                for (int i = 0; i < 3; ++i) mom[i] = damped_force(d, s.moment[b][i], s.ang_vel[b][i], diag[i], dt);
                const Vec3 mb = r.transpose() * mom;
                if (ib(0, 1) == 0 && ib(0, 2) == 0 && ib(1, 2) == 0) {
                    // Its own axes are the body frame's (a brick): the inverse is the diagonal's.
                    const Vec3 turned = r * Vec3(mb.x() / ib(0, 0), mb.y() / ib(1, 1), mb.z() / ib(2, 2));
                    alpha = real ? turned : Vec3(turned / ratio);
                } else {
                    // The symmetric 3 x 3 system solved by its adjugate, for the tensor scaled to
                    // a trace of 1 (its determinant, the cube of its size, would underflow for a
                    // block of 1e-100 m).
                    const double t = ib.trace(), u = 1.0 / t;
                    const double i00 = ib(0, 0) * u, i11 = ib(1, 1) * u, i22 = ib(2, 2) * u;
                    const double i01 = ib(0, 1) * u, i02 = ib(0, 2) * u, i12 = ib(1, 2) * u;
                    const double c00 = i11 * i22 - i12 * i12, c01 = i02 * i12 - i01 * i22, c02 = i01 * i12 - i02 * i11;
                    const double c11 = i00 * i22 - i02 * i02, c12 = i01 * i02 - i00 * i12, c22 = i00 * i11 - i01 * i01;
                    const double det = i00 * c00 + i01 * c01 + i02 * c02;
                    const Vec3 x(c00 * mb.x() + c01 * mb.y() + c02 * mb.z(), c01 * mb.x() + c11 * mb.y() + c12 * mb.z(),
                                 c02 * mb.x() + c12 * mb.y() + c22 * mb.z());
                    // (The determinant, at most 1/27, and the size apart: their product could be
                    // below the least double for a block of 1e-300 kg m^2.)
                    alpha = r * ((x * (1.0 / det)) * (1.0 / (ratio * t)));
                }
            }
            const Vec3 w = s.ang_vel[b] + alpha * kick;
            if (auto_damp) {
                for (int i = 0; i < 3; ++i) sums.add(diag[i], s.moment[b][i], s.ang_vel[b][i], w[i]);
            }
            if (account) {
                const Mat3 r = s.orientation[b].toRotationMatrix();
                energy_rotation(ce[chunk], r * s.inertia_body[b] * r.transpose(), s.moment[b], mom, load_m, s.ang_vel[b],
                                w, s.half_kick[b] != 0, dt);
            }
            s.ang_vel[b] = w;
            s.ang_accel[b] = alpha;
            const Vec3 dtheta = w * dt;
            const double t2 = dtheta.squaredNorm();
            if (t2 > 0) {
                double sin_h_over, cos_h;
                half_turn(t2, sin_h_over, cos_h);
                const Vec3 v = dtheta * sin_h_over;
                const Quat q = Quat(cos_h, v.x(), v.y(), v.z()) * s.orientation[b];
                // Unit again: the product of two unit quaternions is one to a few bits, which a
                // Newton step for 1 / |q| mends (no root, no division); anything else is divided.
                const double n2 = q.squaredNorm();
                const double scale = std::abs(n2 - 1) < 1e-8 ? 1.5 - 0.5 * n2 : 1.0 / std::sqrt(n2);
                s.orientation[b] = Quat(q.coeffs() * scale);
            }
            s.half_kick[b] = 0;
            // Not finite: the integration has become unstable.
            if (bad < 0 && !(v.allFinite() && w.allFinite() && s.centroid[b].allFinite())) {
                bad = b;
            }
        }
        if (n_plain > 0) {
            // (The first in the chunk's order, as the loop above would have found it.)
            const int bad_plain = integrate_plain_blocks(s, rotation_of, plain, n_plain, off, d.local, dt);
            if (bad_plain >= 0 && (bad < 0 || bad_plain < bad)) bad = bad_plain;
        }
    });
    int bad = -1;
    for (int chunk = 0; chunk < n_chunks; ++chunk) {
        if (auto_damp) sums->add(cp[chunk]);
        if (bad < 0) bad = cb[chunk];
    }
    EnergyStep energy;
    if (account) {
        for (int chunk = 0; chunk < n_chunks; ++chunk) energy.add(ce[chunk]);
    }
    {
        thread_local ClumpList clumps;
        list_clumps(s, clumps);
        if (clumps.size() > 0) {
            const int bad_clump =
                integrate_clumps(m, clumps, dt, account ? &energy : nullptr, sums);
            if (bad < 0) bad = bad_clump;
        }
    }
    const int bad_gp = integrate_gridpoints(m, d, dt, sums, account ? &energy : nullptr);
    if (bad < 0 && bad_gp >= 0) bad = m.gridpoints.block[bad_gp];
    if (account) add_energy_step(m, energy);
    return bad;
}

int integrate_gridpoints(Model& m, const Damping& d, double dt, AutoDampingSums* sums, EnergyStep* energy) {
    GridpointSet& g = m.gridpoints;
    const int ng = g.size();
    // Fixed chunks, whatever the number of threads: their sums are added in order (parallel.h).
    constexpr int kChunk = 2048;
    const int n_chunks = (ng + kChunk - 1) / kChunk;
    thread_local std::vector<AutoDampingSums> chunk_sums;
    thread_local std::vector<int> chunk_bad;
    chunk_sums.assign(n_chunks, AutoDampingSums{});
    chunk_bad.assign(n_chunks, -1);
    AutoDampingSums* cs = chunk_sums.data();
    int* cb = chunk_bad.data();
    thread_local std::vector<EnergyStep> chunk_energy;
    if (energy) chunk_energy.assign(n_chunks, EnergyStep{});
    EnergyStep* ce = chunk_energy.data();
    const Vec3 grav = m.gravity;
    const bool gather = sums != nullptr;
    const int threads = thread_count();
    parallel_for(n_chunks, threads, ng >= kParallelMinItems, [&](int chunk) {
        const int hi = std::min(ng, (chunk + 1) * kChunk);
        AutoDampingSums part;
        int bad = -1;
        for (int i = chunk * kChunk; i < hi; ++i) {
            const double mass = g.inertial_mass[i];
            if (!(g.mass[i] > 0) || !(mass > 0)) {
                // Only null zones around it: it does not move.
                g.vel[i].setZero();
                continue;
            }
            const double kick = g.half_kick[i] ? 0.5 * dt : dt;
            const double scale = g.vel_bc[i] ? m.table_factor(g.vel_bc_table[i]) : 1.0;
            Vec3 v;
            for (int k = 0; k < 3; ++k) {
                if (g.vel_bc[i] & (1 << k)) {
                    v[k] = g.vel_bc_value[i][k] * scale;
                    if (energy) {
                        energy_dof(ce[chunk], g.mass[i], g.mass[i] * grav[k], g.applied[i][k] + g.traction[i][k],
                                   g.force[i][k], g.force[i][k], g.vel[i][k], v[k], true, false, dt);
                    }
                    continue;
                }
                const double f = g.force[i][k], vk = g.vel[i][k];
                const double fd = damped_force(d, f, vk, mass, dt);
                v[k] = vk + fd / mass * kick;
                if (gather) part.add(mass, f, vk, v[k]);
                if (energy) {
                    energy_dof(ce[chunk], g.mass[i], g.mass[i] * grav[k], g.applied[i][k] + g.traction[i][k], f, fd,
                               vk, v[k], false, g.half_kick[i] != 0, dt);
                }
            }
            g.vel[i] = v;
            const Vec3 dx = v * dt;
            g.pos[i] += dx;
            g.disp[i] += dx;
            g.half_kick[i] = 0;
            if (bad < 0 && !(v.allFinite() && g.pos[i].allFinite())) bad = i;
        }
        cs[chunk] = part;
        cb[chunk] = bad;
    });
    int bad = -1;
    for (int chunk = 0; chunk < n_chunks; ++chunk) {
        if (energy) energy->add(ce[chunk]);
        if (gather) sums->add(cs[chunk]);
        if (bad < 0) bad = cb[chunk];
    }
    return bad;
}


} // namespace odec
