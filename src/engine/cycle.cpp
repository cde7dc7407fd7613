#include "engine/cycle.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "engine/blocks.h"
#include "engine/contact.h"

namespace odec {

namespace {

using Clock = std::chrono::steady_clock;

struct StageTimer {
    Profile& p;
    Stage s;
    Clock::time_point t0 = Clock::now();
    ~StageTimer() {
        p.seconds[static_cast<int>(s)] += std::chrono::duration<double>(Clock::now() - t0).count();
    }
};

double sign(double x) { return (x > 0) - (x < 0); }

// (m/s)^2: a block moving faster than 1e5 m/s means the numbers have run away.
constexpr double kMaxSpeed2 = 1e10;

bool is_active(const BlockSet& s, int b) { return !(s.flags[b] & kExcavated); }

void apply_loads(Model& m) {
    BlockSet& s = m.blocks;
    for (int b = 0; b < s.size(); ++b) {
        const Vec3 w = s.mass[b] * m.gravity;
        s.force[b] = w + s.applied_force[b];
        s.moment[b].setZero();
        s.force_scale[b] = w.norm() + s.applied_force[b].norm();
    }
}

// Damped force component f acting on a degree of freedom moving at v.
inline double damp_component(const Damping& d, double f, double v, double mass, double dt) {
    switch (d.mode) {
    case DampingMode::Local: return f - d.local * std::abs(f) * sign(v);
    case DampingMode::Auto: return f - d.auto_coefficient * mass * v;
    case DampingMode::Rayleigh: {
        // Mass-proportional part of Rayleigh damping: c = 2 xi omega m.
        const double c = 2.0 * d.rayleigh_fraction * 2.0 * M_PI * d.rayleigh_frequency * mass;
        return f - c * v;
    }
    case DampingMode::Off: break;
    }
    (void)dt;
    return f;
}

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

// Returns the index of a block whose motion became non-finite, or -1.
int integrate(Model& m, double dt) {
    BlockSet& s = m.blocks;
    const Damping& d = m.damping;
    const bool auto_damp = d.mode == DampingMode::Auto;
    if (auto_damp && !(m.damping.auto_coefficient > 0)) m.damping.auto_coefficient = 0.02 / dt;
    AutoDampingPower power;
    int bad = -1;
    for (int b = 0; b < s.size(); ++b) {
        if (!is_active(s, b)) continue;
        if (s.flags[b] & kFixed) {
            // Held still, except for the velocity components a boundary condition drives
            // (the fixed base of a shake table moves as its table says, without turning).
            Vec3 v = Vec3::Zero();
            if (s.vel_bc[b]) {
                double scale = 1.0;
                if (s.vel_bc_table[b] > 0) {
                    const Table* t = m.tables.find(s.vel_bc_table[b]);
                    scale = t ? t->at(m.time) : 0.0;
                }
                for (int i = 0; i < 3; ++i) {
                    if (s.vel_bc[b] & (1 << i)) v[i] = s.vel_bc_value[b][i] * scale;
                }
                const Vec3 dx = v * dt;
                s.centroid[b] += dx;
                s.disp[b] += dx;
            }
            s.vel[b] = v;
            s.ang_vel[b].setZero();
            s.accel[b].setZero();
            s.ang_accel[b].setZero();
            s.half_kick[b] = 0;
            continue;
        }
        const double mass = s.mass[b];
        const double kick = s.half_kick[b] ? 0.5 * dt : dt;
        if (auto_damp) {
            power.damping += mass * s.vel[b].squaredNorm();
            power.forcing += std::abs(s.force[b].dot(s.vel[b])) + std::abs(s.moment[b].dot(s.ang_vel[b]));
        }
        // Translation.
        Vec3 a;
        for (int i = 0; i < 3; ++i) {
            a[i] = damp_component(d, s.force[b][i], s.vel[b][i], mass, dt) / mass;
        }
        Vec3 v = s.vel[b] + a * kick;
        if (s.vel_bc[b]) {
            double scale = 1.0;
            if (s.vel_bc_table[b] > 0) {
                const Table* t = m.tables.find(s.vel_bc_table[b]);
                scale = t ? t->at(m.time) : 0.0;
            }
            for (int i = 0; i < 3; ++i) {
                if (s.vel_bc[b] & (1 << i)) {
                    v[i] = s.vel_bc_value[b][i] * scale;
                    a[i] = 0;
                }
            }
        }
        s.vel[b] = v;
        s.accel[b] = a;
        const Vec3 dx = v * dt;
        s.centroid[b] += dx;
        s.disp[b] += dx;
        // Rotation: angular acceleration from the world inertia tensor (gyroscopic term
        // neglected, as usual for quasi-static block analysis).
        const Mat3 r = s.orientation[b].toRotationMatrix();
        const Mat3 inertia = r * s.inertia_body[b] * r.transpose();
        Vec3 mom;
        for (int i = 0; i < 3; ++i) {
            mom[i] = damp_component(d, s.moment[b][i], s.ang_vel[b][i], inertia(i, i), dt);
        }
        if (auto_damp) power.damping += s.ang_vel[b].dot(inertia.diagonal().cwiseProduct(s.ang_vel[b]));
        const Vec3 alpha = inertia.ldlt().solve(mom);
        const Vec3 w = s.ang_vel[b] + alpha * kick;
        s.ang_vel[b] = w;
        s.ang_accel[b] = alpha;
        const Vec3 dtheta = w * dt;
        const double angle = dtheta.norm();
        if (angle > 0) {
            s.orientation[b] = (Quat(Eigen::AngleAxisd(angle, dtheta / angle)) * s.orientation[b]).normalized();
            s.rotation[b] += dtheta;
        }
        s.half_kick[b] = 0;
        // Not finite, or faster than anything rock can move: the integration has become unstable.
        if (bad < 0 && !(v.allFinite() && w.allFinite() && s.centroid[b].allFinite() && v.squaredNorm() < kMaxSpeed2)) {
            bad = b;
        }
    }
    if (auto_damp) adjust_auto_damping(m.damping, power, m.step, dt);
    return bad;
}

} // namespace

double max_unbalanced_force(const Model& m) {
    const BlockSet& s = m.blocks;
    double fmax = 0;
    for (int b = 0; b < s.size(); ++b) {
        if (!is_active(s, b) || (s.flags[b] & kFixed)) continue;
        Vec3 f = s.force[b];
        for (int i = 0; i < 3; ++i) {
            if (s.vel_bc[b] & (1 << i)) f[i] = 0;
        }
        fmax = std::max(fmax, f.norm());
    }
    return fmax;
}

double unbalanced_ratio(const Model& m) {
    const BlockSet& s = m.blocks;
    double unbal = 0, total = 0;
    for (int b = 0; b < s.size(); ++b) {
        if (!is_active(s, b) || (s.flags[b] & kFixed)) continue;
        unbal += s.force[b].norm();
        total += s.force_scale[b];
    }
    return total > 0 ? unbal / total : 0.0;
}

std::string prepare_cycle(Model& m) {
    const BlockSet& s = m.blocks;
    for (int b = 0; b < s.size(); ++b) {
        if (!is_active(s, b) || (s.flags[b] & kFixed)) continue;
        if (!(s.mass[b] > 0)) {
            const int mat = s.material[b];
            const bool defined = mat > 0 && mat < static_cast<int>(m.materials.size()) && m.materials[mat].defined;
            return "block " + std::to_string(s.id[b]) + " has no mass: " +
                   (defined ? "material " + std::to_string(mat) + " has no density"
                            : "material " + std::to_string(mat) + " is not defined") +
                   " (give one with 'prop mat=" + std::to_string(mat) + " dens=...')";
        }
    }
    if (m.geometry_changed) {
        refresh_world_vertices(m);
        detect_contacts(m);
    }
    if (m.settings.dt_fixed > 0) {
        m.dt = m.settings.dt_fixed;
    } else {
        const double dt = contact_critical_timestep(m);
        if (!(dt > 0)) {
            return "no timestep: there are no contacts to set one, so give it with 'set dt'";
        }
        m.dt = dt;
    }
    // Contacts and timestep now match the geometry; the cycle need not prepare again.
    m.geometry_changed = false;
    return "";
}

CycleResult cycle(Model& m, const CycleLimits& lim, const std::atomic<bool>* interrupt,
                  const ProgressFn& progress, long progress_every) {
    CycleResult res;
    const std::string problem = prepare_cycle(m);
    if (!problem.empty()) {
        res.reason = StopReason::Error;
        res.message = problem;
        return res;
    }
    const double t_start = m.time;
    Profile& prof = m.profile;
    for (;;) {
        if (lim.max_steps > 0 && res.steps >= lim.max_steps) {
            res.reason = StopReason::Steps;
            break;
        }
        if (lim.max_time > 0 && m.time - t_start >= lim.max_time * (1 - 1e-12)) {
            res.reason = StopReason::Time;
            break;
        }
        if (interrupt && interrupt->load(std::memory_order_relaxed)) {
            res.reason = StopReason::Interrupted;
            break;
        }
        if (m.geometry_changed) {
            const std::string p = prepare_cycle(m);
            if (!p.empty()) {
                res.reason = StopReason::Error;
                res.message = p;
                break;
            }
        }
        {
            StageTimer t{prof, Stage::ApplyLoads};
            apply_loads(m);
        }
        {
            StageTimer t{prof, Stage::DetectContacts};
            detect_contacts(m);
        }
        {
            StageTimer t{prof, Stage::UpdateContacts};
            update_contacts(m, m.dt);
        }
        int bad;
        {
            StageTimer t{prof, Stage::Integrate};
            bad = integrate(m, m.dt);
            refresh_world_vertices(m);
        }
        m.time += m.dt;
        ++m.step;
        ++res.steps;
        ++prof.steps;
        {
            StageTimer t{prof, Stage::Record};
            if (m.histories.ncyc > 0 && m.step % m.histories.ncyc == 0) m.histories.sample(m);
        }
        if (bad >= 0) {
            res.reason = StopReason::BlowUp;
            res.message = "the motion of block " + std::to_string(m.blocks.id[bad]) +
                          " has run away (step " + std::to_string(m.step) +
                          "): the timestep is too large for the stiffnesses, or a load is unbounded";
            break;
        }
        if (progress && progress_every > 0 && res.steps % progress_every == 0) progress(m);
        if (lim.ratio > 0 && unbalanced_ratio(m) < lim.ratio) {
            res.reason = StopReason::Ratio;
            break;
        }
    }
    return res;
}

} // namespace odec
