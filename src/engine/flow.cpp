// Fluid flow along the joints: nodes, links, the pressure update and the pressure forces
// (flow.h explains the scheme).
#include "engine/flow.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/grid_cell.h"
#include "engine/model.h"
#include "engine/range.h"
#include "engine/zones.h"

namespace odec {

namespace {

// Whether contact c is one flow runs in: neither of its blocks excavated, and a joint, not a cut
// joined into one mass (a glued contact: 'poly tunnel' rings and radial cuts, joined blocks).
bool flow_contact(const Model& m, int c) {
    const BlockSet& s = m.blocks;
    const int a = m.contacts.block_a[c], b = m.contacts.block_b[c];
    return !((s.flags[a] | s.flags[b]) & kExcavated) && !m.contacts.joined(c);
}

// Whether contact c has a deformable block: its sub-contacts are gridpoints (contact_gridpoint.h).
bool gridpoint_contact(const Model& m, int c) {
    const BlockSet& s = m.blocks;
    return ((s.flags[m.contacts.block_a[c]] | s.flags[m.contacts.block_b[c]]) & kDeformable) != 0;
}

// Smallest cosine between a surface triangle's outward normal and the contact normal for the
// triangle to carry flow links: the faces that lie along the joint.
constexpr double kLinkFacing = 0.5;

struct CellKey {
    std::int64_t x, y, z;
    bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct CellHash {
    std::size_t operator()(const CellKey& k) const {
        return static_cast<std::size_t>(grid_cell_hash(k.x, k.y, k.z));
    }
};

// Points within tol of one another, by cells twice as wide: the points within tol of x lie in the
// 2 x 2 x 2 cells around the corner of its cell nearest it. find gives the nearest point kept within
// `within` (<= tol) of x (the lowest index among equals), or -1.
struct PointGrid {
    double tol;
    std::unordered_map<CellKey, std::vector<int>, CellHash> cells;
    const std::vector<Vec3>* pts;
    double cell() const { return 2 * tol; }
    CellKey key(const Vec3& x) const {
        return {grid_cell(x.x() / cell()), grid_cell(x.y() / cell()), grid_cell(x.z() / cell())};
    }
    int find(const Vec3& x, double within) const {
        const CellKey k = key(x);
        // Toward the nearer neighbour along each axis.
        const int sx = x.x() / cell() - k.x < 0.5 ? -1 : 1, sy = x.y() / cell() - k.y < 0.5 ? -1 : 1,
                  sz = x.z() / cell() - k.z < 0.5 ? -1 : 1;
        int best = -1;
        double best_d = within * within;
        for (int dx = 0; dx <= 1; ++dx)
            for (int dy = 0; dy <= 1; ++dy)
                for (int dz = 0; dz <= 1; ++dz) {
                    auto it = cells.find({k.x + dx * sx, k.y + dy * sy, k.z + dz * sz});
                    if (it == cells.end()) continue;
                    for (int i : it->second) {
                        const double d = ((*pts)[i] - x).squaredNorm();
                        if (d <= best_d && (best < 0 || d < best_d || i < best)) {
                            best_d = d;
                            best = i;
                        }
                    }
                }
        return best;
    }
    void add(int i) { cells[key((*pts)[i])].push_back(i); }
};

// The area of block b's face whose outward normal is nearest n, m^2.
double facing_face_area(const Model& m, int b, const Vec3& n) {
    const Polyhedron& p = m.blocks.shape[b];
    double best = -2, area = 0;
    for (int f = 0; f < p.n_faces(); ++f) {
        const double c = (m.blocks.orientation[b] * p.face_normal(f)).dot(n);
        if (c > best) {
            best = c;
            area = p.face_area(f);
        }
    }
    return area;
}


// A fingerprint of what the flow network is made from: which contacts carry flow, their blocks,
// their sub-contacts' identities and sides, and the partner triangles of gridpoints (FNV-1a).
std::uint64_t contact_shape(const Model& m) {
    const ContactSet& cs = m.contacts;
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&h](std::uint64_t v) {
        for (int i = 0; i < 8; ++i) {
            h ^= (v >> (8 * i)) & 0xff;
            h *= 1099511628211ull;
        }
    };
    mix(static_cast<std::uint64_t>(cs.size()));
    for (int c = 0; c < cs.size(); ++c) {
        mix(static_cast<std::uint64_t>(cs.block_a[c]) << 32 | static_cast<std::uint32_t>(cs.block_b[c]));
        mix(flow_contact(m, c) ? 1 : 0);
        mix(static_cast<std::uint64_t>(cs.sub_offset[c + 1] - cs.sub_offset[c]));
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
            mix(static_cast<std::uint64_t>(cs.sub_key(k)));
            mix(cs.sub_side(k));
            if (cs.sub_side(k) >= 3) {
                const std::array<int, 3> t = cs.sub_triangle(k);
                mix(static_cast<std::uint64_t>(static_cast<std::uint32_t>(t[0])) << 32 | static_cast<std::uint32_t>(t[1]));
                mix(static_cast<std::uint32_t>(t[2]));
            }
        }
    }
    return h;
}

// What the nodes that follow others hold (inflow, volume, conductance) goes to the nodes they
// follow, by the weights.
void gather(const FlowSet& f, std::vector<double>& x) {
    const int nn = static_cast<int>(x.size());
    if (static_cast<int>(f.follow_offset.size()) != nn + 1) return;
    for (int i = 0; i < nn; ++i) {
        for (int e = f.follow_offset[i]; e < f.follow_offset[i + 1]; ++e) x[f.follow_node[e]] += f.follow_w[e] * x[i];
        if (f.follow_offset[i + 1] > f.follow_offset[i]) x[i] = 0;
    }
}

// The nodes that follow others take the pressure there.
void follow(FlowSet& f) {
    const int nn = f.n_nodes();
    if (static_cast<int>(f.follow_offset.size()) != nn + 1) return;
    for (int i = 0; i < nn; ++i) {
        if (f.fixed[i] || f.follow_offset[i + 1] == f.follow_offset[i]) continue;
        double p = 0;
        for (int e = f.follow_offset[i]; e < f.follow_offset[i + 1]; ++e) p += f.follow_w[e] * f.pp[f.follow_node[e]];
        f.pp[i] = std::max(0.0, p);
    }
}

} // namespace

