// The integration stage: central differences for rigid blocks and gridpoints, under one
// damping law (see cycle.h for the law, mass_scaling.h for the masses).
#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/clump.h"
#include "engine/energy.h"
#include "engine/mass_scaling.h"
#include "engine/parallel.h"
#include "engine/stages.h"
#include "engine/table.h"

namespace odec {

namespace {

// Adaptive global damping (Cundall's auto damping): a viscous coefficient c (1/s, force
// c m v) that is nudged every few steps so that the power the damping absorbs stays at
// half the rate at which the unbalanced forces change the kinetic energy. When the model
// still moves with purpose (kinetic energy changing fast) the damping rises to follow;
// as it settles and the forces balance, it eases off, so it never freezes a real motion
// the way a fixed heavy damping would. Explicit viscous damping needs c dt < 2; it is
// kept well inside that.
struct AutoDampingPower {
    double damping = 0; // W per unit c: sum of m v.v (and I w.w)
    double forcing = 0; // W: sum of |f.v| (and |M.w|), the undamped change of kinetic energy
};

void adjust_auto_damping(Damping& d, const AutoDampingPower& p, long step, double dt) {
    const double c_max = 0.5 / dt, c_min = 1e-4 / dt;
    if (!(d.auto_coefficient > 0)) d.auto_coefficient = 0.02 / dt;
    if (step % 5 != 0 || !(p.forcing > 0)) return;
    const double ratio = d.auto_coefficient * p.damping / p.forcing;
    d.auto_coefficient *= ratio < 0.5 ? 1.05 : 1.0 / 1.05;
    d.auto_coefficient = std::clamp(d.auto_coefficient, c_min, c_max);
}

} // namespace

int integrate(Model& m, double dt) {
    BlockSet& s = m.blocks;
    // One damping law for blocks and gridpoints.
    const Damping& d = m.damping;
    const bool auto_damp = d.mode == DampingMode::Auto;
    if (auto_damp && !(m.damping.auto_coefficient > 0)) m.damping.auto_coefficient = 0.02 / dt;
    AutoDampingPower total;
    // Static mode: the blocks' masses follow their joints as they are this step.
    if (!m.settings.dynamic) scale_block_masses(m, true);
    // Fixed chunks of blocks, whatever the number of threads: their sums are added in order.
    constexpr int kChunk = 512;
    const int nb = s.size();
    const int n_chunks = (nb + kChunk - 1) / kChunk;
    thread_local std::vector<AutoDampingPower> chunk_power;
    thread_local std::vector<int> chunk_bad;
    chunk_power.assign(n_chunks, AutoDampingPower{});
    chunk_bad.assign(n_chunks, -1);
    AutoDampingPower* cp = chunk_power.data();
    int* cb = chunk_bad.data();
    // The energy account (energy.h): each step's increments by chunk, added in order.
    const bool account = m.energy.on;
    thread_local std::vector<EnergyStep> chunk_energy;
    if (account) chunk_energy.assign(n_chunks, EnergyStep{});
    EnergyStep* ce = chunk_energy.data();
    const Vec3 grav = m.gravity;
    const int threads = thread_count();
    parallel_for(n_chunks, threads, nb >= kParallelMinBlocks, [&](int chunk) {
        AutoDampingPower& power = cp[chunk];
        int& bad = cb[chunk];
        for (int b = chunk * kChunk; b < std::min(nb, (chunk + 1) * kChunk); ++b) {
            // The pieces of a clump move together, after the blocks alone (clump.h).
            if (!is_rigid_active(s, b) || s.clump[b] != 0) continue;
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
            if (auto_damp) {
                power.damping += mass * s.vel[b].squaredNorm();
                power.forcing += std::abs(s.force[b].dot(s.vel[b])) + std::abs(s.moment[b].dot(s.ang_vel[b]));
            }
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
            // Rotation: angular acceleration from the world inertia tensor (gyroscopic term
            // neglected, as usual for quasi-static block analysis).
            // Static mode gives an isotropic inertia chosen from the joints (mass_scaling.h).
            const double iso = s.inertial_moment[b];
            Mat3 inertia;
            if (iso > 0) {
                inertia = iso * Mat3::Identity();
            } else {
                const Mat3 r = s.orientation[b].toRotationMatrix();
                inertia = (mass / s.mass[b]) * (r * s.inertia_body[b] * r.transpose());
            }
            Vec3 mom;
            for (int i = 0; i < 3; ++i) {
                mom[i] = damped_force(d, s.moment[b][i], s.ang_vel[b][i], inertia(i, i), dt);
            }
            if (auto_damp) power.damping += s.ang_vel[b].dot(inertia.diagonal().cwiseProduct(s.ang_vel[b]));
            // The 3 x 3 inverse in closed form, of the tensor scaled to a trace of 1 (its
            // determinant, the cube of its size, would underflow for a block of 1e-100 m).
            Vec3 alpha;
            if (iso > 0) {
                alpha = mom / iso;
            } else {
                const double t = inertia.trace();
                alpha = (inertia / t).inverse() * (mom / t);
            }
            const Vec3 w = s.ang_vel[b] + alpha * kick;
            if (account) {
                const Mat3 r = s.orientation[b].toRotationMatrix();
                energy_rotation(ce[chunk], r * s.inertia_body[b] * r.transpose(), s.moment[b], mom, load_m, s.ang_vel[b],
                                w, s.half_kick[b] != 0, dt);
            }
            s.ang_vel[b] = w;
            s.ang_accel[b] = alpha;
            const Vec3 dtheta = w * dt;
            const double angle = dtheta.norm();
            if (angle > 0) {
                s.orientation[b] = (Quat(Eigen::AngleAxisd(angle, dtheta / angle)) * s.orientation[b]).normalized();
            }
            s.half_kick[b] = 0;
            // Not finite: the integration has become unstable.
            if (bad < 0 && !(v.allFinite() && w.allFinite() && s.centroid[b].allFinite())) {
                bad = b;
            }
        }
    });
    int bad = -1;
    for (int chunk = 0; chunk < n_chunks; ++chunk) {
        total.damping += cp[chunk].damping;
        total.forcing += cp[chunk].forcing;
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
            const int bad_clump = integrate_clumps(m, clumps, dt, account ? &energy : nullptr,
                                                   auto_damp ? &total.damping : nullptr, &total.forcing);
            if (bad < 0) bad = bad_clump;
        }
    }
    const int bad_gp = integrate_gridpoints(m, d, dt, auto_damp ? &total.damping : nullptr, &total.forcing,
                                            account ? &energy : nullptr);
    if (bad < 0 && bad_gp >= 0) bad = m.gridpoints.block[bad_gp];
    if (account) add_energy_step(m, energy);
    if (auto_damp) adjust_auto_damping(m.damping, total, m.step, dt);
    return bad;
}

