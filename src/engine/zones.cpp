#include "engine/zones.h"

#include "engine/blocks.h"
#include "engine/cable.h"
#include "engine/liner.h"

#include "engine/contact.h"

#include <algorithm>
#include <map>
#include <cmath>
#include <limits>
#include <unordered_map>

#include <Eigen/Eigenvalues>

#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/model.h"
#include "engine/parallel.h"
#include "engine/range.h"
#include "engine/table.h"
#include "engine/zone_model.h"

namespace odec {

namespace {

// Gradients of the shape functions of corners 1..3 of a tetrahedron (rows of the inverse of
// its edge matrix), and its volume; corner 0's gradient is minus their sum.
struct TetGeometry {
    Vec3 grad[4];
    double volume;
};

inline TetGeometry tet_geometry(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3) {
    const Vec3 e1 = x1 - x0, e2 = x2 - x0, e3 = x3 - x0;
    // Rows of J^-1, J = [e1 e2 e3]: (e2 x e3, e3 x e1, e1 x e2) / det.
    const Vec3 c1 = e2.cross(e3), c2 = e3.cross(e1), c3 = e1.cross(e2);
    const double det = e1.dot(c1);
    TetGeometry t;
    const double inv = 1.0 / det;
    t.grad[1] = c1 * inv;
    t.grad[2] = c2 * inv;
    t.grad[3] = c3 * inv;
    t.grad[0] = -(t.grad[1] + t.grad[2] + t.grad[3]);
    t.volume = det / 6.0;
    return t;
}

bool zone_active(const Model& m, int z) {
    return m.zones.model[z] != kZoneNull && !(m.blocks.flags[m.zones.block[z]] & kExcavated);
}

const Material* zone_material(const Model& m, int z) {
    const int mat = m.blocks.material[m.zones.block[z]];
    if (mat <= 0 || mat >= static_cast<int>(m.materials.size()) || !m.materials[mat].defined) return nullptr;
    return &m.materials[mat];
}

} // namespace

bool is_deformable(const Model& m, int b) { return (m.blocks.flags[b] & kDeformable) != 0; }

namespace {

bool point_history(HistoryKind k) {
    return (k >= HistoryKind::XDis && k <= HistoryKind::ZVel) || (k >= HistoryKind::XAcc && k <= HistoryKind::ZAcc);
}
bool zone_history(HistoryKind k) { return k >= HistoryKind::SXX && k <= HistoryKind::SYZ; }

} // namespace

void zone_blocks(Model& m, const std::vector<int>& blocks, const std::vector<int>& body, const BlockMesh& mesh) {
    // Histories of points and zones of the blocks zoned (again) follow where their points are now
    // to the new gridpoints and zones: taken before the old zones go.
    std::vector<char> zoned(m.blocks.size(), 0);
    for (int b : blocks) zoned[b] = 1;
    std::vector<std::pair<size_t, Vec3>> follow;
    for (size_t i = 0; i < m.histories.items.size(); ++i) {
        const History& h = m.histories.items[i];
        if (point_history(h.kind) && h.block_id > 0) {
            const int b = m.block_index(h.block_id);
            if (b < 0 || !zoned[b]) continue;
            follow.emplace_back(i, h.gridpoint >= 0 ? m.gridpoints.pos[h.gridpoint]
                                                    : Vec3(m.blocks.centroid[b] + m.blocks.orientation[b] * h.body_offset));
        } else if (zone_history(h.kind) && h.zone >= 0 && zoned[m.zones.block[h.zone]]) {
            follow.emplace_back(i, zone_centroid(m, h.zone));
        }
    }
    remove_zones(m, blocks);
    GridpointSet& g = m.gridpoints;
    ZoneSet& z = m.zones;
    BlockSet& s = m.blocks;
    // (body, node) -> gridpoint
    std::unordered_map<long long, int> gp_of;
    const long long n_nodes = static_cast<long long>(mesh.nodes.size());
    int first_body = 1;
    for (int b = 0; b < s.size(); ++b) first_body = std::max(first_body, s.body[b] + 1);
    auto gridpoint = [&](int k, int node) {
        const long long key = static_cast<long long>(body[k]) * n_nodes + node;
        auto it = gp_of.find(key);
        if (it != gp_of.end()) return it->second;
        const int b = blocks[k];
        const Vec3& x = mesh.nodes[node];
        g.pos.push_back(x);
        g.ref.push_back(x);
        // A block that was moving keeps its motion: each gridpoint starts with the velocity
        // its point had in the rigid block.
        g.vel.push_back(velocity_at_point(m, b, x - s.centroid[b]));
        g.disp.push_back(Vec3::Zero());
        g.force.push_back(Vec3::Zero());
        g.applied.push_back(Vec3::Zero());
        g.applied_table.push_back(0);
        g.traction.push_back(Vec3::Zero());
        g.mass.push_back(0);
        g.inertial_mass.push_back(0);
        g.stiffness.push_back(0);
        g.force_scale.push_back(0);
        g.nmd_volume.push_back(0);
        g.nmd_rate.push_back(0);
        g.block.push_back(b);
        g.vel_bc.push_back(s.flags[b] & kFixed ? 7 : 0);
        g.vel_bc_value.push_back(Vec3::Zero());
        g.vel_bc_table.push_back(0);
        g.half_kick.push_back(1);
        const int index = g.size() - 1;
        gp_of.emplace(key, index);
        return index;
    };
    for (size_t k = 0; k < blocks.size(); ++k) {
        const int b = blocks[k];
        for (const auto& t : mesh.tets[k]) {
            std::array<int, 4> q;
            for (int i = 0; i < 4; ++i) q[i] = gridpoint(static_cast<int>(k), t[i]);
            z.gp.push_back(q);
            z.block.push_back(b);
            z.model.push_back(s.cons[b]);
            z.state.push_back(0);
            z.stress.push_back(Sym6{0, 0, 0, 0, 0, 0});
            const TetGeometry tg = tet_geometry(g.pos[q[0]], g.pos[q[1]], g.pos[q[2]], g.pos[q[3]]);
            z.volume.push_back(tg.volume);
        }
        std::vector<int> corners;
        for (int node : mesh.corner_node[k]) corners.push_back(gridpoint(static_cast<int>(k), node));
        s.corner_gp[b] = std::move(corners);
        // The shape in world axes about the centroid (see refresh_deformable_vertices).
        const Mat3 r = s.orientation[b].toRotationMatrix();
        for (Vec3& v : s.shape[b].vertices) v = r * v;
        s.orientation[b] = Quat::Identity();
        // Its gridpoints carry its motion from now on, each displaced from where it starts.
        s.ref_orientation[b] = Quat::Identity();
        s.vel[b].setZero();
        s.ang_vel[b].setZero();
        s.flags[b] |= kDeformable;
        s.flags[b] &= static_cast<std::uint8_t>(~kFixed);
        s.body[b] = first_body + body[k];
    }
    z.color_order.clear();
    z.color_offset.clear();
    z.colored_zones = 0;
    update_gridpoint_masses(m);
    m.geometry_changed = true;
    for (const auto& [i, x] : follow) {
        History& h = m.histories.items[i];
        if (point_history(h.kind)) {
            h.gridpoint = find_gridpoint_of_block_near(m, m.block_index(h.block_id), x);
        } else {
            h.zone = find_zone_at(m, x);
        }
    }
}

void remove_zones(Model& m, const std::vector<int>& blocks) {
    if (m.zones.size() == 0) {
        for (int b : blocks) {
            m.blocks.corner_gp[b].clear();
            m.blocks.body[b] = 0;
            m.blocks.zone_edge[b] = 0;
            m.blocks.flags[b] &= static_cast<std::uint8_t>(~kDeformable);
        }
        return;
    }
    std::vector<char> gone(m.blocks.size(), 0);
    for (int b : blocks) gone[b] = 1;
    ZoneSet& z = m.zones;
    GridpointSet& g = m.gridpoints;
    // Keep the zones of the other blocks.
    int w = 0;
    std::vector<char> used(g.size(), 0);
    std::vector<int> new_zone(z.size(), -1);
    for (int i = 0; i < z.size(); ++i) {
        if (gone[z.block[i]]) continue;
        new_zone[i] = w;
        z.gp[w] = z.gp[i];
        z.block[w] = z.block[i];
        z.model[w] = z.model[i];
        z.state[w] = z.state[i];
        z.stress[w] = z.stress[i];
        z.volume[w] = z.volume[i];
        for (int c : z.gp[w]) used[c] = 1;
        ++w;
    }
    z.gp.resize(w); z.block.resize(w); z.model.resize(w); z.state.resize(w);
    z.stress.resize(w); z.volume.resize(w);
    z.grad.clear();
    z.color_order.clear();
    z.color_offset.clear();
    z.colored_zones = 0;
    // Keep the gridpoints still used.
    std::vector<int> new_index(g.size(), -1);
    int n = 0;
    for (int i = 0; i < g.size(); ++i) {
        if (!used[i]) continue;
        new_index[i] = n;
        g.pos[n] = g.pos[i]; g.ref[n] = g.ref[i]; g.vel[n] = g.vel[i]; g.disp[n] = g.disp[i];
        g.force[n] = g.force[i]; g.applied[n] = g.applied[i];
        g.applied_table[n] = g.applied_table[i]; g.traction[n] = g.traction[i]; g.mass[n] = g.mass[i];
        g.inertial_mass[n] = g.inertial_mass[i];
        g.stiffness[n] = g.stiffness[i]; g.force_scale[n] = g.force_scale[i];
        g.nmd_volume[n] = g.nmd_volume[i]; g.nmd_rate[n] = g.nmd_rate[i]; g.block[n] = g.block[i];
        g.vel_bc[n] = g.vel_bc[i]; g.vel_bc_value[n] = g.vel_bc_value[i];
        g.vel_bc_table[n] = g.vel_bc_table[i]; g.half_kick[n] = g.half_kick[i];
        ++n;
    }
    g.pos.resize(n); g.ref.resize(n); g.vel.resize(n); g.disp.resize(n); g.force.resize(n);
    g.applied.resize(n); g.applied_table.resize(n); g.traction.resize(n); g.mass.resize(n); g.inertial_mass.resize(n); g.stiffness.resize(n); g.force_scale.resize(n);
    g.nmd_volume.resize(n); g.nmd_rate.resize(n); g.block.resize(n); g.vel_bc.resize(n);
    g.vel_bc_value.resize(n); g.vel_bc_table.resize(n); g.half_kick.resize(n);
    for (auto& q : z.gp) {
        for (int& c : q) c = new_index[c];
    }
    // Gridpoint sub-contacts follow their gridpoints to the new numbers (before, those of the
    // other zoned blocks kept the old numbers: another gridpoint's history, or one out of range
    // that 'save' refused until the next step).
    renumber_contacts(m, nullptr, &new_index);
    // Loaded faces lose those of the removed zones.
    auto& faces = m.stress_boundary.faces;
    size_t fw = 0;
    for (size_t f = 0; f < faces.size(); ++f) {
        BoundaryFace bf = faces[f];
        bool keep = true;
        for (int& c : bf.gp) {
            c = new_index[c];
            keep = keep && c >= 0;
        }
        if (keep) faces[fw++] = bf;
    }
    faces.resize(fw);
    recompute_tractions(m);
    // Histories follow their gridpoint or zone to its new place; one whose zone or gridpoint
    // went with the blocks (-2) records 0 from now on.
    for (History& h : m.histories.items) {
        if (h.gridpoint >= 0) {
            h.gridpoint = h.gridpoint < static_cast<int>(new_index.size()) && new_index[h.gridpoint] >= 0
                              ? new_index[h.gridpoint]
                              : -2;
        }
        if (h.zone >= 0) {
            h.zone = h.zone < static_cast<int>(new_zone.size()) && new_zone[h.zone] >= 0 ? new_zone[h.zone]
                                                                                          : -2;
        }
        std::vector<int> kept;
        for (int c : h.gridpoints) {
            if (c < static_cast<int>(new_index.size()) && new_index[c] >= 0) kept.push_back(new_index[c]);
        }
        h.gridpoints = std::move(kept);
    }
    // Cable and liner nodes tied to the zones follow their gridpoints to their new places; one
    // whose zone went with the blocks is untied, and tied afresh before the next step.
    auto retie = [&](std::vector<int>& host_block, std::vector<std::array<int, 4>>& host_gp,
                     std::vector<std::array<double, 4>>& host_w) {
        for (size_t i = 0; i < host_gp.size(); ++i) {
            if (host_gp[i][0] < 0) continue;
            bool kept = true;
            for (int& c : host_gp[i]) {
                c = c < static_cast<int>(new_index.size()) ? new_index[c] : -1;
                kept = kept && c >= 0;
            }
            if (!kept) {
                host_block[i] = 0;
                host_gp[i] = {-1, -1, -1, -1};
                host_w[i] = {0, 0, 0, 0};
            }
        }
    };
    retie(m.cables.host_block, m.cables.host_gp, m.cables.host_w);
    retie(m.liners.host_block, m.liners.host_gp, m.liners.host_w);
    // A gridpoint's block is one whose zones still use it.
    for (int i = 0; i < z.size(); ++i) {
        for (int c : z.gp[i]) {
            if (gone[g.block[c]]) g.block[c] = z.block[i];
        }
    }
    for (int b = 0; b < m.blocks.size(); ++b) {
        if (gone[b]) {
            m.blocks.corner_gp[b].clear();
            m.blocks.body[b] = 0;
            m.blocks.zone_edge[b] = 0;
            m.blocks.flags[b] &= static_cast<std::uint8_t>(~kDeformable);
        } else {
            for (int& c : m.blocks.corner_gp[b]) c = new_index[c];
        }
    }
    update_gridpoint_masses(m);
    m.geometry_changed = true;
}

void update_gridpoint_masses(Model& m) {
    GridpointSet& g = m.gridpoints;
    const ZoneSet& z = m.zones;
    std::fill(g.mass.begin(), g.mass.end(), 0.0);
    std::fill(g.stiffness.begin(), g.stiffness.end(), 0.0);
    m.zones.grad.clear();  // the geometry in use may have changed (zoning, `set small`)
    const bool large = m.settings.large_strain;
    for (int i = 0; i < z.size(); ++i) {
        if (!zone_active(m, i)) continue;
        const Material* mat = zone_material(m, i);
        if (!mat) continue;
        const auto& q = z.gp[i];
        const std::vector<Vec3>& x = large ? g.pos : g.ref;
        const TetGeometry t = tet_geometry(x[q[0]], x[q[1]], x[q[2]], x[q[3]]);
        // The mass is the zone's as zoned: a zone that has since changed volume in large strain
        // keeps its mass (and its weight); its stiffness is that of its shape now.
        const Vec3& r0 = g.ref[q[0]];
        // The same arithmetic as tet_geometry's volume: the same bits where nothing has moved.
        const double zoned_volume =
            large ? (g.ref[q[1]] - r0).dot((g.ref[q[2]] - r0).cross(g.ref[q[3]] - r0)) / 6.0 : t.volume;
        const double quarter = 0.25 * mat->density * zoned_volume;
        double norms[4], sum = 0;
        for (int k = 0; k < 4; ++k) {
            norms[k] = t.grad[k].norm();
            sum += norms[k];
        }
        const double modulus = (mat->bulk + 4.0 * mat->shear / 3.0) * t.volume;
        for (int k = 0; k < 4; ++k) {
            g.mass[q[k]] += quarter;
            g.stiffness[q[k]] += modulus * norms[k] * sum;
        }
    }
    g.inertial_mass = g.mass; // until the cycle chooses them (mass_scaling.h)
}

void refresh_deformable_vertices(Model& m) {
    BlockSet& s = m.blocks;
    for (int b = 0; b < s.size(); ++b) {
        if (!(s.flags[b] & kDeformable)) continue;
        const auto& corners = s.corner_gp[b];
        Vec3* out = s.world_vertices.data() + s.vertex_offset[b];
        Vec3 c = Vec3::Zero(), local = Vec3::Zero(), d = Vec3::Zero();
        for (size_t v = 0; v < corners.size(); ++v) {
            out[v] = m.gridpoints.pos[corners[v]];
            c += out[v];
            local += s.shape[b].vertices[v];
            d += m.gridpoints.disp[corners[v]];
        }
        // The block's centroid and displacement follow its corners (for ranges and tables):
        // its shape was put in world axes when it was zoned, so the centroid is the mean of
        // the corners less the mean of the shape's vertices about it.
        if (!corners.empty()) {
            const double n = static_cast<double>(corners.size());
            s.centroid[b] = (c - local) / n;
            s.disp[b] = d / n;
        }
    }
}

std::string zones_problem(const Model& m) {
    const ZoneSet& z = m.zones;
    const BlockSet& s = m.blocks;
    std::vector<char> seen(s.size(), 0);
    for (int i = 0; i < z.size(); ++i) {
        const int b = z.block[i];
        if (seen[b] || !zone_active(m, i)) continue;
        seen[b] = 1;
        const int mat = s.material[b];
        const Material* mp = zone_material(m, i);
        const std::string id = std::to_string(s.id[b]);
        if (!mp) {
            return "the zones of block " + id + " have no material: material " + std::to_string(mat) +
                   " is not defined (give one with 'prop mat=" + std::to_string(mat) + " dens=... k=... g=...')";
        }
        if (!(mp->density > 0)) {
            return "the zones of block " + id + " have no mass: material " + std::to_string(mat) +
                   " has no density (give one with 'prop mat=" + std::to_string(mat) + " dens=...')";
        }
        if (!(mp->bulk > 0) || !(mp->shear > 0)) {
            return "the zones of block " + id + " have no stiffness: material " + std::to_string(mat) +
                   " needs a bulk and a shear modulus (give them with 'prop mat=" + std::to_string(mat) +
                   " k=... g=...' or 'ymod=... prat=...')";
        }
    }
    for (int i = 0; i < z.size(); ++i) {
        if (!zone_active(m, i)) continue;
        const auto& q = z.gp[i];
        const std::vector<Vec3>& x = m.settings.large_strain ? m.gridpoints.pos : m.gridpoints.ref;
        const TetGeometry t = tet_geometry(x[q[0]], x[q[1]], x[q[2]], x[q[3]]);
        if (!(t.volume > 0)) {
            return "a zone of block " + std::to_string(s.id[z.block[i]]) +
                   " has turned inside out (its volume is no longer positive): the deformation is too large "
                   "for its zones";
        }
    }
    return "";
}

namespace {

// The stiffness the joints can add to each surface gridpoint of a deformable block that has
// something to touch (a rigid block, or a block of another continuum): the stiffest joint
// material over the gridpoint's share of its surface, twice (the spring ties it to a point
// of the other block). Empty when no gridpoint can touch anything.
std::vector<double> joint_stiffness_on_gridpoints(const Model& m) {
    const BlockSet& s = m.blocks;
    const ContactSet& cs = m.contacts;
    double kj = 0;
    for (const JointMaterial& j : m.joint_materials) {
        if (j.defined) kj = std::max(kj, std::max(j.kn, j.ks));
    }
    if (!(kj > 0) || !cs.surface_ready || static_cast<int>(cs.surface_offset.size()) != s.size() + 1) return {};
    int first_body = -1;
    bool other = false;
    for (int b = 0; b < s.size() && !other; ++b) {
        if (s.flags[b] & kExcavated) continue;
        if (!(s.flags[b] & kDeformable)) other = true;
        else if (first_body < 0) first_body = s.body[b];
        else other = s.body[b] != first_body;
    }
    if (!other) return {};
    const GridpointSet& g = m.gridpoints;
    std::vector<double> k(g.size(), 0.0);
    for (int b = 0; b < s.size(); ++b) {
        if (s.flags[b] & kExcavated) continue;
        for (int t = cs.surface_offset[b]; t < cs.surface_offset[b + 1]; ++t) {
            const auto& q = cs.surface_tri[t];
            const double area = 0.5 * (g.pos[q[1]] - g.pos[q[0]]).cross(g.pos[q[2]] - g.pos[q[0]]).norm();
            for (int c : q) k[c] += 2.0 * kj * area / 3.0;
        }
    }
    return k;
}

} // namespace

std::vector<double> gridpoint_stiffness(const Model& m, double joint_factor) {
    std::vector<double> k = m.gridpoints.stiffness;
    const std::vector<double> joint = joint_stiffness_on_gridpoints(m);
    for (size_t i = 0; i < joint.size() && i < k.size(); ++i) k[i] += joint_factor * joint[i];
    // The grout of cables tied to the zones (cable.h).
    add_cable_gridpoint_stiffness(m, k);
    add_liner_gridpoint_stiffness(m, k);
    return k;
}

double zone_critical_timestep(const Model& m) {
    const GridpointSet& g = m.gridpoints;
    const std::vector<double> stiff = gridpoint_stiffness(m);
    double dt = 0;
    for (int i = 0; i < g.size(); ++i) {
        const double k = stiff[i];
        if (!(g.mass[i] > 0) || !(k > 0) || g.vel_bc[i] == 7) continue;
        const double d = 2.0 * std::sqrt(g.mass[i] / k);
        if (dt == 0 || d < dt) dt = d;
    }
    // The bound on the stiffness is already on the safe side; a little more margin for the
    // geometry that changes between refreshes in large strain.
    return 0.9 * dt;
}

namespace {

// Shape-function gradients and volume of every zone from these positions.
void refresh_zone_geometry(ZoneSet& z, const std::vector<Vec3>& x) {
    const int nz = z.size();
    z.grad.resize(nz);
    const int threads = thread_count();
    parallel_for(nz, threads, nz >= kParallelMinItems, [&](int i) {
        const auto& q = z.gp[i];
        const TetGeometry t = tet_geometry(x[q[0]], x[q[1]], x[q[2]], x[q[3]]);
        auto& g = z.grad[i];
        for (int k = 0; k < 3; ++k) {
            g[3 * k] = t.grad[k + 1].x();
            g[3 * k + 1] = t.grad[k + 1].y();
            g[3 * k + 2] = t.grad[k + 1].z();
        }
        z.volume[i] = t.volume;
    });
}

} // namespace

namespace {

// Zones are taken in chunks of consecutive indices (the mesher numbers neighbours close
// together, so a chunk is a compact piece of the mesh, and a thread walking it reuses what it
// loaded). The chunks are coloured greedily in order: each takes the first colour that none of
// the chunks sharing a gridpoint with it has. Up to 256 colours (a few dozen are usual); a
// chunk that finds none goes to a last colour, always there, run on one thread.
void color_zones(ZoneSet& z, int n_gp) {
    constexpr int kColors = 256, kWords = kColors / 64;
    const int nz = z.size();
    const int n_chunks = (nz + kZoneChunk - 1) / kZoneChunk;
    std::vector<std::array<std::uint64_t, kWords>> used(n_gp, std::array<std::uint64_t, kWords>{});
    std::vector<int> color(n_chunks);
    std::vector<int> count(kColors + 1, 0);
    for (int ch = 0; ch < n_chunks; ++ch) {
        const int lo = ch * kZoneChunk, hi = std::min(nz, lo + kZoneChunk);
        std::array<std::uint64_t, kWords> taken{};
        for (int i = lo; i < hi; ++i) {
            for (int c : z.gp[i]) {
                for (int w = 0; w < kWords; ++w) taken[w] |= used[c][w];
            }
        }
        int col = kColors; // the serial colour
        for (int w = 0; w < kWords && col == kColors; ++w) {
            if (~taken[w]) col = 64 * w + __builtin_ctzll(~taken[w]);
        }
        color[ch] = col;
        ++count[col];
        if (col < kColors) {
            for (int i = lo; i < hi; ++i) {
                for (int c : z.gp[i]) used[c][col / 64] |= std::uint64_t{1} << (col % 64);
            }
        }
    }
    std::vector<int> start(kColors + 2, 0);
    for (int c = 0; c <= kColors; ++c) start[c + 1] = start[c] + count[c];
    std::vector<int> next(start.begin(), start.end() - 1);
    z.color_order.assign(n_chunks, 0);
    for (int ch = 0; ch < n_chunks; ++ch) z.color_order[next[color[ch]]++] = ch;
    // Drop the empty colours (the serial one stays last).
    z.color_offset.assign(1, 0);
    for (int c = 0; c < kColors; ++c) {
        if (start[c + 1] > start[c]) z.color_offset.push_back(start[c + 1]);
    }
    z.color_offset.push_back(n_chunks);
    z.colored_zones = nz;
}

// Elastic strain energy per unit volume of a stress: p^2 / 2K + s:s / 4G.
double strain_energy_density(const ZoneMaterialConstants& c, const Sym6& s) {
    const double p = (s[0] + s[1] + s[2]) / 3.0;
    const double d0 = s[0] - p, d1 = s[1] - p, d2 = s[2] - p;
    const double dev = d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
    return (c.bulk > 0 ? p * p / (2.0 * c.bulk) : 0.0) + (c.shear > 0 ? dev / (4.0 * c.shear) : 0.0);
}

// Plastic work per unit volume of a step that took the stress from s0 to s1 under the strain
// increment de (tensor components): the mean stress's work less the change of elastic energy.
double plastic_work(const ZoneMaterialConstants& c, const Sym6& s0, const Sym6& s1, const Sym6& de) {
    double w = 0;
    for (int k = 0; k < 6; ++k) w += (k < 3 ? 0.5 : 1.0) * (s0[k] + s1[k]) * de[k];
    return w - (strain_energy_density(c, s1) - strain_energy_density(c, s0));
}

} // namespace

void zone_forces(Model& m, double dt) {
    GridpointSet& g = m.gridpoints;
    ZoneSet& z = m.zones;
    const int ng = g.size();
    const Vec3 grav = m.gravity;
    const int threads = thread_count();
    // Loads that follow a table: its factor at this step's time, looked up once per table.
    std::map<int, double> factors;
    for (int i = 0; i < ng; ++i) {
        if (g.applied_table[i] != 0) factors.emplace(g.applied_table[i], 0.0);
    }
    for (const BoundaryFace& bf : m.stress_boundary.faces) {
        if (bf.table != 0) factors.emplace(bf.table, 0.0);
    }
    for (auto& [n, f] : factors) f = m.table_factor(n);
    // Each gridpoint's force starts as its weight and loads; pass 1 below neither reads nor
    // writes it, so in the parallel region it is set with the first pass.
    auto init = [&](int i) {
        const Vec3 w = g.mass[i] * grav;
        const Vec3 applied = g.applied_table[i] == 0 ? g.applied[i] : Vec3(factors.at(g.applied_table[i]) * g.applied[i]);
        g.force[i] = w + applied + g.traction[i];
        g.force_scale[i] = w.norm() + applied.norm() + g.traction[i].norm();
        g.nmd_volume[i] = 0;
        g.nmd_rate[i] = 0;
    };
    // The loaded faces that follow a table (those without are in `traction`), after `init`.
    auto table_faces = [&] {
        for (const BoundaryFace& bf : m.stress_boundary.faces) {
            if (bf.table == 0) continue;
            const Vec3 f = factors.at(bf.table) * bf.force / 3.0;
            for (int c : bf.gp) {
                g.force[c] += f;
                g.force_scale[c] += f.norm();
            }
        }
    };
    const int nz = z.size();
    if (nz == 0) {
        parallel_for(ng, threads, ng >= kParallelMinItems, init);
        if (!factors.empty()) table_faces();
        return;
    }
    const bool large = m.settings.large_strain;
    // In large strain the zones follow their corners; in small strain their geometry is that
    // of the model when zoned, computed once.
    if (large || z.grad.size() != static_cast<size_t>(nz)) refresh_zone_geometry(z, large ? g.pos : g.ref);
    if (z.colored_zones != nz || z.color_offset.empty()) color_zones(z, ng);
    // Material constants once per material; per zone whether it carries stress.
    thread_local std::vector<ZoneMaterialConstants> constants; // kept: no allocation per step
    constants.assign(m.materials.size(), ZoneMaterialConstants());
    for (size_t k = 0; k < m.materials.size(); ++k) {
        if (m.materials[k].defined) constants[k] = zone_constants(m.materials[k]);
    }
    const ZoneMaterialConstants* cst = constants.data();
    const int* bmat = m.blocks.material.data();
    const Vec3* vel = g.vel.data();
    const int* order = z.color_order.data();
    const int n_colors = static_cast<int>(z.color_offset.size()) - 1;
    // The energy account (energy.h): what yielding zones dissipate, by chunk, added in order.
    thread_local std::vector<double> chunk_plastic;
    const bool account = m.energy.on;
    if (account) chunk_plastic.assign((nz + kZoneChunk - 1) / kZoneChunk, 0.0);
    double* plastic = chunk_plastic.data();
    // The last colour holds the zones that found no colour (usually none): one thread takes them.
    // Pass 1: volumetric strain rates, averaged at the gridpoints (volume-weighted).
    auto pass1 = [&](int i) {
        if (!zone_active(m, i)) return;
        const auto& q = z.gp[i];
        const auto& gr = z.grad[i];
        const Vec3 v0 = vel[q[0]];
        const Vec3 d1 = vel[q[1]] - v0, d2 = vel[q[2]] - v0, d3 = vel[q[3]] - v0;
        const double ev = d1.x() * gr[0] + d1.y() * gr[1] + d1.z() * gr[2] + d2.x() * gr[3] + d2.y() * gr[4] +
                          d2.z() * gr[5] + d3.x() * gr[6] + d3.y() * gr[7] + d3.z() * gr[8];
        const double vev = z.volume[i] * ev;
        for (int k = 0; k < 4; ++k) {
            g.nmd_rate[q[k]] += vev;
            g.nmd_volume[q[k]] += z.volume[i];
        }
    };
    // Pass 2: strain increments, stresses and corner forces.
    auto pass2 = [&](int i) {
        if (!zone_active(m, i)) return;
        const auto& q = z.gp[i];
        const auto& gr = z.grad[i];
        // Velocity gradient L_ab = sum_k (v_k - v_0)_a grad_k,b over corners 1..3.
        const Vec3 v0 = vel[q[0]];
        const Vec3 d1 = vel[q[1]] - v0, d2 = vel[q[2]] - v0, d3 = vel[q[3]] - v0;
        double l[3][3];
        for (int a = 0; a < 3; ++a) {
            for (int b = 0; b < 3; ++b) l[a][b] = d1[a] * gr[b] + d2[a] * gr[3 + b] + d3[a] * gr[6 + b];
        }
        const double ev = l[0][0] + l[1][1] + l[2][2];
        const double ev_bar = 0.25 * (g.nmd_rate[q[0]] + g.nmd_rate[q[1]] + g.nmd_rate[q[2]] + g.nmd_rate[q[3]]);
        const double dv = (ev_bar - ev) / 3.0;
        const Sym6 de = {(l[0][0] + dv) * dt, (l[1][1] + dv) * dt, (l[2][2] + dv) * dt,
                         0.5 * (l[0][1] + l[1][0]) * dt, 0.5 * (l[0][2] + l[2][0]) * dt,
                         0.5 * (l[1][2] + l[2][1]) * dt};
        Sym6& s = z.stress[i];
        if (large) {
            // Jaumann rotation of the stress by the spin over the step, w = (L - L^T) dt / 2:
            // sigma += w sigma - sigma w.
            const double wxy = 0.5 * (l[0][1] - l[1][0]) * dt, wxz = 0.5 * (l[0][2] - l[2][0]) * dt,
                         wyz = 0.5 * (l[1][2] - l[2][1]) * dt;
            const double sxx = s[0], syy = s[1], szz = s[2], sxy = s[3], sxz = s[4], syz = s[5];
            s[0] = sxx + 2.0 * (wxy * sxy + wxz * sxz);
            s[1] = syy + 2.0 * (-wxy * sxy + wyz * syz);
            s[2] = szz + 2.0 * (-wxz * sxz - wyz * syz);
            s[3] = sxy + wxy * (syy - sxx) + wxz * syz + wyz * sxz;
            s[4] = sxz + wxz * (szz - sxx) + wxy * syz - wyz * sxy;
            s[5] = syz + wyz * (szz - syy) - wxy * sxz - wxz * sxy;
        }
        const ZoneMaterialConstants& c = cst[bmat[z.block[i]]];
        if (z.model[i] == kZoneMohrCoulomb) {
            Sym6 before;
            if (account) before = s;
            const std::uint8_t now = mohr_coulomb_increment(c, de, s);
            if (account && now) plastic[i / kZoneChunk] += z.volume[i] * plastic_work(c, before, s, de);
            z.state[i] = static_cast<std::uint8_t>((z.state[i] & (kShearPast | kTensionPast)) | now |
                                                   ((now & kShearNow) ? kShearPast : 0) |
                                                   ((now & kTensionNow) ? kTensionPast : 0));
        } else {
            elastic_increment(c, de, s);
        }
        // Corner forces -V sigma grad_k; corner 0 takes minus the sum of the others.
        const double v = z.volume[i];
        Vec3 f0 = Vec3::Zero();
        for (int k = 0; k < 3; ++k) {
            const double ax = gr[3 * k], ay = gr[3 * k + 1], az = gr[3 * k + 2];
            const Vec3 f(-v * (s[0] * ax + s[3] * ay + s[4] * az), -v * (s[3] * ax + s[1] * ay + s[5] * az),
                         -v * (s[4] * ax + s[5] * ay + s[2] * az));
            g.force[q[k + 1]] += f;
            g.force_scale[q[k + 1]] += f.norm();
            f0 -= f;
        }
        g.force[q[0]] += f0;
        g.force_scale[q[0]] += f0.norm();
    };
    // Colour by colour: no two chunks of a colour share a gridpoint, so the threads never add
    // into the same number, and each gridpoint sums its zones in the same order (colour, then
    // zone) however many threads there are and however the chunks are shared out.
    auto chunk_range = [&](int ch, auto&& body) {
        const int lo = ch * kZoneChunk, hi = std::min(nz, lo + kZoneChunk);
        for (int i = lo; i < hi; ++i) body(i);
    };
    const bool parallel = threads > 1 && nz >= kParallelMinZones;
    // Inside the parallel region, on every thread: the colours in order, a barrier after each.
    auto by_colour = [&](auto&& pass) {
        for (int c = 0; c < n_colors; ++c) {
            const int lo = z.color_offset[c], hi = z.color_offset[c + 1];
            if (c == n_colors - 1) {
                if (lo == hi) continue; // no zone found no colour: no barrier either
#pragma omp single
                for (int k = lo; k < hi; ++k) chunk_range(order[k], pass);
                continue;
            }
#pragma omp for schedule(dynamic, 1)
            for (int k = lo; k < hi; ++k) chunk_range(order[k], pass);
        }
    };
    // One parallel region a step: the gridpoints' start, pass 1, the averages, the loaded faces
    // that follow a table, pass 2.
    auto passes = [&] {
#pragma omp for schedule(static)
        for (int i = 0; i < ng; ++i) init(i);
        by_colour(pass1);
#pragma omp for schedule(static)
        for (int i = 0; i < ng; ++i) {
            if (g.nmd_volume[i] > 0) g.nmd_rate[i] /= g.nmd_volume[i];
        }
        if (!factors.empty()) {
#pragma omp single
            table_faces();
        }
        by_colour(pass2);
    };
    if (parallel) {
#pragma omp parallel num_threads(threads)
        passes();
    } else {
        passes(); // no OpenMP region entered (parallel.h); its worksharing runs on this thread
    }
    if (account) {
        double sum = 0;
        for (double p : chunk_plastic) sum += p;
        m.energy.plastic += sum;
    }
}

std::vector<int> select_gridpoints(const Model& m, const Range& r) {
    const GridpointSet& g = m.gridpoints;
    std::vector<int> out;
    // A gridpoint shared by blocks of one continuum passes when one of its blocks does.
    std::vector<char> pass(g.size(), 0);
    const ZoneSet& z = m.zones;
    for (int i = 0; i < z.size(); ++i) {
        const int b = z.block[i];
        if (m.blocks.flags[b] & kExcavated) continue;
        for (int c : z.gp[i]) {
            if (!pass[c] && r.contains_point(m, g.pos[c], b)) pass[c] = 1;
        }
    }
    for (int i = 0; i < g.size(); ++i) {
        if (pass[i]) out.push_back(i);
    }
    return out;
}

std::vector<std::pair<int, int>> boundary_faces(const Model& m) {
    const ZoneSet& z = m.zones;
    // Sorted corner triple -> (zone, opposite corner); a second sighting marks it interior.
    struct Entry {
        std::array<int, 3> key;
        int zone, corner;
    };
    std::vector<Entry> all;
    all.reserve(4 * static_cast<size_t>(z.size()));
    for (int i = 0; i < z.size(); ++i) {
        if (!zone_active(m, i)) continue;
        const auto& q = z.gp[i];
        for (int k = 0; k < 4; ++k) {
            std::array<int, 3> f;
            int n = 0;
            for (int j = 0; j < 4; ++j) {
                if (j != k) f[n++] = q[j];
            }
            std::sort(f.begin(), f.end());
            all.push_back({f, i, k});
        }
    }
    std::sort(all.begin(), all.end(), [](const Entry& a, const Entry& b) {
        return a.key != b.key ? a.key < b.key : a.zone < b.zone;
    });
    std::vector<std::pair<int, int>> out;
    for (size_t i = 0; i < all.size();) {
        size_t j = i + 1;
        while (j < all.size() && all[j].key == all[i].key) ++j;
        if (j == i + 1) out.emplace_back(all[i].zone, all[i].corner);
        i = j;
    }
    std::sort(out.begin(), out.end());
    return out;
}

namespace {

Sym6 stress_at(const Vec3& x, const Sym6& s, const Sym6& gx, const Sym6& gy, const Sym6& gz) {
    Sym6 r;
    for (int k = 0; k < 6; ++k) r[k] = s[k] + x.x() * gx[k] + x.y() * gy[k] + x.z() * gz[k];
    return r;
}

// Corners of zone z's face opposite corner k, and its area vector (area times outward normal).
std::array<int, 3> face_corners(const ZoneSet& z, int i, int k) {
    std::array<int, 3> f;
    int n = 0;
    for (int j = 0; j < 4; ++j) {
        if (j != k) f[n++] = z.gp[i][j];
    }
    std::sort(f.begin(), f.end());
    return f;
}

} // namespace

void recompute_tractions(Model& m) {
    GridpointSet& g = m.gridpoints;
    std::fill(g.traction.begin(), g.traction.end(), Vec3::Zero());
    for (const BoundaryFace& bf : m.stress_boundary.faces) {
        if (bf.table != 0) continue;
        for (int c : bf.gp) g.traction[c] += bf.force / 3.0;
    }
}

int apply_boundary_stress(Model& m, const Range& r, const Sym6& s, const Sym6& gx, const Sym6& gy,
                          const Sym6& gz, int table) {
    const ZoneSet& z = m.zones;
    const GridpointSet& g = m.gridpoints;
    auto& faces = m.stress_boundary.faces;
    std::vector<BoundaryFace> loaded;
    const FaceCover cover(m);
    for (const auto& [i, k] : boundary_faces(m)) {
        const std::array<int, 3> f = face_corners(z, i, k);
        const Vec3 centre = (g.pos[f[0]] + g.pos[f[1]] + g.pos[f[2]]) / 3.0;
        if (!r.contains_point(m, centre, z.block[i])) continue;
        const auto& q = z.gp[i];
        const TetGeometry t = tet_geometry(g.pos[q[0]], g.pos[q[1]], g.pos[q[2]], g.pos[q[3]]);
        const Vec3 area = -3.0 * t.volume * t.grad[k];  // outward, |area| = face area
        // A face against another block (a joint, a zoned block on a rigid one) is no boundary.
        if (cover.covered(z.block[i], centre, area.normalized())) continue;
        const Sym6 st = stress_at(centre, s, gx, gy, gz);
        const Vec3 force(st[0] * area.x() + st[3] * area.y() + st[4] * area.z(),
                         st[3] * area.x() + st[1] * area.y() + st[5] * area.z(),
                         st[4] * area.x() + st[5] * area.y() + st[2] * area.z());
        loaded.push_back({f, force, table});
    }
    // Replace what was on those faces.
    std::sort(loaded.begin(), loaded.end(), [](const BoundaryFace& a, const BoundaryFace& b) { return a.gp < b.gp; });
    size_t w = 0;
    for (size_t i = 0; i < faces.size(); ++i) {
        const bool replaced = std::binary_search(loaded.begin(), loaded.end(), faces[i],
                                                 [](const BoundaryFace& a, const BoundaryFace& b) { return a.gp < b.gp; });
        if (!replaced) faces[w++] = faces[i];
    }
    faces.resize(w);
    faces.insert(faces.end(), loaded.begin(), loaded.end());
    recompute_tractions(m);
    return static_cast<int>(loaded.size());
}

int remove_boundary_stress(Model& m, const Range& r) {
    auto& faces = m.stress_boundary.faces;
    const GridpointSet& g = m.gridpoints;
    size_t w = 0;
    int removed = 0;
    for (size_t i = 0; i < faces.size(); ++i) {
        const auto& f = faces[i].gp;
        const Vec3 centre = (g.pos[f[0]] + g.pos[f[1]] + g.pos[f[2]]) / 3.0;
        if (r.contains_point(m, centre, g.block[f[0]])) {
            ++removed;
            continue;
        }
        faces[w++] = faces[i];
    }
    faces.resize(w);
    recompute_tractions(m);
    return removed;
}

int set_insitu_stress(Model& m, const Range& r, const Sym6& s, const Sym6& gx, const Sym6& gy, const Sym6& gz) {
    ZoneSet& z = m.zones;
    int n = 0;
    for (int i = 0; i < z.size(); ++i) {
        if (m.blocks.flags[z.block[i]] & kExcavated) continue;
        const Vec3 c = zone_centroid(m, i);
        if (!r.contains_point(m, c, z.block[i])) continue;
        z.stress[i] = stress_at(c, s, gx, gy, gz);
        ++n;
    }
    return n;
}

Vec3 gridpoint_velocity_at_t(const Model& m, int i) {
    const GridpointSet& g = m.gridpoints;
    if (g.half_kick[i] || !(g.mass[i] > 0) || !(g.inertial_mass[i] > 0)) return g.vel[i];
    Vec3 v = g.vel[i];
    // Half a step of the last acceleration (force over mass, damping aside).
    for (int k = 0; k < 3; ++k) {
        if (!(g.vel_bc[i] & (1 << k))) v[k] += 0.5 * m.dt * g.force[i][k] / g.inertial_mass[i];
    }
    return v;
}

void principal_stresses(const Sym6& s, Vec3& values, Mat3* directions) {
    Mat3 t;
    t << s[0], s[3], s[4], s[3], s[1], s[5], s[4], s[5], s[2];
    Eigen::SelfAdjointEigenSolver<Mat3> eig;
    eig.computeDirect(t, directions ? Eigen::ComputeEigenvectors : Eigen::EigenvaluesOnly);
    values = eig.eigenvalues();
    if (directions) *directions = eig.eigenvectors();
}

Vec3 zone_centroid(const Model& m, int z) {
    const auto& q = m.zones.gp[z];
    const auto& x = m.gridpoints.pos;
    return 0.25 * (x[q[0]] + x[q[1]] + x[q[2]] + x[q[3]]);
}

int find_zone_at(const Model& m, const Vec3& p) {
    const ZoneSet& z = m.zones;
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (int i = 0; i < z.size(); ++i) {
        if (m.blocks.flags[z.block[i]] & kExcavated) continue;
        const auto& q = z.gp[i];
        const auto& x = m.gridpoints.pos;
        const TetGeometry t = tet_geometry(x[q[0]], x[q[1]], x[q[2]], x[q[3]]);
        // Barycentric coordinates: N_k = 1/4 + grad_k . (p - centroid).
        const Vec3 c = 0.25 * (x[q[0]] + x[q[1]] + x[q[2]] + x[q[3]]);
        double lowest = 1;
        for (int k = 0; k < 4; ++k) lowest = std::min(lowest, 0.25 + t.grad[k].dot(p - c));
        if (lowest >= -1e-9) return i;
        const double d = (c - p).squaredNorm();
        if (d < best_d) {
            best_d = d;
            best = i;
        }
    }
    return best;
}

int find_gridpoint_of_block_near(const Model& m, int b, const Vec3& p) {
    // The corners of its zones (a gridpoint it shares with a block joined to it is its own too).
    const GridpointSet& g = m.gridpoints;
    const ZoneSet& z = m.zones;
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (int zi = 0; zi < z.size(); ++zi) {
        if (z.block[zi] != b) continue;
        for (int i : z.gp[zi]) {
            const double d = (g.pos[i] - p).squaredNorm();
            if (d < best_d || (d == best_d && i < best)) {
                best_d = d;
                best = i;
            }
        }
    }
    return best;
}

int find_gridpoint_near(const Model& m, const Vec3& p) {
    const GridpointSet& g = m.gridpoints;
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (int i = 0; i < g.size(); ++i) {
        if (m.blocks.flags[g.block[i]] & kExcavated) continue;
        const double d = (g.pos[i] - p).squaredNorm();
        if (d < best_d) {
            best_d = d;
            best = i;
        }
    }
    return best;
}

} // namespace odec
