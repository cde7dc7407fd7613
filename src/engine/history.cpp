#include "engine/history.h"

#include <cmath>
#include <cstdio>

#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/cycle.h"
#include "engine/energy.h"
#include "engine/flow.h"
#include "engine/model.h"

namespace odec {

double history_value(const Model& m, const History& h) {
    switch (h.kind) {
    case HistoryKind::Unbalanced: return max_unbalanced_force(m);
    case HistoryKind::Time: return m.time;
    case HistoryKind::Step: return static_cast<double>(m.step);
    case HistoryKind::Ratio: return unbalanced_ratio(m);
    case HistoryKind::Fish: return 0.0; // read through HistorySet::external
    case HistoryKind::CableForce:
    case HistoryKind::CableGrout: {
        // 0 once the cable was deleted.
        const CableSet& cs = m.cables;
        const int c = cs.index(h.cable_id);
        if (c < 0) return 0.0;
        const int k = h.cable_item - 1;
        if (h.kind == HistoryKind::CableForce) {
            return k >= 0 && k < cs.segments_of(c) ? cs.axial[cs.first_segment(c) + k] : 0.0;
        }
        return k >= 0 && k <= cs.segments_of(c) ? cs.grout_force[cs.node_offset[c] + k] : 0.0;
    }
    case HistoryKind::PorePressure:
    case HistoryKind::Aperture: {
        const FlowSet& f = m.flow;
        const int i = flow_node_at(m, h.point);
        if (i < 0) return 0.0;
        if (h.kind == HistoryKind::PorePressure) return f.pp[i];
        return i < static_cast<int>(f.area.size()) && f.area[i] > 0 ? f.volume[i] / f.area[i] : 0.0;
    }
    case HistoryKind::FlowRate: return fixed_inflow(m);
    case HistoryKind::LinerNx:
    case HistoryKind::LinerMx: {
        // 0 once the liner was deleted.
        const LinerSet& ls = m.liners;
        const int c = ls.index(h.cable_id);
        if (c < 0) return 0.0;
        const int e = ls.elem_offset[c] + h.cable_item - 1;
        if (e < ls.elem_offset[c] || e >= ls.elem_offset[c + 1]) return 0.0;
        const LinerResultants r = liner_resultants(ls, e);
        return h.kind == HistoryKind::LinerNx ? r.nx : r.mx;
    }
    case HistoryKind::Energy: {
        double v = 0;
        energy_term(m, h.source, v);
        return v;
    }
    case HistoryKind::Damp:
        if (m.damping.mode == DampingMode::Auto) return m.damping.auto_coefficient;
        if (m.damping.mode == DampingMode::Rayleigh) return 2.0 * m.damping.rayleigh_fraction * 2.0 * M_PI * m.damping.rayleigh_frequency;
        return 0.0;
    case HistoryKind::NForce:
    case HistoryKind::SForce: {
        int c = contact_index(m, h.contact_id);
        if (c < 0) c = find_contact_at(m, h.point);
        if (c < 0) return 0.0;
        const ContactSet& cs = m.contacts;
        double fn = 0;
        Vec3 fs = Vec3::Zero();
        const double kn = contact_kn(m, c);
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
            fn += cs.sub_sn_for(c, k, kn) * cs.sub_area[k];
            fs += cs.sub_shear_stress(c, k) * static_cast<double>(cs.sub_area[k]);
        }
        return h.kind == HistoryKind::NForce ? fn : fs.norm();
    }
    case HistoryKind::NStress:
    case HistoryKind::SStress:
    case HistoryKind::NDis:
    case HistoryKind::SDis: {
        // Follow the contact by id; when it has gone (blocks parted and met again), the one at the point.
        int c = contact_index(m, h.contact_id);
        if (c < 0) c = find_contact_at(m, h.point);
        if (c < 0) return 0.0;
        const ContactInfo ci = contact_info(m, c, false); // stresses and displacements only
        if (h.kind == HistoryKind::NStress) return ci.normal_stress;
        if (h.kind == HistoryKind::SStress) return ci.shear_stress;
        if (h.kind == HistoryKind::NDis) return ci.normal_disp;
        return ci.shear_disp;
    }
    case HistoryKind::SXX:
    case HistoryKind::SYY:
    case HistoryKind::SZZ:
    case HistoryKind::SXY:
    case HistoryKind::SXZ:
    case HistoryKind::SYZ: {
        if (h.zone < 0 || h.zone >= m.zones.size()) return 0.0;
        return m.zones.stress[h.zone][static_cast<int>(h.kind) - static_cast<int>(HistoryKind::SXX)];
    }
    case HistoryKind::XReaction:
    case HistoryKind::YReaction:
    case HistoryKind::ZReaction: {
        const int k = static_cast<int>(h.kind) - static_cast<int>(HistoryKind::XReaction);
        double sum = 0;
        const GridpointSet& g = m.gridpoints;
        for (int i : h.gridpoints) {
            if (i < g.size() && (g.vel_bc[i] & (1 << k))) sum += g.force[i][k];
        }
        for (int id : h.blocks) {
            const int b = m.block_index(id);
            if (b < 0) continue;
            const bool held = (m.blocks.flags[b] & kFixed) || (m.blocks.vel_bc[b] & (1 << k));
            if (held) sum += m.blocks.force[b][k];
        }
        return sum;
    }
    default: break;
    }
    if (h.gridpoint != -1) {
        if (h.gridpoint < 0 || h.gridpoint >= m.gridpoints.size()) return 0.0;
        const Vec3& d = m.gridpoints.disp[h.gridpoint];
        switch (h.kind) {
        case HistoryKind::XDis: return d.x();
        case HistoryKind::YDis: return d.y();
        case HistoryKind::ZDis: return d.z();
        case HistoryKind::XVel: return gridpoint_velocity_at_t(m, h.gridpoint).x();
        case HistoryKind::YVel: return gridpoint_velocity_at_t(m, h.gridpoint).y();
        case HistoryKind::ZVel: return gridpoint_velocity_at_t(m, h.gridpoint).z();
        case HistoryKind::XAcc:
        case HistoryKind::YAcc:
        case HistoryKind::ZAcc: {
            // The gridpoint's acceleration in the last step: its unbalanced force over its mass.
            const double mass = m.gridpoints.inertial_mass[h.gridpoint];
            if (!(m.gridpoints.mass[h.gridpoint] > 0) || !(mass > 0)) return 0.0;
            return m.gridpoints.force[h.gridpoint][static_cast<int>(h.kind) - static_cast<int>(HistoryKind::XAcc)] / mass;
        }
        default: return 0.0;
        }
    }
    const int b = m.block_index(h.block_id);
    if (b < 0) return 0.0; // the block was deleted
    // The material point: where the block's turn and translation have taken it (its
    // displacement exact for any rotation: point_displacement).
    const BlockSet& s = m.blocks;
    const Eigen::Vector3d lever = s.orientation[b] * h.body_offset;
    switch (h.kind) {
    case HistoryKind::XAcc:
    case HistoryKind::YAcc:
    case HistoryKind::ZAcc: {
        // Translation, the angular acceleration about the centroid and the centripetal part of
        // the spin (the acceleration of a point of a rigid body, however fast it turns).
        const Vec3 w = spin_at_t(m, b);
        const Vec3 a = s.accel[b] + s.ang_accel[b].cross(lever) + w.cross(w.cross(lever));
        return a[static_cast<int>(h.kind) - static_cast<int>(HistoryKind::XAcc)];
    }
    case HistoryKind::XDis: return point_displacement(m, b, h.body_offset).x();
    case HistoryKind::YDis: return point_displacement(m, b, h.body_offset).y();
    case HistoryKind::ZDis: return point_displacement(m, b, h.body_offset).z();
    case HistoryKind::XVel: return velocity_at_point(m, b, lever).x();
    case HistoryKind::YVel: return velocity_at_point(m, b, lever).y();
    case HistoryKind::ZVel: return velocity_at_point(m, b, lever).z();
    default: return 0.0;
    }
}

