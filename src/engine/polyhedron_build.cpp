// Building convex polyhedra: from faces, from points, and by cutting one with a plane.
//
// Every block starts as one of these constructions and is then cut by joint sets, so the
// shapes that leave this file must be closed, convex and consistently oriented, or mass
// properties, contact detection and later cuts all go quietly wrong.
//
// From faces. A person types the faces in whatever winding comes to mind, so the winding
// is not trusted: after merging coincident corners and dropping corners that only sit on
// a straight edge (which also heals T-junctions, where one face lists a point on an edge
// that its neighbour does not), each face is turned so that all the other vertices lie
// behind its plane. That single test is also the convexity test: a solid is convex exactly
// when every face plane has all vertices on one side. What remains is topology: with
// outward windings, every directed edge must meet its reverse exactly once, and the
// faces must form one shell (V - E + F = 2).
//
// Convex hull. Points are added one at a time, farthest first (the quickhull order), so
// that each new point sees the current hull clearly and the visible region is a clean
// patch whose horizon is a single loop. Points within the tolerance of the hull are
// dropped rather than added, which keeps near-degenerate slivers out of the result.
// Triangles whose planes agree within the tolerance are then merged into polygon faces by
// taking the boundary loop of each coplanar patch, seeded from the largest triangle since
// its normal is the best determined. Merging can leave a corner on a straight edge between
// two faces; such corners (used by fewer than three faces) are removed from both faces.
//
// Splitting. A cut must conserve volume to round-off, so each intersection point is
// computed once per edge (from its lower-numbered end, whichever face asks first) and
// shared by both parts, and vertices within a hair of the plane are kept on it rather
// than producing a near-duplicate point. The cap polygon is not found by sorting points
// by angle, which can disagree with the side faces when points are nearly collinear;
// it is whatever closes each part: the directed edges of the clipped faces that have no
// reverse partner are exactly the cap's boundary, and chaining them gives its loop with
// the right winding for free.
#include "engine/polyhedron.h"
#include "engine/polyhedron_detail.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

namespace odec {

namespace detail {

// Diagonal of the bounding box: the length that relative tolerances scale with.
double extent(const std::vector<Vec3>& pts) {
    if (pts.empty()) return 0;
    Vec3 lo = pts[0], hi = pts[0];
    for (const Vec3& v : pts) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
    }
    return (hi - lo).norm();
}

bool read_face_loops(const std::vector<std::vector<Vec3>>& faces, double tol, std::vector<Vec3>& v, Loops& loops,
                     std::string& error) {
    if (faces.size() < 4) {
        error = "a closed solid needs at least 4 faces (got " + std::to_string(faces.size()) + ")";
        return false;
    }
    // Merge corners within tol: the first one met stands for the others.
    v.clear();
    loops.assign(faces.size(), {});
    for (size_t f = 0; f < faces.size(); ++f) {
        for (const Vec3& x : faces[f]) {
            if (!x.allFinite()) {
                error = "face " + std::to_string(f + 1) + " has a vertex that is not a finite number";
                return false;
            }
            int found = -1;
            for (size_t i = 0; i < v.size() && found < 0; ++i) {
                if ((v[i] - x).norm() <= tol) found = static_cast<int>(i);
            }
            if (found < 0) {
                found = static_cast<int>(v.size());
                v.push_back(x);
            }
            auto& loop = loops[f];
            if (loop.empty() || loop.back() != found) loop.push_back(found);
        }
        auto& loop = loops[f];
        while (loop.size() > 1 && loop.front() == loop.back()) loop.pop_back();
        if (loop.size() < 3) {
            error = "face " + std::to_string(f + 1) + " has fewer than 3 distinct vertices";
            return false;
        }
        std::vector<int> sorted = loop;
        std::sort(sorted.begin(), sorted.end());
        if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
            error = "face " + std::to_string(f + 1) + " visits a vertex twice";
            return false;
        }
    }
    return true;
}

