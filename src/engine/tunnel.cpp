// Tunnel geometry (see tunnel.h for the pattern).
//
// Why polygons and rays. Every block of the pattern lies between two neighbouring rays from
// the axis and two boundaries that cross both rays once: two rings, or the last ring and the
// box. A quadrilateral with two corners on each of two rays less than 180 degrees apart is
// always convex (its diagonals cross), and the outermost block of a sector is the wedge
// between its rays, cut by the chord of the last ring and clipped by the box: an
// intersection of convex sets, so convex too, even where the sector holds a corner of the
// box. No block needs splitting, and every face between two blocks is one polygon that both
// list with the same corners: the faces conform, as a mesher that zones the blocks later
// needs.
//
// Why equal area. A polygon inscribed in the circle has less area than the circle, by 2.5 %
// for 16 sides; a tunnel's response (the Kirsch solution for a hole under stress) depends
// first on the size of the opening, so the wall polygon is made with the circle's area, its
// corners a little outside the circle and its sides a little inside.
//
// Why exact angles. The rays are at 360 j / n degrees with sines and cosines exact at
// multiples of 90, so that with n a multiple of 4 the rays along the box's mid-planes, and
// the faces on them, lie exactly on those planes: a quarter model cut there by `delete range
// plane ...` keeps whole blocks. Points where a ray meets the box are put on the box's side
// exactly, and a ray that passes within a millionth of a box corner goes through the corner.
//
// Every corner is computed once from its 2D position and its station along the axis, by the
// same expression for every block that uses it, so that two blocks sharing a face have it
// with the same bits.
#include "engine/tunnel.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "engine/blocks.h"
#include "engine/clump.h"
#include "engine/jset.h"