static const char* kind_word(HistoryKind k) {
    switch (k) {
    case HistoryKind::Unbalanced: return "unbal";
    case HistoryKind::Time: return "time";
    case HistoryKind::Step: return "step";
    case HistoryKind::Ratio: return "ratio";
    case HistoryKind::XDis: return "xdis";
    case HistoryKind::YDis: return "ydis";
    case HistoryKind::ZDis: return "zdis";
    case HistoryKind::XVel: return "xvel";
    case HistoryKind::YVel: return "yvel";
    case HistoryKind::ZVel: return "zvel";
    case HistoryKind::NStress: return "nstress";
    case HistoryKind::SStress: return "sstress";
    case HistoryKind::NDis: return "ndis";
    case HistoryKind::SDis: return "sdis";
    case HistoryKind::SXX: return "sxx";
    case HistoryKind::SYY: return "syy";
    case HistoryKind::SZZ: return "szz";
    case HistoryKind::SXY: return "sxy";
    case HistoryKind::SXZ: return "sxz";
    case HistoryKind::SYZ: return "syz";
    case HistoryKind::XReaction: return "xreaction";
    case HistoryKind::YReaction: return "yreaction";
    case HistoryKind::ZReaction: return "zreaction";
    case HistoryKind::NForce: return "nf_sum";
    case HistoryKind::SForce: return "sf_sum";
    case HistoryKind::XAcc: return "xacc";
    case HistoryKind::YAcc: return "yacc";
    case HistoryKind::ZAcc: return "zacc";
    case HistoryKind::Damp: return "damp";
    case HistoryKind::Fish: return "fish";
    case HistoryKind::Energy: return "energy";
    case HistoryKind::CableForce: return "cable_force";
    case HistoryKind::CableGrout: return "cable_grout";
    case HistoryKind::PorePressure: return "pp";
    case HistoryKind::Aperture: return "aperture";
    case HistoryKind::FlowRate: return "flowrate";
    case HistoryKind::LinerNx: return "liner_nx";
    case HistoryKind::LinerMx: return "liner_mx";
    }
    return "?";
}