// Newell normal of a loop (twice the vector area; not normalised). Taken relative to the
// loop's first vertex: far from the origin, cross products of absolute coordinates lose
// most of their digits to cancellation.
Vec3 loop_area_vector(const std::vector<Vec3>& v, const std::vector<int>& loop) {
    Vec3 n = Vec3::Zero();
    const size_t m = loop.size();
    const Vec3 o = v[loop[0]];
    for (size_t k = 1; k + 1 < m; ++k) n += (v[loop[k]] - o).cross(v[loop[k + 1]] - o);
    return n;
}

Vec3 loop_center(const std::vector<Vec3>& v, const std::vector<int>& loop) {
    Vec3 c = Vec3::Zero();
    for (int i : loop) c += v[i];
    return c / static_cast<double>(loop.size());
}

// True when b lies on the segment a-c within tol (so that dropping b changes nothing).
bool on_segment(const Vec3& a, const Vec3& b, const Vec3& c, double tol) {
    const Vec3 ac = c - a;
    const double len2 = ac.squaredNorm();
    if (len2 == 0) return (b - a).norm() <= tol;
    const double t = (b - a).dot(ac) / len2;
    if (t <= 0 || t >= 1) return false;
    return (a + t * ac - b).norm() <= tol;
}

// Remove from each loop the corners that only lie on a straight edge: vertices used by
// fewer than three faces that sit on the segment between their loop neighbours.
void drop_edge_vertices(const std::vector<Vec3>& v, Loops& loops, double tol) {
    bool changed = true;
    while (changed) {
        changed = false;
        std::vector<int> uses(v.size(), 0);
        for (const auto& loop : loops)
            for (int i : loop) ++uses[i];
        for (auto& loop : loops) {
            for (size_t k = 0; k < loop.size() && loop.size() > 3; ++k) {
                const size_t m = loop.size();
                const int a = loop[(k + m - 1) % m], b = loop[k], c = loop[(k + 1) % m];
                if (uses[b] < 3 && on_segment(v[a], v[b], v[c], tol)) {
                    loop.erase(loop.begin() + static_cast<long>(k));
                    --uses[b];
                    changed = true;
                    --k;
                }
            }
        }
    }
}

// Flat polyhedron from loops over v, keeping only the vertices the loops use (in their
// original order, so the result does not depend on how loops were found).
Polyhedron assemble(const std::vector<Vec3>& v, const Loops& loops, const std::vector<int>& tags) {
    std::vector<int> remap(v.size(), -1);
    for (const auto& loop : loops)
        for (int i : loop) remap[i] = 0;
    Polyhedron p;
    for (size_t i = 0; i < v.size(); ++i) {
        if (remap[i] < 0) continue;
        remap[i] = static_cast<int>(p.vertices.size());
        p.vertices.push_back(v[i]);
    }
    p.face_offsets.push_back(0);
    for (const auto& loop : loops) {
        for (int i : loop) p.face_vertices.push_back(remap[i]);
        p.face_offsets.push_back(static_cast<int>(p.face_vertices.size()));
    }
    bool any_tag = false;
    for (int t : tags) any_tag = any_tag || t != 0;
    if (any_tag) p.face_joint = tags;
    return p;
}