namespace odec {

namespace {

constexpr double kPi = 3.14159265358979323846;
using Vec2 = Eigen::Vector2d;

// Direction of ray j of n, from +u toward +v.
Vec2 ray(int j, int n) {
    const double deg = 360.0 * (j % n) / n;
    return Vec2(cos_deg(deg), sin_deg(deg));
}

double cross2(const Vec2& p, const Vec2& q) { return p.x() * q.y() - p.y() * q.x(); }

// Distance from the axis of the outer boundary of the last ring: where the rings would reach.
double outer_distance(const TunnelSpec& s, bool box) {
    return box ? std::min(s.half_u, s.half_v) : equal_area_circumradius(s.outer_radius, s.n_sides);
}

// The ratio in use: given, or the one that makes ring distances grow geometrically.
double ratio_in_use(const TunnelSpec& s, bool box) {
    if (s.ratio > 0) return s.ratio;
    const double r0 = equal_area_circumradius(s.radius, s.n_sides);
    return std::pow(outer_distance(s, box) / r0, 1.0 / s.n_rings);
}

// Thickness of each ring, from the wall outward (n_rings of them), measured along a ray.
std::vector<double> ring_thicknesses(const TunnelSpec& s, bool box) {
    const double r0 = equal_area_circumradius(s.radius, s.n_sides);
    const double span = outer_distance(s, box) - r0;
    const double q = ratio_in_use(s, box);
    const int m = s.n_rings;
    // t1 (1 + q + ... + q^(m-1)) = span.
    double sum = 0, term = 1;
    for (int k = 0; k < m; ++k) {
        sum += term;
        term *= q;
    }
    std::vector<double> t(m);
    double tk = span / sum;
    for (int k = 0; k < m; ++k) {
        t[k] = tk;
        tk *= q;
    }
    return t;
}

// Where ray d meets the box |x| <= hu, |y| <= hv: on a side exactly, or at a corner.
Vec2 box_point(const Vec2& d, double hu, double hv) {
    const double inf = std::numeric_limits<double>::infinity();
    const double tu = d.x() != 0 ? hu / std::abs(d.x()) : inf;
    const double tv = d.y() != 0 ? hv / std::abs(d.y()) : inf;
    if (std::abs(tu - tv) <= 1e-6 * std::min(tu, tv)) return Vec2(std::copysign(hu, d.x()), std::copysign(hv, d.y()));
    if (tu < tv) return Vec2(std::copysign(hu, d.x()), d.y() * tu);
    return Vec2(d.x() * tv, std::copysign(hv, d.y()));
}

} // namespace

double equal_area_circumradius(double r, int n) {
    // Area of the n-gon of circumradius R: n R^2 sin(2 pi / n) / 2.
    return r * std::sqrt(2.0 * kPi / (n * std::sin(2.0 * kPi / n)));
}

TunnelFrame tunnel_frame(const Vec3& a, const Vec3& b) {
    TunnelFrame f;
    const Vec3 d = b - a;
    f.length = d.norm();
    f.w = f.length > 0 ? Vec3(d / f.length) : Vec3(Vec3::UnitY());
    const Vec3 h = f.w.cross(Vec3::UnitZ());
    if (h.norm() < 1e-9) {
        f.u = Vec3::UnitX();
        f.v = Vec3::UnitY();
    } else {
        f.u = h.normalized();
        f.v = f.u.cross(f.w);
    }
    return f;
}

std::vector<std::vector<Vec2>> tunnel_rings(const TunnelSpec& s, bool box) {
    const int n = s.n_sides;
    const int count = box ? s.n_rings : s.n_rings + 1;
    const std::vector<double> t = ring_thicknesses(s, box);
    std::vector<std::vector<Vec2>> rings(count, std::vector<Vec2>(n));
    double rho = equal_area_circumradius(s.radius, n);
    for (int k = 0; k < count; ++k) {
        if (k == s.n_rings) rho = outer_distance(s, box); // the last one exactly where asked
        for (int j = 0; j < n; ++j) rings[k][j] = rho * ray(j, n);
        if (k < s.n_rings) rho += t[k];
    }
    return rings;
}

std::string tunnel_problem(const TunnelSpec& s, bool box, std::string& keyword) {
    auto text = [](double x) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.6g", x);
        return std::string(buf);
    };
    const double scale = std::max({s.a.cwiseAbs().maxCoeff(), s.b.cwiseAbs().maxCoeff(), s.half_u, s.half_v,
                                   s.outer_radius});
    const double length = (s.b - s.a).norm();
    if (!(length > 1e-9 * scale) || !std::isfinite(length)) {
        keyword = "b";
        return "the tunnel's axis has no length";
    }
    if (!(s.radius > 0) || !std::isfinite(s.radius)) {
        keyword = "radius";
        return "the radius must be a finite number > 0";
    }
    if (s.n_sides < 3 || s.n_rings < 1 || s.n_segments < 1) {
        keyword = s.n_sides < 3 ? "ntheta" : (s.n_rings < 1 ? "nrad" : "nseg");
        return "the tunnel needs at least 3 sides, 1 ring and 1 segment";
    }
    const double r0 = equal_area_circumradius(s.radius, s.n_sides);
    const double reach = outer_distance(s, box);
    if (!(reach > r0 * (1 + 1e-6))) {
        if (box) {
            keyword = "box";
            return "the box (half-size " + text(std::min(s.half_u, s.half_v)) +
                   " m) must reach beyond the tunnel wall, whose corners lie " + text(r0) +
                   " m from the axis (a polygon of " + std::to_string(s.n_sides) + " sides with the area of the circle)";
        }
        keyword = "outer";
        return "the outermost ring (radius " + text(s.outer_radius) + " m) must be larger than the tunnel (radius " +
               text(s.radius) + " m)";
    }
    const std::vector<double> t = ring_thicknesses(s, box);
    const double thinnest = *std::min_element(t.begin(), t.end());
    if (!(thinnest >= 1e-6 * reach) || !std::isfinite(thinnest)) {
        keyword = s.ratio > 0 ? "ratio" : "nrad";
        return "with " + std::to_string(s.n_rings) + " rings and ratio " + text(ratio_in_use(s, box)) +
               " the thinnest ring is " + text(thinnest) + " m thick, less than a millionth of the " +
               (box ? "box" : "outermost ring") + ": use fewer rings or a ratio nearer 1";
    }
    // Corners must stay distinct at these coordinates (doubles keep about 16 digits).
    const double side = 2 * r0 * std::sin(kPi / s.n_sides);
    const double smallest = std::min({thinnest, side, length / s.n_segments});
    if (!(smallest >= 1e-9 * scale)) {
        keyword = "radius";
        return "the smallest block edge (" + text(smallest) + " m) is too small beside coordinates of " + text(scale) +
               " m: make the tunnel larger or move the origin near the model";
    }
    return "";
}

