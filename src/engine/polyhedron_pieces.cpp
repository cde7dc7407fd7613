// Solids that need not be convex, built as convex pieces that fill them exactly.
//
// Every block is convex: contact detection, cutting and the joint stresses rely on it. A
// solid whose faces bound a non-convex shape (an L-shaped block, a voussoir whose intrados
// is a polygon bent the other way, a prism whose side is folded inward) is therefore built as
// convex pieces, which the caller joins so that they act as one body. Their volumes, first
// and second moments add up to the solid's own, since together they fill it without overlap.
//
// The faces. They are read as make_from_faces reads them (corners merged within the
// tolerance, corners on a straight edge dropped), but their winding cannot be taken from
// convexity: it is propagated from one face to the next across shared edges (neighbours run
// a shared edge in opposite directions), and the whole surface turned outward if it encloses
// a negative volume. Each corner is then moved onto the planes of the faces through it (the
// smallest move that does so; directions in which those planes are nearly parallel are left
// alone), so that rounded coordinates give faces that are planar to round-off.
//
// The pieces. Every face of the solid lies either on the boundary of its convex hull or on
// a plane that some corner of the solid lies in front of (an "inner" face). Cutting the hull
// by the planes of all inner faces therefore gives convex cells that each lie wholly inside
// or wholly outside the solid: none is crossed by the solid's surface. A cell is kept when
// its centroid is inside (the winding number of the surface around it, a sum of solid angles,
// is 1). The kept cells tile the solid exactly, but many are slivers between nearly parallel
// face planes, so they are gathered into groups, one to begin with, and each group into one
// piece at the end. What keeps a group from being convex is its reflex edges (where the
// solid's surface folds inward: at the others it is locally, hence wholly, convex). So each
// reflex edge, deepest first, divides every group that alone holds some stretch of it (an
// edge between two groups already lies on a plane that divides them) by a plane through the
// edge that splits its angle into two convex ones: through that group's own centroid when
// that plane does, else the plane halving the angle. (Planes through one common point, or
// halving the angles, of two nearly opposite edges of a drum would cross in a thin wedge;
// the groups' own centroids keep the parts stout.)
// A group is then merged into the convex hull of its cells, which is exact when that hull has
// exactly their volume (their union is convex) and none of its faces lies partly on the
// solid's surface and partly inside it; what cannot be merged that way is merged pair by pair,
// and finally pieces of different groups are merged where the same holds. A face of a piece
// is either on the solid's surface (tag 0) or between two pieces (the joined tag): the area of
// the solid's own faces it covers, found by clipping them to it, says which.
#include "engine/polyhedron.h"
#include "engine/polyhedron_detail.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace odec {

using namespace detail;

namespace {

struct Plane {
    Vec3 n;     // unit normal
    double d;   // n . x = d on the plane
};

// Outward unit normal and offset of each face of an outward-wound solid.
std::vector<Plane> face_planes(const std::vector<Vec3>& v, const Loops& loops) {
    std::vector<Plane> planes;
    for (const auto& loop : loops) {
        const Vec3 n = loop_area_vector(v, loop).normalized();
        planes.push_back(Plane{n, n.dot(loop_center(v, loop))});
    }
    return planes;
}

// Solid angle of triangle a b c (positions relative to the viewpoint), signed: positive when
// the triangle turns counter-clockwise as seen from the viewpoint (Van Oosterom and
// Strackee's formula).
double solid_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    return 2.0 * std::atan2(num, den);
}

// How many times the outward-wound surface winds around p: 1 inside, 0 outside.
double winding_number(const std::vector<Vec3>& v, const Loops& loops, const Vec3& p) {
    double w = 0;
    for (const auto& loop : loops) {
        const Vec3 a = v[loop[0]] - p;
        for (size_t k = 1; k + 1 < loop.size(); ++k) w += solid_angle(a, v[loop[k]] - p, v[loop[k + 1]] - p);
    }
    return w / (4.0 * M_PI);
}

// Two orthonormal directions across unit normal n, so that u x w = n.
void plane_basis(const Vec3& n, Vec3& u, Vec3& w) {
    const Vec3 t = std::abs(n.x()) < 0.6 ? Vec3::UnitX() : (std::abs(n.y()) < 0.6 ? Vec3::UnitY() : Vec3::UnitZ());
    u = n.cross(t).normalized();
    w = n.cross(u);
}