// Topology of outward-wound loops: each directed edge used once and met by its reverse,
// one shell. Returns an empty string when closed, else the problem (naming a face).
std::string closure_problem(const Loops& loops, int n_vertices) {
    std::map<std::pair<int, int>, int> edge_face;
    for (size_t f = 0; f < loops.size(); ++f) {
        const auto& loop = loops[f];
        for (size_t k = 0; k < loop.size(); ++k) {
            const std::pair<int, int> e(loop[k], loop[(k + 1) % loop.size()]);
            if (!edge_face.emplace(e, static_cast<int>(f)).second) {
                return "face " + std::to_string(f + 1) + " shares an edge with more than one other face: the solid is not closed";
            }
        }
    }
    for (const auto& [e, f] : edge_face) {
        if (!edge_face.count({e.second, e.first})) {
            return "face " + std::to_string(f + 1) + " has an edge that no other face shares: the solid is not closed";
        }
    }
    std::vector<char> used(static_cast<size_t>(n_vertices), 0);
    for (const auto& loop : loops)
        for (int i : loop) used[i] = 1;
    const long n_used = std::count(used.begin(), used.end(), 1);
    const long n_edges = static_cast<long>(edge_face.size()) / 2;
    if (n_used - n_edges + static_cast<long>(loops.size()) != 2) {
        return "the faces do not form one closed shell";
    }
    return "";
}

} // namespace detail

using namespace detail;

bool is_convex_polyhedron(const Polyhedron& p, double tol, std::string* why) {
    auto fail = [&](const std::string& s) {
        if (why) *why = s;
        return false;
    };
    const int nf = p.n_faces();
    if (nf < 4) return fail("fewer than 4 faces");
    if (!p.face_joint.empty() && static_cast<int>(p.face_joint.size()) != nf) {
        return fail("face_joint does not match the faces");
    }
    Loops loops(nf);
    for (int f = 0; f < nf; ++f) {
        if (p.face_size(f) < 3) return fail("face " + std::to_string(f + 1) + " has fewer than 3 vertices");
        for (int k = 0; k < p.face_size(f); ++k) loops[f].push_back(p.face_vertex(f, k));
        const Vec3 a = loop_area_vector(p.vertices, loops[f]);
        if (a.squaredNorm() == 0) return fail("face " + std::to_string(f + 1) + " has no area");
        const Vec3 n = a.normalized();
        const Vec3 c = loop_center(p.vertices, loops[f]);
        for (int i : loops[f]) {
            if (std::abs(n.dot(p.vertices[i] - c)) > tol) return fail("face " + std::to_string(f + 1) + " is not planar");
        }
        for (const Vec3& v : p.vertices) {
            if (n.dot(v - c) > tol) return fail("face " + std::to_string(f + 1) + " has a vertex in front of it: not convex");
        }
    }
    const std::string closed = closure_problem(loops, p.n_vertices());
    if (!closed.empty()) return fail(closed);
    if (mass_properties(p).volume <= 0) return fail("no volume");
    return true;
}

bool make_from_faces(const std::vector<std::vector<Vec3>>& faces, double tol, Polyhedron& out,
                     std::string& error) {
    tol = std::max(tol, 0.0);
    std::vector<Vec3> v;
    Loops loops;
    if (!read_face_loops(faces, tol, v, loops, error)) return false;
    for (size_t f = 0; f < loops.size(); ++f) {
        const Vec3 a = loop_area_vector(v, loops[f]);
        const double len = a.norm();
        if (len <= 0 || 0.5 * len <= tol * tol) {
            error = "face " + std::to_string(f + 1) + " has no area";
            return false;
        }
        const Vec3 n = a / len;
        const Vec3 c = loop_center(v, loops[f]);
        for (int i : loops[f]) {
            if (std::abs(n.dot(v[i] - c)) > tol) {
                error = "face " + std::to_string(f + 1) + " is not planar";
                return false;
            }
        }
    }
    drop_edge_vertices(v, loops, tol);

    // Turn each face so that the solid lies behind it; vertices on both sides mean the
    // solid is not convex, vertices on neither side mean it is flat.
    for (size_t f = 0; f < loops.size(); ++f) {
        auto& loop = loops[f];
        const Vec3 n = loop_area_vector(v, loop).normalized();
        const Vec3 c = loop_center(v, loop);
        double smin = 0, smax = 0;
        for (const Vec3& x : v) {
            const double s = n.dot(x - c);
            smin = std::min(smin, s);
            smax = std::max(smax, s);
        }
        if (smax > tol && smin < -tol) {
            error = "face " + std::to_string(f + 1) + " has vertices on both sides of its plane: the solid is not convex";
            return false;
        }
        if (smax <= tol && smin >= -tol) {
            error = "the faces enclose no volume: every vertex lies in the plane of face " + std::to_string(f + 1);
            return false;
        }
        if (smax > tol) std::reverse(loop.begin(), loop.end());
        // The face polygon itself must turn one way only.
        const Vec3 nout = loop_area_vector(v, loop).normalized();
        const size_t m = loop.size();
        for (size_t k = 0; k < m; ++k) {
            const Vec3& a = v[loop[(k + m - 1) % m]];
            const Vec3& b = v[loop[k]];
            const Vec3& d = v[loop[(k + 1) % m]];
            const Vec3 e1 = b - a;
            if (e1.norm() == 0) continue;
            if ((e1.normalized().cross(d - b)).dot(nout) < -tol) {
                error = "face " + std::to_string(f + 1) + " is not convex";
                return false;
            }
        }
    }
    const std::string closed = closure_problem(loops, static_cast<int>(v.size()));
    if (!closed.empty()) {
        error = closed;
        return false;
    }
    Polyhedron p = assemble(v, loops, {});
    if (mass_properties(p).volume <= 0) {
        error = "the faces enclose no volume";
        return false;
    }
    out = std::move(p);
    return true;
}