namespace {

// A convex prism on the polygon `poly` (counter-clockwise in u, v) between the planes of two
// stations: corners from `at`, face tags per side (side i from corner i to i + 1) and per end.
template <class At>
Polyhedron prism(const std::vector<Vec2>& poly, const std::vector<int>& side_tag, int tag0, int tag1, bool flip,
                 At&& at) {
    Polyhedron p;
    const int k = static_cast<int>(poly.size());
    for (const Vec2& q : poly) p.vertices.push_back(at(0, q));
    for (const Vec2& q : poly) p.vertices.push_back(at(1, q));
    std::vector<std::vector<int>> loops;
    std::vector<int> end0, end1;
    for (int i = k - 1; i >= 0; --i) end0.push_back(i);
    for (int i = 0; i < k; ++i) end1.push_back(k + i);
    loops.push_back(end0);
    loops.push_back(end1);
    for (int i = 0; i < k; ++i) {
        const int j = (i + 1) % k;
        loops.push_back({i, j, k + j, k + i});
    }
    p.face_offsets.push_back(0);
    for (auto& loop : loops) {
        // The loops above face outward when (u, v, w) is right-handed.
        if (flip) std::reverse(loop.begin(), loop.end());
        p.face_vertices.insert(p.face_vertices.end(), loop.begin(), loop.end());
        p.face_offsets.push_back(static_cast<int>(p.face_vertices.size()));
    }
    p.face_joint.push_back(tag0);
    p.face_joint.push_back(tag1);
    p.face_joint.insert(p.face_joint.end(), side_tag.begin(), side_tag.end());
    bool any = false;
    for (int t : p.face_joint) any = any || t != 0;
    if (!any) p.face_joint.clear();
    return p;
}

} // namespace

bool make_tunnel_blocks(const TunnelSpec& s, int tag, std::vector<TunnelBlock>& out, std::string& error) {
    const TunnelFrame f = tunnel_frame(s.a, s.b);
    const int n = s.n_sides, m = s.n_rings, ns = s.n_segments;
    const bool flip = f.u.cross(f.v).dot(f.w) < 0;
    const std::vector<std::vector<Vec2>> ring = tunnel_rings(s, true);

    // Where each ray meets the box, and the box corners inside each sector, in order.
    std::vector<Vec2> hit(n);
    for (int j = 0; j < n; ++j) hit[j] = box_point(ray(j, n), s.half_u, s.half_v);
    std::vector<std::vector<Vec2>> corners(n);
    for (int j = 0; j < n; ++j) {
        const Vec2 d0 = ray(j, n), d1 = ray(j + 1, n);
        for (const Vec2& c : {Vec2(s.half_u, s.half_v), Vec2(-s.half_u, s.half_v), Vec2(-s.half_u, -s.half_v),
                             Vec2(s.half_u, -s.half_v)}) {
            if (c == hit[j] || c == hit[(j + 1) % n]) continue;
            if (cross2(d0, c) > 0 && cross2(c, d1) > 0) corners[j].push_back(c);
        }
        std::sort(corners[j].begin(), corners[j].end(), [&](const Vec2& p, const Vec2& q) {
            return std::atan2(cross2(d0, p), d0.dot(p)) < std::atan2(cross2(d0, q), d0.dot(q));
        });
    }

    // Stations along the axis; the last is b itself.
    std::vector<Vec3> station(ns + 1);
    for (int k = 0; k <= ns; ++k) station[k] = k == ns ? s.b : Vec3(s.a + (s.b - s.a) * (static_cast<double>(k) / ns));

    const double scale = std::max({s.a.cwiseAbs().maxCoeff(), s.b.cwiseAbs().maxCoeff(), s.half_u + s.half_v, f.length});
    const double tol = 1e-9 * scale;
    out.clear();
    out.reserve(static_cast<size_t>(ns) * (1 + static_cast<size_t>(n) * m));
    for (int seg = 0; seg < ns; ++seg) {
        auto at = [&](int end, const Vec2& q) { return Vec3(station[seg + end] + q.x() * f.u + q.y() * f.v); };
        const int tag0 = seg == 0 ? 0 : tag, tag1 = seg == ns - 1 ? 0 : tag;
        auto add = [&](const std::vector<Vec2>& poly, const std::vector<int>& sides, int layer, int sector) {
            TunnelBlock blk;
            blk.shape = prism(poly, sides, tag0, tag1, flip, at);
            blk.layer = layer;
            blk.segment = seg;
            blk.sector = sector;
            std::string why;
            if (!is_convex_polyhedron(blk.shape, tol, &why)) {
                error = "block " + std::to_string(out.size() + 1) + " of the tunnel is not a valid convex block (" + why + ")";
                return false;
            }
            out.push_back(std::move(blk));
            return true;
        };
        if (!add(ring[0], std::vector<int>(n, tag), 0, -1)) return false;
        for (int k = 1; k <= m; ++k) {
            for (int j = 0; j < n; ++j) {
                const int jn = (j + 1) % n;
                std::vector<Vec2> poly{ring[k - 1][j]};
                std::vector<int> sides{tag}; // along ray j
                if (k < m) {
                    poly.push_back(ring[k][j]);
                    poly.push_back(ring[k][jn]);
                    sides.push_back(tag); // ring k
                } else {
                    poly.push_back(hit[j]);
                    for (const Vec2& c : corners[j]) {
                        poly.push_back(c);
                        sides.push_back(0); // the box
                    }
                    poly.push_back(hit[jn]);
                    sides.push_back(0);
                }
                poly.push_back(ring[k - 1][jn]);
                sides.push_back(tag); // along ray j + 1
                sides.push_back(tag); // ring k - 1
                if (!add(poly, sides, k, j)) return false;
            }
        }
    }
    return true;
}

