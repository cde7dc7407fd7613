#include "engine/cycle.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/contact_gridpoint.h"
#include "engine/mass_scaling.h"

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

std::string num_text(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", x);
    return buf;
}

bool is_active(const BlockSet& s, int b) { return !(s.flags[b] & kExcavated); }
// A rigid block that moves as a whole (not excavated, not divided into zones).
bool is_rigid_active(const BlockSet& s, int b) { return !(s.flags[b] & (kExcavated | kDeformable)); }

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
    // One damping law for blocks and gridpoints.
    const Damping& d = m.damping;
    const bool auto_damp = d.mode == DampingMode::Auto;
    if (auto_damp && !(m.damping.auto_coefficient > 0)) m.damping.auto_coefficient = 0.02 / dt;
    AutoDampingPower power;
    int bad = -1;
    // Static mode: the blocks' masses follow their joints as they are this step.
    if (!m.settings.dynamic) scale_block_masses(m);
    for (int b = 0; b < s.size(); ++b) {
        if (!is_rigid_active(s, b)) continue;
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
            a[i] = damp_component(d, s.force[b][i], s.vel[b][i], mass, dt) / mass;
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
            mom[i] = damp_component(d, s.moment[b][i], s.ang_vel[b][i], inertia(i, i), dt);
        }
        if (auto_damp) power.damping += s.ang_vel[b].dot(inertia.diagonal().cwiseProduct(s.ang_vel[b]));
        const Vec3 alpha = iso > 0 ? Vec3(mom / iso) : Vec3(inertia.ldlt().solve(mom));
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
        // Not finite: the integration has become unstable.
        if (bad < 0 && !(v.allFinite() && w.allFinite() && s.centroid[b].allFinite())) {
            bad = b;
        }
    }
    const int bad_gp = integrate_gridpoints(m, d, dt, auto_damp ? &power.damping : nullptr, &power.forcing);
    if (bad < 0 && bad_gp >= 0) bad = m.gridpoints.block[bad_gp];
    if (auto_damp) adjust_auto_damping(m.damping, power, m.step, dt);
    return bad;
}

// Kinetic energy of a free block, J (velocities at t - dt/2), leaving out the velocity
// components a boundary condition prescribes: those are imposed, not earned.
double kinetic_energy(const BlockSet& s, int b) {
    const Vec3 w = s.ang_vel[b];
    Vec3 v = s.vel[b];
    for (int i = 0; i < 3; ++i) {
        if (s.vel_bc[b] & (1 << i)) v[i] = 0;
    }
    // With the masses the integration uses: what the forces' work turns into (mass_scaling.h).
    const double mass = s.inertial_mass[b];
    double spin;
    if (s.inertial_moment[b] > 0) {
        spin = s.inertial_moment[b] * w.squaredNorm();
    } else {
        const Mat3 r = s.orientation[b].toRotationMatrix();
        spin = (mass / s.mass[b]) * w.dot(r * s.inertia_body[b] * r.transpose() * w);
    }
    return 0.5 * mass * v.squaredNorm() + 0.5 * spin;
}

// The likely cause of a run-away of block b, for the message.
std::string runaway_cause(const Model& m, int b) {
    std::string cause = m.settings.dt_fixed > 0
                            ? "the forced timestep (set dt " + num_text(m.settings.dt_fixed) +
                                  ") is too large for the stiffnesses: try 'set dt auto'"
                            : "the timestep is too large for the stiffnesses";
    const Vec3& f = m.blocks.applied_force[b];
    if (f.squaredNorm() > 0) {
        cause = "the load applied to block " + std::to_string(m.blocks.id[b]) + " ('bound ...load', " +
                num_text(f.stableNorm()) + " N) is too large for what holds it, or " + cause;
    } else if (m.settings.dt_fixed <= 0) {
        cause += ", or a load is unbounded";
    }
    return cause;
}