namespace {

struct HullTri {
    int v[3];
    Vec3 n;              // unit outward normal
    double area = 0;
    bool alive = true;
    std::vector<int> outside; // points in front of this triangle, not yet on the hull
};

class HullBuilder {
public:
    HullBuilder(const std::vector<Vec3>& pts, double eps) : p_(pts), eps_(eps) {}

    double dist(int t, int i) const { return tris_[t].n.dot(p_[i] - p_[tris_[t].v[0]]); }

    int add_tri(int a, int b, int c) {
        HullTri t;
        t.v[0] = a;
        t.v[1] = b;
        t.v[2] = c;
        const Vec3 cr = (p_[b] - p_[a]).cross(p_[c] - p_[a]);
        t.area = 0.5 * cr.norm();
        t.n = t.area > 0 ? Vec3(cr.normalized()) : Vec3(Vec3::Zero());
        tris_.push_back(t);
        const int id = static_cast<int>(tris_.size()) - 1;
        for (int k = 0; k < 3; ++k) edges_[{t.v[k], t.v[(k + 1) % 3]}] = id;
        return id;
    }

    int neighbour(int t, int k) const {
        const auto it = edges_.find({tris_[t].v[(k + 1) % 3], tris_[t].v[k]});
        return it == edges_.end() ? -1 : it->second;
    }

    // Give each point to the triangle it is farthest in front of, or drop it.
    void assign(const std::vector<int>& points, const std::vector<int>& candidates) {
        for (int i : points) {
            int best = -1;
            double best_d = eps_;
            for (int t : candidates) {
                const double d = dist(t, i);
                if (d > best_d) {
                    best_d = d;
                    best = t;
                }
            }
            if (best >= 0) tris_[best].outside.push_back(i);
        }
    }

    void run(const int s[4]) {
        add_tri(s[0], s[2], s[1]);
        add_tri(s[0], s[1], s[3]);
        add_tri(s[1], s[2], s[3]);
        add_tri(s[0], s[3], s[2]);
        std::vector<int> rest;
        for (int i = 0; i < static_cast<int>(p_.size()); ++i) {
            if (i != s[0] && i != s[1] && i != s[2] && i != s[3]) rest.push_back(i);
        }
        assign(rest, {0, 1, 2, 3});
        for (;;) {
            // Farthest outside point over the whole hull.
            int eye = -1, from = -1;
            double far = 0;
            for (int t = 0; t < static_cast<int>(tris_.size()); ++t) {
                if (!tris_[t].alive) continue;
                for (int i : tris_[t].outside) {
                    const double d = dist(t, i);
                    if (d > far) {
                        far = d;
                        eye = i;
                        from = t;
                    }
                }
            }
            if (eye < 0) break;
            add_point(eye, from);
        }
    }

