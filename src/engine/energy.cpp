// The energy account (energy.h).
#include "engine/energy.h"

#include <algorithm>
#include <cmath>

#include "engine/model.h"
#include "engine/stages.h"

namespace odec {

namespace {

bool contact_live(const Model& m, int c) {
    const BlockSet& s = m.blocks;
    return !((s.flags[m.contacts.block_a[c]] | s.flags[m.contacts.block_b[c]]) & kExcavated);
}

// Kinetic energy of the model with the velocity `vel(i)` of each degree of freedom: real masses,
// prescribed components left out. `minus`: the velocity half a step before t, from the last
// acceleration, so that the reading is m v- . v+ / 2 (energy.h); else m v . v / 2.
double kinetic_reading(const Model& m, bool minus) {
    const BlockSet& s = m.blocks;
    const double dt = minus ? m.dt : 0.0;
    double e = 0;
    for (int b = 0; b < s.size(); ++b) {
        if (!is_rigid_active(s, b) || (s.flags[b] & kFixed) || !(s.mass[b] > 0)) continue;
        const bool given = s.half_kick[b] != 0;
        Vec3 v1 = s.vel[b], v0 = given ? v1 : Vec3(v1 - dt * s.accel[b]);
        for (int i = 0; i < 3; ++i) {
            if (s.vel_bc[b] & (1 << i)) v0[i] = v1[i] = 0;
        }
        const Vec3 w1 = s.ang_vel[b], w0 = given ? w1 : Vec3(w1 - dt * s.ang_accel[b]);
        const Mat3 r = s.orientation[b].toRotationMatrix();
        const Mat3 inertia = r * s.inertia_body[b] * r.transpose();
        e += 0.5 * s.mass[b] * v0.dot(v1) + 0.5 * w0.dot(inertia * w1);
    }
    const GridpointSet& g = m.gridpoints;
    for (int i = 0; i < g.size(); ++i) {
        if (!(g.mass[i] > 0) || !(g.inertial_mass[i] > 0)) continue;
        const bool given = g.half_kick[i] != 0;
        for (int k = 0; k < 3; ++k) {
            if (g.vel_bc[i] & (1 << k)) continue;
            const double v1 = g.vel[i][k];
            // The undamped acceleration: exact without damping, which the account is meant for.
            const double v0 = given ? v1 : v1 - dt * g.force[i][k] / g.inertial_mass[i];
            e += 0.5 * g.mass[i] * v0 * v1;
        }
    }
    return e;
}

} // namespace

EnergyReading energy_reading(const Model& m) {
    const EnergyAccount& a = m.energy;
    EnergyReading r;
    if (!a.on) return r;
    r.jstrain = joint_strain_energy(m);
    r.zstrain = zone_strain_energy(m);
    double dk = 0, du = 0;
    if (!a.cycling) {
        // What commands have changed since the cycle left the model.
        dk = stored_kinetic_energy(m) - a.mark_kinetic;
        du = r.jstrain + r.zstrain - a.mark_strain;
    }
    r.kinetic = a.kinetic + dk;
    r.gravity = a.gravity - a.pending_gravity;
    r.load = a.load - a.pending_load;
    r.velocity = a.velocity - a.pending_velocity;
    r.damping = a.damping - a.pending_damping;
    r.slip = a.slip;
    r.plastic = a.plastic;
    r.initial = a.initial;
    r.given = a.given + dk + du;
    return r;
}

double joint_strain_energy(const Model& m) {
    const ContactSet& cs = m.contacts;
    double e = 0;
    for (int c = 0; c < cs.size(); ++c) {
        const JointMaterial* jp = contact_joint_material(m, c);
        if (!jp || !contact_live(m, c)) continue;
        const JointMaterial& j = *jp;
        const double hn = j.kn > 0 ? 0.5 / j.kn : 0.0, hs = j.ks > 0 ? 0.5 / j.ks : 0.0;
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
            const double sn = cs.sub_sn_for(c, k, j.kn);
            e += cs.sub_area[k] * (hn * sn * sn + hs * cs.sub_ss[k].squaredNorm());
        }
    }
    return e;
}

double zone_strain_energy(const Model& m) {
    const ZoneSet& z = m.zones;
    const int n_mat = static_cast<int>(m.materials.size());
    double e = 0;
    for (int i = 0; i < z.size(); ++i) {
        const int b = z.block[i];
        if (z.model[i] == kZoneNull || (m.blocks.flags[b] & kExcavated)) continue;
        const int mat = m.blocks.material[b];
        if (mat <= 0 || mat >= n_mat || !m.materials[mat].defined) continue;
        const Material& mt = m.materials[mat];
        const Sym6& s = z.stress[i];
        const double p = (s[0] + s[1] + s[2]) / 3.0;
        const double d0 = s[0] - p, d1 = s[1] - p, d2 = s[2] - p;
        const double dev = d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
        double u = 0;
        if (mt.bulk > 0) u += p * p / (2.0 * mt.bulk);
        if (mt.shear > 0) u += dev / (4.0 * mt.shear);
        e += z.volume[i] * u;
    }
    return e;
}

double stored_kinetic_energy(const Model& m) { return kinetic_reading(m, false); }

void start_energy_account(Model& m) {
    EnergyAccount a;
    a.on = true;
    a.start_step = m.step;
    a.kinetic = kinetic_reading(m, true);
    const double strain = joint_strain_energy(m) + zone_strain_energy(m);
    a.initial = a.kinetic + strain;
    a.peak = std::abs(a.initial);
    a.mark_kinetic = stored_kinetic_energy(m);
    a.mark_strain = strain;
    m.energy = a;
}

