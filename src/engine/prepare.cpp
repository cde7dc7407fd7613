// Preparing the cycle: the model can cycle, contacts match the geometry, the timestep and the
// masses are chosen.
#include <algorithm>
#include <cmath>

#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/contact_gridpoint.h"
#include "engine/mass_scaling.h"
#include "engine/cable.h"
#include "engine/flow.h"
#include "engine/stages.h"

namespace odec {

namespace {

// Blocks that overlap where they carry no stress yet (blocks just made, placed or cut, not
// loaded by cycling or 'insitu') deeper than the overlap tolerance, named with how deep;
// "" when none do. Their joints would throw them apart at the first step.
std::string overlap_problem(const Model& m) {
    const ContactSet& cs = m.contacts;
    const BlockSet& s = m.blocks;
    struct Deep {
        double depth, tol;
        int c;
    };
    std::vector<Deep> deep;
    auto size_of = [&](int b) { return std::cbrt(std::max(0.0, s.volume[b])); };
    for (int c = 0; c < cs.size(); ++c) {
        const double depth = -cs.gap[c];
        if (!(depth > 0)) continue;
        bool unstressed = true;
        const double kn = contact_kn(m, c);
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1] && unstressed; ++k) {
            unstressed = cs.sub_sn_for(c, k, kn) == 0 && cs.sub_ss[k].squaredNorm() == 0;
        }
        if (!unstressed) continue;
        const double tol = m.settings.ovtol > 0 ? m.settings.ovtol
                                                 : kOverlapFraction * std::min(size_of(cs.block_a[c]), size_of(cs.block_b[c]));
        if (depth > tol) deep.push_back(Deep{depth, tol, c});
    }
    if (deep.empty()) return "";
    std::stable_sort(deep.begin(), deep.end(), [](const Deep& x, const Deep& y) { return x.depth > y.depth; });
    std::string text = std::to_string(deep.size()) + (deep.size() == 1 ? " pair" : " pairs") +
                       " of blocks overlap deeper than the overlap tolerance (" +
                       (m.settings.ovtol > 0 ? num_text(m.settings.ovtol) + " m, 'set ovtol'"
                                             : std::string("0.5 % of the smaller block's size, the cube root of its volume")) +
                       ") where they carry no stress yet, and their joints would throw them apart at the first step "
                       "(correct their coordinates, or let the joints push them apart with a larger 'set ovtol'):";
    constexpr size_t kShown = 10;
    for (size_t i = 0; i < deep.size() && i < kShown; ++i) {
        const int c = deep[i].c;
        const Vec3 x = contact_point(m, c);
        text += "\n    blocks " + std::to_string(s.id[cs.block_a[c]]) + " and " + std::to_string(s.id[cs.block_b[c]]) +
                " overlap " + num_text(deep[i].depth) + " m deep near (" + num_text(x.x()) + "," + num_text(x.y()) + "," +
                num_text(x.z()) + ")" + (m.settings.ovtol > 0 ? "" : " (tolerance " + num_text(deep[i].tol) + " m)");
    }
    if (deep.size() > kShown) text += "\n    and " + std::to_string(deep.size() - kShown) + " more pairs";
    return text;
}

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
        // The applied loads at their largest (their tables at the largest |y|), with the
        // moment each could give at any orientation.
        double applied = 0, moment = 0;
        for (const BlockLoad& l : s.loads[b]) {
            double k = 1;
            if (l.table > 0) {
                const Table* t = m.tables.find(l.table);
                k = t ? t->max_abs() : 0.0;
            }
            applied += k * l.force.stableNorm();
            moment += k * (l.couple.stableNorm() + l.lever.stableNorm() * l.force.stableNorm());
        }
        const Vec3 w = s.mass[b] * m.gravity;
        if (!std::isfinite(s.mass[b]) || !s.inertia_body[b].allFinite() || !w.allFinite() ||
            !std::isfinite(w.stableNorm() + applied) || !std::isfinite(moment)) {
            return "the load on block " + std::to_string(s.id[b]) + " is not a finite number (mass " +
                   num_text(s.mass[b]) + " kg, gravity " + num_text(m.gravity.stableNorm()) + " m/s^2, applied force " +
                   num_text(applied) + " N, its moment " + num_text(moment) + " N m): give smaller values";
        }
    }
    {
        const std::string zp = zones_problem(m);
        if (!zp.empty()) return zp;
        const std::string cp = cables_problem(m);
        if (!cp.empty()) return cp;
        const std::string fp = flow_problem(m);
        if (!fp.empty()) return fp;
        const std::string lp = liners_problem(m);
        if (!lp.empty()) return lp;
    }
    if (m.geometry_changed) {
        refresh_world_vertices(m);
        detect_contacts(m);
        update_gridpoint_masses(m);
        // Cable nodes are tied to whatever rock holds them now.
        attach_cable_nodes(m);
        attach_liner_nodes(m);
        const std::string overlap = overlap_problem(m);
        if (!overlap.empty()) return overlap;
    }
    refresh_liner_stiffness(m.liners); // not saved: rebuilt after 'restore'
    // A joint material may be assigned before its properties are given ('change jmat'), but not
    // cycled without them: such a joint would hold nothing.
    if (const int c = contact_without_joint_properties(m, false); c >= 0) {
        const int jm = m.contacts.jmat(c);
        return "contact " + std::to_string(m.contacts.id[c]) + " has joint material " + std::to_string(jm) +
               ", which has no properties: give them with 'prop jmat=" + std::to_string(jm) + " jkn ... jks ...'";
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
        const double cable_dt = cable_critical_timestep(m);
        if (cable_dt > 0 && m.settings.dt_fixed > cable_dt) {
            return "the forced timestep " + num_text(m.settings.dt_fixed) +
                   " s ('set dt') is larger than the stable limit of the cables, about " + num_text(cable_dt) +
                   " s with the steel's mass (cb_dens): the motion would run away. Use 'set dt auto' or a "
                   "timestep below " + num_text(cable_dt) + " s";
        }
        const double liner_dt = liner_critical_timestep(m);
        if (liner_dt > 0 && m.settings.dt_fixed > liner_dt) {
            return "the forced timestep " + num_text(m.settings.dt_fixed) +
                   " s ('set dt') is larger than the stable limit of the liners, about " + num_text(liner_dt) +
                   " s with the liner's mass (li_dens): the motion would run away. Use 'set dt auto' or a "
                   "timestep below " + num_text(liner_dt) + " s";
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
        // The loads without a table as they are (they may balance the weight), those with one at
        // their largest.
        Vec3 steady = s.mass[b] * m.gravity;
        double varying = 0;
        for (const BlockLoad& l : s.loads[b]) {
            if (l.table <= 0) {
                steady += l.force;
            } else {
                const Table* t = m.tables.find(l.table);
                varying += (t ? t->max_abs() : 0.0) * l.force.stableNorm();
            }
        }
        const double applied = fixed ? 0.0 : block_applied_force_bound(m, b);
        const double accel = fixed ? 0.0 : (steady.stableNorm() + varying) / s.inertial_mass[b];
        const double speed = v.stableNorm();
        const double move = speed * m.dt + (s.half_kick[b] ? 0.5 : 1.0) * accel * m.dt * m.dt;
        double size = 0;
        for (const Vec3& x : s.shape[b].vertices) size = std::max(size, x.norm());
        if (!(move <= 0.5 * size)) {
            std::string cause;
            if (speed * m.dt >= accel * m.dt * m.dt) {
                cause = "its velocity, " + num_text(speed) + " m/s ('ini' or 'bound ...vel'" +
                        (s.vel_bc_table[b] > 0 ? std::string(" times its table") : std::string()) + "), is too large";
            } else if (applied > 0) {
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

} // namespace odec