    void add_point(int eye, int from) {
        // The patch of triangles the point sees, grown from the one it was assigned to.
        std::vector<int> visible{from};
        std::set<int> seen{from};
        for (size_t q = 0; q < visible.size(); ++q) {
            for (int k = 0; k < 3; ++k) {
                const int u = neighbour(visible[q], k);
                if (u >= 0 && !seen.count(u) && dist(u, eye) > eps_) {
                    seen.insert(u);
                    visible.push_back(u);
                }
            }
        }
        // Horizon: edges of the patch whose far side is not visible; must be one loop.
        std::vector<std::pair<int, int>> horizon;
        std::map<int, int> next;
        for (int t : visible) {
            for (int k = 0; k < 3; ++k) {
                const int u = neighbour(t, k);
                if (u < 0 || !seen.count(u)) {
                    horizon.emplace_back(tris_[t].v[k], tris_[t].v[(k + 1) % 3]);
                    if (!next.emplace(horizon.back().first, horizon.back().second).second) next[horizon.back().first] = -1;
                }
            }
        }
        bool simple = !horizon.empty() && next.size() == horizon.size();
        if (simple) {
            int at = horizon[0].first;
            size_t steps = 0;
            do {
                const auto it = next.find(at);
                if (it == next.end() || it->second < 0) {
                    simple = false;
                    break;
                }
                at = it->second;
                ++steps;
            } while (at != horizon[0].first && steps <= horizon.size());
            simple = simple && steps == horizon.size();
        }
        if (!simple) {
            // The point barely sees the hull and the patch is not a clean disc; leave it
            // out (it lies within about eps of the hull) rather than break the surface.
            auto& out = tris_[from].outside;
            out.erase(std::remove(out.begin(), out.end(), eye), out.end());
            return;
        }
        std::vector<int> orphans;
        for (int t : visible) {
            HullTri& tri = tris_[t];
            tri.alive = false;
            for (int i : tri.outside) {
                if (i != eye) orphans.push_back(i);
            }
            tri.outside.clear();
            for (int k = 0; k < 3; ++k) edges_.erase({tri.v[k], tri.v[(k + 1) % 3]});
        }
        std::vector<int> fresh;
        for (const auto& e : horizon) fresh.push_back(add_tri(e.first, e.second, eye));
        std::sort(orphans.begin(), orphans.end());
        assign(orphans, fresh);
    }