// A run-away told by the physics rather than by a speed: with damping at most taking energy
// out, the kinetic energy of the free blocks can never exceed what the model had when the
// cycling began (kinetic energy and the strain energy stored in the joints) plus the work
// the loads have done since (gravity and applied forces on the free blocks: their force
// times the displacement, exact as both are constant while cycling) plus the work the
// velocity boundaries can have done (bounded by |force . velocity| dt summed). A numerical
// instability pumps energy in from nowhere, growing it geometrically, so a generous margin
// still stops it within a few steps of its start, long before numbers overflow.
struct EnergyWatch {
    std::vector<Vec3> start;   // (n_blocks) centroid when the cycling began
    std::vector<double> size;  // (n_blocks) m, largest vertex distance from the centroid
    bool neighbours = false;   // more than one block: there is something to pass through
    double initial = 0;        // J, kinetic + joint strain energy then
    double boundary_work = 0;  // J, bound on the work of prescribed velocities since
    double peak_work = 0;      // J, the most work gravity and the applied loads have done
    double floor = 0;          // J, noise level below which nothing is judged
    static constexpr double kMargin = 4.0;

    // Kinetic energy of the free blocks, J.
    double kinetic(const Model& m) const {
        const BlockSet& s = m.blocks;
        double e = 0;
        for (int b = 0; b < s.size(); ++b) {
            if ((s.flags[b] & (kExcavated | kFixed)) || !(s.mass[b] > 0)) continue;
            e += kinetic_energy(s, b);
        }
        return e;
    }
    // Energy given to the blocks from outside the cycle (by FISH between steps).
    void given(double energy) {
        if (energy > 0 && std::isfinite(energy)) initial += energy;
    }
    // Whether the blocks changed in number since begin(): the arrays no longer match.
    bool stale(const Model& m) const { return start.size() != static_cast<size_t>(m.blocks.size()); }

    void begin(const Model& m) {
        const BlockSet& s = m.blocks;
        start = s.centroid;
        size.assign(s.size(), 0.0);
        int active = 0;
        for (int b = 0; b < s.size(); ++b) {
            for (const Vec3& v : s.shape[b].vertices) size[b] = std::max(size[b], v.norm());
            if (!(s.flags[b] & kExcavated)) ++active;
        }
        neighbours = active > 1;
        initial = 0;
        double mass = 0;
        for (int b = 0; b < s.size(); ++b) {
            if ((s.flags[b] & (kExcavated | kFixed)) || !(s.mass[b] > 0)) continue;
            initial += kinetic_energy(s, b);
            mass += s.inertial_mass[b];
        }
        const ContactSet& cs = m.contacts;
        const int n_jmat = static_cast<int>(m.joint_materials.size());
        for (int c = 0; c < cs.size(); ++c) {
            const int jm = cs.jmat[c];
            if (jm <= 0 || jm >= n_jmat || !m.joint_materials[jm].defined) continue;
            const JointMaterial& j = m.joint_materials[jm];
            for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
                const double u = cs.sub_un[k] + cs.sub_udil[k];
                double un = u > 0 ? u : (cs.joined[c] ? -u : std::min(-u, j.kn > 0 ? j.tension / j.kn : 0.0));
                if (!(un >= 0)) un = 0;
                double e = 0.5 * j.kn * un * un;
                if (j.ks > 0) e += 0.5 * cs.sub_ss[k].squaredNorm() / j.ks;
                initial += cs.sub_area[k] * e;
            }
        }
        boundary_work = 0;
        peak_work = 0;
        // A millimetre per second over all the free mass: below it, nothing is judged.
        floor = 0.5 * mass * 1e-6;
    }

    // After a step: the block whose motion ran away, or -1. `energy` and `available`
    // receive the totals.
    // The contact whose closure has gone deeper than half the smaller of its two blocks (one
    // block is passing through the other), or -1; `depth` receives that closure.
    int sunk(const Model& m, double& depth) const {
        const ContactSet& cs = m.contacts;
        for (int c = 0; c < cs.size(); ++c) {
            const int a = cs.block_a[c], b = cs.block_b[c];
            const double limit = 0.5 * std::min(size[a], size[b]);
            for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
                if (cs.sub_un[k] > limit) {
                    depth = cs.sub_un[k];
                    return c;
                }
            }
        }
        return -1;
    }

    int check(const Model& m, double& energy, double& available, int& jumper) {
        jumper = -1;
        const BlockSet& s = m.blocks;
        double work = 0, ke = 0, ke_max = -1;
        int worst = -1;
        for (int b = 0; b < s.size(); ++b) {
            if (s.flags[b] & kExcavated) continue;
            if (s.vel_bc[b]) {
                const Vec3 load = s.mass[b] * m.gravity + s.applied_force[b];
                boundary_work += m.dt * (std::abs(s.force[b].dot(s.vel[b])) + std::abs(load.dot(s.vel[b])));
            }
            if ((s.flags[b] & kFixed) || !(s.mass[b] > 0)) continue;
            // Moving more than half its size in one step, a block jumps past the blocks in
            // its way: contact detection cannot see them.
            if (jumper < 0 && neighbours && s.vel[b].stableNorm() * m.dt > 0.5 * size[b]) jumper = b;
            const double e = kinetic_energy(s, b);
            ke += e;
            if (!(e <= ke_max)) {
                ke_max = e;
                worst = b;
            }
            work += (s.mass[b] * m.gravity + s.applied_force[b]).dot(s.centroid[b] - start[b]);
        }
        energy = ke;
        // The most work the loads have done at any time: the energy they put in may have been
        // carried back up since (an undamped block bouncing), and explicit impacts do not
        // conserve energy exactly, so the budget is the largest the exchange has been.
        peak_work = std::max(peak_work, work);
        available = initial + peak_work + boundary_work;
        if (std::isfinite(ke) && ke <= kMargin * available + floor && jumper < 0) return -1;
        return worst;
    }
};

} // namespace