double hydrostatic_pressure(const Model& m, const Vec3& x) {
    const FlowSet& f = m.flow;
    if (!f.has_wtable) return 0;
    const double g = m.gravity.norm();
    if (!(g > 0)) return 0;
    // Depth below the table along gravity: the table is the level surface through height wtable.
    const Vec3 up = -m.gravity / g;
    const double depth = f.wtable - up.dot(x);
    return depth > 0 ? f.density * g * depth : 0.0;
}

void flow_sync(Model& m) {
    FlowSet& f = m.flow;
    const ContactSet& cs = m.contacts;
    if (f.revision == cs.revision && f.n_subs_seen == cs.n_subs() &&
        static_cast<int>(f.volume.size()) == f.n_nodes()) {
        return;
    }
    const int ns = cs.n_subs();
    // A refresh that left the joints as they were (the same contacts, sub-contacts and partner
    // triangles: the blocks moved a little) keeps the nodes and links; the nodes' places follow
    // their points.
    const std::uint64_t shape = contact_shape(m);
    if (f.n_subs_seen == ns && f.shape == shape && static_cast<int>(f.sub_node.size()) == ns &&
        static_cast<int>(f.volume.size()) == f.n_nodes()) {
        std::vector<Vec3> sum(f.n_nodes(), Vec3::Zero());
        std::vector<int> count(f.n_nodes(), 0);
        for (int c = 0; c < cs.size(); ++c) {
            for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
                const int node = f.sub_node[k];
                if (node < 0) continue;
                sum[node] += sub_point(m, c, k);
                ++count[node];
            }
        }
        for (int i = 0; i < f.n_nodes(); ++i) {
            if (count[i] > 0) f.pos[i] = sum[i] / count[i];
        }
        f.revision = cs.revision;
        return;
    }
    f.shape = shape;
    // The points, and which contacts carry flow.
    std::vector<Vec3> pts(ns, Vec3::Zero());
    std::vector<char> live(ns, 0);
    for (int c = 0; c < cs.size(); ++c) {
        if (!flow_contact(m, c)) continue;
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
            pts[k] = sub_point(m, c, k);
            live[k] = 1;
        }
    }
    const double ctol = cs.ctol > 0 ? cs.ctol : contact_tolerance(m);
    const double merge = std::max(1e-3 * ctol, 1e-12);
    // Nodes: the first point of each group within `merge` of one another.
    std::vector<int> node_of(ns, -1);
    std::vector<int> first; // first point of each node
    std::vector<Vec3> sum;
    std::vector<int> count;
    PointGrid grid{merge, {}, &pts};
    grid.cells.reserve(static_cast<std::size_t>(ns));
    for (int k = 0; k < ns; ++k) {
        if (!live[k]) continue;
        const int near = grid.find(pts[k], merge);
        if (near >= 0) {
            node_of[k] = node_of[near];
        } else {
            node_of[k] = static_cast<int>(first.size());
            first.push_back(k);
            sum.push_back(Vec3::Zero());
            count.push_back(0);
            grid.add(k);
        }
        sum[node_of[k]] += pts[k];
        ++count[node_of[k]];
    }
    const int nn = static_cast<int>(first.size());
    std::vector<Vec3> pos(nn);
    for (int i = 0; i < nn; ++i) pos[i] = sum[i] / count[i];
    // The state of the old nodes, carried by position.
    std::vector<double> pp(nn, 0.0);
    std::vector<std::uint8_t> fixed(nn, 0);
    // The same nodes as before, each where it was (a model just restored): the volumes of the last
    // step still hold.
    bool same = nn == f.n_nodes();
    {
        const double carry = 0.5 * ctol;
        PointGrid old{std::max(carry, 1e-12), {}, &f.pos};
        for (int i = 0; i < f.n_nodes(); ++i) old.add(i);
        for (int i = 0; i < nn; ++i) {
            const int o = f.n_nodes() > 0 ? old.find(pos[i], carry) : -1;
            same = same && o == i;
            if (o >= 0) {
                pp[i] = f.pp[o];
                fixed[i] = f.fixed[o];
            } else {
                pp[i] = hydrostatic_pressure(m, pos[i]);
            }
        }
    }
    f.pos = std::move(pos);
    f.pp = std::move(pp);
    f.fixed = std::move(fixed);
    f.sub_node = std::move(node_of);
    // Links: each contact polygon fanned into triangles, the linear finite-element weights.
    f.link_a.clear();
    f.link_b.clear();
    f.link_sa.clear();
    f.link_sb.clear();
    f.link_w.clear();
    std::vector<int> ring;
    std::vector<double> angle;
    struct Edge {
        int i, j;
        double w;
    };
    std::vector<Edge> edges;
    // The linear finite-element weights of the triangle of points v in the plane of normal n, scaled
    // by `scale`, added to the edges.
    std::unordered_map<std::int64_t, int> edge_at; // (i, j) -> its place in edges
    auto add = [&](int i, int j, double w) {
        if (i > j) std::swap(i, j);
        const std::int64_t key = (static_cast<std::int64_t>(i) << 32) | static_cast<std::uint32_t>(j);
        auto [it, fresh] = edge_at.emplace(key, static_cast<int>(edges.size()));
        if (fresh) edges.push_back({i, j, w});
        else edges[it->second].w += w;
    };
    auto triangle = [&](const int v[3], const Vec3& n, double scale) {
        // Twice the area, in the plane.
        const Vec3 e1 = pts[v[1]] - pts[v[0]], e2 = pts[v[2]] - pts[v[0]];
        const double area2 = (e1.cross(e2)).dot(n);
        if (!(std::abs(area2) > 1e-14 * (e1.squaredNorm() + e2.squaredNorm()))) return;
        for (int q = 0; q < 3; ++q) {
            // The corner q; the edge opposite it joins the other two.
            const Vec3 u = pts[v[(q + 1) % 3]] - pts[v[q]], w = pts[v[(q + 2) % 3]] - pts[v[q]];
            const double cot = u.dot(w) / std::abs(u.cross(w).dot(n));
            add(v[(q + 1) % 3], v[(q + 2) % 3], 0.5 * scale * cot);
        }
    };
    auto emit = [&] {
        edge_at.clear();
        for (const Edge& e : edges) {
            const int na = f.sub_node[e.i], nb = f.sub_node[e.j];
            if (na == nb || !(e.w > 0)) continue;
            f.link_a.push_back(na);
            f.link_b.push_back(nb);
            f.link_sa.push_back(e.i);
            f.link_sb.push_back(e.j);
            f.link_w.push_back(e.w);
        }
    };
    const BlockSet& bs = m.blocks;
    const GridpointSet& g = m.gridpoints;
    for (int c = 0; c < cs.size(); ++c) {
        if (!flow_contact(m, c)) continue;
        const int k0 = cs.sub_offset[c], k1 = cs.sub_offset[c + 1];
        if (k1 - k0 < 3) continue;
        const Vec3 n = cs.normal(c);
        if (gridpoint_contact(m, c)) continue; // linked below, block by block
        Vec3 ctr = Vec3::Zero();
        for (int k = k0; k < k1; ++k) ctr += pts[k];
        ctr /= (k1 - k0);
        const Vec3 t1 = n.unitOrthogonal(), t2 = n.cross(t1);
        ring.clear();
        angle.assign(k1 - k0, 0.0);
        for (int k = k0; k < k1; ++k) {
            const Vec3 d = pts[k] - ctr;
            angle[k - k0] = std::atan2(d.dot(t2), d.dot(t1));
            ring.push_back(k);
        }
        std::sort(ring.begin(), ring.end(), [&](int x, int y) {
            const double ax = angle[x - k0], ay = angle[y - k0];
            return ax < ay || (ax == ay && x < y);
        });
        edges.clear();
        const int r = static_cast<int>(ring.size());
        for (int t = 1; t + 1 < r; ++t) {
            const int v[3] = {ring[0], ring[t], ring[t + 1]};
            triangle(v, n, 1.0);
        }
        emit();
    }
    // The two faces of a joint between zoned blocks hold one film of water, but their meshes need
    // not match. One face carries the film's network, the other follows it: each of its gridpoints
    // takes the pressure of the point it meets on the leading face (the corners of that triangle by
    // their weights) and gives those corners its inflow and its volume by the same weights (as its
    // force goes to them). The face that follows is the one more of whose gridpoints meet triangles
    // lying wholly in the joint (the larger face, around a smaller one: the smaller face's mesh ends
    // where the joint ends); b on a tie. A node follows one triangle, the first in contact order,
    // and only if its pressure is its own to give up (not fixed).
    std::vector<std::vector<std::pair<int, double>>> follows(nn);
    std::vector<std::int8_t> follower_side(cs.size(), 0); // 3 or 4 for joints between zoned blocks
    {
        std::unordered_map<int, int> sub_of_gp[2];
        for (int c = 0; c < cs.size(); ++c) {
            if (!flow_contact(m, c)) continue;
            const int a = cs.block_a[c], b = cs.block_b[c];
            if (!((bs.flags[a] & kDeformable) && (bs.flags[b] & kDeformable))) continue;
            sub_of_gp[0].clear();
            sub_of_gp[1].clear();
            for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
                if (cs.sub_side(k) == 3 || cs.sub_side(k) == 4) sub_of_gp[cs.sub_side(k) - 3].emplace(cs.sub_vertex(k), k);
            }
            // The nodes sub-contact k would follow, or false.
            // The nodes sub-contact k would follow: the corners of the triangle it meets that are
            // in the joint, their weights scaled to sum to 1 (-1 for a corner off it). Returns how
            // many are in the joint.
            auto leaders = [&](int k, std::pair<int, double> by[3]) {
                const std::array<int, 3> tri = cs.sub_triangle(k);
                if (tri[0] < 0) return 0;
                const auto& other = sub_of_gp[cs.sub_side(k) == 3 ? 1 : 0];
                int in = 0;
                double sum = 0;
                for (int i = 0; i < 3; ++i) {
                    auto it = other.find(tri[i]);
                    by[i] = {-1, 0.0};
                    if (it == other.end()) continue;
                    by[i] = {f.sub_node[it->second], cs.sub_weights(k)[i]};
                    sum += by[i].second;
                    ++in;
                }
                if (!(sum > 0)) return 0;
                for (int i = 0; i < 3; ++i) by[i].second /= sum;
                return in;
            };
            long can[2] = {0, 0}, all[2] = {0, 0};
            std::pair<int, double> by[3];
            for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
                const int side = cs.sub_side(k) - 3;
                if (side < 0 || side > 1) continue;
                ++all[side];
                can[side] += leaders(k, by) == 3;
            }
            if (all[0] == 0 || all[1] == 0) continue;
            // The larger face follows: the smaller one's mesh ends where the joint ends, and one
            // face of a block that meets several blocks leads or follows in all of its joints.
            // Faces alike: the one more of whose gridpoints meet triangles wholly in the joint.
            const double fa = facing_face_area(m, a, cs.normal(c)), fb = facing_face_area(m, b, -cs.normal(c));
            int side;
            if (std::abs(fa - fb) > 1e-6 * std::max(fa, fb)) side = fa > fb ? 3 : 4;
            else side = can[0] * all[1] > can[1] * all[0] ? 3 : 4;
            follower_side[c] = static_cast<std::int8_t>(side);
            for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
                if (cs.sub_side(k) != side) continue;
                const int node = f.sub_node[k];
                if (node < 0 || f.fixed[node] || !follows[node].empty()) continue;
                if (leaders(k, by) == 0) continue;
                bool ok = true;
                for (const auto& e : by) ok = ok && e.first != node;
                if (!ok) continue;
                for (const auto& e : by) {
                    if (e.first >= 0 && e.second != 0) follows[node].push_back(e);
                }
            }
        }
    }
    // A node may follow nodes that follow others (the gridpoints along the edge where a block's
    // face meets the next block): each follows, in the end, nodes that lead, with the weights
    // multiplied along the way. A node whose chain comes back to itself leads instead.
    {
        std::vector<std::int8_t> state(nn, 0); // 0 not seen, 1 being resolved, 2 done
        auto resolve = [&](auto&& self, int n) -> void {
            if (state[n] == 2) return;
            if (follows[n].empty()) {
                state[n] = 2;
                return;
            }
            state[n] = 1;
            std::vector<std::pair<int, double>> mine = follows[n];
            std::vector<std::pair<int, double>> out;
            for (const auto& e : mine) {
                if (state[e.first] == 1) {
                    out.clear();
                    follows[n].clear();
                    state[n] = 2;
                    return;
                }
                self(self, e.first);
                if (follows[e.first].empty()) {
                    out.push_back(e);
                } else {
                    for (const auto& l : follows[e.first]) out.push_back({l.first, e.second * l.second});
                }
            }
            // One entry per node followed, in the order first met.
            std::vector<std::pair<int, double>> unique;
            for (const auto& e : out) {
                bool found = false;
                for (auto& u : unique) {
                    if (u.first == e.first) {
                        u.second += e.second;
                        found = true;
                        break;
                    }
                }
                if (!found) unique.push_back(e);
            }
            bool self_loop = false;
            for (const auto& u : unique) self_loop = self_loop || u.first == n;
            if (self_loop) unique.clear();
            follows[n] = std::move(unique);
            state[n] = 2;
        };
        for (int i = 0; i < nn; ++i) resolve(resolve, i);
    }
    f.follow_offset.assign(nn + 1, 0);
    f.follow_node.clear();
    f.follow_w.clear();
    for (int i = 0; i < nn; ++i) {
        for (const auto& e : follows[i]) {
            f.follow_node.push_back(e.first);
            f.follow_w.push_back(e.second);
        }
        f.follow_offset[i + 1] = static_cast<int>(f.follow_node.size());
    }
    // Deformable blocks: the surface triangles whose three corners are flow points of the block's
    // gridpoints (in any of its contacts, so that water passes between the joints the block's face
    // meets), facing the joint. Each corner stands for its sub-contact in the joint the triangle
    // faces best, and counts with its share of the film's conductance there: 1 on a rigid block or
    // on a face that leads, 0 on a face that follows; a triangle takes the mean of its corners'.
    struct GpSub {
        int sub;
        double scale;
        Vec3 normal; // its contact's normal, pointing away from the block
    };
    std::unordered_map<int, std::vector<GpSub>> gp_subs;
    std::vector<std::vector<int>> subs_of_block(bs.size());
    for (int c = 0; c < cs.size(); ++c) {
        if (!flow_contact(m, c) || !gridpoint_contact(m, c)) continue;
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
            const int side = cs.sub_side(k);
            if (side == 3) subs_of_block[cs.block_a[c]].push_back(k);
            else if (side == 4) subs_of_block[cs.block_b[c]].push_back(k);
        }
    }
    const bool have_surface = static_cast<int>(cs.surface_offset.size()) == bs.size() + 1;
    std::vector<double> wet_area(ns, 0.0);
    // Whether the surface a gridpoint meets across its joint lies flat to the joint there.
    std::vector<char> partner_flat(ns, 0);
    for (int c = 0; c < cs.size(); ++c) {
        if (!flow_contact(m, c) || !gridpoint_contact(m, c)) continue;
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
            if (cs.sub_side(k) < 3) continue;
            const bool of_a = cs.sub_side(k) == 3;
            const Vec3 toward = of_a ? Vec3(-cs.normal(c)) : cs.normal(c); // the partner's outward normal
            const std::array<int, 3> tri = cs.sub_triangle(k);
            if (tri[0] >= 0) {
                const Vec3 nt = (g.pos[tri[1]] - g.pos[tri[0]]).cross(g.pos[tri[2]] - g.pos[tri[0]]);
                partner_flat[k] = nt.dot(toward) >= kFlatToPlane * nt.norm();
                continue;
            }
            const int o = of_a ? cs.block_b[c] : cs.block_a[c];
            const Polyhedron& shape = bs.shape[o];
            const Vec3 xp = bs.centroid[o] + bs.orientation[o] * cs.sub_point_local(k);
            for (int fc = 0; fc < shape.n_faces() && !partner_flat[k]; ++fc) {
                const Vec3 nf = bs.orientation[o] * shape.face_normal(fc);
                if (nf.dot(toward) < kFlatToPlane) continue;
                const Vec3 v0 = bs.centroid[o] + bs.orientation[o] * shape.vertices[shape.face_vertex(fc, 0)];
                partner_flat[k] = std::abs(nf.dot(xp - v0)) <= ctol;
            }
        }
    }
    for (int blk = 0; blk < bs.size() && have_surface; ++blk) {
        if (subs_of_block[blk].size() < 3) continue;
        gp_subs.clear();
        for (int k : subs_of_block[blk]) {
            const int c = cs.sub_owner(k);
            const bool of_a = cs.sub_side(k) == 3;
            const int other = of_a ? cs.block_b[c] : cs.block_a[c];
            const double scale = (bs.flags[other] & kDeformable) && follower_side[c] == cs.sub_side(k) ? 0.0 : 1.0;
            gp_subs[cs.sub_vertex(k)].push_back({k, scale, of_a ? cs.normal(c) : Vec3(-cs.normal(c))});
        }
        edges.clear();
        for (int t = cs.surface_offset[blk]; t < cs.surface_offset[blk + 1]; ++t) {
            const auto& q = cs.surface_tri[t];
            const Vec3 nrm = (g.pos[q[1]] - g.pos[q[0]]).cross(g.pos[q[2]] - g.pos[q[0]]);
            const double len = nrm.norm();
            if (!(len > 0)) continue;
            // The wetted area of each corner's sub-contacts: its third of the triangle, shared in
            // proportion to their areas by those whose joint the triangle lies flat to and whose
            // partner surface lies flat to it too (a face across the joint, not the edge or corner
            // of a block met across a joint crossing: the water of a joint pushes once).
            for (int i = 0; i < 3; ++i) {
                auto it = gp_subs.find(q[i]);
                if (it == gp_subs.end()) continue;
                // With none such (a gridpoint on the joint crossing, whose partner point lies on
                // the other block's edge), those whose joint the triangle lies flat to.
                double total = 0;
                bool need_flat = true;
                for (int pass = 0; pass < 2 && !(total > 0); ++pass) {
                    need_flat = pass == 0;
                    for (const GpSub& e : it->second) {
                        if (nrm.dot(e.normal) >= kFlatToPlane * len && (!need_flat || partner_flat[e.sub])) total += cs.sub_area[e.sub];
                    }
                }
                if (!(total > 0)) continue;
                for (const GpSub& e : it->second) {
                    const double cosine = nrm.dot(e.normal) / len;
                    if (cosine < kFlatToPlane || (need_flat && !partner_flat[e.sub])) continue;
                    wet_area[e.sub] += 0.5 * len * cosine / 3.0 * cs.sub_area[e.sub] / total;
                }
            }
            const GpSub* corner[3];
            bool all = true;
            for (int i = 0; i < 3 && all; ++i) {
                auto it = gp_subs.find(q[i]);
                all = it != gp_subs.end();
                if (!all) break;
                // The sub-contact whose joint the triangle faces best (the first among equals).
                corner[i] = nullptr;
                double best = -2;
                for (const GpSub& e : it->second) {
                    const double cosine = nrm.dot(e.normal) / len;
                    if (cosine > best) {
                        best = cosine;
                        corner[i] = &e;
                    }
                }
                all = best >= kLinkFacing;
            }
            if (!all) continue;
            const int v[3] = {corner[0]->sub, corner[1]->sub, corner[2]->sub};
            const double scale = (corner[0]->scale + corner[1]->scale + corner[2]->scale) / 3.0;
            if (scale > 0) triangle(v, nrm / len, scale);
        }
        emit();
    }
    f.link_q.assign(f.n_links(), 0.0);
    f.inflow.assign(nn, 0.0);
    f.volume.assign(nn, 0.0);
    if (!same) f.last_volume.clear();
    f.area.assign(nn, 0.0);
    f.sub_aperture.assign(ns, 0.0);
    // The share of each sub-contact's area the water wets: all of it between rigid blocks; for a
    // gridpoint, its area on surface triangles flat to the joint (halved against a zoned block, as
    // its area is), so that where blocks meet along an edge or at a corner (a joint crossing) the
    // water does not push a second time on faces its own joints already wet.
    f.sub_wet.assign(ns, 1.0);
    for (int k = 0; k < ns; ++k) {
        if (cs.sub_side(k) < 3 || f.sub_node[k] < 0) continue;
        const int c = cs.sub_owner(k);
        const int other = cs.sub_side(k) == 3 ? cs.block_b[c] : cs.block_a[c];
        const double wet = wet_area[k] * ((bs.flags[other] & kDeformable) ? 0.5 : 1.0);
        f.sub_wet[k] = cs.sub_area[k] > 0 ? std::min(1.0, wet / cs.sub_area[k]) : 0.0;
    }
    f.revision = cs.revision;
    f.n_subs_seen = ns;
    ++f.rebuilds;
}