    // Merge coplanar triangles into polygon loops over p_.
    Loops faces() const {
        std::vector<int> order;
        for (int t = 0; t < static_cast<int>(tris_.size()); ++t) {
            if (tris_[t].alive) order.push_back(t);
        }
        std::stable_sort(order.begin(), order.end(),
                         [&](int a, int b) { return tris_[a].area > tris_[b].area; });
        std::map<int, int> cluster; // triangle -> cluster
        Loops loops;
        int n_clusters = 0;
        for (int seed : order) {
            if (cluster.count(seed)) continue;
            const int c = n_clusters++;
            const Vec3 n = tris_[seed].n;
            const Vec3 o = p_[tris_[seed].v[0]];
            std::vector<int> members{seed};
            cluster[seed] = c;
            for (size_t q = 0; q < members.size(); ++q) {
                for (int k = 0; k < 3; ++k) {
                    const int u = neighbour(members[q], k);
                    if (u < 0 || cluster.count(u) || tris_[u].n.dot(n) <= 0) continue;
                    bool flat = true;
                    for (int j = 0; j < 3; ++j) flat = flat && std::abs(n.dot(p_[tris_[u].v[j]] - o)) <= eps_;
                    if (!flat) continue;
                    cluster[u] = c;
                    members.push_back(u);
                }
            }
            // Boundary loop of the patch.
            std::map<int, int> next;
            bool pinched = false;
            for (int t : members) {
                for (int k = 0; k < 3; ++k) {
                    const int u = neighbour(t, k);
                    const auto it = cluster.find(u);
                    if (u >= 0 && it != cluster.end() && it->second == c) continue;
                    pinched = pinched || !next.emplace(tris_[t].v[k], tris_[t].v[(k + 1) % 3]).second;
                }
            }
            std::vector<int> loop;
            if (!pinched && !next.empty()) {
                int at = next.begin()->first;
                do {
                    loop.push_back(at);
                    const auto it = next.find(at);
                    at = it == next.end() ? -1 : it->second;
                } while (at >= 0 && at != next.begin()->first && loop.size() <= next.size());
                if (at < 0) loop.clear();
            }
            if (pinched || loop.size() != next.size()) {
                // Not a disc: keep its triangles as faces of their own.
                for (int t : members) loops.push_back({tris_[t].v[0], tris_[t].v[1], tris_[t].v[2]});
            } else {
                loops.push_back(std::move(loop));
            }
        }
        return loops;
    }

private:
    const std::vector<Vec3>& p_;
    double eps_;
    std::vector<HullTri> tris_;
    std::map<std::pair<int, int>, int> edges_; // directed edge -> live triangle
};

} // namespace

bool make_convex_hull(const std::vector<Vec3>& points, double tol, Polyhedron& out, std::string& error) {
    const int n = static_cast<int>(points.size());
    if (n < 4) {
        error = "a convex hull needs at least 4 points (got " + std::to_string(n) + ")";
        return false;
    }
    for (const Vec3& x : points) {
        if (!x.allFinite()) {
            error = "a point is not a finite number";
            return false;
        }
    }
    // A floor under the tolerance keeps round-off from making hair-thin triangles.
    const double eps = std::max(tol, 1e-12 * extent(points));
    // Starting tetrahedron from well-spread points.
    int s[4];
    s[0] = 0;
    for (int i = 1; i < n; ++i) {
        const Vec3& a = points[i];
        const Vec3& b = points[s[0]];
        if (std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3)) s[0] = i;
    }
    auto farthest = [&](auto&& measure) {
        int best = -1;
        double best_d = -1;
        for (int i = 0; i < n; ++i) {
            const double d = measure(points[i]);
            if (d > best_d) {
                best_d = d;
                best = i;
            }
        }
        return std::make_pair(best, best_d);
    };
    const Vec3 p0 = points[s[0]];
    auto r1 = farthest([&](const Vec3& x) { return (x - p0).norm(); });
    if (r1.second <= eps) {
        error = "the points coincide";
        return false;
    }
    s[1] = r1.first;
    const Vec3 axis = (points[s[1]] - p0).normalized();
    auto r2 = farthest([&](const Vec3& x) { return (x - p0 - axis * axis.dot(x - p0)).norm(); });
    if (r2.second <= eps) {
        error = "the points are collinear";
        return false;
    }
    s[2] = r2.first;
    const Vec3 normal = (points[s[1]] - p0).cross(points[s[2]] - p0).normalized();
    auto r3 = farthest([&](const Vec3& x) { return std::abs(normal.dot(x - p0)); });
    if (r3.second <= eps) {
        error = "the points are coplanar";
        return false;
    }
    s[3] = r3.first;
    if (normal.dot(points[s[3]] - p0) < 0) std::swap(s[1], s[2]);

    HullBuilder hull(points, eps);
    hull.run(s);
    Loops loops = hull.faces();
    drop_edge_vertices(points, loops, eps);
    Polyhedron p = assemble(points, loops, {});
    std::string why;
    if (!is_convex_polyhedron(p, 4 * eps, &why)) {
        error = "the convex hull could not be built robustly (" + why + ")";
        return false;
    }
    out = std::move(p);
    return true;
}

