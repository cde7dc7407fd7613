// Clumps: the pieces of a rigid solid that is not convex, moving as one rigid body (clump.h).
#include "engine/clump.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "engine/blocks.h"
#include "engine/energy.h"
#include "engine/stages.h"

namespace odec {

ClumpList list_clumps(const BlockSet& s) {
    ClumpList out;
    list_clumps(s, out);
    return out;
}

void list_clumps(const BlockSet& s, ClumpList& out) {
    out.key.clear();
    out.offset.clear();
    out.pieces.clear();
    thread_local std::vector<std::pair<int, int>> items;
    items.clear();
    for (int b = 0; b < s.size(); ++b) {
        if (s.clump[b] != 0) items.emplace_back(s.clump[b], b);
    }
    if (items.empty()) return;
    std::sort(items.begin(), items.end());
    for (size_t i = 0; i < items.size(); ++i) {
        if (i == 0 || items[i].first != items[i - 1].first) {
            out.key.push_back(items[i].first);
            out.offset.push_back(static_cast<int>(i));
        }
        out.pieces.push_back(items[i].second);
    }
    out.offset.push_back(static_cast<int>(items.size()));
}

std::vector<int> clump_pieces(const BlockSet& s, int b) {
    if (s.clump[b] == 0) return {b};
    std::vector<int> out;
    for (int i = 0; i < s.size(); ++i) {
        if (s.clump[i] == s.clump[b]) out.push_back(i);
    }
    return out;
}

int complete_clumps(const BlockSet& s, std::vector<int>& blocks, int* clumps) {
    std::vector<int> keys;
    for (int b : blocks) {
        if (s.clump[b] != 0) keys.push_back(s.clump[b]);
    }
    if (clumps) *clumps = 0;
    if (keys.empty()) return 0;
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    std::vector<char> chosen(s.size(), 0);
    for (int b : blocks) chosen[b] = 1;
    std::vector<int> completed;
    int added = 0;
    for (int b = 0; b < s.size(); ++b) {
        if (chosen[b] || s.clump[b] == 0 || !std::binary_search(keys.begin(), keys.end(), s.clump[b])) continue;
        blocks.push_back(b);
        completed.push_back(s.clump[b]);
        ++added;
    }
    std::sort(blocks.begin(), blocks.end());
    std::sort(completed.begin(), completed.end());
    if (clumps) *clumps = static_cast<int>(std::unique(completed.begin(), completed.end()) - completed.begin());
    return added;
}

int dissolve_clumps(Model& m, const std::vector<int>& blocks) {
    BlockSet& s = m.blocks;
    std::vector<int> keys;
    for (int b : blocks) {
        if (s.clump[b] != 0) keys.push_back(s.clump[b]);
    }
    if (keys.empty()) return 0;
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    for (int b = 0; b < s.size(); ++b) {
        if (s.clump[b] != 0 && std::binary_search(keys.begin(), keys.end(), s.clump[b])) s.clump[b] = 0;
    }
    // The pieces now meet: the next detection finds the contacts between them.
    m.geometry_changed = true;
    return static_cast<int>(keys.size());
}

ClumpBody clump_body(const BlockSet& s, const int* p, int n, const Vec3* vel_in, const Vec3* spin_in) {
    auto vel = [&](int i) { return vel_in ? vel_in[i] : s.vel[p[i]]; };
    auto spin = [&](int i) { return spin_in ? spin_in[i] : s.ang_vel[p[i]]; };
    ClumpBody body;
    double total = 0, volume = 0;
    for (int i = 0; i < n; ++i) {
        total += s.mass[p[i]];
        volume += s.volume[p[i]];
    }
    // Massless pieces (no density yet): their volumes weigh them.
    const bool massless = !(total > 0);
    const double sum = massless ? volume : total;
    auto weight = [&](int b) { return massless ? s.volume[b] : s.mass[b]; };
    for (int i = 0; i < n; ++i) body.centroid += (weight(p[i]) / sum) * s.centroid[p[i]];
    for (int i = 0; i < n; ++i) body.vel += (weight(p[i]) / sum) * vel(i);
    body.mass = total;
    Vec3 momentum = Vec3::Zero(); // angular, about the centroid
    bool one_spin = true;
    for (int i = 0; i < n; ++i) {
        const int b = p[i];
        const Vec3 r = s.centroid[b] - body.centroid;
        const Mat3 rot = s.orientation[b].toRotationMatrix();
        const Mat3 own = rot * (massless ? s.inertia_unit[b] : s.inertia_body[b]) * rot.transpose();
        const Mat3 piece = own + weight(b) * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
        body.inertia += piece;
        momentum += own * spin(i) + weight(b) * r.cross(vel(i));
        if (spin(i) != spin(0)) one_spin = false;
    }
    // The pieces turn together: their common spin. Should they not (set apart by FISH), the
    // spin that keeps their angular momentum.
    body.spin = one_spin ? spin(0) : Vec3(body.inertia.ldlt().solve(momentum));
    if (massless) body.inertia.setZero();
    return body;
}

void set_clump_motion(BlockSet& s, const int* p, int n, const Vec3& vel, const Vec3& spin) {
    const ClumpBody body = clump_body(s, p, n);
    for (int i = 0; i < n; ++i) {
        const int b = p[i];
        s.vel[b] = vel + spin.cross(s.centroid[b] - body.centroid);
        s.ang_vel[b] = spin;
        s.half_kick[b] = 1;
    }
}

void set_clump_component_at_t(Model& m, int b, int k, double value, bool spin) {
    BlockSet& s = m.blocks;
    const std::vector<int> p = clump_pieces(s, b);
    const int n = static_cast<int>(p.size());
    std::vector<Vec3> vel(n), turn(n);
    for (int i = 0; i < n; ++i) {
        vel[i] = velocity_at_t(m, p[i]);
        turn[i] = spin_at_t(m, p[i]);
    }
    const ClumpBody body = clump_body(s, p.data(), n, vel.data(), turn.data());
    // b's centroid keeps its velocity (but for the component given): the clump's follows.
    const Vec3 lever = s.centroid[b] - body.centroid;
    Vec3 w = body.spin, v_b = body.vel + w.cross(lever);
    (spin ? w : v_b)[k] = value;
    const Vec3 v = v_b - w.cross(lever);
    for (int i = 0; i < n; ++i) {
        const int c = p[i];
        Vec3 lead_v = vel[i] - s.vel[c], lead_w = turn[i] - s.ang_vel[c];
        if (!lead_v.allFinite()) lead_v.setZero();
        if (!lead_w.allFinite()) lead_w.setZero();
        const Vec3 at_t = v + w.cross(s.centroid[c] - body.centroid);
        s.vel[c] = (s.flags[c] & kFixed) ? at_t : Vec3(at_t - lead_v);
        s.ang_vel[c] = w - lead_w;
    }
}

int integrate_clumps(Model& m, const ClumpList& cl, double dt, EnergyStep* energy, AutoDampingSums* sums) {
    BlockSet& s = m.blocks;
    const Damping& d = m.damping;
    const Vec3 grav = m.gravity;
    int bad = -1;
    for (int c = 0; c < cl.size(); ++c) {
        const int* p = cl.pieces.data() + cl.offset[c];
        const int n = cl.offset[c + 1] - cl.offset[c];
        bool moves = true;
        for (int i = 0; i < n; ++i) moves = moves && is_rigid_active(s, p[i]);
        if (!moves) continue; // excavated (as a whole: clump.h)
        const ClumpBody body = clump_body(s, p, n);
        // The sums over the pieces: force, moment about the clump's centroid, inertial mass;
        // what holds or drives any piece holds or drives the clump.
        Vec3 force = Vec3::Zero(), moment = Vec3::Zero(), load_f = Vec3::Zero(), load_m = Vec3::Zero();
        double inertial_mass = 0;
        bool fixed = false, half = false, scaled_moment = false;
        std::uint8_t bc = 0;
        Vec3 bc_value = Vec3::Zero();
        int bc_table[3] = {0, 0, 0};
        for (int i = 0; i < n; ++i) {
            const int b = p[i];
            const Vec3 r = s.centroid[b] - body.centroid;
            force += s.force[b];
            moment += s.moment[b] + r.cross(s.force[b]);
            inertial_mass += s.inertial_mass[b];
            fixed = fixed || (s.flags[b] & kFixed);
            half = half || s.half_kick[b];
            scaled_moment = scaled_moment || s.inertial_moment[b] > 0;
            for (int k = 0; k < 3; ++k) {
                if ((s.vel_bc[b] & (1 << k)) && !(bc & (1 << k))) {
                    bc = static_cast<std::uint8_t>(bc | (1 << k));
                    bc_value[k] = s.vel_bc_value[b][k];
                    bc_table[k] = s.vel_bc_table[b];
                }
            }
            if (energy && !s.loads[b].empty()) {
                Vec3 f = Vec3::Zero(), mm = Vec3::Zero();
                block_applied_load(m, b, m.time, f, mm);
                load_f += f;
                load_m += mm + r.cross(f);
            }
        }
        Vec3 v0 = body.vel;
        const Vec3 w0 = body.spin;
        Vec3 v = Vec3::Zero(), w = Vec3::Zero(), a = Vec3::Zero(), alpha = Vec3::Zero();
        if (fixed) {
            // Held still, except for the velocity components a boundary condition drives.
            for (int k = 0; k < 3; ++k) {
                if (!(bc & (1 << k))) continue;
                v[k] = bc_value[k] * m.table_factor(bc_table[k]);
                if (energy) {
                    energy_dof(*energy, body.mass, body.mass * grav[k], load_f[k], force[k], force[k], v0[k], v[k], true,
                               false, dt);
                }
            }
        } else {
            const double kick = half ? 0.5 * dt : dt;
            for (int k = 0; k < 3; ++k) a[k] = damped_force(d, force[k], v0[k], inertial_mass, dt) / inertial_mass;
            v = v0 + a * kick;
            for (int k = 0; k < 3; ++k) {
                if (bc & (1 << k)) {
                    v[k] = bc_value[k] * m.table_factor(bc_table[k]);
                    a[k] = 0;
                } else if (sums) {
                    sums->add(inertial_mass, force[k], v0[k], v[k]);
                }
            }
            if (energy) {
                for (int k = 0; k < 3; ++k) {
                    const bool held = bc & (1 << k);
                    const double fd = d.mode == DampingMode::Off ? force[k] : a[k] * inertial_mass;
                    energy_dof(*energy, body.mass, body.mass * grav[k], load_f[k], force[k], fd, v0[k], v[k], held,
                               half && !held, dt);
                }
            }
            // The inertia the rotation divides by. With the real masses (or masses raised by
            // mscale) the clump's tensor about its centroid. Static mode gives each piece an
            // isotropic inertia from its joints (mass_scaling.h); the clump's springs about its
            // centroid are bounded by twice the sum of the pieces' about their own centroids and
            // of their stiffness times the squared distance of their centroids, so the clump
            // takes twice the sum of the pieces' inertias about its centroid, isotropic.
            Mat3 inertia = Mat3::Zero();
            double iso = 0;
            for (int i = 0; i < n; ++i) {
                const int b = p[i];
                const Vec3 r = s.centroid[b] - body.centroid;
                const double f = s.mass[b] > 0 ? s.inertial_mass[b] / s.mass[b] : 1.0;
                const Mat3 rot = s.orientation[b].toRotationMatrix();
                const Mat3 own = f * (rot * s.inertia_body[b] * rot.transpose());
                if (scaled_moment) {
                    iso += (s.inertial_moment[b] > 0 ? s.inertial_moment[b] : own.trace() / 3.0) +
                           s.inertial_mass[b] * r.squaredNorm();
                } else {
                    inertia += own + s.inertial_mass[b] * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
                }
            }
            if (scaled_moment) {
                iso *= 2.0;
                inertia = iso * Mat3::Identity();
            }
            Vec3 mom;
            for (int k = 0; k < 3; ++k) mom[k] = damped_force(d, moment[k], w0[k], inertia(k, k), dt);
            alpha = scaled_moment ? Vec3(mom / iso) : Vec3(inertia.ldlt().solve(mom));
            w = w0 + alpha * kick;
            if (sums) {
                for (int k = 0; k < 3; ++k) sums->add(inertia(k, k), moment[k], w0[k], w[k]);
            }
            if (energy) energy_rotation(*energy, body.inertia, moment, mom, load_m, w0, w, half, dt);
        }
        // The clump's motion over the step, and each piece where it takes it.
        const Vec3 centroid = body.centroid + v * dt;
        const Vec3 dtheta = w * dt;
        const double angle = dtheta.norm();
        const Quat turn = angle > 0 ? Quat(Eigen::AngleAxisd(angle, dtheta / angle)) : Quat::Identity();
        for (int i = 0; i < n; ++i) {
            const int b = p[i];
            const Vec3 r = angle > 0 ? Vec3(turn * (s.centroid[b] - body.centroid)) : Vec3(s.centroid[b] - body.centroid);
            const Vec3 x = centroid + r;
            s.disp[b] += x - s.centroid[b];
            s.centroid[b] = x;
            if (angle > 0) s.orientation[b] = (turn * s.orientation[b]).normalized();
            s.vel[b] = v + w.cross(r);
            s.ang_vel[b] = w;
            s.accel[b] = a + alpha.cross(r);
            s.ang_accel[b] = alpha;
            s.half_kick[b] = 0;
            if (bad < 0 && !(s.vel[b].allFinite() && w.allFinite() && x.allFinite())) bad = b;
        }
    }
    return bad;
}

std::string clumps_problem(const BlockSet& s) {
    const ClumpList cl = list_clumps(s);
    for (int c = 0; c < cl.size(); ++c) {
        const int first = cl.pieces[cl.offset[c]];
        const std::string name = "clump " + std::to_string(cl.key[c]);
        if (cl.key[c] < 0) return name + ": its name is out of range";
        for (int k = cl.offset[c]; k < cl.offset[c + 1]; ++k) {
            const int b = cl.pieces[k];
            if (s.flags[b] & kDeformable) return name + ": block " + std::to_string(s.id[b]) + " is deformable";
            if ((s.flags[b] & kExcavated) != (s.flags[first] & kExcavated)) {
                return name + ": some of its pieces are excavated and some not";
            }
        }
    }
    return "";
}

} // namespace odec