using Pt2 = Eigen::Vector2d;

double cross2(const Pt2& a, const Pt2& b) { return a.x() * b.y() - a.y() * b.x(); }

double signed_area(const std::vector<Pt2>& poly) {
    double a = 0;
    for (size_t k = 0; k < poly.size(); ++k) a += cross2(poly[k], poly[(k + 1) % poly.size()]);
    return 0.5 * a;
}

// Area of the part of `subject` (a simple polygon, either winding) inside the convex,
// counter-clockwise polygon `clip`. Clipping a non-convex polygon edge by edge may leave
// zero-width bridges along the clip's edges; they add no area.
double clipped_area(std::vector<Pt2> subject, const std::vector<Pt2>& clip) {
    for (size_t e = 0; e < clip.size() && !subject.empty(); ++e) {
        const Pt2& c0 = clip[e];
        const Pt2& c1 = clip[(e + 1) % clip.size()];
        const Pt2 dir = c1 - c0;
        std::vector<Pt2> out;
        for (size_t k = 0; k < subject.size(); ++k) {
            const Pt2& p = subject[k];
            const Pt2& q = subject[(k + 1) % subject.size()];
            const double sp = cross2(dir, p - c0), sq = cross2(dir, q - c0);
            if (sp >= 0) out.push_back(p);
            if ((sp >= 0) != (sq >= 0)) out.push_back(p + (q - p) * (sp / (sp - sq)));
        }
        subject = std::move(out);
    }
    return subject.size() < 3 ? 0.0 : std::abs(signed_area(subject));
}

// The solid, ready for the pieces: its corners, outward-wound faces and their planes.
struct Solid {
    std::vector<Vec3> v;
    Loops loops;
    std::vector<Plane> planes;
    double size = 0;        // diagonal of the bounding box, m
};

// The fraction of face f of piece p that lies on the solid's surface (0: all inside it).
double surface_fraction(const Solid& s, const Polyhedron& p, int f, double plane_tol) {
    const Vec3 n = p.face_normal(f);
    const Vec3 o = p.vertices[p.face_vertex(f, 0)];
    const double d = n.dot(o);
    Vec3 u, w;
    plane_basis(n, u, w);
    std::vector<Pt2> face;
    for (int k = 0; k < p.face_size(f); ++k) {
        const Vec3 x = p.vertices[p.face_vertex(f, k)] - o;
        face.emplace_back(u.dot(x), w.dot(x));
    }
    const double area = std::abs(signed_area(face));
    if (!(area > 0)) return 0;
    if (signed_area(face) < 0) std::reverse(face.begin(), face.end());
    double covered = 0;
    for (size_t g = 0; g < s.loops.size(); ++g) {
        if (s.planes[g].n.dot(n) < 1 - 1e-6 || std::abs(s.planes[g].d - d) > plane_tol) continue;
        std::vector<Pt2> poly;
        for (int i : s.loops[g]) {
            const Vec3 x = s.v[i] - o;
            poly.emplace_back(u.dot(x), w.dot(x));
        }
        covered += clipped_area(poly, face);
    }
    return std::min(1.0, covered / area);
}

// A face that is partly on the solid's surface and partly inside it cannot carry one joint
// tag: such a piece is not wanted.
bool has_mixed_face(const Solid& s, const Polyhedron& p, double plane_tol) {
    for (int f = 0; f < p.n_faces(); ++f) {
        const double frac = surface_fraction(s, p, f, plane_tol);
        if (frac > 1e-6 && frac < 1 - 1e-6) return true;
    }
    return false;
}

struct Cell {
    Polyhedron shape;
    double volume = 0;
};

void bounds_of(const Polyhedron& p, Vec3& lo, Vec3& hi) { p.bounds(lo, hi); }

bool boxes_touch(const Polyhedron& a, const Polyhedron& b, double tol) {
    Vec3 alo, ahi, blo, bhi;
    bounds_of(a, alo, ahi);
    bounds_of(b, blo, bhi);
    for (int i = 0; i < 3; ++i) {
        if (alo[i] > bhi[i] + tol || blo[i] > ahi[i] + tol) return false;
    }
    return true;
}