double max_unbalanced_force(const Model& m) {
    const BlockSet& s = m.blocks;
    double fmax = 0;
    for (int b = 0; b < s.size(); ++b) {
        if (!is_rigid_active(s, b) || (s.flags[b] & kFixed)) continue;
        Vec3 f = s.force[b];
        for (int i = 0; i < 3; ++i) {
            if (s.vel_bc[b] & (1 << i)) f[i] = 0;
        }
        fmax = std::max(fmax, f.norm());
    }
    const GridpointSet& g = m.gridpoints;
    for (int i = 0; i < g.size(); ++i) {
        if (!(g.mass[i] > 0) || g.vel_bc[i] == 7) continue;
        Vec3 f = g.force[i];
        for (int k = 0; k < 3; ++k) {
            if (g.vel_bc[i] & (1 << k)) f[k] = 0;
        }
        fmax = std::max(fmax, f.norm());
    }
    return fmax;
}

double unbalanced_ratio(const Model& m) {
    const BlockSet& s = m.blocks;
    double unbal = 0, total = 0;
    for (int b = 0; b < s.size(); ++b) {
        if (!is_rigid_active(s, b) || (s.flags[b] & kFixed)) continue;
        unbal += s.force[b].norm();
        total += s.force_scale[b];
    }
    const GridpointSet& g = m.gridpoints;
    for (int i = 0; i < g.size(); ++i) {
        if (!(g.mass[i] > 0) || g.vel_bc[i] == 7) continue;
        Vec3 f = g.force[i];
        for (int k = 0; k < 3; ++k) {
            if (g.vel_bc[i] & (1 << k)) f[k] = 0;
        }
        unbal += f.norm();
        total += g.force_scale[i];
    }
    return total > 0 ? unbal / total : 0.0;
}

namespace {

// What preparing a cycle changes (contact detection and the timestep), kept so that a
// cycle refused before its first step leaves the model exactly as it was.
struct PrepareUndo {
    bool saved = false;
    ContactSet contacts;
    std::vector<int> vertex_offset;
    std::vector<Vec3> world_vertices;
    double dt = 0;
    bool geometry_changed = false;
    // Choosing the inertial masses may slow velocities down (mass_scaling.h).
    std::vector<double> block_mass, block_moment, gp_mass;
    std::vector<Vec3> vel, ang_vel, gp_vel;
    MassScalingReport report;