bool split_by_plane(const Polyhedron& p, const Vec3& n, double d, double tol, Polyhedron& below,
                    Polyhedron& above) {
    return split_by_plane(p, n, d, tol, 0, below, above, nullptr);
}

bool split_by_plane(const Polyhedron& p, const Vec3& n, double d, double tol, int cap_joint,
                    Polyhedron& below, Polyhedron& above, SplitOutcome* outcome) {
    auto report = [&](SplitOutcome o) {
        if (outcome) *outcome = o;
        return o == SplitOutcome::Split;
    };
    const int nv = p.n_vertices();
    const int nf = p.n_faces();
    if (nv < 4 || nf < 4) return report(SplitOutcome::Missed);
    // Vertices this close to the plane are on it: a plane through a face or a corner does
    // not cut, and a corner a round-off away does not make a second, near-identical point.
    const double on = 1e-9 * extent(p.vertices);
    std::vector<double> s(nv);
    double smin = 0, smax = 0;
    for (int i = 0; i < nv; ++i) {
        s[i] = n.dot(p.vertices[i]) - d;
        smin = std::min(smin, s[i]);
        smax = std::max(smax, s[i]);
    }
    if (smax <= on || -smin <= on) return report(SplitOutcome::Missed);
    if (smax <= tol || -smin <= tol) return report(SplitOutcome::Sliver);
    std::vector<int> side(nv);
    for (int i = 0; i < nv; ++i) side[i] = s[i] > on ? 1 : (s[i] < -on ? -1 : 0);

    // Global numbering: the old vertices, then one new point per crossed edge.
    std::vector<Vec3> v = p.vertices;
    std::map<std::pair<int, int>, int> crossing;
    auto cross_point = [&](int a, int b) {
        const std::pair<int, int> key(std::min(a, b), std::max(a, b));
        const auto it = crossing.find(key);
        if (it != crossing.end()) return it->second;
        const int lo = key.first, hi = key.second;
        const double t = s[lo] / (s[lo] - s[hi]);
        v.push_back(p.vertices[lo] + t * (p.vertices[hi] - p.vertices[lo]));
        const int id = static_cast<int>(v.size()) - 1;
        crossing.emplace(key, id);
        return id;
    };
    Loops lo_loops, hi_loops;
    std::vector<int> lo_tags, hi_tags;
    for (int f = 0; f < nf; ++f) {
        const int m = p.face_size(f);
        std::vector<int> lo_poly, hi_poly;
        bool lo_strict = false, hi_strict = false;
        for (int k = 0; k < m; ++k) {
            const int a = p.face_vertex(f, k), b = p.face_vertex(f, (k + 1) % m);
            if (side[a] <= 0) lo_poly.push_back(a);
            if (side[a] >= 0) hi_poly.push_back(a);
            lo_strict = lo_strict || side[a] < 0;
            hi_strict = hi_strict || side[a] > 0;
            if (side[a] * side[b] < 0) {
                const int x = cross_point(a, b);
                lo_poly.push_back(x);
                hi_poly.push_back(x);
            }
        }
        const int tag = p.face_joint.empty() ? 0 : p.face_joint[f];
        if (lo_strict && lo_poly.size() >= 3) {
            lo_loops.push_back(std::move(lo_poly));
            lo_tags.push_back(tag);
        }
        if (hi_strict && hi_poly.size() >= 3) {
            hi_loops.push_back(std::move(hi_poly));
            hi_tags.push_back(tag);
        }
    }
    // The cap of a part: the reverse of its unpartnered edges, chained into one loop.
    auto cap_of = [](const Loops& loops, std::vector<int>& cap) {
        std::set<std::pair<int, int>> edges;
        for (const auto& loop : loops)
            for (size_t k = 0; k < loop.size(); ++k) edges.emplace(loop[k], loop[(k + 1) % loop.size()]);
        std::map<int, int> next;
        for (const auto& e : edges) {
            if (edges.count({e.second, e.first})) continue;
            if (!next.emplace(e.second, e.first).second) return false;
        }
        if (next.size() < 3) return false;
        const int start = next.begin()->first;
        int at = start;
        do {
            cap.push_back(at);
            const auto it = next.find(at);
            if (it == next.end()) return false;
            at = it->second;
        } while (at != start && cap.size() <= next.size());
        return cap.size() == next.size() && at == start;
    };
    std::vector<int> lo_cap, hi_cap;
    if (!cap_of(lo_loops, lo_cap) || !cap_of(hi_loops, hi_cap)) return report(SplitOutcome::Missed);
    lo_loops.push_back(std::move(lo_cap));
    lo_tags.push_back(cap_joint);
    hi_loops.push_back(std::move(hi_cap));
    hi_tags.push_back(cap_joint);
    below = assemble(v, lo_loops, lo_tags);
    above = assemble(v, hi_loops, hi_tags);
    return report(SplitOutcome::Split);
}