long TunnelCutPlan::n_pieces() const {
    long n = 0;
    for (const auto& p : pieces) n += static_cast<long>(p.size());
    return n;
}

TunnelCutPlan plan_tunnel_cut(const Model& m, const TunnelSpec& s, const std::vector<int>& targets, int tag,
                              double sliver_tol) {
    TunnelCutPlan plan;
    const TunnelFrame f = tunnel_frame(s.a, s.b);
    const int n = s.n_sides, m_rings = s.n_rings, ns = s.n_segments;
    const std::vector<std::vector<Vec2>> ring = tunnel_rings(s, false); // rings 0 .. n_rings
    // Rays and sector chords in world axes.
    std::vector<Vec3> ray3(n), across(n), chord(n);
    for (int j = 0; j < n; ++j) {
        const Vec2 d = ray(j, n);
        ray3[j] = d.x() * f.u + d.y() * f.v;
        across[j] = -d.y() * f.u + d.x() * f.v; // normal of the plane through the axis and ray j
    }
    for (int j = 0; j < n; ++j) chord[j] = (ray3[j] + ray3[(j + 1) % n]).normalized();

    for (int b : targets) {
        const Vec3 c0 = m.blocks.centroid[b];
        const Vec3 a_rel = s.a - c0; // the axis's start, seen from the block's centroid
        Polyhedron turned = m.blocks.shape[b];
        const Mat3 rot = m.blocks.orientation[b].toRotationMatrix();
        for (Vec3& x : turned.vertices) x = rot * x;
        int slivers = 0;
        // Cut p by the plane nrm.(x - a) = offset; false when it does not cross p.
        auto split = [&](const Polyhedron& p, const Vec3& nrm, double offset, Polyhedron& lo, Polyhedron& hi) {
            SplitOutcome why = SplitOutcome::Missed;
            split_by_plane(p, nrm, nrm.dot(a_rel) + offset, sliver_tol, tag, lo, hi, &why);
            if (why == SplitOutcome::Sliver) ++slivers;
            return why == SplitOutcome::Split;
        };
        // A point inside a convex piece, relative to the axis's start.
        auto inner = [&](const Polyhedron& p) {
            Vec3 c = Vec3::Zero();
            for (const Vec3& x : p.vertices) c += x;
            return Vec3(c / static_cast<double>(p.n_vertices()) - a_rel);
        };
        std::vector<Polyhedron> pieces;
        std::vector<int> layers;
        auto done = [&](Polyhedron p, int layer) {
            pieces.push_back(std::move(p));
            layers.push_back(layer);
        };

        // Along the axis: the parts beyond a and b are done; the rest is cut into segments.
        std::vector<Polyhedron> work{turned}, next;
        for (int end = 0; end < 2; ++end) {
            next.clear();
            const double at = end == 0 ? 0.0 : f.length;
            for (Polyhedron& p : work) {
                Polyhedron lo, hi;
                if (split(p, f.w, at, lo, hi)) {
                    done(end == 0 ? lo : hi, -1);
                    next.push_back(end == 0 ? hi : lo);
                } else if ((f.w.dot(inner(p)) < at) == (end == 0)) {
                    done(p, -1);
                } else {
                    next.push_back(p);
                }
            }
            work.swap(next);
        }
        for (int k = 1; k < ns; ++k) {
            next.clear();
            for (Polyhedron& p : work) {
                Polyhedron lo, hi;
                if (split(p, f.w, f.length * (static_cast<double>(k) / ns), lo, hi)) {
                    next.push_back(lo);
                    next.push_back(hi);
                } else {
                    next.push_back(p);
                }
            }
            work.swap(next);
        }
        // Around the axis: the plane through rays 0 (and n/2) first, then each ray's plane
        // only in the half that holds that ray, where the plane is the ray's own half-plane.
        // (With n odd the first plane also divides the sector opposite ray 0: one cut more,
        // the pieces still convex and each within one sector.)
        for (int j = 0; j < n; ++j) {
            const double deg = 360.0 * j / n;
            if (j > 0 && deg == 180.0) continue; // the plane of ray 0 again
            next.clear();
            for (Polyhedron& p : work) {
                const bool upper = f.v.dot(inner(p)) >= 0;
                Polyhedron lo, hi;
                if ((j == 0 || upper == (deg < 180.0)) && split(p, across[j], 0.0, lo, hi)) {
                    next.push_back(lo);
                    next.push_back(hi);
                } else {
                    next.push_back(p);
                }
            }
            work.swap(next);
        }
        // In each sector, the wall's chord and every ring's, from the inside out.
        for (Polyhedron& p : work) {
            const Vec3 q = inner(p);
            double deg = std::atan2(f.v.dot(q), f.u.dot(q)) * (180.0 / kPi);
            if (deg < 0) deg += 360.0;
            const int j = std::min(n - 1, std::max(0, static_cast<int>(deg * n / 360.0)));
            Polyhedron rest = p;
            int layer = 0;
            for (; layer <= m_rings; ++layer) {
                const double offset = ring[layer][j].norm() * chord[j].dot(ray3[j]);
                Polyhedron lo, hi;
                if (split(rest, chord[j], offset, lo, hi)) {
                    done(lo, layer);
                    rest = hi;
                } else if (chord[j].dot(inner(rest)) <= offset) {
                    break;
                }
            }
            done(rest, layer);
        }
        plan.slivers_skipped += slivers;
        bool reached = false;
        for (int l : layers) reached = reached || (l >= 0 && l <= m_rings);
        if (!reached || pieces.size() < 2) continue;
        plan.blocks.push_back(b);
        plan.origins.push_back(c0);
        plan.pieces.push_back(std::move(pieces));
        plan.layers.push_back(std::move(layers));
    }
    return plan;
}

int apply_tunnel_cut(Model& m, const TunnelCutPlan& plan, int core_group) {
    // Cut pieces of clumps: their clumps end once the cut is made (the blocks' indices hold).
    std::vector<int> cut_clumps;
    for (int b : plan.blocks) {
        if (m.blocks.clump[b] != 0) cut_clumps.push_back(b);
    }
    for (size_t k = 0; k < plan.blocks.size(); ++k) {
        const std::vector<int> made = replace_by_pieces(m, plan.blocks[k], plan.pieces[k], plan.origins[k]);
        for (size_t i = 0; i < made.size(); ++i) {
            if (plan.layers[k][i] == 0 && core_group >= 0) m.blocks.group[made[i]] = core_group;
        }
    }
    m.slivers_skipped += plan.slivers_skipped;
    if (!plan.blocks.empty()) {
        // Contacts name vertices and faces of the old shapes.
        m.contacts.clear();
        refresh_world_vertices(m);
    }
    m.geometry_changed = true;
    return dissolve_clumps(m, cut_clumps);
}

} // namespace odec