// The convex hull of cells that together are convex, or false.
bool merge_cells(const Solid& s, const std::vector<const Cell*>& cells, double plane_tol, Cell& out) {
    std::vector<Vec3> pts;
    double volume = 0;
    for (const Cell* c : cells) {
        pts.insert(pts.end(), c->shape.vertices.begin(), c->shape.vertices.end());
        volume += c->volume;
    }
    Polyhedron hull;
    std::string ignored;
    if (!make_convex_hull(pts, 1e-10 * s.size, hull, ignored)) return false;
    const double hv = mass_properties(hull).volume;
    if (!(std::abs(hv - volume) <= 1e-9 * volume)) return false;
    if (has_mixed_face(s, hull, plane_tol)) return false;
    out.shape = std::move(hull);
    out.volume = hv;
    return true;
}

// Merge cells pair by pair while some pair's union is convex (in a fixed order). `budget`
// counts down the pairs tried; false when it runs out (the solid is too intricate).
bool merge_pairwise(const Solid& s, std::vector<Cell>& cells, double plane_tol, long& budget) {
    bool changed = true;
    while (changed) {
        changed = false;
        for (size_t i = 0; i < cells.size(); ++i) {
            for (size_t j = i + 1; j < cells.size();) {
                Cell merged;
                if (boxes_touch(cells[i].shape, cells[j].shape, 1e-9 * s.size)) {
                    if (--budget < 0) return false;
                    if (merge_cells(s, {&cells[i], &cells[j]}, plane_tol, merged)) {
                        cells[i] = std::move(merged);
                        cells.erase(cells.begin() + static_cast<long>(j));
                        changed = true;
                        continue;
                    }
                }
                ++j;
            }
        }
    }
    return true;
}

// Read the faces into merged corners and loops; false with `error` on bad input.
bool read_faces(const std::vector<std::vector<Vec3>>& faces, double tol, Solid& s, std::string& error) {
    if (!read_face_loops(faces, tol, s.v, s.loops, error)) return false;
    s.size = extent(s.v);
    for (size_t f = 0; f < s.loops.size(); ++f) {
        const Vec3 a = loop_area_vector(s.v, s.loops[f]);
        const double len = a.norm();
        if (len <= 0 || 0.5 * len <= tol * tol) {
            error = "face " + std::to_string(f + 1) + " has no area";
            return false;
        }
        const Vec3 n = a / len;
        const Vec3 c = loop_center(s.v, s.loops[f]);
        for (int i : s.loops[f]) {
            if (std::abs(n.dot(s.v[i] - c)) > tol) {
                error = "face " + std::to_string(f + 1) + " is not planar";
                return false;
            }
        }
        // A simple polygon: no two edges that are not neighbours meet.
        Vec3 u, w;
        plane_basis(n, u, w);
        std::vector<Pt2> p;
        for (int i : s.loops[f]) p.emplace_back(u.dot(s.v[i] - c), w.dot(s.v[i] - c));
        const size_t m = p.size();
        for (size_t i = 0; i < m; ++i) {
            for (size_t j = i + 2; j < m; ++j) {
                if (i == 0 && j == m - 1) continue;
                const Pt2 &a0 = p[i], &a1 = p[(i + 1) % m], &b0 = p[j], &b1 = p[(j + 1) % m];
                const double d1 = cross2(a1 - a0, b0 - a0), d2 = cross2(a1 - a0, b1 - a0);
                const double d3 = cross2(b1 - b0, a0 - b0), d4 = cross2(b1 - b0, a1 - b0);
                if (((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0)) && d1 != 0 && d2 != 0 && d3 != 0 && d4 != 0) {
                    error = "face " + std::to_string(f + 1) + " crosses itself";
                    return false;
                }
            }
        }
    }
    drop_edge_vertices(s.v, s.loops, tol);
    return true;
}

