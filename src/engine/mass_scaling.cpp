#include "engine/mass_scaling.h"

#include <algorithm>
#include <cmath>

#include "engine/cable.h"
#include "engine/flow.h"
#include "engine/liner.h"
#include "engine/contact.h"
#include "engine/model.h"
#include "engine/parallel.h"
#include "engine/zones.h"

namespace odec {

namespace {

// A gridpoint's stable step is 0.9 * 2 sqrt(m / k) (zones.h): m = k (dt / 1.8)^2 makes it dt.
constexpr double kGridpointSpan = 1.8;
// Static mode: every gridpoint runs at its own limit, so the joints' part of its stiffness (exact
// on average, not where the meshes on a joint's two sides do not match) is doubled.
constexpr double kJointMargin = 2.0;
// Rigid blocks: m = s kt dt^2, I = s kr dt^2 (see the header).
constexpr double kBlockFactor = 1.0 / (0.9 * 0.9);
// The least a rigid block's mass and inertia are scaled to, as a fraction of the real ones.
constexpr double kBlockFloor = 1.0 / 16.0;

void assign_block_masses(Model& m, const std::vector<double>& kt, const std::vector<double>& kr);

bool moves_as_rigid(const BlockSet& s, int b) {
    return !(s.flags[b] & (kExcavated | kDeformable | kFixed)) && s.mass[b] > 0;
}

// Inertia a block's rotation uses now, for comparing with a new one (kg m^2).
double current_moment(const BlockSet& s, int b) {
    if (s.inertial_moment[b] > 0) return s.inertial_moment[b];
    const double f = s.mass[b] > 0 ? s.inertial_mass[b] / s.mass[b] : 1.0;
    return f * s.inertia_body[b].trace() / 3.0;
}

// A velocity just given ('ini', creation: half_kick) is kept as given.
void set_block(BlockSet& s, int b, double mass, double moment) {
    if (!s.half_kick[b]) {
        const double next_moment =
            moment > 0 ? moment : (s.mass[b] > 0 ? mass / s.mass[b] : 1.0) * s.inertia_body[b].trace() / 3.0;
        s.vel[b] *= velocity_factor(s.inertial_mass[b], mass);
        s.ang_vel[b] *= velocity_factor(current_moment(s, b), next_moment);
    }
    s.inertial_mass[b] = mass;
    s.inertial_moment[b] = moment;
}

void set_gridpoint(GridpointSet& g, int i, double mass) {
    if (!g.half_kick[i]) g.vel[i] *= velocity_factor(g.inertial_mass[i], mass);
    g.inertial_mass[i] = mass;
}

// Median of the gridpoints' own stable steps with real masses, s (0: none).
double median_gridpoint_timestep(const Model& m, const std::vector<double>& k) {
    const GridpointSet& g = m.gridpoints;
    std::vector<double> steps;
    steps.reserve(g.size());
    for (int i = 0; i < g.size(); ++i) {
        if (!(g.mass[i] > 0) || !(k[i] > 0) || g.vel_bc[i] == 7) continue;
        steps.push_back(kGridpointSpan * std::sqrt(g.mass[i] / k[i]));
    }
    if (steps.empty()) return 0;
    auto mid = steps.begin() + static_cast<long>(steps.size() / 2);
    std::nth_element(steps.begin(), mid, steps.end());
    return *mid;
}

double total_real_mass(const Model& m) {
    double total = 0;
    const BlockSet& s = m.blocks;
    for (int b = 0; b < s.size(); ++b) {
        if (moves_as_rigid(s, b)) total += s.mass[b];
    }
    const GridpointSet& g = m.gridpoints;
    for (int i = 0; i < g.size(); ++i) {
        if (g.mass[i] > 0 && g.vel_bc[i] != 7) total += g.mass[i];
    }
    return total;
}

// Dynamic mode: the masses a step uses, the real ones (`block_mass`, `gridpoint_mass`) with
// those that `mscale` raises (partial_scaling), given to the blocks and gridpoints at once, so
// that a mass chosen again as it was leaves its velocity as it was (each `step` of a dynamic run
// chooses them again: momentum must not be lost between commands).
void give_masses(Model& m, const std::vector<double>& block_mass, const std::vector<double>& gridpoint_mass) {
    BlockSet& s = m.blocks;
    for (int b = 0; b < s.size(); ++b) {
        if (s.inertial_mass[b] != block_mass[b] || s.inertial_moment[b] != 0) set_block(s, b, block_mass[b], 0.0);
    }
    GridpointSet& g = m.gridpoints;
    for (int i = 0; i < g.size(); ++i) {
        if (g.inertial_mass[i] != gridpoint_mass[i]) set_gridpoint(g, i, gridpoint_mass[i]);
    }
}

// The report's share of a mass that `mscale` raised from `real` to `scaled`.
void count_raised(MassScalingReport& r, double real, double scaled) {
    const double f = scaled / real;
    r.added += scaled - real;
    r.min_factor = r.min_factor > 0 ? std::min(r.min_factor, f) : f;
    r.max_factor = std::max(r.max_factor, f);
}

// A block held by the grout of cables or the bond of liners has its own step, 0.9 * 2 sqrt(m / kt)
// (cable_critical_timestep).
constexpr double kGroutSpan = 0.9 * 2.0;

// Dynamic mode with `mscale dt`: raise what needs it in the masses to be given; returns the
// report's counts.
void partial_scaling(Model& m, double target, std::vector<double>& block_mass, std::vector<double>& gridpoint_mass,
                     MassScalingReport& r) {
    r.min_factor = r.max_factor = 0;
    auto count = [&](double real, double scaled) { count_raised(r, real, scaled); };
    GridpointSet& g = m.gridpoints;
    const std::vector<double> k = gridpoint_stiffness(m);
    for (int i = 0; i < g.size(); ++i) {
        if (!(g.mass[i] > 0) || !(k[i] > 0) || g.vel_bc[i] == 7) continue;
        const double need = k[i] * (target / kGridpointSpan) * (target / kGridpointSpan);
        if (need > g.mass[i]) {
            gridpoint_mass[i] = need;
            count(g.mass[i], need);
            ++r.n_gridpoints;
        }
    }
    // Blocks: the automatic step is dtfrac * 2 sqrt(m / k) with k the stiffest contact, and a
    // block held by grout or a liner's bond has its own (kGroutSpan).
    BlockSet& s = m.blocks;
    const double k_max = stiffest_contact(m);
    const double span = 2.0 * m.settings.dtfrac;
    const double need_contacts = k_max > 0 ? k_max * (target / span) * (target / span) : 0.0;
    std::vector<double> kt(s.size(), 0.0), kr(s.size(), 0.0);
    add_cable_block_stiffness(m, kt, kr);
    add_liner_block_stiffness(m, kt, kr);
    for (int b = 0; b < s.size(); ++b) {
        if (!moves_as_rigid(s, b)) continue;
        const double need = std::max(need_contacts, kt[b] * (target / kGroutSpan) * (target / kGroutSpan));
        if (!(need > s.mass[b])) continue;
        block_mass[b] = need;
        count(s.mass[b], need);
        ++r.n_blocks;
    }
}

// The cable and liner nodes that `mscale` raised (after their masses are chosen).
void count_raised_nodes(const Model& m, MassScalingReport& r) {
    auto count = [&](double real, double scaled) {
        if (!(scaled > real) || !(real > 0)) return;
        count_raised(r, real, scaled);
        ++r.n_nodes;
    };
    for (int i = 0; i < m.cables.n_nodes(); ++i) count(m.cables.mass[i], m.cables.inertial_mass[i]);
    for (int i = 0; i < m.liners.n_nodes(); ++i) count(m.liners.mass[i], m.liners.inertial_mass[i]);
}

} // namespace

void scale_block_masses(Model& m, bool from_contact_update) {
    BlockSet& s = m.blocks;
    const ContactSet& cs = m.contacts;
    const int n = s.size();
    thread_local std::vector<double> walked_kt, walked_kr;
    if (from_contact_update && static_cast<int>(cs.joint_kt.size()) == n && static_cast<int>(cs.joint_kr.size()) == n) {
        assign_block_masses(m, cs.joint_kt, cs.joint_kr);
        return;
    }
    std::vector<double>& kt = walked_kt;
    std::vector<double>& kr = walked_kr;
    kt.assign(n, 0.0);
    kr.assign(n, 0.0);
    for (int c = 0; c < cs.size(); ++c) {
        const JointMaterial* jp = contact_joint_material(m, c);
        if (!jp) continue;
        const int a = cs.block_a[c], b = cs.block_b[c];
        if ((s.flags[a] | s.flags[b]) & kExcavated) continue;
        const bool ra = moves_as_rigid(s, a), rb = moves_as_rigid(s, b);
        if (!ra && !rb) continue;
        const double k = std::max(jp->kn, jp->ks);
        for (int i = cs.sub_offset[c]; i < cs.sub_offset[c + 1]; ++i) {
            const double ki = k * cs.sub_area[i];
            if (!(ki > 0)) continue;
            const Vec3 x = sub_point(m, c, i);
            if (ra) {
                kt[a] += ki;
                kr[a] += ki * (x - s.centroid[a]).squaredNorm();
            }
            if (rb) {
                kt[b] += ki;
                kr[b] += ki * (x - s.centroid[b]).squaredNorm();
            }
        }
    }
    add_cable_block_stiffness(m, kt, kr);
    add_liner_block_stiffness(m, kt, kr);
    assign_block_masses(m, kt, kr);
}

namespace {

void assign_block_masses(Model& m, const std::vector<double>& kt, const std::vector<double>& kr) {
    BlockSet& s = m.blocks;
    const int n = s.size();
    const double dt2 = m.dt * m.dt;
    const int threads = thread_count();
    // Each block alone: on the threads in a large model.
    parallel_for(n, threads, n >= kParallelMinBlocks, [&](int b) {
        if (!moves_as_rigid(s, b)) return;
        if (!(kt[b] > 0) || !std::isfinite(kt[b])) {
            // Touching nothing: it moves as its real mass would.
            if (s.inertial_mass[b] != s.mass[b] || s.inertial_moment[b] != 0) set_block(s, b, s.mass[b], 0.0);
            return;
        }
        // Never below a fraction of the real mass and inertia: a block losing its last contact
        // area (a wedge sliding off) would otherwise be thrown by its own weight.
        const double real_moment = s.inertia_body[b].trace() / 3.0;
        const double mass = std::max(kBlockFactor * kt[b] * dt2, kBlockFloor * s.mass[b]);
        // Springs all at the centroid give no turning stiffness: the real inertia per unit
        // mass, at the scaled mass, then.
        const double moment = kr[b] > 0 ? std::max(kBlockFactor * kr[b] * dt2, kBlockFloor * real_moment)
                                        : mass * real_moment / s.mass[b];
        if (mass != s.inertial_mass[b] || moment != s.inertial_moment[b]) set_block(s, b, mass, moment);
    });
}

} // namespace

std::string choose_timestep_and_masses(Model& m, double rigid_dt, double zone_dt) {
    MassScalingReport r;
    r.is_static = !m.settings.dynamic;
    r.total = total_real_mass(m);
    double real_dt = rigid_dt;
    if (zone_dt > 0 && (!(real_dt > 0) || zone_dt < real_dt)) real_dt = zone_dt;
    // Cables (cable.h): their nodes' own stable step with real masses.
    const double cable_dt = cable_critical_timestep(m);
    if (cable_dt > 0 && (!(real_dt > 0) || cable_dt < real_dt)) real_dt = cable_dt;
    // Liners (liner.h): their nodes' own stable step with real masses (dynamic mode).
    const double liner_dt = m.settings.dynamic ? liner_critical_timestep(m) : 0.0;
    if (liner_dt > 0 && (!(real_dt > 0) || liner_dt < real_dt)) real_dt = liner_dt;
    r.real_dt = real_dt;
    double dt = 0;
    if (r.is_static) {
        if (m.settings.dt_fixed > 0) {
            dt = m.settings.dt_fixed;
        } else {
            const double zone_static = median_gridpoint_timestep(m, gridpoint_stiffness(m));
            dt = rigid_dt;
            if (zone_static > 0 && (!(dt > 0) || zone_static < dt)) dt = zone_static;
            // Nothing else to set the pace: the cables' own step with the steel's mass.
            if (!(dt > 0)) dt = cable_dt;
            // Every block held: the flow alone sets the pace (flow.h).
            if (!(dt > 0) && m.flow.on) dt = flow_stable_timestep(m);
        }
        if (!(dt > 0)) {
            return m.cables.size() > 0
                       ? "no timestep: there are no contacts or zones to set one, and the cables have no density "
                         "(cb_dens) to set it: give one, or the timestep with 'set dt'"
                       : "no timestep: there are no contacts or zones to set one, so give it with 'set dt'";
        }
        m.dt = dt;
        GridpointSet& g = m.gridpoints;
        const std::vector<double> k = gridpoint_stiffness(m, kJointMargin);
        const double span2 = (dt / kGridpointSpan) * (dt / kGridpointSpan);
        for (int i = 0; i < g.size(); ++i) {
            const double mass = (g.mass[i] > 0 && k[i] > 0) ? k[i] * span2 : g.mass[i];
            if (mass != g.inertial_mass[i]) set_gridpoint(g, i, mass);
        }
        scale_block_masses(m, false);
        const std::string cp = choose_cable_masses(m, 0.0);
        if (!cp.empty()) return cp;
        const std::string lp = choose_liner_masses(m);
        if (!lp.empty()) return lp;
    } else {
        std::vector<double> block_mass = m.blocks.mass, gridpoint_mass = m.gridpoints.mass;
        dt = m.settings.dt_fixed > 0 ? m.settings.dt_fixed : real_dt;
        if (!(dt > 0) && m.flow.on) dt = flow_stable_timestep(m);
        if (!(dt > 0)) {
            give_masses(m, block_mass, gridpoint_mass);
            return "no timestep: there are no contacts or zones to set one, so give it with 'set dt'";
        }
        if (m.settings.dt_fixed <= 0 && m.settings.mscale_dt > dt) {
            partial_scaling(m, m.settings.mscale_dt, block_mass, gridpoint_mass, r);
            dt = m.settings.mscale_dt;
        }
        give_masses(m, block_mass, gridpoint_mass);
        m.dt = dt;
        const double raise_to = m.settings.dt_fixed <= 0 && m.settings.mscale_dt >= dt ? m.settings.mscale_dt : 0.0;
        const std::string cp = choose_cable_masses(m, raise_to);
        if (!cp.empty()) return cp;
        const std::string lp = choose_liner_masses(m, raise_to);
        if (!lp.empty()) return lp;
        if (raise_to > 0) count_raised_nodes(m, r);
    }
    r.dt = m.dt;
    const MassScalingReport& old = m.mass_scaling;
    r.fresh = old.fresh || r.is_static != old.is_static || r.dt != old.dt || r.n_gridpoints != old.n_gridpoints ||
              r.n_blocks != old.n_blocks || r.n_nodes != old.n_nodes;
    m.mass_scaling = r;
    return "";
}

} // namespace odec