int integrate_gridpoints(Model& m, const Damping& d, double dt, double* damping_power, double* forcing_power,
                         EnergyStep* energy) {
    GridpointSet& g = m.gridpoints;
    const int ng = g.size();
    // Fixed chunks, whatever the number of threads: their sums are added in order (parallel.h).
    constexpr int kChunk = 2048;
    const int n_chunks = (ng + kChunk - 1) / kChunk;
    thread_local std::vector<double> chunk_damping, chunk_forcing;
    thread_local std::vector<int> chunk_bad;
    chunk_damping.assign(n_chunks, 0.0);
    chunk_forcing.assign(n_chunks, 0.0);
    chunk_bad.assign(n_chunks, -1);
    double* cd = chunk_damping.data();
    double* cf = chunk_forcing.data();
    int* cb = chunk_bad.data();
    thread_local std::vector<EnergyStep> chunk_energy;
    if (energy) chunk_energy.assign(n_chunks, EnergyStep{});
    EnergyStep* ce = chunk_energy.data();
    const Vec3 grav = m.gravity;
    const bool power = damping_power != nullptr;
    const int threads = thread_count();
    parallel_for(n_chunks, threads, ng >= kParallelMinItems, [&](int chunk) {
        const int hi = std::min(ng, (chunk + 1) * kChunk);
        double pd = 0, pf = 0;
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
                double fd = f;
                switch (d.mode) {
                case DampingMode::Local: fd = f - d.local * std::abs(f) * sign(vk); break;
                case DampingMode::Auto: fd = f - d.auto_coefficient * mass * vk; break;
                case DampingMode::Rayleigh:
                    fd = f - 2.0 * d.rayleigh_fraction * 2.0 * M_PI * d.rayleigh_frequency * mass * vk;
                    break;
                case DampingMode::Off: break;
                }
                v[k] = vk + fd / mass * kick;
                if (energy) {
                    energy_dof(ce[chunk], g.mass[i], g.mass[i] * grav[k], g.applied[i][k] + g.traction[i][k], f, fd,
                               vk, v[k], false, g.half_kick[i] != 0, dt);
                }
            }
            if (power) {
                pd += mass * g.vel[i].squaredNorm();
                pf += std::abs(g.force[i].dot(g.vel[i]));
            }
            g.vel[i] = v;
            const Vec3 dx = v * dt;
            g.pos[i] += dx;
            g.disp[i] += dx;
            g.half_kick[i] = 0;
            if (bad < 0 && !(v.allFinite() && g.pos[i].allFinite())) bad = i;
        }
        cd[chunk] = pd;
        cf[chunk] = pf;
        cb[chunk] = bad;
    });
    int bad = -1;
    for (int chunk = 0; chunk < n_chunks; ++chunk) {
        if (energy) energy->add(ce[chunk]);
        if (power) {
            *damping_power += cd[chunk];
            *forcing_power += cf[chunk];
        }
        if (bad < 0) bad = cb[chunk];
    }
    return bad;
}


} // namespace odec