void flow_apertures(Model& m) {
    FlowSet& f = m.flow;
    const ContactSet& cs = m.contacts;
    std::fill(f.volume.begin(), f.volume.end(), 0.0);
    std::fill(f.area.begin(), f.area.end(), 0.0);
    for (int c = 0; c < cs.size(); ++c) {
        const JointMaterial* j = contact_joint_material(m, c);
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
            const int node = f.sub_node[k];
            if (node < 0) continue;
            double a = 0;
            if (j) {
                a = std::max(j->azero - sub_closure(m, c, k), j->ares);
                if (j->amax > 0) a = std::min(a, j->amax);
            }
            a = std::max(a, 0.0);
            f.sub_aperture[k] = a;
            f.volume[node] += a * cs.sub_area[k] * f.sub_wet[k];
            f.area[node] += cs.sub_area[k] * f.sub_wet[k];
        }
    }
    gather(f, f.volume);
}

void flow_ready(Model& m) {
    ensure_contacts_current(m, true);
    flow_sync(m);
}

int set_flow_pressure(Model& m, const std::vector<int>& nodes, const PressureSpec& spec, bool fix) {
    FlowSet& f = m.flow;
    for (int i : nodes) {
        const double p = spec.wtable ? hydrostatic_pressure(m, f.pos[i]) : spec.p + spec.grad.dot(f.pos[i]);
        f.pp[i] = std::max(0.0, p);
        if (fix) f.fixed[i] = 1;
    }
    f.last_volume.clear();
    return static_cast<int>(nodes.size());
}