// Wind every face outward; false with `error` when the faces are not one closed surface.
bool orient(Solid& s, std::string& error) {
    const int nf = static_cast<int>(s.loops.size());
    // Undirected edge -> the faces that use it, with the direction each runs it (+1: low to high).
    std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> uses;
    for (int f = 0; f < nf; ++f) {
        const auto& loop = s.loops[f];
        for (size_t k = 0; k < loop.size(); ++k) {
            const int a = loop[k], b = loop[(k + 1) % loop.size()];
            uses[{std::min(a, b), std::max(a, b)}].emplace_back(f, a < b ? 1 : -1);
        }
    }
    std::vector<std::vector<std::pair<int, int>>> edges_of(static_cast<size_t>(nf)); // (edge index, dir)
    std::vector<std::vector<std::pair<int, int>>> edge_list;
    for (const auto& [e, u] : uses) {
        if (u.size() != 2 || u[0].first == u[1].first) {
            error = "face " + std::to_string(u[0].first + 1) +
                    (u.size() == 1 ? " has an edge that no other face shares: the solid is not closed"
                                   : " shares an edge with more than one other face: the solid is not closed");
            return false;
        }
        const int id = static_cast<int>(edge_list.size());
        edge_list.push_back(u);
        for (const auto& [f, dir] : u) edges_of[f].emplace_back(id, dir);
    }
    std::vector<int> flip(static_cast<size_t>(nf), -1);
    flip[0] = 0;
    std::vector<int> queue{0};
    for (size_t q = 0; q < queue.size(); ++q) {
        const int f = queue[q];
        for (const auto& [e, dir] : edges_of[f]) {
            const int dir_f = flip[f] ? -dir : dir;
            const auto& u = edge_list[e];
            const auto& other = u[0].first == f ? u[1] : u[0];
            const int want = other.second == dir_f ? 1 : 0; // the other face must run it backwards
            if (flip[other.first] < 0) {
                flip[other.first] = want;
                queue.push_back(other.first);
            } else if (flip[other.first] != want) {
                error = "face " + std::to_string(other.first + 1) +
                        " cannot face outward with its neighbours: the faces do not bound one solid";
                return false;
            }
        }
    }
    for (int f = 0; f < nf; ++f) {
        if (flip[f] < 0) {
            error = "the faces do not form one closed shell (face " + std::to_string(f + 1) + " is not joined to face 1)";
            return false;
        }
        if (flip[f]) std::reverse(s.loops[f].begin(), s.loops[f].end());
    }
    const std::string closed = closure_problem(s.loops, static_cast<int>(s.v.size()));
    if (!closed.empty()) {
        error = closed;
        return false;
    }
    const double volume = mass_properties(assemble(s.v, s.loops, {})).volume;
    if (volume < 0) {
        for (auto& loop : s.loops) std::reverse(loop.begin(), loop.end());
    }
    if (!(std::abs(volume) > 0)) {
        error = "the faces enclose no volume";
        return false;
    }
    return true;
}

// Move each corner onto the planes of its faces (those with more than three corners): the
// smallest move that satisfies them, leaving alone the directions in which they are nearly
// parallel, and no more than tol.
void snap_to_planes(Solid& s, double tol) {
    const std::vector<Plane> planes = face_planes(s.v, s.loops);
    std::vector<std::vector<int>> faces_at(s.v.size());
    for (size_t f = 0; f < s.loops.size(); ++f) {
        if (s.loops[f].size() < 4) continue; // a triangle is planar wherever its corners go
        for (int i : s.loops[f]) faces_at[i].push_back(static_cast<int>(f));
    }
    std::vector<Vec3> moved = s.v;
    for (size_t i = 0; i < s.v.size(); ++i) {
        const auto& fs = faces_at[i];
        if (fs.empty()) continue;
        Eigen::MatrixXd a(static_cast<long>(fs.size()), 3);
        Eigen::VectorXd r(static_cast<long>(fs.size()));
        for (size_t k = 0; k < fs.size(); ++k) {
            a.row(static_cast<long>(k)) = planes[fs[k]].n.transpose();
            r[static_cast<long>(k)] = planes[fs[k]].d - planes[fs[k]].n.dot(s.v[i]);
        }
        Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
        svd.setThreshold(1e-3);
        const Vec3 dx = svd.solve(r);
        if (dx.allFinite() && dx.norm() <= tol) moved[i] = s.v[i] + dx;
    }
    s.v = std::move(moved);
}

} // namespace