    explicit PrepareUndo(const Model& m)
        : dt(m.dt), geometry_changed(m.geometry_changed), block_mass(m.blocks.inertial_mass),
          block_moment(m.blocks.inertial_moment), gp_mass(m.gridpoints.inertial_mass), vel(m.blocks.vel),
          ang_vel(m.blocks.ang_vel), gp_vel(m.gridpoints.vel), report(m.mass_scaling) {
        if (m.geometry_changed) {
            saved = true;
            contacts = m.contacts;
            vertex_offset = m.blocks.vertex_offset;
            world_vertices = m.blocks.world_vertices;
        }
    }
    void undo(Model& m) {
        if (saved) {
            m.contacts = std::move(contacts);
            m.blocks.vertex_offset = std::move(vertex_offset);
            m.blocks.world_vertices = std::move(world_vertices);
        }
        m.dt = dt;
        m.geometry_changed = geometry_changed;
        if (block_mass.size() == m.blocks.inertial_mass.size() && gp_mass.size() == m.gridpoints.inertial_mass.size()) {
            m.blocks.inertial_mass = std::move(block_mass);
            m.blocks.inertial_moment = std::move(block_moment);
            m.blocks.vel = std::move(vel);
            m.blocks.ang_vel = std::move(ang_vel);
            m.gridpoints.inertial_mass = std::move(gp_mass);
            m.gridpoints.vel = std::move(gp_vel);
        }
        m.mass_scaling = report;
    }
};

std::string prepare_cycle_once(Model& m);

} // namespace

std::string prepare_cycle(Model& m) {
    PrepareUndo undo(m);
    std::string problem = prepare_cycle_once(m);
    if (!problem.empty()) undo.undo(m);
    return problem;
}

double real_mass_timestep(Model& m, std::string* why) {
    PrepareUndo undo(m);
    const Settings keep = m.settings;
    m.settings.dynamic = true;
    m.settings.mscale_dt = 0;
    m.settings.dt_fixed = 0;
    const std::string problem = prepare_cycle_once(m);
    const double dt = problem.empty() ? m.mass_scaling.real_dt : 0.0;
    if (why) *why = problem;
    m.settings = keep;
    undo.undo(m);
    return dt;
}