std::string history_default_label(const History& h) {
    if (h.kind == HistoryKind::Fish) return "@" + h.source;
    if (h.kind == HistoryKind::Energy) return "energy " + h.source + " (J)";
    std::string s = kind_word(h.kind);
    char buf[160];
    if (h.kind == HistoryKind::CableForce || h.kind == HistoryKind::CableGrout) {
        std::snprintf(buf, sizeof buf, " cable %d %s %d (N)", h.cable_id,
                      h.kind == HistoryKind::CableForce ? "segment" : "node", h.cable_item);
        s += buf;
    } else if (h.kind == HistoryKind::LinerNx || h.kind == HistoryKind::LinerMx) {
        std::snprintf(buf, sizeof buf, " liner %d element %d (%s)", h.cable_id, h.cable_item,
                      h.kind == HistoryKind::LinerNx ? "N/m" : "N m/m");
        s += buf;
    } else if (h.zone >= 0) {
        std::snprintf(buf, sizeof buf, " (%g,%g,%g) zone %d", h.point.x(), h.point.y(), h.point.z(), h.zone + 1);
        s += buf;
    } else if (h.gridpoint >= 0) {
        std::snprintf(buf, sizeof buf, " (%g,%g,%g) gp %d", h.point.x(), h.point.y(), h.point.z(), h.gridpoint + 1);
        s += buf;
    } else if (!h.gridpoints.empty() || !h.blocks.empty()) {
        std::snprintf(buf, sizeof buf, " of %zu gridpoints, %zu blocks", h.gridpoints.size(), h.blocks.size());
        s += buf;
    } else if (h.block_id > 0) {
        std::snprintf(buf, sizeof buf, " (%g,%g,%g) block %d", h.point.x(), h.point.y(), h.point.z(), h.block_id);
        s += buf;
    } else if (h.contact_id > 0) {
        std::snprintf(buf, sizeof buf, " (%g,%g,%g) contact %d", h.point.x(), h.point.y(), h.point.z(), h.contact_id);
        s += buf;
    } else if (h.kind == HistoryKind::PorePressure || h.kind == HistoryKind::Aperture) {
        std::snprintf(buf, sizeof buf, " (%g,%g,%g) (%s)", h.point.x(), h.point.y(), h.point.z(),
                      h.kind == HistoryKind::PorePressure ? "Pa" : "m");
        s += buf;
    } else if (h.kind == HistoryKind::FlowRate) {
        s += " (m^3/s)";
    }
    return s;
}

std::string HistorySet::sample(const Model& m) {
    if (items.empty()) return "";
    // Every value first, kept only when all were had. A FISH history's function may run
    // commands that add histories or reset their samples ('hist', 'reset hist' in a command
    // block), so the list may change while it is read: the histories there at the start are
    // read by index, a FISH one through a copy of its name.
    const size_t n = items.size();
    std::vector<double> v(n, 0.0);
    for (size_t k = 0; k < n && k < items.size(); ++k) {
        if (items[k].kind != HistoryKind::Fish) {
            v[k] = history_value(m, items[k]);
            continue;
        }
        History probe;
        probe.kind = HistoryKind::Fish;
        probe.source = items[k].source;
        std::string error;
        if (!external) error = "FISH is not running";
        else if (external(probe, static_cast<int>(k) + 1, v[k], error)) continue;
        return "history " + std::to_string(k + 1) + " (@" + probe.source + ") failed at step " + std::to_string(m.step) +
               ", which stands without its sample: " + error;
    }
    // A value goes to each history that still has every sample before this one; one made
    // while the values were read starts with the next sample.
    const size_t at = sample_steps.size();
    sample_steps.push_back(m.step);
    for (size_t k = 0; k < items.size(); ++k) {
        History& h = items[k];
        if (k < n && static_cast<size_t>(h.first) + h.values.size() == at) {
            h.values.push_back(v[k]);
        } else if (h.values.empty() && static_cast<size_t>(h.first) >= at) {
            h.first = static_cast<long>(at) + 1;
        }
    }
    return "";
}

void HistorySet::clear_values() {
    sample_steps.clear();
    for (History& h : items) {
        h.values.clear();
        h.first = 0;
    }
}

} // namespace odec