bool make_convex_pieces(const std::vector<std::vector<Vec3>>& faces, double tol, int inner_tag, SolidPieces& out,
                        std::string& error) {
    tol = std::max(tol, 0.0);
    Solid s;
    if (!read_faces(faces, tol, s, error) || !orient(s, error)) return false;
    snap_to_planes(s, tol);
    s.planes = face_planes(s.v, s.loops);
    const Polyhedron whole = assemble(s.v, s.loops, {});
    const MassProperties mp = mass_properties(whole);
    if (!(mp.volume > 0)) {
        error = "the faces enclose no volume";
        return false;
    }
    const double cut_tol = 1e-10 * s.size;
    const double plane_tol = std::max(tol, 1e-9 * s.size);

    // Inner faces: a corner of the solid lies in front of their plane.
    std::vector<Plane> cuts;
    auto add_cut = [&](const Plane& p) {
        for (const Plane& q : cuts) {
            if (std::abs(q.n.dot(p.n)) > 1 - 1e-12 && std::abs(q.d - (q.n.dot(p.n) > 0 ? p.d : -p.d)) <= cut_tol) return;
        }
        cuts.push_back(p);
    };
    // A corner deeper than this in front of a face's plane makes the face inner, and an edge
    // whose neighbour face rises this far in front of the other's plane is reflex: far below
    // the tolerance of the input, so that the pieces fill the solid exactly, but above round-off.
    const double depth_tol = 1e-9 * s.size;
    std::vector<char> inner(s.loops.size(), 0);
    for (size_t f = 0; f < s.loops.size(); ++f) {
        std::vector<char> own(s.v.size(), 0);
        for (int i : s.loops[f]) own[i] = 1;
        for (size_t i = 0; i < s.v.size(); ++i) {
            inner[f] = inner[f] || (!own[i] && s.planes[f].n.dot(s.v[i]) - s.planes[f].d > depth_tol);
        }
        if (inner[f]) add_cut(s.planes[f]);
    }
    if (cuts.empty()) {
        // Convex: one piece, its faces as given.
        Polyhedron p = whole;
        std::string why;
        if (!is_convex_polyhedron(p, std::max(tol, 1e-9 * s.size), &why)) {
            error = "the solid could not be built (" + why + ")";
            return false;
        }
        out.pieces.assign(1, std::move(p));
        out.whole = mp;
        return true;
    }
    // The hull, cut into cells by the planes of the inner faces; the cells inside the solid
    // tile it exactly.
    Polyhedron hull;
    if (!make_convex_hull(s.v, 1e-10 * s.size, hull, error)) {
        error = "the solid could not be divided into convex pieces (its hull: " + error + ")";
        return false;
    }
    // Bounds on the work, so that no input makes odec cycle for minutes: the cells the planes
    // may make and the pairs of them whose union may be tried.
    constexpr size_t kMaxCells = 5000;
    constexpr long kMaxMerges = 100000;
    const std::string too_intricate = "the solid is too intricate to divide into convex pieces (more than " +
                                      std::to_string(kMaxCells) + " cells, or " + std::to_string(kMaxMerges) +
                                      " unions to try): give it as several blocks";
    std::vector<Polyhedron> cut_cells{std::move(hull)};
    for (const Plane& p : cuts) {
        std::vector<Polyhedron> next;
        for (Polyhedron& c : cut_cells) {
            Polyhedron below, above;
            if (split_by_plane(c, p.n, p.d, cut_tol, 0, below, above)) {
                next.push_back(std::move(below));
                next.push_back(std::move(above));
            } else {
                next.push_back(std::move(c));
            }
        }
        cut_cells = std::move(next);
        if (cut_cells.size() > kMaxCells) {
            error = too_intricate;
            return false;
        }
    }
    // Groups of cells, one to begin with: all the cells inside the solid.
    std::vector<std::vector<Cell>> groups(1);
    for (Polyhedron& c : cut_cells) {
        const MassProperties cm = mass_properties(c);
        if (cm.volume > 0 && winding_number(s.v, s.loops, cm.centroid) > 0.5) groups[0].push_back(Cell{std::move(c), cm.volume});
    }
    // Reflex edges, deepest first. Each divides the group of cells it lies in by a plane
    // through it that splits its angle into two convex ones: through the group's centroid
    // when that does (so that the parts are stout), else halving the angle. An edge that
    // already lies between two groups is left alone.
    struct Reflex {
        int i, j;          // its corners
        Vec3 dir;          // unit, from i to j, as face f runs it
        int f, g;          // its faces
        double depth;      // m, how far face g rises in front of face f's plane
    };
    std::vector<Reflex> reflex;
    {
        std::map<std::pair<int, int>, int> face_of; // directed edge -> face
        for (size_t f = 0; f < s.loops.size(); ++f) {
            const auto& loop = s.loops[f];
            for (size_t k = 0; k < loop.size(); ++k) face_of[{loop[k], loop[(k + 1) % loop.size()]}] = static_cast<int>(f);
        }
        for (const auto& [e, f] : face_of) {
            if (e.first > e.second) continue;
            const int g = face_of.at({e.second, e.first});
            const Vec3 dir = (s.v[e.second] - s.v[e.first]).normalized();
            const Vec3& nf = s.planes[f].n;
            if (nf.cross(s.planes[g].n).dot(dir) >= 0) continue; // convex (or flat) edge
            double deepest = 0;
            for (int i : s.loops[g]) deepest = std::max(deepest, nf.dot(s.v[i]) - s.planes[f].d);
            if (deepest > depth_tol) reflex.push_back(Reflex{e.first, e.second, dir, f, g, deepest});
        }
        std::stable_sort(reflex.begin(), reflex.end(), [](const Reflex& a, const Reflex& b) { return a.depth > b.depth; });
    }
    const double on_tol = 1e-9 * s.size;
    for (const Reflex& r : reflex) {
        // The stretches of the edge (parameter 0 to 1) in each group's cells.
        const Vec3 &p0 = s.v[r.i], &p1 = s.v[r.j];
        std::vector<std::pair<double, int>> events; // (parameter, +1 or -1 for group k, coded k+1)
        for (size_t k = 0; k < groups.size(); ++k) {
            std::vector<std::pair<double, double>> spans;
            for (const Cell& c : groups[k]) {
                double t0 = 0, t1 = 1;
                const Polyhedron& q = c.shape;
                for (int f = 0; f < q.n_faces() && t0 < t1; ++f) {
                    const Vec3 n = q.face_normal(f);
                    const double h0 = n.dot(p0 - q.vertices[q.face_vertex(f, 0)]) - on_tol;
                    const double h1 = n.dot(p1 - q.vertices[q.face_vertex(f, 0)]) - on_tol;
                    if (h0 > 0 && h1 > 0) t1 = -1;
                    else if (h0 > 0) t0 = std::max(t0, h0 / (h0 - h1));
                    else if (h1 > 0) t1 = std::min(t1, h0 / (h0 - h1));
                }
                if (t1 - t0 > 1e-9) spans.emplace_back(t0, t1);
            }
            std::sort(spans.begin(), spans.end());
            for (size_t i = 0; i < spans.size();) {
                double lo = spans[i].first, hi = spans[i].second;
                size_t j = i + 1;
                while (j < spans.size() && spans[j].first <= hi + 1e-9) hi = std::max(hi, spans[j++].second);
                events.emplace_back(lo, static_cast<int>(k) + 1);
                events.emplace_back(hi, -(static_cast<int>(k) + 1));
                i = j;
            }
        }
        // The groups that alone hold some stretch of it: the edge is reflex there. Where two
        // groups hold it, it lies on a plane that already divides them.
        std::sort(events.begin(), events.end(), [](const auto& x, const auto& y) {
            return x.first < y.first || (x.first == y.first && x.second < y.second);
        });
        std::vector<int> open;
        std::vector<char> alone(groups.size(), 0);
        for (size_t i = 0; i < events.size(); ++i) {
            const int k = std::abs(events[i].second) - 1;
            if (events[i].second > 0) open.push_back(k);
            else open.erase(std::find(open.begin(), open.end(), k));
            const double next = i + 1 < events.size() ? events[i + 1].first : events[i].first;
            if (open.size() == 1 && next - events[i].first > 1e-6) alone[open[0]] = 1;
        }
        std::vector<int> to_cut;
        for (size_t k = 0; k < groups.size(); ++k) {
            if (alone[k]) to_cut.push_back(static_cast<int>(k));
        }
        if (to_cut.empty()) continue;
        // Across the edge: x along face f away from the edge, y into the solid from face f;
        // the solid spans the angles 0 to theta (more than pi at a reflex edge).
        constexpr double kMargin = 10.0 * M_PI / 180.0; // keep the plane this far from either face
        const Vec3& nf = s.planes[r.f].n;
        const Vec3 x = nf.cross(r.dir).normalized();
        const Vec3 y = -nf;
        auto angle = [&](const Vec3& w) {
            const double a = std::atan2(w.dot(y), w.dot(x));
            return a < 0 ? a + 2 * M_PI : a;
        };
        const double theta = angle(r.dir.cross(s.planes[r.g].n));
        const double lo = theta - M_PI + kMargin, hi = M_PI - kMargin;
        // Each group the edge runs through alone is divided by its own plane: through the edge
        // and the group's centroid when that plane divides the edge's angle, else halving it.
        for (int k : to_cut) {
            double gv = 0;
            Vec3 gc = Vec3::Zero();
            for (const Cell& c : groups[k]) {
                const MassProperties cm = mass_properties(c.shape);
                gv += cm.volume;
                gc += cm.volume * cm.centroid;
            }
            double phi = 0.5 * theta;
            Vec3 w = gc / gv - p0;
            w -= r.dir * r.dir.dot(w);
            if (w.norm() > 1e-6 * s.size && lo < hi) {
                const double a = angle(w.normalized());
                if (a >= lo && a <= hi) phi = a;
            }
            const Vec3 d = std::cos(phi) * x + std::sin(phi) * y;
            const Vec3 n = r.dir.cross(d).normalized();
            const double off = n.dot(p0);
            std::vector<Cell> below, above;
            for (Cell& c : groups[k]) {
                Polyhedron lo_part, hi_part;
                if (split_by_plane(c.shape, n, off, cut_tol, 0, lo_part, hi_part)) {
                    const double vl = mass_properties(lo_part).volume, vh = mass_properties(hi_part).volume;
                    below.push_back(Cell{std::move(lo_part), vl});
                    above.push_back(Cell{std::move(hi_part), vh});
                } else {
                    (n.dot(mass_properties(c.shape).centroid) <= off ? below : above).push_back(std::move(c));
                }
            }
            groups[k] = std::move(below);
            groups.push_back(std::move(above));
        }
        size_t n_cells = 0;
        for (const auto& g : groups) n_cells += g.size();
        if (n_cells > kMaxCells) {
            error = too_intricate;
            return false;
        }
    }
    // Each group into one convex piece where its cells make one; else pair by pair.
    std::vector<Cell> pieces;
    long budget = kMaxMerges;
    for (std::vector<Cell>& g : groups) {
        if (g.empty()) continue;
        std::vector<const Cell*> ptrs;
        for (const Cell& c : g) ptrs.push_back(&c);
        Cell merged;
        if (g.size() > 1 && merge_cells(s, ptrs, plane_tol, merged)) {
            pieces.push_back(std::move(merged));
            continue;
        }
        if (!merge_pairwise(s, g, plane_tol, budget)) {
            error = too_intricate;
            return false;
        }
        for (Cell& c : g) pieces.push_back(std::move(c));
    }
    if (!merge_pairwise(s, pieces, plane_tol, budget)) {
        error = too_intricate;
        return false;
    }

    // Tag the faces between pieces, and check that the pieces fill the solid exactly.
    double volume = 0;
    Vec3 moment = Vec3::Zero();
    out.pieces.clear();
    for (Cell& c : pieces) {
        Polyhedron& p = c.shape;
        p.face_joint.assign(static_cast<size_t>(p.n_faces()), 0);
        for (int f = 0; f < p.n_faces(); ++f) {
            if (surface_fraction(s, p, f, plane_tol) < 0.5) p.face_joint[f] = inner_tag;
        }
        std::string why;
        if (!is_convex_polyhedron(p, 1e-7 * s.size, &why)) {
            error = "the solid could not be divided into convex pieces (" + why + ")";
            return false;
        }
        const MassProperties pm = mass_properties(p);
        volume += pm.volume;
        moment += pm.volume * pm.centroid;
        out.pieces.push_back(std::move(p));
    }
    if (!(std::abs(volume - mp.volume) <= 1e-8 * mp.volume) ||
        !((moment / volume - mp.centroid).norm() <= 1e-8 * s.size)) {
        error = "the solid could not be divided into convex pieces exactly (they hold " + std::to_string(volume) +
                " m^3, the solid " + std::to_string(mp.volume) + " m^3)";
        out.pieces.clear();
        return false;
    }
    out.whole = mp;
    return true;
}

} // namespace odec