void mark_energy(Model& m) {
    EnergyAccount& a = m.energy;
    a.cycling = false;
    if (!a.on) return;
    a.mark_kinetic = stored_kinetic_energy(m);
    a.mark_strain = joint_strain_energy(m) + zone_strain_energy(m);
}

void take_energy(Model& m) {
    EnergyAccount& a = m.energy;
    if (!a.on) return;
    if (!a.cycling) {
        const double dk = stored_kinetic_energy(m) - a.mark_kinetic;
        const double du = joint_strain_energy(m) + zone_strain_energy(m) - a.mark_strain;
        a.kinetic += dk;
        a.given += dk + du;
    }
    a.cycling = true;
}

void energy_rotation(EnergyStep& e, const Mat3& inertia, const Vec3& m, const Vec3& md, const Vec3& load_moment,
                     const Vec3& w0, const Vec3& w1, bool half, double dt) {
    const Vec3 before = half ? Vec3(Vec3::Zero()) : w0;
    const Vec3 minus = half ? Vec3(2 * w0 - w1) : w0;
    const Vec3 w = 0.5 * dt * (before + w1), p = 0.5 * dt * w1;
    e.load += load_moment.dot(w);
    e.pending_load += load_moment.dot(p);
    e.damping += (m - md).dot(w);
    e.pending_damping += (m - md).dot(p);
    e.kinetic += 0.5 * minus.dot(inertia * w1);
}

void add_energy_step(Model& m, const EnergyStep& e) {
    EnergyAccount& a = m.energy;
    a.gravity += e.gravity;
    a.load += e.load;
    a.velocity += e.velocity;
    a.damping += e.damping;
    a.pending_gravity = e.pending_gravity;
    a.pending_load = e.pending_load;
    a.pending_velocity = e.pending_velocity;
    a.pending_damping = e.pending_damping;
    a.kinetic = e.kinetic;
    // The energy put in (its magnitudes) or the kinetic energy, whichever is larger.
    const double put = std::abs(a.initial) + std::abs(a.given) + std::abs(a.gravity - a.pending_gravity) +
                       std::abs(a.load - a.pending_load) + std::abs(a.velocity - a.pending_velocity);
    a.peak = std::max({a.peak, put, std::abs(a.kinetic)});
}

const std::vector<EnergyTermInfo>& energy_terms() {
    static const std::vector<EnergyTermInfo> terms = {
        {"kinetic", "kinetic energy of the free blocks and gridpoints (translation and rotation, real masses)"},
        {"jstrain", "strain energy stored in the joints' springs"},
        {"zstrain", "elastic strain energy stored in the zones"},
        {"gravity", "work done by gravity since the account began"},
        {"load", "work done by the applied loads ('bound xload ...', 'bound stress') since"},
        {"velocity", "work done by the prescribed velocities ('bound xvel ...', a moving 'fix') since"},
        {"boundary", "work done at the boundary: load + velocity"},
        {"damping", "energy dissipated by damping since"},
        {"slip", "energy dissipated in the joints (friction, breaking) since"},
        {"plastic", "energy dissipated by the zones' plastic flow since"},
        {"initial", "stored energy (kinetic + jstrain + zstrain) when the account began"},
        {"given", "stored energy changed by commands between steps since"},
        {"error", "kinetic + jstrain + zstrain + damping + slip + plastic - (initial + given + gravity + boundary)"},
    };
    return terms;
}

bool is_energy_term(const std::string& name) {
    for (const EnergyTermInfo& t : energy_terms()) {
        if (name == t.name) return true;
    }
    return false;
}

bool energy_term(const Model& m, const std::string& name, double& value) {
    value = 0;
    if (!is_energy_term(name)) return false;
    if (!m.energy.on) return true;
    const EnergyReading r = energy_reading(m);
    if (name == "kinetic") value = r.kinetic;
    else if (name == "jstrain") value = r.jstrain;
    else if (name == "zstrain") value = r.zstrain;
    else if (name == "gravity") value = r.gravity;
    else if (name == "load") value = r.load;
    else if (name == "velocity") value = r.velocity;
    else if (name == "boundary") value = r.load + r.velocity;
    else if (name == "damping") value = r.damping;
    else if (name == "slip") value = r.slip;
    else if (name == "plastic") value = r.plastic;
    else if (name == "initial") value = r.initial;
    else if (name == "given") value = r.given;
    else value = r.error();
    return true;
}

std::string energy_caveat(const Model& m) {
    if (m.cables.size() > 0) {
        return "the model has cables: their strain energy, the work their grout does on the rock and what its "
               "slip and the steel's yield dissipate are not in the account, so the balance leaves them out";
    }
    if (m.liners.size() > 0) {
        return "the model has liners: their strain energy, the work their bond does on the rock and what its "
               "slip dissipates are not in the account, so the balance leaves them out";
    }
    if (!m.settings.dynamic) {
        return "static mode: the blocks and gridpoints move with scaled masses, so the kinetic energy (with the "
               "real masses) and the balance are not physical; the account is meant for dynamic analysis "
               "('config dyn')";
    }
    const BlockSet& s = m.blocks;
    int raised = 0;
    for (int b = 0; b < s.size(); ++b) {
        if (is_rigid_active(s, b) && !(s.flags[b] & kFixed) && s.inertial_mass[b] != s.mass[b]) ++raised;
    }
    const GridpointSet& g = m.gridpoints;
    for (int i = 0; i < g.size(); ++i) {
        if (g.mass[i] > 0 && g.inertial_mass[i] != g.mass[i]) ++raised;
    }
    if (raised > 0) {
        return "'mscale' has raised the masses of " + std::to_string(raised) +
               " blocks and gridpoints: they move with masses that are not theirs, so the kinetic energy (with "
               "the real masses) and the balance are not physical there";
    }
    return "";
}

} // namespace odec