double flow_stable_timestep(Model& m) {
    FlowSet& f = m.flow;
    flow_sync(m);
    flow_apertures(m);
    const int nn = f.n_nodes();
    std::vector<double> sumc(nn, 0.0);
    for (int l = 0; l < f.n_links(); ++l) {
        const double a = 0.5 * (f.sub_aperture[f.link_sa[l]] + f.sub_aperture[f.link_sb[l]]);
        const double c = a * a * a / (12.0 * f.viscosity) * f.link_w[l];
        sumc[f.link_a[l]] += c;
        sumc[f.link_b[l]] += c;
    }
    gather(f, sumc);
    double dt = 0;
    for (int i = 0; i < nn; ++i) {
        if (f.fixed[i] || !(sumc[i] > 0) || !(f.volume[i] > 0)) continue;
        const double d = 0.8 * f.volume[i] / (f.bulk * sumc[i]);
        if (dt == 0 || d < dt) dt = d;
    }
    // No free node stores water (every pressure fixed): nothing evolves, a nominal second.
    return dt > 0 ? dt : (nn > 0 ? 1.0 : 0.0);
}

std::string flow_problem(const Model& m) {
    const FlowSet& f = m.flow;
    if (!f.on) return "";
    bool any = false;
    for (const JointMaterial& j : m.joint_materials) any = any || (j.defined && (j.azero > 0 || j.ares > 0));
    if (!any) {
        return "fluid flow is on but no joint material has a hydraulic aperture: give 'prop jmat=n azero=...' "
               "(or 'set flow off')";
    }
    return "";
}

