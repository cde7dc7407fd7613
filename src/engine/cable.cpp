#include "engine/cable.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/mass_scaling.h"
#include "engine/model.h"
#include "engine/stages.h"

namespace odec {

namespace {

// The step a node takes is at most kNodeSpan sqrt(m / k), k its stiffness bound: m = k (dt / kNodeSpan)^2.
// Central differences are stable up to 2 sqrt(m / k); a cable is a chain whose highest mode reaches
// the bound, and local damping near that limit pumps it up, so the nodes keep well inside it.
constexpr double kNodeSpan = 1.0;

double axial_stiffness(const CableMaterial& p, double l0) { return l0 > 0 ? p.e * p.area / l0 : 0.0; }

// The unit direction of the cable at node i (of cable c): its segment at an end, the mean of its
// two segments inside.
Vec3 node_direction(const CableSet& cs, int c, int i) {
    const int first = cs.node_offset[c], last = cs.node_offset[c + 1] - 1;
    Vec3 t = Vec3::Zero();
    if (i > first) {
        const Vec3 d = cs.pos[i] - cs.pos[i - 1];
        const double l = d.norm();
        if (l > 0) t += d / l;
    }
    if (i < last) {
        const Vec3 d = cs.pos[i + 1] - cs.pos[i];
        const double l = d.norm();
        if (l > 0) t += d / l;
    }
    const double n = t.norm();
    return n > 0 ? Vec3(t / n) : Vec3::UnitX();
}

// Velocity of the rock a node is tied to (at t - dt/2, as the joints read it); `index` receives
// the host block's index (-1: none).
Vec3 host_velocity(const Model& m, int i, int& index) {
    const CableSet& cs = m.cables;
    return rock_tie_velocity(m, cs.host_block[i], cs.host_lever[i], cs.host_gp[i], cs.host_w[i], index);
}

// Barycentric weights of x in the tetrahedron a, b, c, d; false when it is degenerate.
bool barycentric(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& x,
                 std::array<double, 4>& w) {
    Mat3 e;
    e.col(0) = b - a;
    e.col(1) = c - a;
    e.col(2) = d - a;
    const double det = e.determinant();
    if (!(std::abs(det) > 0)) return false;
    const Vec3 l = e.inverse() * (x - a);
    w = {1.0 - l.sum(), l[0], l[1], l[2]};
    return true;
}

// Tie node i to the rock at its position.
void attach_node(Model& m, int i) {
    CableSet& cs = m.cables;
    find_rock_tie(m, cs.pos[i], cs.host_block[i], cs.host_lever[i], cs.host_gp[i], cs.host_w[i]);
}

void refresh_stiffness(CableSet& cs) {
    for (int c = 0; c < cs.size(); ++c) {
        const CableMaterial& p = cs.materials[cs.material[c]];
        const int first = cs.node_offset[c], last = cs.node_offset[c + 1] - 1;
        for (int i = first; i <= last; ++i) {
            double k = cs.host_block[i] > 0 ? p.kbond * cs.length[i] : 0.0;
            const int seg = cs.first_segment(c) + (i - first);
            if (i > first) k += 2.0 * axial_stiffness(p, cs.rest_length[seg - 1]);
            if (i < last) k += 2.0 * axial_stiffness(p, cs.rest_length[seg]);
            cs.stiffness[i] = k;
        }
    }
}

// A new inertial mass for node i (velocity_factor).
void set_node_mass(CableSet& cs, int i, double mass) {
    cs.vel[i] *= velocity_factor(cs.inertial_mass[i], mass);
    cs.inertial_mass[i] = mass;
}

} // namespace

int CableSet::index(int cable_id) const {
    const auto it = std::lower_bound(id.begin(), id.end(), cable_id);
    return (it != id.end() && *it == cable_id) ? static_cast<int>(it - id.begin()) : -1;
}

Vec3 rock_tie_velocity(const Model& m, int block_id, const Vec3& lever, const std::array<int, 4>& gp,
                       const std::array<double, 4>& w, int& index) {
    index = block_id > 0 ? m.block_index(block_id) : -1;
    if (index < 0) return Vec3::Zero();
    if (gp[0] >= 0) {
        const GridpointSet& g = m.gridpoints;
        Vec3 v = Vec3::Zero();
        for (int k = 0; k < 4; ++k) {
            const int q = gp[k];
            if (!g.half_kick[q]) v += w[k] * g.vel[q];
        }
        return v;
    }
    const BlockSet& s = m.blocks;
    if (s.half_kick[index] || ((s.flags[index] & kFixed) && !s.vel_bc[index])) return Vec3::Zero();
    return s.vel[index] + s.ang_vel[index].cross(s.orientation[index] * lever);
}

void find_rock_tie(const Model& m, const Vec3& x, int& block_id, Vec3& lever, std::array<int, 4>& gp_out,
                   std::array<double, 4>& w_out) {
    const BlockSet& s = m.blocks;
    block_id = 0;
    lever.setZero();
    gp_out = {-1, -1, -1, -1};
    w_out = {0, 0, 0, 0};
    for (int b = 0; b < s.size(); ++b) {
        if (s.flags[b] & kExcavated) continue;
        const Vec3 local = s.orientation[b].conjugate() * (x - s.centroid[b]);
        if (!contains_point(s.shape[b], local, 1e-9)) continue;
        if (s.flags[b] & kDeformable) {
            // The zone of this block holding the point, or the nearest by its lowest weight.
            const ZoneSet& z = m.zones;
            const GridpointSet& g = m.gridpoints;
            int best = -1;
            double best_low = -std::numeric_limits<double>::infinity();
            std::array<double, 4> best_w{};
            for (int q = 0; q < z.size(); ++q) {
                if (z.block[q] != b) continue;
                const auto& p = z.gp[q];
                std::array<double, 4> w;
                if (!barycentric(g.pos[p[0]], g.pos[p[1]], g.pos[p[2]], g.pos[p[3]], x, w)) continue;
                const double low = std::min(std::min(w[0], w[1]), std::min(w[2], w[3]));
                if (low > best_low) {
                    best_low = low;
                    best = q;
                    best_w = w;
                }
                if (low >= 0) break;
            }
            if (best < 0) continue;
            // Just outside its zones (on the block's surface, within the tolerance): the weights
            // clipped to the zone.
            double sum = 0;
            for (double& w : best_w) sum += (w = std::max(w, 0.0));
            for (double& w : best_w) w /= sum;
            block_id = s.id[b];
            gp_out = z.gp[best];
            w_out = best_w;
            return;
        }
        block_id = s.id[b];
        lever = local;
        return;
    }
}

bool rock_tie_holds(const Model& m, int block_id, const Vec3& lever, const std::array<int, 4>& gp) {
    const BlockSet& s = m.blocks;
    const int b = m.block_index(block_id);
    if (b < 0 || (s.flags[b] & kExcavated)) return false;
    if (gp[0] < 0) return !(s.flags[b] & kDeformable) && contains_point(s.shape[b], lever, 1e-9);
    if (!(s.flags[b] & kDeformable)) return false;
    const ZoneSet& z = m.zones;
    for (int q = 0; q < z.size(); ++q) {
        if (z.block[q] == b && z.gp[q] == gp) return true;
    }
    return false;
}

bool rock_tie_kept(const Model& m, int old_block_id, int new_block_id) {
    const int was = old_block_id > 0 ? m.block_index(old_block_id) : -1;
    return was >= 0 && !(m.blocks.flags[was] & kExcavated) && new_block_id == old_block_id;
}

int add_cable(Model& m, const Vec3& p1, const Vec3& p2, int n_segments, int mat, double pretension,
              std::string& why) {
    CableSet& cs = m.cables;
    if (mat < 1 || mat >= static_cast<int>(cs.materials.size()) || !cs.materials[mat].defined) {
        why = "cable material " + std::to_string(mat) + " is not defined: give it with 'prop mat=" +
              std::to_string(mat) + " cb_area ... cb_e ... cb_kbond ... cb_sbond ...'";
        return -1;
    }
    const CableMaterial& p = cs.materials[mat];
    if (!(p.area > 0) || !(p.e > 0)) {
        why = "cable material " + std::to_string(mat) + " needs a cross-section area (cb_area) and a Young's "
              "modulus (cb_e) above 0";
        return -1;
    }
    const double len = (p2 - p1).norm();
    if (!(len > 0) || !std::isfinite(len)) {
        why = "the two ends of the cable are the same point";
        return -1;
    }
    if (p.ytens > 0 && pretension > p.ytens) {
        why = "the pretension, " + num_text(pretension) + " N, is above the cable's tensile yield force (cb_yield " +
              num_text(p.ytens) + " N)";
        return -1;
    }
    const int c = cs.size();
    cs.id.push_back(cs.next_id++);
    cs.material.push_back(mat);
    if (cs.node_offset.empty()) cs.node_offset.push_back(0);
    const int first = cs.n_nodes();
    const int n_nodes = n_segments + 1;
    const double h = len / n_segments;
    for (int k = 0; k < n_nodes; ++k) {
        const Vec3 x = k == n_segments ? p2 : Vec3(p1 + (p2 - p1) * (static_cast<double>(k) / n_segments));
        cs.pos.push_back(x);
        cs.vel.push_back(Vec3::Zero());
        cs.disp.push_back(Vec3::Zero());
        cs.force.push_back(Vec3::Zero());
        const double share = (k == 0 || k == n_segments) ? 0.5 * h : h;
        cs.length.push_back(share);
        cs.mass.push_back(p.density * p.area * share);
        cs.inertial_mass.push_back(p.density * p.area * share);
        cs.stiffness.push_back(0);
        cs.host_block.push_back(0);
        cs.host_lever.push_back(Vec3::Zero());
        cs.host_gp.push_back({-1, -1, -1, -1});
        cs.host_w.push_back({0, 0, 0, 0});
        cs.grout_force.push_back(0);
        cs.slip.push_back(0);
        cs.state.push_back(0);
        cs.vel_bc.push_back(0);
        cs.vel_bc_value.push_back(Vec3::Zero());
    }
    cs.node_offset.push_back(first + n_nodes);
    for (int k = 0; k < n_segments; ++k) {
        cs.axial.push_back(pretension);
        cs.rest_length.push_back((cs.pos[first + k + 1] - cs.pos[first + k]).norm());
        cs.seg_state.push_back(0);
    }
    for (int i = first; i < first + n_nodes; ++i) attach_node(m, i);
    refresh_stiffness(cs);
    m.geometry_changed = true; // masses and timestep follow
    return c;
}

namespace {

// Whether node i's tie to the rock still stands.
bool tie_holds(const Model& m, int i) {
    const CableSet& cs = m.cables;
    return rock_tie_holds(m, cs.host_block[i], cs.host_lever[i], cs.host_gp[i]);
}

} // namespace

void attach_cable_nodes(Model& m) {
    CableSet& cs = m.cables;
    // A node keeps its tie while it stands (it follows its material point wherever the grout has
    // let it slip); one whose rock was deleted, excavated, cut away or zoned anew, and one in no
    // rock, is tied to whatever holds it now. The grout of a node whose rock is gone (deleted or
    // excavated: the node is then free, or grouted anew into a filled block) starts again from
    // nothing; one whose block was only zoned again keeps its force and slip.
    for (int i = 0; i < cs.n_nodes(); ++i) {
        if (cs.host_block[i] > 0 && tie_holds(m, i)) continue;
        const int was = cs.host_block[i];
        attach_node(m, i);
        if (!rock_tie_kept(m, was, cs.host_block[i])) {
            cs.grout_force[i] = 0;
            cs.slip[i] = 0;
            cs.state[i] &= static_cast<std::uint8_t>(~(kGroutSlipNow | kGroutSlipPast));
        }
    }
    refresh_stiffness(cs);
}

std::string cables_problem(const Model& m) {
    const CableSet& cs = m.cables;
    for (int c = 0; c < cs.size(); ++c) {
        const int mat = cs.material[c];
        if (mat < 1 || mat >= static_cast<int>(cs.materials.size()) || !cs.materials[mat].defined ||
            !(cs.materials[mat].area > 0) || !(cs.materials[mat].e > 0)) {
            return "cable " + std::to_string(cs.id[c]) + ": its material " + std::to_string(mat) +
                   " has no cross-section area (cb_area) or Young's modulus (cb_e)";
        }
        if (m.settings.dynamic && !(cs.materials[mat].density > 0)) {
            return "cable " + std::to_string(cs.id[c]) + ": its material " + std::to_string(mat) +
                   " has no density (cb_dens), which dynamic mode needs for the nodes' masses";
        }
    }
    return "";
}

double cable_critical_timestep(const Model& m) {
    const CableSet& cs = m.cables;
    double dt = 0;
    for (int i = 0; i < cs.n_nodes(); ++i) {
        if (cs.vel_bc[i] || !(cs.mass[i] > 0) || !(cs.stiffness[i] > 0)) continue;
        const double d = kNodeSpan * std::sqrt(cs.mass[i] / cs.stiffness[i]);
        if (dt == 0 || d < dt) dt = d;
    }
    // A light rigid block held by stiff grout.
    std::vector<double> kt(m.blocks.size(), 0.0), kr(m.blocks.size(), 0.0);
    add_cable_block_stiffness(m, kt, kr);
    const BlockSet& s = m.blocks;
    for (int b = 0; b < s.size(); ++b) {
        if (!(kt[b] > 0) || (s.flags[b] & (kFixed | kDeformable | kExcavated)) || !(s.mass[b] > 0)) continue;
        const double d = 0.9 * 2.0 * std::sqrt(s.mass[b] / kt[b]);
        if (dt == 0 || d < dt) dt = d;
    }
    return dt;
}

std::string choose_cable_masses(Model& m, double raise_to) {
    CableSet& cs = m.cables;
    if (cs.n_nodes() == 0) return "";
    refresh_stiffness(cs);
    for (int c = 0; c < cs.size(); ++c) {
        for (int i = cs.node_offset[c]; i < cs.node_offset[c + 1]; ++i) {
            double mass = cs.mass[i];
            if (!m.settings.dynamic) {
                mass = cs.stiffness[i] * (m.dt / kNodeSpan) * (m.dt / kNodeSpan);
            } else if (raise_to > 0) {
                mass = std::max(mass, cs.stiffness[i] * (raise_to / kNodeSpan) * (raise_to / kNodeSpan));
            }
            if (!(mass > 0) || !std::isfinite(mass)) {
                return "node " + std::to_string(i - cs.node_offset[c] + 1) + " of cable " + std::to_string(cs.id[c]) +
                       " gets no usable mass (" + num_text(mass) + " kg): give its material a density (cb_dens) and "
                       "a cross-section (cb_area) and modulus (cb_e) of sensible size";
            }
            if (mass != cs.inertial_mass[i]) set_node_mass(cs, i, mass);
        }
    }
    return "";
}

void add_cable_gridpoint_stiffness(const Model& m, std::vector<double>& k) {
    const CableSet& cs = m.cables;
    for (int c = 0; c < cs.size(); ++c) {
        const CableMaterial& p = cs.materials[cs.material[c]];
        for (int i = cs.node_offset[c]; i < cs.node_offset[c + 1]; ++i) {
            if (cs.host_block[i] <= 0 || cs.host_gp[i][0] < 0) continue;
            for (int q = 0; q < 4; ++q) {
                const int g = cs.host_gp[i][q];
                if (g < static_cast<int>(k.size())) k[g] += cs.host_w[i][q] * p.kbond * cs.length[i];
            }
        }
    }
}

void add_cable_block_stiffness(const Model& m, std::vector<double>& kt, std::vector<double>& kr) {
    const CableSet& cs = m.cables;
    for (int c = 0; c < cs.size(); ++c) {
        const CableMaterial& p = cs.materials[cs.material[c]];
        for (int i = cs.node_offset[c]; i < cs.node_offset[c + 1]; ++i) {
            if (cs.host_block[i] <= 0 || cs.host_gp[i][0] >= 0) continue;
            const int b = m.block_index(cs.host_block[i]);
            if (b < 0 || b >= static_cast<int>(kt.size())) continue;
            const double k = p.kbond * cs.length[i];
            kt[b] += k;
            kr[b] += k * cs.host_lever[i].squaredNorm();
        }
    }
}

void cable_forces(Model& m, double dt) {
    CableSet& cs = m.cables;
    if (cs.size() == 0) return;
    BlockSet& s = m.blocks;
    GridpointSet& g = m.gridpoints;
    // Static mode: the grout's stiffness on the rigid blocks, for their masses.
    if (!m.settings.dynamic && static_cast<int>(m.contacts.joint_kt.size()) == s.size() &&
        static_cast<int>(m.contacts.joint_kr.size()) == s.size()) {
        add_cable_block_stiffness(m, m.contacts.joint_kt, m.contacts.joint_kr);
    }
    // Each node starts with the weight of its steel (cb_dens; the real mass, in static mode too).
    for (int i = 0; i < cs.n_nodes(); ++i) cs.force[i] = cs.mass[i] * m.gravity;
    for (int c = 0; c < cs.size(); ++c) {
        const CableMaterial& p = cs.materials[cs.material[c]];
        const int first = cs.node_offset[c], last = cs.node_offset[c + 1] - 1;
        const double ytens = p.ytens > 0 ? p.ytens : std::numeric_limits<double>::infinity();
        // Segments.
        for (int i = first; i < last; ++i) {
            const int seg = cs.first_segment(c) + (i - first);
            Vec3 t = cs.pos[i + 1] - cs.pos[i];
            const double l = t.norm();
            t = l > 0 ? Vec3(t / l) : Vec3::UnitX();
            const auto vel = [&](int j) { return cs.vel_bc[j] ? cs.vel_bc_value[j] : cs.vel[j]; };
            const double stretch = (vel(i + 1) - vel(i)).dot(t) * dt;
            double f = cs.axial[seg] + axial_stiffness(p, cs.rest_length[seg]) * stretch;
            std::uint8_t st = cs.seg_state[seg] & kCableYieldPast;
            if (f > ytens) {
                f = ytens;
                st |= kCableYieldTensionNow | kCableYieldPast;
            } else if (f < -p.ycomp) {
                f = -p.ycomp;
                // A cable that carries no compression (ycomp 0) goes slack: it does not yield.
                if (p.ycomp > 0) st |= kCableYieldCompNow | kCableYieldPast;
            }
            cs.axial[seg] = f;
            cs.seg_state[seg] = st;
            cs.force[i] += f * t;
            cs.force[i + 1] -= f * t;
        }
        // Grout, and what the node passes to the rock.
        for (int i = first; i <= last; ++i) {
            if (cs.host_block[i] <= 0) continue;
            int b = -1;
            const Vec3 vh = host_velocity(m, i, b);
            if (b < 0 || (s.flags[b] & kExcavated)) continue;
            const Vec3 t = node_direction(cs, c, i);
            const Vec3 vn = cs.vel_bc[i] ? cs.vel_bc_value[i] : cs.vel[i];
            const double du = (vn - vh).dot(t) * dt;
            const double k = p.kbond * cs.length[i];
            double f = cs.grout_force[i] - k * du;
            std::uint8_t st = cs.state[i] & kGroutSlipPast;
            const double cap = p.sbond > 0 ? p.sbond * cs.length[i] : std::numeric_limits<double>::infinity();
            if (std::abs(f) > cap) {
                const double capped = std::copysign(cap, f);
                if (k > 0) cs.slip[i] += (capped - f) / k;
                f = capped;
                st |= kGroutSlipNow | kGroutSlipPast;
            }
            cs.grout_force[i] = f;
            cs.state[i] = st;
            // The node keeps the axial part of its forces; the rock takes the grout's reaction
            // and everything across the axis.
            const Vec3 total = cs.force[i] + f * t;
            const double axial = total.dot(t);
            const Vec3 on_rock = -f * t + (cs.force[i] - cs.force[i].dot(t) * t);
            cs.force[i] = axial * t;
            if (cs.host_gp[i][0] >= 0) {
                for (int q = 0; q < 4; ++q) {
                    const int gp = cs.host_gp[i][q];
                    const Vec3 share = cs.host_w[i][q] * on_rock;
                    g.force[gp] += share;
                    g.force_scale[gp] += share.norm();
                }
            } else {
                const Vec3 lever = s.orientation[b] * cs.host_lever[i];
                s.force[b] += on_rock;
                s.moment[b] += lever.cross(on_rock);
                s.force_scale[b] += on_rock.norm();
            }
        }
    }
}

int integrate_cables(Model& m, double dt, AutoDampingSums* sums) {
    CableSet& cs = m.cables;
    const Damping& d = m.damping;
    int bad = -1;
    // The model's damping law, as on blocks and gridpoints (stages.h).
    auto damp = [&](double f, double v, double mass) { return damped_force(d, f, v, mass, dt); };
    for (int c = 0; c < cs.size(); ++c) {
        for (int i = cs.node_offset[c]; i < cs.node_offset[c + 1]; ++i) {
            Vec3 v;
            if (cs.vel_bc[i]) {
                v = cs.vel_bc_value[i];
            } else {
                const double mass = cs.inertial_mass[i];
                int b = -1;
                Vec3 vh = Vec3::Zero();
                if (cs.host_block[i] > 0) {
                    // The rock's velocity at t + dt/2: blocks and gridpoints have just moved.
                    vh = host_velocity(m, i, b);
                    if (b >= 0 && (m.blocks.flags[b] & kExcavated)) b = -1;
                }
                if (b >= 0) {
                    const Vec3 t = node_direction(cs, c, i);
                    const double va0 = cs.vel[i].dot(t), fa = cs.force[i].dot(t);
                    const double va = va0 + damp(fa, va0, mass) / mass * dt;
                    if (sums) sums->add(mass, fa, va0, va);
                    v = vh - vh.dot(t) * t + va * t;
                } else {
                    v = cs.vel[i];
                    for (int k = 0; k < 3; ++k) {
                        v[k] += damp(cs.force[i][k], v[k], mass) / mass * dt;
                        if (sums) sums->add(mass, cs.force[i][k], cs.vel[i][k], v[k]);
                    }
                }
            }
            cs.vel[i] = v;
            const Vec3 dx = v * dt;
            cs.pos[i] += dx;
            cs.disp[i] += dx;
            if (bad < 0 && !std::isfinite(cs.pos[i].squaredNorm())) bad = i;
        }
    }
    return bad;
}

double cable_strain_energy(const Model& m) {
    const CableSet& cs = m.cables;
    double e = 0;
    for (int c = 0; c < cs.size(); ++c) {
        const CableMaterial& p = cs.materials[cs.material[c]];
        for (int k = 0; k < cs.segments_of(c); ++k) {
            const int seg = cs.first_segment(c) + k;
            const double ks = axial_stiffness(p, cs.rest_length[seg]);
            if (ks > 0) e += 0.5 * cs.axial[seg] * cs.axial[seg] / ks;
        }
        for (int i = cs.node_offset[c]; i < cs.node_offset[c + 1]; ++i) {
            const double k = p.kbond * cs.length[i];
            if (k > 0 && cs.host_block[i] > 0) e += 0.5 * cs.grout_force[i] * cs.grout_force[i] / k;
        }
    }
    return e;
}

double cable_max_unbalanced(const Model& m) {
    const CableSet& cs = m.cables;
    double f = 0;
    for (int i = 0; i < cs.n_nodes(); ++i) {
        if (!cs.vel_bc[i]) f = std::max(f, cs.force[i].norm());
    }
    return f;
}

void cable_unbalanced_sums(const Model& m, double& unbal, double& total) {
    const CableSet& cs = m.cables;
    for (int c = 0; c < cs.size(); ++c) {
        const int first = cs.node_offset[c], last = cs.node_offset[c + 1] - 1;
        for (int i = first; i <= last; ++i) {
            if (cs.vel_bc[i]) continue;
            const int seg = cs.first_segment(c) + (i - first);
            double scale = std::abs(cs.grout_force[i]);
            if (i > first) scale += std::abs(cs.axial[seg - 1]);
            if (i < last) scale += std::abs(cs.axial[seg]);
            unbal += cs.force[i].norm();
            total += scale;
        }
    }
}

int nearest_cable_segment(const Model& m, const Vec3& x, int& cable) {
    const CableSet& cs = m.cables;
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    cable = -1;
    for (int c = 0; c < cs.size(); ++c) {
        for (int k = 0; k < cs.segments_of(c); ++k) {
            const int i = cs.node_offset[c] + k;
            const double d = (0.5 * (cs.pos[i] + cs.pos[i + 1]) - x).stableNorm();
            if (best < 0 || d < best_d) {
                best = cs.first_segment(c) + k;
                best_d = d;
                cable = c;
            }
        }
    }
    return best;
}

int nearest_cable_node(const Model& m, const Vec3& x, int& cable) {
    const CableSet& cs = m.cables;
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    cable = -1;
    for (int c = 0; c < cs.size(); ++c) {
        for (int i = cs.node_offset[c]; i < cs.node_offset[c + 1]; ++i) {
            const double d = (cs.pos[i] - x).stableNorm();
            if (best < 0 || d < best_d) {
                best = i;
                best_d = d;
                cable = c;
            }
        }
    }
    return best;
}

void remove_cables(Model& m, std::vector<int> cables) {
    CableSet& cs = m.cables;
    std::sort(cables.begin(), cables.end());
    cables.erase(std::unique(cables.begin(), cables.end()), cables.end());
    if (cables.empty()) return;
    CableSet out;
    out.next_id = cs.next_id;
    out.materials = cs.materials;
    out.node_offset.push_back(0);
    size_t r = 0;
    for (int c = 0; c < cs.size(); ++c) {
        if (r < cables.size() && cables[r] == c) {
            ++r;
            continue;
        }
        out.id.push_back(cs.id[c]);
        out.material.push_back(cs.material[c]);
        for (int i = cs.node_offset[c]; i < cs.node_offset[c + 1]; ++i) {
            out.pos.push_back(cs.pos[i]); out.vel.push_back(cs.vel[i]); out.disp.push_back(cs.disp[i]);
            out.force.push_back(cs.force[i]); out.length.push_back(cs.length[i]); out.mass.push_back(cs.mass[i]);
            out.inertial_mass.push_back(cs.inertial_mass[i]); out.stiffness.push_back(cs.stiffness[i]);
            out.host_block.push_back(cs.host_block[i]); out.host_lever.push_back(cs.host_lever[i]);
            out.host_gp.push_back(cs.host_gp[i]); out.host_w.push_back(cs.host_w[i]);
            out.grout_force.push_back(cs.grout_force[i]); out.slip.push_back(cs.slip[i]);
            out.state.push_back(cs.state[i]); out.vel_bc.push_back(cs.vel_bc[i]);
            out.vel_bc_value.push_back(cs.vel_bc_value[i]);
        }
        out.node_offset.push_back(out.n_nodes());
        for (int k = 0; k < cs.segments_of(c); ++k) {
            const int seg = cs.first_segment(c) + k;
            out.axial.push_back(cs.axial[seg]);
            out.rest_length.push_back(cs.rest_length[seg]);
            out.seg_state.push_back(cs.seg_state[seg]);
        }
    }
    if (out.size() == 0) out.node_offset.clear();
    cs = std::move(out);
    m.geometry_changed = true;
}

void reset_cable_displacements(Model& m) {
    for (Vec3& d : m.cables.disp) d.setZero();
}

} // namespace odec