namespace {

std::string prepare_cycle_once(Model& m) {
    const BlockSet& s = m.blocks;
    for (int b = 0; b < s.size(); ++b) {
        if (!is_rigid_active(s, b) || (s.flags[b] & kFixed)) continue;
        if (!(s.mass[b] > 0)) {
            const int mat = s.material[b];
            const bool defined = mat > 0 && mat < static_cast<int>(m.materials.size()) && m.materials[mat].defined;
            return "block " + std::to_string(s.id[b]) + " has no mass: " +
                   (defined ? "material " + std::to_string(mat) + " has no density"
                            : "material " + std::to_string(mat) + " is not defined") +
                   " (give one with 'prop mat=" + std::to_string(mat) + " dens=...')";
        }
    }
    // The loads must be numbers: gravity or a density near the top of the double range
    // makes a weight of inf, which would turn every velocity to NaN in the first step.
    for (int b = 0; b < s.size(); ++b) {
        if (!is_rigid_active(s, b) || (s.flags[b] & kFixed)) continue;
        const Vec3 w = s.mass[b] * m.gravity + s.applied_force[b];
        if (!std::isfinite(s.mass[b]) || !s.inertia_body[b].allFinite() || !w.allFinite()) {
            return "the load on block " + std::to_string(s.id[b]) + " is not a finite number (mass " +
                   num_text(s.mass[b]) + " kg, gravity " + num_text(m.gravity.stableNorm()) + " m/s^2, applied force " +
                   num_text(s.applied_force[b].stableNorm()) + " N): give smaller values";
        }
    }
    {
        const std::string zp = zones_problem(m);
        if (!zp.empty()) return zp;
    }
    if (m.geometry_changed) {
        refresh_world_vertices(m);
        detect_contacts(m);
        update_gridpoint_masses(m);
    }
    // A joint material may be assigned before its properties are given ('change jmat'), but not
    // cycled without them: such a joint would hold nothing.
    {
        const ContactSet& cs = m.contacts;
        const int n_jmat = static_cast<int>(m.joint_materials.size());
        bool any_defined = false;
        for (const JointMaterial& j : m.joint_materials) any_defined = any_defined || j.defined;
        for (int c = 0; c < cs.size() && any_defined; ++c) {
            const int jm = cs.jmat[c];
            if (jm > 0 && (jm >= n_jmat || !m.joint_materials[jm].defined)) {
                return "contact " + std::to_string(cs.id[c]) + " has joint material " + std::to_string(jm) +
                       ", which has no properties: give them with 'prop jmat=" + std::to_string(jm) + " jkn ... jks ...'";
            }
        }
    }
    refresh_contact_surface(m); // the zones' step allows for the joints on their surface
    const double zone_dt = zone_critical_timestep(m);
    // In dynamic mode a forced step beyond the stable limit can only blow up: refuse it before
    // cycling. In static mode the masses are chosen for whatever step is forced.
    if (m.settings.dt_fixed > 0 && m.settings.dynamic) {
        if (zone_dt > 0 && m.settings.dt_fixed > zone_dt / 0.9) {
            return "the forced timestep " + num_text(m.settings.dt_fixed) +
                   " s ('set dt') is larger than the stable limit of the zones, about " + num_text(zone_dt / 0.9) +
                   " s: the motion would run away. Use 'set dt auto' or a timestep below " + num_text(zone_dt) + " s";
        }
        int worst = -1;
        const double limit = stable_timestep_limit(m, &worst);
        if (limit > 0 && m.settings.dt_fixed > limit) {
            const double automatic = contact_critical_timestep(m);
            return "the forced timestep " + num_text(m.settings.dt_fixed) +
                   " s ('set dt') is larger than the stable limit, about " + num_text(limit) + " s" +
                   (worst >= 0 ? " (set by block " + std::to_string(s.id[worst]) + " on its contacts)" : "") +
                   ": the motion would run away. Use 'set dt auto' (" + num_text(automatic) +
                   " s now) or a timestep below " + num_text(limit) + " s";
        }
    }
    {
        const std::string p = choose_timestep_and_masses(m, contact_critical_timestep(m), zone_dt);
        if (!p.empty()) return p;
    }
    // No block may jump more than half its size in its first step: it would pass the blocks
    // in its way unseen (and numbers that large only grow). The first step moves a block by
    // v dt + a dt^2 (a dt^2 / 2 when its velocity was just given), v its velocity (prescribed
    // ones at the largest their table reaches), a its loads over its mass.
    int active = 0;
    for (int b = 0; b < s.size() && active < 2; ++b) active += is_active(s, b) ? 1 : 0;
    for (int b = 0; b < s.size() && active > 1; ++b) {
        if (!is_rigid_active(s, b) || !(s.mass[b] > 0)) continue;
        const bool fixed = s.flags[b] & kFixed;
        if (fixed && !s.vel_bc[b]) continue;
        Vec3 v = fixed ? Vec3::Zero() : s.vel[b];
        if (s.vel_bc[b]) {
            double scale = 1.0;
            if (s.vel_bc_table[b] > 0) {
                const Table* t = m.tables.find(s.vel_bc_table[b]);
                scale = 0;
                if (t) {
                    for (const auto& p : t->points) scale = std::max(scale, std::abs(p.second));
                }
            }
            for (int i = 0; i < 3; ++i) {
                if (s.vel_bc[b] & (1 << i)) v[i] = s.vel_bc_value[b][i] * scale;
            }
        }
        const double accel =
            fixed ? 0.0 : (s.mass[b] * m.gravity + s.applied_force[b]).stableNorm() / s.inertial_mass[b];
        const double speed = v.stableNorm();
        const double move = speed * m.dt + (s.half_kick[b] ? 0.5 : 1.0) * accel * m.dt * m.dt;
        double size = 0;
        for (const Vec3& x : s.shape[b].vertices) size = std::max(size, x.norm());
        if (!(move <= 0.5 * size)) {
            std::string cause;
            if (speed * m.dt >= accel * m.dt * m.dt) {
                cause = "its velocity, " + num_text(speed) + " m/s ('ini' or 'bound ...vel'" +
                        (s.vel_bc_table[b] > 0 ? std::string(" times its table") : std::string()) + "), is too large";
            } else if (s.applied_force[b].squaredNorm() > 0) {
                cause = "its load, " + num_text(accel) + " m/s^2 with the applied force, is too large";
            } else if (m.settings.dt_fixed > 0) {
                cause = "the forced timestep is too large: try 'set dt auto'";
            } else {
                cause = "the timestep is too large for gravity: the joints are too soft to hold the blocks";
            }
            return "block " + std::to_string(s.id[b]) + " would move " + num_text(move) + " m in one step of " +
                   num_text(m.dt) + " s, more than half its size (" + num_text(size) +
                   " m), passing the blocks in its way unseen: " + cause;
        }
    }
    // Explicit viscous damping c m v is stable only for c dt < 2: beyond it each step
    // reverses and amplifies the velocity it should damp.
    if (m.damping.mode == DampingMode::Rayleigh) {
        const double c = 2.0 * m.damping.rayleigh_fraction * 2.0 * M_PI * m.damping.rayleigh_frequency;
        if (!(c * m.dt < 2.0)) {
            return "Rayleigh damping of fraction " + num_text(m.damping.rayleigh_fraction) + " at " +
                   num_text(m.damping.rayleigh_frequency) + " Hz is unstable at the timestep " + num_text(m.dt) +
                   " s (4 pi fraction frequency dt = " + num_text(c * m.dt) +
                   ", must be below 2): lower the frequency below " + num_text(1.0 / (2 * M_PI * m.damping.rayleigh_fraction * m.dt)) + " Hz";
        }
    }
    // Contacts and timestep now match the geometry; the cycle need not prepare again.
    m.geometry_changed = false;
    return "";
}

} // namespace