std::string flow_step(Model& m, double dt) {
    FlowSet& f = m.flow;
    flow_sync(m);
    flow_apertures(m);
    const int nn = f.n_nodes(), nl = f.n_links();
    const double mu = f.viscosity;
    std::vector<double> cond(nl), sumc(nn, 0.0), head(nn);
    for (int l = 0; l < nl; ++l) {
        const double a = 0.5 * (f.sub_aperture[f.link_sa[l]] + f.sub_aperture[f.link_sb[l]]);
        cond[l] = a * a * a / (12.0 * mu) * f.link_w[l];
        sumc[f.link_a[l]] += cond[l];
        sumc[f.link_b[l]] += cond[l];
    }
    gather(f, sumc);
    follow(f);
    // The pressure a hydrostatic column adds between two points: rho g . x.
    for (int i = 0; i < nn; ++i) head[i] = f.density * m.gravity.dot(f.pos[i]);
    auto flows = [&] {
        std::fill(f.inflow.begin(), f.inflow.end(), 0.0);
        for (int l = 0; l < nl; ++l) {
            const int a = f.link_a[l], b = f.link_b[l];
            double q = cond[l] * ((f.pp[a] - head[a]) - (f.pp[b] - head[b]));
            // A free node at zero pressure is dry: it gives no water (joints above a water table stay dry).
            if ((q > 0 && !f.fixed[a] && !(f.pp[a] > 0)) || (q < 0 && !f.fixed[b] && !(f.pp[b] > 0))) q = 0;
            f.link_q[l] = q;
            f.inflow[a] -= q;
            f.inflow[b] += q;
        }
        gather(f, f.inflow);
    };
    if (f.mode == FlowMode::Steady) {
        constexpr double kRelax = 0.8;
        double dt_min = 0;
        for (int i = 0; i < nn; ++i) {
            if (f.fixed[i] || !(sumc[i] > 0) || !(f.volume[i] > 0)) continue;
            const double d = f.volume[i] / (f.bulk * sumc[i]);
            if (dt_min == 0 || d < dt_min) dt_min = d;
        }
        f.dt = kRelax * dt_min;
        for (int it = 0; it < f.substeps; ++it) {
            flows();
            for (int i = 0; i < nn; ++i) {
                if (f.fixed[i] || !(sumc[i] > 0)) continue;
                f.pp[i] = std::max(0.0, f.pp[i] + (f.volume[i] > 0 ? kRelax : 1.0) * f.inflow[i] / sumc[i]);
            }
            follow(f);
            ++f.steps;
        }
    } else {
        double dt_min = 0;
        for (int i = 0; i < nn; ++i) {
            if (f.fixed[i] || !(sumc[i] > 0) || !(f.volume[i] > 0)) continue;
            const double d = 0.8 * f.volume[i] / (f.bulk * sumc[i]);
            if (dt_min == 0 || d < dt_min) dt_min = d;
        }
        long n = 1;
        if (dt_min > 0 && dt > dt_min) n = static_cast<long>(std::ceil(dt / dt_min));
        constexpr long kMaxSub = 100000;
        if (n > kMaxSub) {
            return "transient flow would need " + std::to_string(n) + " sub-steps in one mechanical step of " +
                   std::to_string(dt) + " s (its stable step is " + std::to_string(dt_min) +
                   " s); the most is " + std::to_string(kMaxSub) + ": use 'set flow steady', a larger azero or a "
                   "smaller fluid bulk modulus";
        }
        const double h = dt / n;
        f.dt = h;
        // The change of volume since the last step squeezes or draws the water.
        const bool have_last = f.last_volume.size() == f.volume.size();
        for (int i = 0; i < nn && have_last; ++i) {
            if (f.fixed[i] || !(f.volume[i] > 0)) continue;
            const double mean = 0.5 * (f.volume[i] + f.last_volume[i]);
            f.pp[i] = std::max(0.0, f.pp[i] - f.bulk * (f.volume[i] - f.last_volume[i]) / mean);
        }
        for (long it = 0; it < n; ++it) {
            flows();
            for (int i = 0; i < nn; ++i) {
                if (f.fixed[i] || !(sumc[i] > 0)) continue;
                if (f.volume[i] > 0) f.pp[i] = std::max(0.0, f.pp[i] + f.bulk * h / f.volume[i] * f.inflow[i]);
                else f.pp[i] = std::max(0.0, f.pp[i] + f.inflow[i] / sumc[i]);
            }
            follow(f);
            ++f.steps;
        }
        f.time += dt;
        f.last_volume = f.volume;
    }
    // The pressure pushes the two blocks of every sub-contact apart.
    BlockSet& s = m.blocks;
    GridpointSet& g = m.gridpoints;
    const ContactSet& cs = m.contacts;
    f.block_force.assign(s.size(), Vec3::Zero());
    f.block_moment.assign(s.size(), Vec3::Zero());
    for (int c = 0; c < cs.size(); ++c) {
        const int a = cs.block_a[c], b = cs.block_b[c];
        const Vec3 n = cs.normal(c);
        if (gridpoint_contact(m, c)) {
            // On the gridpoint, and the opposite force on its partner point: the corners of the
            // triangle it meets by their weights, or the rigid block there with its moment (as the
            // joint's own force, joint_law.cpp).
            for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
                const int node = f.sub_node[k];
                if (node < 0 || !(f.pp[node] > 0) || !(cs.sub_area[k] > 0)) continue;
                const bool of_a = cs.sub_side(k) == 3;
                const int gp = cs.sub_vertex(k), o = of_a ? b : a;
                const Vec3 fg = (of_a ? -1.0 : 1.0) * f.pp[node] * cs.sub_area[k] * f.sub_wet[k] * n; // on the gridpoint
                const double fn = fg.norm();
                g.force[gp] += fg;
                g.force_scale[gp] += fn;
                const std::array<int, 3> tri = cs.sub_triangle(k);
                if (tri[0] >= 0) {
                    const Vec3 w = cs.sub_weights(k);
                    for (int i = 0; i < 3; ++i) {
                        g.force[tri[i]] -= w[i] * fg;
                        g.force_scale[tri[i]] += w[i] * fn;
                    }
                } else {
                    const Vec3 lever = s.orientation[o] * cs.sub_point_local(k);
                    s.force[o] -= fg;
                    s.moment[o] -= lever.cross(fg);
                    s.force_scale[o] += fn;
                    f.block_force[o] -= fg;
                    f.block_moment[o] -= lever.cross(fg);
                }
            }
            continue;
        }
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
            const int node = f.sub_node[k];
            if (node < 0 || !(f.pp[node] > 0) || !(cs.sub_area[k] > 0)) continue;
            const Vec3 x = sub_point(m, c, k);
            const Vec3 fb = f.pp[node] * cs.sub_area[k] * n;
            const Vec3 mb = (x - s.centroid[b]).cross(fb), ma = -(x - s.centroid[a]).cross(fb);
            s.force[b] += fb;
            s.moment[b] += mb;
            s.force[a] -= fb;
            s.moment[a] += ma;
            s.force_scale[a] += fb.norm();
            s.force_scale[b] += fb.norm();
            f.block_force[b] += fb;
            f.block_moment[b] += mb;
            f.block_force[a] -= fb;
            f.block_moment[a] += ma;
        }
    }
    return "";
}