bool make_prism(const std::vector<Vec3>& a_loop, const std::vector<Vec3>& b_loop, double tol,
                Polyhedron& out, std::string& error) {
    const size_t m = a_loop.size();
    if (m < 3) {
        error = "prism: polygon a needs at least 3 vertices (got " + std::to_string(m) + ")";
        return false;
    }
    if (b_loop.size() != m) {
        error = "prism: polygons a and b have different numbers of vertices (" + std::to_string(m) + " and " +
                std::to_string(b_loop.size()) + ")";
        return false;
    }
    tol = std::max(tol, 0.0);
    // b may start at any vertex and run either way: find the matching that makes every
    // a-to-b offset the same translation.
    std::vector<Vec3> b;
    for (int dir = 1; dir >= -1 && b.empty(); dir -= 2) {
        for (size_t shift = 0; shift < m && b.empty(); ++shift) {
            std::vector<Vec3> cand(m);
            for (size_t i = 0; i < m; ++i) {
                const long j = (static_cast<long>(shift) + dir * static_cast<long>(i) + 2 * static_cast<long>(m)) %
                               static_cast<long>(m);
                cand[i] = b_loop[static_cast<size_t>(j)];
            }
            const Vec3 t = cand[0] - a_loop[0];
            bool ok = true;
            for (size_t i = 1; i < m && ok; ++i) ok = (cand[i] - a_loop[i] - t).norm() <= tol;
            if (ok) b = std::move(cand);
        }
    }
    if (b.empty()) {
        error = "prism: polygon b is not a translated copy of polygon a";
        return false;
    }
    std::vector<std::vector<Vec3>> faces{a_loop, b};
    for (size_t i = 0; i < m; ++i) {
        const size_t j = (i + 1) % m;
        faces.push_back({a_loop[i], a_loop[j], b[j], b[i]});
    }
    std::string inner;
    if (!make_from_faces(faces, tol, out, inner)) {
        // Faces 1 and 2 are the two polygons; name them as the user wrote them.
        if (inner.rfind("face 1 ", 0) == 0) inner = "polygon a " + inner.substr(7);
        else if (inner.rfind("face 2 ", 0) == 0) inner = "polygon b " + inner.substr(7);
        else if (inner.rfind("face ", 0) == 0) inner = "a side " + inner;
        error = "prism: " + inner;
        return false;
    }
    return true;
}

bool make_tetra(const Vec3& v1, const Vec3& v2, const Vec3& v3, const Vec3& v4, double tol,
                Polyhedron& out, std::string& error) {
    const std::vector<std::vector<Vec3>> faces{{v1, v2, v3}, {v1, v2, v4}, {v1, v3, v4}, {v2, v3, v4}};
    std::string inner;
    if (!make_from_faces(faces, tol, out, inner)) {
        error = "tetra: the four vertices do not span a volume (" + inner + ")";
        return false;
    }
    return true;
}

} // namespace odec