CycleResult cycle(Model& m, const CycleLimits& lim, const std::atomic<bool>* interrupt,
                  const ProgressFn& progress, long progress_every) {
    CycleResult res;
    // The step counter stops at kMaxStep rather than overflow (a model restored at a step
    // near it could otherwise count past what a long holds).
    auto step_limit_reached = [&] {
        if (m.step < kMaxStep && m.profile.steps < kMaxStep) return false;
        res.reason = StopReason::Error;
        res.message = "the step number has reached " + std::to_string(std::max(m.step, m.profile.steps)) +
                      ", the most odec counts (1e18): the model cannot cycle further";
        return true;
    };
    if (step_limit_reached()) return res;
    PrepareUndo undo(m);
    const std::string problem = prepare_cycle_once(m);
    if (!problem.empty()) {
        undo.undo(m);
        res.reason = StopReason::Error;
        res.message = problem;
        return res;
    }
    // A time limit so far away that no run of steps reaches it would cycle for ever.
    constexpr double kMaxSteps = 2e9;
    if (lim.max_time > 0 && !(lim.max_time / m.dt <= kMaxSteps)) {
        res.reason = StopReason::Error;
        res.message = "a time of " + num_text(lim.max_time) + " s is more than 2e9 steps of " + num_text(m.dt) +
                      " s, the most one command may take (" + num_text(kMaxSteps * m.dt) + " s)";
        undo.undo(m);
        return res;
    }
    const double t_start = m.time;
    Profile& prof = m.profile;
    EnergyWatch watch;
    watch.begin(m);
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
        if (step_limit_reached()) break;
        if (!std::isfinite(m.time + m.dt)) {
            res.reason = StopReason::Error;
            res.message = "the model time, " + num_text(m.time) + " s, would pass the largest number odec holds "
                          "with a step of " + num_text(m.dt) + " s: the model cannot cycle further";
            break;
        }
        if (lim.each_step) {
            // What the functions give the blocks ('ini xvel', 'b_xvel(b) = ...') is energy the
            // run-away check must allow for, as it allows for what the loads give.
            const double ke_before = watch.kinetic(m);
            const std::string p = lim.each_step(m);
            if (!p.empty()) {
                res.reason = StopReason::Error;
                res.message = p;
                break;
            }
            if (!watch.stale(m)) watch.given(watch.kinetic(m) - ke_before);
        }
        // The functions may have changed the blocks (a 'jset', 'poly' or 'gen' in a command
        // block): contacts, masses and timestep follow, and the run-away checks start afresh
        // from the new blocks.
        if (m.geometry_changed || watch.stale(m)) {
            const std::string p = prepare_cycle_once(m);
            if (!p.empty()) {
                res.reason = StopReason::Error;
                res.message = p;
                break;
            }
            watch.begin(m);
        }
        {
            StageTimer t{prof, Stage::ApplyLoads};
            apply_loads(m);
        }
        {
            StageTimer t{prof, Stage::DetectContacts};
            detect_contacts(m);
        }
        if (m.zones.size() > 0) {
            // Zone forces first: they start the gridpoints' forces, which contacts add to.
            StageTimer t{prof, Stage::Zones};
            zone_forces(m, m.dt);
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
        // Said before the histories are sampled: a FISH history may change the blocks.
        if (bad >= 0) {
            res.reason = StopReason::BlowUp;
            res.message = "the motion of block " + std::to_string(m.blocks.id[bad]) + " has run away (step " +
                          std::to_string(m.step) + "): its velocity is no longer a finite number; likely cause: " +
                          runaway_cause(m, bad);
        }
        {
            StageTimer t{prof, Stage::Record};
            if (m.histories.ncyc > 0 && m.step % m.histories.ncyc == 0) {
                // A FISH history may give the blocks energy too.
                bool fish = false;
                for (const History& h : m.histories.items) fish = fish || h.kind == HistoryKind::Fish;
                const double ke_before = fish ? watch.kinetic(m) : 0.0;
                m.histories.sample(m);
                if (fish && !watch.stale(m)) watch.given(watch.kinetic(m) - ke_before);
            }
        }
        if (bad >= 0) break;
        if (m.geometry_changed || watch.stale(m)) {
            // A FISH history changed the blocks: the checks below wait for the next step, which
            // prepares the model again first.
            if (progress && progress_every > 0 && res.steps % progress_every == 0) progress(m);
            continue;
        }
        double energy = 0, available = 0;
        int jumper = -1;
        const int runaway = watch.check(m, energy, available, jumper);
        if (jumper >= 0) {
            res.reason = StopReason::BlowUp;
            res.message = "the motion of block " + std::to_string(m.blocks.id[jumper]) + " has run away (step " +
                          std::to_string(m.step) + "): it moved " + num_text(m.blocks.vel[jumper].stableNorm() * m.dt) +
                          " m in one step, more than half its size, passing through the blocks in its way "
                          "unseen; likely cause: " + runaway_cause(m, jumper);
            break;
        }
        double depth = 0;
        const int deep = runaway < 0 ? watch.sunk(m, depth) : -1;
        if (deep >= 0) {
            const ContactSet& cs = m.contacts;
            const BlockSet& s = m.blocks;
            // The block that moves: the free one, or the lighter.
            int mover = cs.block_b[deep], other = cs.block_a[deep];
            if ((s.flags[mover] & kFixed) || (!(s.flags[other] & kFixed) && s.mass[other] < s.mass[mover])) {
                std::swap(mover, other);
            }
            const int jm = cs.jmat[deep];
            const bool has_jmat = jm > 0 && jm < static_cast<int>(m.joint_materials.size());
            res.reason = StopReason::BlowUp;
            res.message = "the motion of block " + std::to_string(s.id[mover]) + " has run away (step " +
                          std::to_string(m.step) + "): it has sunk " + num_text(depth) + " m into block " +
                          std::to_string(s.id[other]) + ", more than half the smaller block's size; likely cause: " +
                          (has_jmat ? "the joints (jmat " + std::to_string(jm) + ", jkn " +
                                          num_text(m.joint_materials[jm].kn) + " Pa/m) are too soft for the load on them"
                                    : std::string("the contact has no joint material to hold it")) +
                          (m.settings.dt_fixed > 0 ? ", or the forced timestep is too large" : "");
            break;
        }
        if (runaway >= 0) {
            res.reason = StopReason::BlowUp;
            res.message = "the motion of block " + std::to_string(m.blocks.id[runaway]) + " has run away (step " +
                          std::to_string(m.step) + "): the kinetic energy, " + num_text(energy) +
                          " J, is far beyond the " + num_text(available) +
                          " J that the loads and the initial state could have given; likely cause: " +
                          runaway_cause(m, runaway);
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