std::vector<int> flow_nodes_in_range(const Model& m, const Range& r) {
    const FlowSet& f = m.flow;
    const ContactSet& cs = m.contacts;
    std::vector<int> first(f.n_nodes(), -1); // a sub-contact of each node
    for (int k = 0; k < static_cast<int>(f.sub_node.size()) && k < cs.n_subs(); ++k) {
        if (f.sub_node[k] >= 0 && first[f.sub_node[k]] < 0) first[f.sub_node[k]] = k;
    }
    std::vector<int> out;
    for (int i = 0; i < f.n_nodes(); ++i) {
        if (first[i] < 0) continue;
        const int c = cs.sub_owner(first[i]);
        if (r.contains_contact(m, f.pos[i], cs.block_a[c], cs.block_b[c])) out.push_back(i);
    }
    return out;
}

int flow_node_at(const Model& m, const Vec3& x) {
    const FlowSet& f = m.flow;
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (int i = 0; i < f.n_nodes(); ++i) {
        const double d = (f.pos[i] - x).squaredNorm();
        if (d < best_d) {
            best_d = d;
            best = i;
        }
    }
    return best;
}

ContactFlow contact_flow(const Model& m, int c) {
    const FlowSet& f = m.flow;
    const ContactSet& cs = m.contacts;
    ContactFlow r;
    double area = 0;
    if (static_cast<int>(f.sub_node.size()) != cs.n_subs()) return r;
    for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
        const int node = f.sub_node[k];
        if (node < 0) continue;
        const double w = cs.sub_area[k];
        r.pp += w * f.pp[node];
        r.aperture += w * f.sub_aperture[k];
        area += w;
    }
    if (area > 0) {
        r.pp /= area;
        r.aperture /= area;
    }
    for (int l = 0; l < f.n_links(); ++l) {
        if (f.link_sa[l] >= cs.sub_offset[c] && f.link_sa[l] < cs.sub_offset[c + 1]) r.flow += std::abs(f.link_q[l]);
    }
    return r;
}

double flow_unbalance(const Model& m) {
    const FlowSet& f = m.flow;
    double out = 0, moved = 0;
    for (int i = 0; i < f.n_nodes() && i < static_cast<int>(f.inflow.size()); ++i) {
        if (!f.fixed[i]) out += std::abs(f.inflow[i]);
    }
    for (double q : f.link_q) moved += std::abs(q);
    return moved > 0 ? out / moved : 0.0;
}

double fixed_inflow(const Model& m) {
    const FlowSet& f = m.flow;
    double q = 0;
    // What the network takes from a fixed node is what the boundary feeds in there.
    for (int i = 0; i < f.n_nodes() && i < static_cast<int>(f.inflow.size()); ++i) {
        if (f.fixed[i] && f.inflow[i] < 0) q -= f.inflow[i];
    }
    return q;
}

} // namespace odec
