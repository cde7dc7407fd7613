// Contact detection: which blocks touch, along which plane, over which area.
//
// Broad phase. Each block's bounding box, grown by ctol/2 on every side, is dropped into
// a uniform grid of cells about twice the mean block size (blocks larger than a cell go
// into every cell they cover). Two boxes that share a cell are a candidate pair; the pair
// is reported only from the cell holding the low corner of the boxes' intersection, so
// no pair is seen twice and no hash set is needed. Work and memory grow linearly with the
// number of blocks, and the candidates come out sorted, so results never depend on the
// order of anything but block indices.
//
// When to look again. A pair missed by the broad phase was more than ctol apart; to meet,
// one of its blocks must move more than ctol/2. So the broad phase reruns only once some
// block has moved (translation plus rotation times its radius) more than ctol/2 since the
// last run. The contact geometry (common plane, sub-contacts, areas) is refreshed more
// often, for the contacts of any block that moved more than ctol/10 since its own last
// refresh: between refreshes the sub-contact points ride on their blocks and the normal
// stays put, which keeps the per-step work down to the joint law alone.
//
// Incremental passes. The work of a pass follows what moved, not how big the model is.
// A block counts as moved when it went more than ctol/10 from where its contacts were
// last built (geo_centroid, geo_orientation: per block, saved with the model). Both kinds
// of pass then treat an existing contact alike: between two blocks that did not move it
// is kept exactly as it is (same sub-contacts, same history, same arrays); a contact with
// a moved block is rebuilt from its old plane (warm start, features near it only). What a
// full pass adds is the broad phase (linear, cheap) and the narrow phase for candidate
// pairs that have no contact yet, which are few in a packed rock mass (those are tested
// even between blocks that hardly moved: skipped pass after pass, a slow creep could
// close their gap unseen); a contact whose pair is no longer a candidate is dropped. Only a rebuilt block takes its current pose as
// its new geometry reference; the ctol/2 reference for the broad phase moves for all. A
// full pass starts from scratch (every pair built, every reference reset) only when the
// model changed, nothing was detected yet, ctol changed, or the caches do not fit.
// The result of a pass is a plan: per contact of the new list, an old contact kept or a
// rebuilt one. The rebuilt ones are built a window of some thousands at a time, and after
// each window the plan is carried out in place as far as it reaches, front to back (Rewrite):
// kept contacts ahead of the first change in size are not touched at all and the rest only
// move down; where a rebuilt contact would overwrite old state not yet read, that state is
// moved up to open a gap. So even a pass that rebuilds every contact holds one contact set
// and a window, never two sets, and the arrays come out the same whatever the windows.
// Nothing here depends on more than block and contact order, so results stay
// deterministic, and a restored model (which has the same references) continues with the
// same passes and the same bits.
//
// Sub-contacts. Seen along the common-plane normal, each block presents the faces that
// face the plane, a face tilted to it cut down to the part within ctol of the plane (so that
// a face tilting away fades out instead of vanishing: edge-face and vertex-face contacts get
// a small area that grows continuously into the face-face one as the blocks align), a face
// on the plane (within ctol of it from end to end) whole. The contact
// polygon is where the two footprints overlap (piece by piece, each a convex clip). Its
// vertices are the sub-contacts: vertices of either block lying over the other's face,
// and crossings of an edge of one with an edge of the other (partial overlaps at edges
// are cut exactly). Each takes the median-dual share of the polygon's area, half of each
// of its two fan triangles from the centre (a third of each adjacent triangle of the
// polygon's own), on the faces themselves rather than as seen along the normal. Where a face
// tilted to the plane is involved, the corners that press in carry their own share of their
// faces instead (present_faces). Forces at the polygon's vertices span the whole contact, so a
// block can carry its load out to its edge before it tips, as a rigid block must.
// The energy the springs hold, A (kn un^2 + |ss|^2 / ks) / 2, changes with a sub-contact's area
// A: so the areas are made not to jump at a refresh while the springs are loaded (a corner's
// own area does not follow the block's tilt; a face that comes to lie on the plane gives its
// corners the shares they had; slivers beside a face on the plane add no area).
// Every polygon vertex carries a key (which block vertex, or which two edges cross there),
// so a sub-contact that existed before keeps its history; a new one starts with the
// overlap the geometry shows at its point.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <type_traits>

#include "engine/blocks.h"
#include "engine/common_plane.h"
#include "engine/contact.h"
#include "engine/simd.h"
#include "engine/contact_gridpoint.h"
#include "engine/model.h"
#include "engine/parallel.h"

namespace odec {

namespace {

constexpr int kCap = 96; // polygon vertex capacity: a face clipped by a face
// A crossing of edges this close to a corner (times ctol, seen along the normal) is the corner
// (snap_to_corner).
constexpr double kCornerSnap = 1e-3;
// The depth (times ctol) past which a corner that carries no sub-contact and has pressed into
// the other block has its contact rebuilt at once (detect_contacts).
constexpr double kClosingDepth = 1e-6;
// A rebuild that would leave a contact's springs holding more than this times the energy they
// held is held to what they held (limit_rebuild_energy).
constexpr double kRebuildGrowth = 1.5;

// Labels. An edge label names a polyhedron edge or the band line of a face, on one block;
// a vertex key names a block vertex, or the crossing of two edge labels. Keys survive
// small motions, so a sub-contact can find its own history after a refresh.
constexpr std::int32_t kEdgeSideB = 1 << 30;
constexpr std::int32_t kEdgeBand = 1 << 29;

inline std::int32_t edge_label(int side, int i, int j, int nv) {
    const int lo = std::min(i, j), hi = std::max(i, j);
    return (side ? kEdgeSideB : 0) | (lo * nv + hi);
}
constexpr std::int32_t kEdgeTouch = 1 << 28;
inline std::int32_t band_label(int side, int face) { return (side ? kEdgeSideB : 0) | kEdgeBand | face; }
// The line where a tilted face of a enters a face of b: the edge of their real overlap.
inline std::int32_t touch_label(int face_a, int face_b) {
    return kEdgeTouch | ((face_a & 0x3FFF) << 14) | (face_b & 0x3FFF);
}
// Keys: bit 62 clear: a block vertex, side in bit 61, vertex index below; bit 62 set: the
// crossing of two labels (31 bits each), the lower in bits 31..61. Never negative.
inline std::int64_t corner_key(int side, int vertex) { return (static_cast<std::int64_t>(side) << 61) | vertex; }
inline std::int64_t crossing_key(std::int32_t e1, std::int32_t e2) {
    const std::int64_t lo = std::min(e1, e2), hi = std::max(e1, e2);
    return (std::int64_t{1} << 62) | (lo << 31) | hi;
}
inline bool is_crossing(std::int64_t key) { return (key >> 62) & 1; }
inline std::int32_t crossing_lo(std::int64_t key) { return static_cast<std::int32_t>((key >> 31) & 0x7FFFFFFF); }
inline std::int32_t crossing_hi(std::int64_t key) { return static_cast<std::int32_t>(key & 0x7FFFFFFF); }
inline int corner_vertex(std::int64_t key) { return static_cast<int>(key & ((std::int64_t{1} << 61) - 1)); }
// A point on the line where a tilted face enters the other block: it slides along its edge
// as the overlap changes, so it is not a material point and its closure is the geometry's.
inline bool on_touch_line(std::int64_t key) {
    return is_crossing(key) && ((crossing_lo(key) & kEdgeTouch) != 0 || (crossing_hi(key) & kEdgeTouch) != 0);
}
// A crossing of two block edges: not a point of a band or overlap line.
inline bool is_edge_crossing(std::int64_t key) {
    return is_crossing(key) && !((crossing_lo(key) | crossing_hi(key)) & (kEdgeBand | kEdgeTouch));
}
// The ends i < j of the edge that edge label `label` names on a block of nv vertices; false for
// a band or overlap line, and for a block of 16384 vertices or more, whose labels are not decoded.
inline bool edge_ends(std::int32_t label, int nv, int& i, int& j) {
    if ((label & (kEdgeBand | kEdgeTouch)) || nv <= 0 || nv >= 16384) return false;
    const int idx = label & (kEdgeTouch - 1);
    i = idx / nv;
    j = idx % nv;
    return i < nv; // else not a label of this block's edges
}
// Two edges of one block crossing at their common vertex are that vertex: clipping one
// footprint by the other finds the other's vertices as crossings of its own edges.
inline std::int64_t as_vertex(std::int64_t key, int nv_a, int nv_b) {
    if (!is_edge_crossing(key)) return key;
    const std::int32_t l1 = crossing_lo(key), l2 = crossing_hi(key);
    if ((l1 & kEdgeSideB) != (l2 & kEdgeSideB)) return key;  // edges of different blocks
    const int side = (l1 & kEdgeSideB) ? 1 : 0;
    const int nv = side ? nv_b : nv_a;
    int i1, j1, i2, j2;
    if (!edge_ends(l1, nv, i1, j1) || !edge_ends(l2, nv, i2, j2)) return key;
    if (i1 == i2 || i1 == j2) return corner_key(side, i1);
    if (j1 == i2 || j1 == j2) return corner_key(side, j1);
    return key;
}

// A crossing of two block edges that lies within `snap` of an end of either edge, as seen along
// the normal, is that corner (the nearest; corner_key), else the crossing itself. Blocks cut to
// one thickness (the voussoirs of a plane arch, the stones of a wall) have their side faces on
// one plane: a corner of one lies on the other's side face, in or out of its footprint by the
// rounding of its coordinates. Taken as a crossing while it is out, it would carry the sliver
// share of a crossing, and as a corner pressing in, its own area, a thousand times more: the
// hinge of such an arch would change its stiffness, and its springs their energy, with the
// last bit of a coordinate.
std::int64_t snap_to_corner(std::int64_t key, double u, double v, const std::vector<double>& uv_a,
                            const std::vector<double>& uv_b, double snap) {
    if (!is_edge_crossing(key)) return key;
    std::int64_t out = key;
    double best = snap * snap;
    for (const std::int32_t l : {crossing_lo(key), crossing_hi(key)}) {
        const int side = (l & kEdgeSideB) ? 1 : 0;
        const std::vector<double>& uv = side ? uv_b : uv_a;
        int i, j;
        if (!edge_ends(l, static_cast<int>(uv.size() / 2), i, j)) continue;
        for (const int vtx : {i, j}) {
            const double du = uv[2 * vtx] - u, dv = uv[2 * vtx + 1] - v;
            const double d2 = du * du + dv * dv;
            if (d2 <= best) { // false for NaN: a corner of no presented face
                best = d2;
                out = corner_key(side, vtx);
            }
        }
    }
    return out;
}

struct Poly {
    int n = 0;
    double u[kCap], v[kCap], h[kCap];
    std::int64_t vkey[kCap];   // vertex keys
    std::int32_t ekey[kCap];   // label of the edge from vertex i to i + 1
};

// out becomes p: its n vertices only (a whole Poly is 3.4 KB, and clipping copies one at every
// edge of the clipping polygon).
inline void copy_poly(Poly& out, const Poly& p) {
    out.n = p.n;
    std::copy(p.u, p.u + p.n, out.u);
    std::copy(p.v, p.v + p.n, out.v);
    std::copy(p.h, p.h + p.n, out.h);
    std::copy(p.vkey, p.vkey + p.n, out.vkey);
    std::copy(p.ekey, p.ekey + p.n, out.ekey);
}

inline void put(Poly& out, const Poly& p, int i) {
    out.u[out.n] = p.u[i]; out.v[out.n] = p.v[i]; out.h[out.n] = p.h[i];
    out.vkey[out.n] = p.vkey[i]; out.ekey[out.n] = p.ekey[i]; ++out.n;
}
inline void put_cut(Poly& out, const Poly& p, int i, int j, double t, std::int32_t cut_label) {
    out.u[out.n] = p.u[i] + t * (p.u[j] - p.u[i]);
    out.v[out.n] = p.v[i] + t * (p.v[j] - p.v[i]);
    out.h[out.n] = p.h[i] + t * (p.h[j] - p.h[i]);
    out.vkey[out.n] = crossing_key(p.ekey[i], cut_label);
    out.ekey[out.n] = 0; // set by the caller
    ++out.n;
}

// Sutherland-Hodgman step: keep d >= -eps, with d given per vertex; the new edge along
// the cut gets `cut_label`.
template <class D>
void clip_step(const Poly& p, D&& dist, double eps, std::int32_t cut_label, Poly& out) {
    out.n = 0;
    for (int i = 0; i < p.n && out.n < kCap - 1; ++i) {
        const int j = (i + 1) % p.n;
        const double di = dist(i), dj = dist(j);
        const bool in_i = di >= -eps, in_j = dj >= -eps;
        if (in_i) put(out, p, i);
        if (in_i && !in_j) {
            // The cut on the line itself (d = 0), so that a vertex of the clipping polygon
            // comes out where it is; kept on the edge when both ends lie within eps of it.
            put_cut(out, p, i, j, std::clamp(di / (di - dj), 0.0, 1.0), cut_label);
            out.ekey[out.n - 1] = cut_label; // the boundary now runs along the cut
        } else if (!in_i && in_j) {
            put_cut(out, p, i, j, std::clamp(di / (di - dj), 0.0, 1.0), cut_label);
            out.ekey[out.n - 1] = p.ekey[i]; // and leaves it along the clipped edge
        }
    }
}

// Keep the part of p where s*h >= -tol.
void clip_band(const Poly& p, double s, double tol, std::int32_t label, Poly& out) {
    clip_step(p, [&](int i) { return s * p.h[i] + tol; }, 0.0, label, out);
}

// Keep the part of p inside convex polygon c (orientation `orient`); eps keeps points
// that lie on c's edges as they are, rather than cutting them into near twins.
void clip_convex(const Poly& p, const Poly& c, double orient, double eps, Poly& out, Poly& tmp) {
    copy_poly(out, p);
    for (int k = 0; k < c.n && out.n > 0; ++k) {
        const int k1 = (k + 1) % c.n;
        const double eu = c.u[k1] - c.u[k], ev = c.v[k1] - c.v[k];
        const double len = std::sqrt(eu * eu + ev * ev);
        if (!(len > 0)) continue;
        const double su = orient * eu / len, sv = orient * ev / len;
        clip_step(out, [&](int i) { return su * (out.v[i] - c.v[k]) - sv * (out.u[i] - c.u[k]); }, eps, c.ekey[k], tmp);
        copy_poly(out, tmp);
    }
}

double signed_area(const Poly& p) {
    double a = 0;
    for (int i = 0; i < p.n; ++i) {
        const int j = (i + 1) % p.n;
        a += p.u[i] * p.v[j] - p.u[j] * p.v[i];
    }
    return 0.5 * a;
}

// A face presented to the plane: its footprint piece and the plane it lies in.
struct Piece {
    int face = 0;
    Poly poly;            // band-clipped face in (u, v, h)
    double orient = 1;    // sign of the projected area
    double area = 0;      // projected area
    double h0 = 0, hu = 0, hv = 0; // face height above the common plane: h0 + hu u + hv v
    bool flat = false;    // the whole face lies within the band: it is on the plane
    double c = 1;         // cosine of the face's angle to the plane
    double height(double u, double v) const { return h0 + hu * u + hv * v; }
};

struct Frame {
    Vec3 p, e1, e2, n;
    void to_plane(const Vec3& x, double& u, double& v, double& h) const {
        const Vec3 d = x - p;
        u = e1.dot(d);
        v = e2.dot(d);
        h = n.dot(d);
    }
};

Frame make_frame(const CommonPlane& cp) {
    Frame f;
    f.p = cp.point;
    f.n = cp.normal;
    // A fixed rule for the in-plane axes keeps results independent of history.
    shear_axes(f.n, f.e1, f.e2);
    return f;
}

// Faces of s facing the plane (side 0: block a, facing +n; side 1: block b, facing -n),
// cut to the band within tol of the plane.
void present_faces(const BlockView& s, const Frame& fr, int side, double tol, std::vector<Piece>& out,
                   std::vector<double>& nodal) {
    out.clear();
    nodal.assign(s.n_vertices(), 0.0);
    thread_local std::vector<double> weight;
    weight.assign(s.n_vertices(), 0.0);
    const double sign = side == 0 ? 1.0 : -1.0;
    const Polyhedron& p = *s.topo;
    const int nv = p.n_vertices();
    Poly face;
    for (int f = 0; f < p.n_faces(); ++f) {
        const int m = p.face_size(f);
        if (m > kCap / 2) continue;
        const Vec3 nf = world_face_normal(s, f);
        const double c = sign * nf.dot(fr.n);
        if (c < 0.01) continue; // edge-on or facing away: no footprint
        face.n = m;
        double hlo = std::numeric_limits<double>::infinity(), hhi = -hlo;
        for (int k = 0; k < m; ++k) {
            const int vi = p.face_vertex(f, k), vj = p.face_vertex(f, (k + 1) % m);
            fr.to_plane(s.v[vi], face.u[k], face.v[k], face.h[k]);
            face.vkey[k] = corner_key(side, vi);
            face.ekey[k] = edge_label(side, vi, vj, nv);
            hlo = std::min(hlo, face.h[k]);
            hhi = std::max(hhi, face.h[k]);
        }
        // Each vertex's own area, for when it presses into a face tilted to it: its share of
        // its faces tilted to the plane that face it (the median-dual share of a fan from the
        // face's centre, on the face itself, not as seen along the normal), averaged with
        // weights c^8, so that the face that lies closest to the plane all but sets it. So it
        // hardly changes as the block turns: a corner of a block on its edge has the share of
        // its base whether the block leans 6 or 20 degrees, the same as the share the contact
        // polygon gives it once the base lies on the plane. An area that changed while the
        // spring held a load would change the energy the spring holds without work. Where the
        // block leans about 45 degrees onto a corner, the faces share the weight. A face on the
        // plane carries its own area through the contact polygon, so only tilted faces count.
        if (hhi - hlo > tol) {
            Vec3 cen = Vec3::Zero();
            for (int k = 0; k < m; ++k) cen += s.v[p.face_vertex(f, k)];
            cen /= m;
            const double c2 = c * c, c4 = c2 * c2, w = c4 * c4;
            for (int k = 0; k < m; ++k) {
                const Vec3& xi = s.v[p.face_vertex(f, (k + m - 1) % m)];
                const Vec3& xk = s.v[p.face_vertex(f, k)];
                const Vec3& xj = s.v[p.face_vertex(f, (k + 1) % m)];
                const double share = 0.25 * ((xk - cen).cross(xj - cen).norm() + (xi - cen).cross(xk - cen).norm());
                const int vk = p.face_vertex(f, k);
                nodal[vk] += w * share;
                weight[vk] += w;
            }
        }
        out.emplace_back();
        Piece& pc = out.back();
        // A face on the plane (within tol of it from end to end) is presented whole: cut
        // where it hovers above the band, its corners would take shares of a part of it, and
        // keep them when it lands (between refreshes), unlike the shares of the same face
        // landed. A face tilted to the plane fades out with the band.
        if (hhi - hlo <= tol && (side == 0 ? hhi + tol : tol - hlo) > 0) copy_poly(pc.poly, face);
        else clip_band(face, sign, tol, band_label(side, f), pc.poly);
        const double a = signed_area(pc.poly);
        if (pc.poly.n < 3 || a == 0) {
            out.pop_back();
            continue;
        }
        pc.face = f;
        pc.flat = hhi - hlo <= tol;
        pc.orient = a > 0 ? 1.0 : -1.0;
        pc.area = std::abs(a);
        // Plane nf.x = nf.x0 written as a height over (u, v).
        const double nn = nf.dot(fr.n);
        pc.h0 = face.h[0] + (nf.dot(fr.e1) * face.u[0] + nf.dot(fr.e2) * face.v[0]) / nn;
        pc.hu = -nf.dot(fr.e1) / nn;
        pc.hv = -nf.dot(fr.e2) / nn;
        pc.c = c;
    }
    for (int i = 0; i < nv; ++i) {
        if (weight[i] > 0) nodal[i] /= weight[i];
    }
}

// Where each block's vertices lie on the common plane, (u, v) per vertex, from the corners of
// the faces it presents (NaN for the vertices of none).
void corner_places(const std::vector<Piece>& pieces, int nv, std::vector<double>& uv) {
    uv.assign(2 * static_cast<size_t>(nv), std::numeric_limits<double>::quiet_NaN());
    for (const Piece& pc : pieces) {
        for (int k = 0; k < pc.poly.n; ++k) {
            const std::int64_t key = pc.poly.vkey[k];
            if (is_crossing(key)) continue;
            const int vtx = corner_vertex(key);
            if (vtx >= nv) continue;
            uv[2 * vtx] = pc.poly.u[k];
            uv[2 * vtx + 1] = pc.poly.v[k];
        }
    }
}

// The key of a point of a contact polygon between the faces pa and pb present (blocks of nv_a
// and nv_b vertices): two edges of one block crossing at their vertex are that vertex
// (as_vertex), a crossing near a corner is the corner (snap_to_corner).
struct PolygonKeys {
    int nv_a, nv_b;
    double snap;
    std::vector<double>& uv_a;
    std::vector<double>& uv_b;
    PolygonKeys(const std::vector<Piece>& pa, const std::vector<Piece>& pb, int nv_a_, int nv_b_, double tol,
                std::vector<double>& uv_a_, std::vector<double>& uv_b_)
        : nv_a(nv_a_), nv_b(nv_b_), snap(kCornerSnap * tol), uv_a(uv_a_), uv_b(uv_b_) {
        corner_places(pa, nv_a, uv_a);
        corner_places(pb, nv_b, uv_b);
    }
    std::int64_t operator()(std::int64_t key, double u, double v) const {
        return snap_to_corner(as_vertex(key, nv_a, nv_b), u, v, uv_a, uv_b, snap);
    }
};

struct NewSub {
    std::int64_t key;
    double area;
    Vec3 x;        // world point
    double closure;
    bool nodal;    // a block vertex pressing into a tilted face: its area is its own
    bool flat;     // found where two faces lie on the plane
    bool operator<(const NewSub& o) const { return key < o.key; }
};

// Sub-contacts at the vertices of the contact polygon: each piece of a's footprint
// clipped by each piece of b's. A vertex shared by several pieces is one sub-contact. tol: ctol.
void polygon_subcontacts(const Frame& fr, const std::vector<Piece>& pa, const std::vector<Piece>& pb, double tol,
                         double eps, double min_area, std::vector<NewSub>& out, std::vector<double>& face_area_a,
                         std::vector<double>& face_area_b, const std::vector<double>& nodal_a,
                         const std::vector<double>& nodal_b) {
    const int nv_a = static_cast<int>(nodal_a.size()), nv_b = static_cast<int>(nodal_b.size());
    out.clear();
    // An edge's own area: the mean of its ends' own areas.
    auto edge_own_area = [&](std::int32_t label) {
        const bool of_b = (label & kEdgeSideB) != 0;
        int i, j;
        if (!edge_ends(label, of_b ? nv_b : nv_a, i, j)) return 0.0;
        const std::vector<double>& own = of_b ? nodal_b : nodal_a;
        return 0.5 * (own[i] + own[j]);
    };
    thread_local std::vector<double> uv_a, uv_b;
    const PolygonKeys key_at(pa, pb, nv_a, nv_b, tol, uv_a, uv_b);
    Poly q, tmp;
    // Faces on the plane first. Where two faces lie on the plane and overlap over an area of at
    // least ctol^2, the blocks meet face to face, and a face tilted beside one of them can reach
    // into the other block in a sliver along the edge of their overlap, as thin as the overlap is
    // deep: such a sliver (every corner of it within a hundredth of ctol of that edge) is left
    // out, so that a corner of the face on the plane carries its share alone (not its own area
    // as well, on top of the share of the point beside it), and the areas do not jump as slivers
    // come and go. Where faces on the plane overlap only in a strip (blocks meeting along an
    // edge), the corners pressing in through the faces beside them carry the contact.
    thread_local std::vector<std::array<double, 4>> edges; // the overlaps' edges (u0, v0, u1, v1)
    edges.clear();
    double flat_area = 0;
    auto near_edge = [&](double u, double v) {
        for (const auto& e : edges) {
            const double du = e[2] - e[0], dv = e[3] - e[1], len2 = du * du + dv * dv;
            const double t = len2 > 0 ? std::clamp(((u - e[0]) * du + (v - e[1]) * dv) / len2, 0.0, 1.0) : 0.0;
            const double x = u - e[0] - t * du, y = v - e[1] - t * dv;
            if (x * x + y * y <= 1e-4 * tol * tol) return true;
        }
        return false;
    };
    for (int pass = 0; pass < 2; ++pass) {
    for (const Piece& A : pa) {
        for (const Piece& B : pb) {
            const bool tilted = !(A.flat && B.flat);
            if (tilted != (pass == 1)) continue;
            clip_convex(A.poly, B.poly, B.orient, eps, q, tmp);
            if (q.n < 3) continue;
            for (int i = 0; i < q.n; ++i) q.vkey[i] = key_at(q.vkey[i], q.u[i], q.v[i]);
            if (!tilted) {
                flat_area += std::abs(signed_area(q));
                for (int i = 0; i < q.n; ++i) {
                    const int j = (i + 1) % q.n;
                    edges.push_back({q.u[i], q.v[i], q.u[j], q.v[j]});
                }
            }
            bool has_corner = false, crossing_carried = false;
            if (tilted) {
                // A face tilted to the plane touches the other only where the two solids
                // really overlap: keep the part where a's surface is at or above b's. Blocks
                // meeting along an edge or at a corner then carry nothing while they only
                // touch, and no tolerance band lends them area.
                clip_step(q, [&](int i) { return A.height(q.u[i], q.v[i]) - B.height(q.u[i], q.v[i]); }, eps,
                          touch_label(A.face, B.face), tmp);
                copy_poly(q, tmp);
                if (q.n < 3) continue;
                bool sliver = flat_area >= tol * tol;
                // The deepest a corner of either block presses in here, and the deepest a
                // crossing of an edge of a with an edge of b lies in.
                double corner_depth = -std::numeric_limits<double>::infinity(), crossing_depth = corner_depth;
                for (int i = 0; i < q.n; ++i) {
                    q.vkey[i] = key_at(q.vkey[i], q.u[i], q.v[i]);
                    const double d = A.height(q.u[i], q.v[i]) - B.height(q.u[i], q.v[i]);
                    if (ContactSet::key_side(q.vkey[i]) < 2) corner_depth = std::max(corner_depth, d);
                    else if (is_edge_crossing(q.vkey[i])) crossing_depth = std::max(crossing_depth, d);
                    sliver = sliver && near_edge(q.u[i], q.v[i]);
                }
                if (sliver) continue;
                // The corners carry the overlap where one of them is its deepest point. Where
                // two edges cross deeper in than every corner (an edge of a thin piece striking
                // across an edge of the other, a corner grazing beside), the crossings carry it
                // as well (below): the grazing corner alone, with its own area, left the
                // crossing's overlap unfelt while it deepened, and the contact flipped between
                // the two at every refresh (pieces of the collapsing corpus arch sank 3 to 57 mm
                // into each other that way).
                crossing_carried = crossing_depth > corner_depth + kCornerSnap * tol;
                has_corner = corner_depth > -std::numeric_limits<double>::infinity() && !crossing_carried;
            }
            double cu = 0, cv = 0;
            for (int i = 0; i < q.n; ++i) { cu += q.u[i]; cv += q.v[i]; }
            cu /= q.n;
            cv /= q.n;
            // Fan triangles from the centre; each vertex takes half of its two triangles,
            // the median-dual share (a third of each triangle, for the polygon's own).
            double total = 0;
            const int first = static_cast<int>(out.size());
            for (int i = 0; i < q.n; ++i) {
                const int j = (i + 1) % q.n, k = (i + q.n - 1) % q.n;
                const double t_next = 0.5 * std::abs((q.u[i] - cu) * (q.v[j] - cv) - (q.u[j] - cu) * (q.v[i] - cv));
                const double t_prev = 0.5 * std::abs((q.u[k] - cu) * (q.v[i] - cv) - (q.u[i] - cu) * (q.v[k] - cv));
                const double share = 0.5 * (t_next + t_prev);
                total += share;
                // Where a tilted face is involved, the vertices that press in carry the
                // contact with their own areas (a spring that does not stiffen as it
                // closes, so the force is the same loading and unloading); the points where
                // the overlap's edge crosses a face edge slide with the overlap and carry
                // nothing. Where an edge of a crosses an edge of b deeper in than any corner,
                // those crossings carry it too, each with an area of its own: the smaller of
                // the two edges' (the mean of its ends' own areas), or its share of the overlap
                // where that is larger (edges of faces that lie on the plane have no own area).
                // A share of the overlap grows and shrinks with the overlap between refreshes:
                // the spring would give back less than it took (the corpus arch's pieces,
                // striking at speed, lost 3 to 7 % of the energy that way). Where no vertex
                // presses in and no edges cross (an overlap bounded by its edge alone), its
                // points carry their shares.
                const int side = ContactSet::key_side(q.vkey[i]);
                const bool nodal = tilted && (side < 2 || (crossing_carried && is_edge_crossing(q.vkey[i])));
                if (tilted && (has_corner || crossing_carried) && !nodal) continue;
                double area = share;
                if (!tilted) {
                    // Both faces on the plane: the share on the faces themselves, not as seen
                    // along the normal (a block that rocks on its base keeps its areas as it
                    // turns): on a's face for a's corner, on b's for b's, between for a crossing.
                    area /= side == 0 ? A.c : side == 1 ? B.c : std::sqrt(A.c * B.c);
                }
                if (nodal && side < 2) {
                    const int vertex = corner_vertex(q.vkey[i]);
                    const std::vector<double>& own = side == 0 ? nodal_a : nodal_b;
                    area = vertex < static_cast<int>(own.size()) ? own[vertex] : 0.0;
                } else if (nodal) {
                    area = std::max(share, std::min(edge_own_area(crossing_lo(q.vkey[i])), edge_own_area(crossing_hi(q.vkey[i]))));
                }
                if (!(area > min_area)) continue;
                const double ha = A.height(q.u[i], q.v[i]), hb = B.height(q.u[i], q.v[i]);
                NewSub ns;
                ns.key = q.vkey[i];
                ns.area = area;
                ns.nodal = nodal;
                ns.flat = !tilted;
                ns.x = fr.p + q.u[i] * fr.e1 + q.v[i] * fr.e2 + 0.5 * (ha + hb) * fr.n;
                ns.closure = ha - hb; // a's surface above b's: overlap
                out.push_back(ns);
            }
            (void)first;
            face_area_a[A.face] += total;
            face_area_b[B.face] += total;
        }
    }
    }
    // One sub-contact per key, in key order (the order history is matched in).
    std::stable_sort(out.begin(), out.end());
    int w = 0;
    for (int r = 0; r < static_cast<int>(out.size()); ++r) {
        if (w > 0 && out[w - 1].key == out[r].key) {
            // Where faces lie on the plane, the point carries their shares alone: a corner
            // of a face on the plane is also found pressing into the other block through the
            // faces beside it (a sliver as thin as the overlap), which adds no area. A vertex's
            // own area counts once, however many face pairs it is found in.
            if (out[w - 1].flat != out[r].flat) {
                if (out[r].flat) out[w - 1] = out[r];
            } else if (out[w - 1].nodal || out[r].nodal) {
                out[w - 1].area = std::max(out[w - 1].area, out[r].area);
                out[w - 1].nodal = true;
            } else {
                out[w - 1].area += out[r].area;
            }
        } else {
            out[w++] = out[r];
        }
    }
    out.resize(w);
}

double movement(const ContactSet& cs, const BlockSet& s, int b, const std::vector<Vec3>& ref_c,
                const std::vector<Quat>& ref_q) {
    const double dx = (s.centroid[b] - ref_c[b]).norm();
    const Quat dq = s.orientation[b] * ref_q[b].conjugate();
    const double sin_half = std::min(1.0, dq.vec().norm());
    // (Below 1e-3 from its series, exact to the last bit: the term left out is below 1e-22 of it.)
    const double s2 = sin_half * sin_half;
    const double half = sin_half < 1e-3 ? sin_half * (1 + s2 * (1.0 / 6) * (1 + 0.45 * s2)) : std::asin(sin_half);
    return dx + 2.0 * half * cs.radius[b];
}

// movement() of blocks b .. b + 3, four at a time (the same operations lane by lane; the
// arcsine lane by lane where the series does not serve).
ODEC_SIMD_CLONES
void movements4(const ContactSet& cs, const BlockSet& s, int b, const std::vector<Vec3>& ref_c, const std::vector<Quat>& ref_q,
                double out[4]) {
    using simd::V4;
    V4 c[3], r[3];
    simd::load_xyz4(s.centroid[b].data(), c[0], c[1], c[2]);
    simd::load_xyz4(ref_c[b].data(), r[0], r[1], r[2]);
    const V4 d0 = c[0] - r[0], d1 = c[1] - r[1], d2 = c[2] - r[2];
    V4 dx;
    const V4 dd = simd::sum3(d0 * d0, d1 * d1, d2 * d2);
    for (int l = 0; l < 4; ++l) dx[l] = std::sqrt(dd[l]);
    // q times the reference's conjugate (Eigen's product; the conjugate's vector negated).
    const simd::Quat4 q = simd::load_quats4(s.orientation[b].coeffs().data());
    simd::Quat4 ref = simd::load_quats4(ref_q[b].coeffs().data());
    ref.x = -ref.x;
    ref.y = -ref.y;
    ref.z = -ref.z;
    const simd::Quat4 dq = simd::quat_product4(q, ref);
    const V4 qq = simd::sum3(dq.x * dq.x, dq.y * dq.y, dq.z * dq.z);
    const V4 one = simd::splat(1.0);
    V4 norm;
    for (int l = 0; l < 4; ++l) norm[l] = std::sqrt(qq[l]);
    const V4 sin_half = norm < one ? norm : one; // std::min(1.0, norm)
    const V4 s2 = sin_half * sin_half;
    V4 half = sin_half * (one + s2 * simd::splat(1.0 / 6) * (one + simd::splat(0.45) * s2));
    for (int l = 0; l < 4; ++l) {
        if (!(sin_half[l] < 1e-3)) half[l] = std::asin(sin_half[l]);
    }
    const V4 moved = dx + simd::splat(2.0) * half * simd::load4(cs.radius.data() + b);
    for (int l = 0; l < 4; ++l) out[l] = moved[l];
}

// Whether sub-contacts [k0, k1) of x carry corner `vertex` of block side `side` (0: block a,
// 1: block b; off: the blocks' first entries in wv, the world vertices): one of them is that
// corner, or a corner of the other block within `snap` of it as seen along the normal nrm (two
// blocks' corners meeting, the sub-contact keyed by one of them).
bool corner_carried(const ContactSet& x, int k0, int k1, const std::vector<Vec3>& wv, const int off[2], int side,
                    int vertex, const Vec3& nrm, double snap) {
    const Vec3& p = wv[off[side] + vertex];
    for (int k = k0; k < k1; ++k) {
        const int sk = x.sub_side(k);
        if (sk > 1) continue;
        const int vk = corner_vertex(x.sub_key(k));
        if (sk == side) {
            if (vk == vertex) return true;
            continue;
        }
        const Vec3 d = wv[off[sk] + vk] - p;
        if ((d - nrm.dot(d) * nrm).squaredNorm() <= snap * snap) return true;
    }
    return false;
}

void clear_arrays(ContactSet& x) {
    x.id.clear(); x.block_a.clear(); x.block_b.clear(); x.normal_code.clear(); x.gap.clear();
    x.joint.clear(); x.free_motion.clear(); x.sub_offset.assign(1, 0);
    x.sub_code.clear(); x.key_table = KeyTable{};
    x.sub_area.clear(); x.sub_point.clear(); x.sub_un.clear(); x.sub_udil.clear();
    x.sub_us.clear(); x.sub_ss.clear(); x.sub_tri.clear();
}

// f applied to each per-contact array of x but the offsets.
template <class F>
void each_contact_array(ContactSet& x, F&& f) {
    f(x.id); f(x.block_a); f(x.block_b); f(x.normal_code); f(x.gap); f(x.joint);
    f(x.free_motion);
}
// f applied to each per-sub-contact array of x, the triangles too when `tri` and the dilations
// when `dil`.
template <class F>
void each_sub_array(ContactSet& x, bool tri, bool dil, F&& f) {
    f(x.sub_code); f(x.sub_area); f(x.sub_point); f(x.sub_un);
    f(x.sub_us); f(x.sub_ss);
    if (tri) f(x.sub_tri);
    if (dil) f(x.sub_udil);
}

constexpr std::array<int, 3> kNoTri = {-1, -1, -1};

// sub_tri is kept only once some sub-contact has a triangle: then it has an entry for each
// sub-contact (-1s for those without).
// The point as the set holds it: a code (point_code.h), copied as it is when a sub-contact keeps
// its point. Its flags are none until its history is pushed (push_history, push_inherited).
void push_sub(ContactSet& to, std::int64_t key, double area, const TaggedPointCode& local,
              const std::array<int, 3>& tri = kNoTri) {
    if (tri[0] >= 0 || !to.sub_tri.empty()) {
        to.sub_tri.resize(to.sub_code.size(), kNoTri);
        to.sub_tri.push_back(tri);
    }
    to.push_key(key);
    to.sub_area.push_back(area);
    to.sub_point.push_back(local);
    to.set_sub_flags(to.n_subs() - 1, 0);
}
void push_sub(ContactSet& to, std::int64_t key, double area, const Vec3& local,
              const std::array<int, 3>& tri = kNoTri) {
    push_sub(to, key, area, tagged_point(encode_point(local), 0), tri);
}

// Where an old contact's state is while a pass rewrites the set (Rewrite): its entries at c,
// its sub-contacts at [k0, k1). c = -1: no old contact.
// Cosine of the turn of a contact's plane between two of its refreshes beyond which the contact
// changed what it is (an edge against an edge become a face on a face, say), 10 degrees: a
// block that rocks or rolls turns its contacts' planes by a fraction of a degree between
// refreshes (ctol/10 of motion).
constexpr double kTurned = 0.984807753012208;

struct OldRef {
    int c = -1, k0 = 0, k1 = 0;
};

// The contacts one window of a pass rebuilt, built on the threads: the jobs (contacts to build)
// go in chunks, chunk p into parts[p], so fresh contact f (numbered in job order) is contact
// local[f] of parts[part[f]]. A contact new to the model has id 0 here: it takes its id when
// it joins the contact set, in job order (take_id), so the ids never depend on the threads.
struct Rebuilt {
    std::vector<ContactSet> parts;
    std::vector<int> part, local;
    const ContactSet& set(int f) const { return parts[part[f]]; }
};

int take_id(ContactSet& cs, int id) { return id > 0 ? id : cs.next_id++; }

// Rewrites the contact set in place, front to back, into the contacts a pass lists, while the
// contacts still to be rebuilt read their old state from it. The old state not yet read lies
// beyond what is written: old contact e at e + gc, its sub-contacts from its old offset + gk,
// that offset at e + go of the offsets (which the pass writes anew below it: the new offsets
// of what is written run up to wc, which stays below the old offsets still to be read). Kept
// contacts only move down (or stay where they are, untouched); when a rebuilt one would reach
// old state still to be read (it gained sub-contacts, or is a new contact), the unread rest is
// moved up by a gap, one array at a time. So a pass never holds two whole contact sets, nor
// two sets of offsets, and the result is the same arrays whatever the gaps were.
class Rewrite {
public:
    explicit Rewrite(ContactSet& cs) : cs_(cs), tri_(!cs.sub_tri.empty()), dil_(!cs.sub_udil.empty()) {
        if (cs_.sub_offset.empty()) cs_.sub_offset.assign(1, 0);
    }
    int written() const { return wc_; }
    // Where old contact e is now (e < 0: none), while it is still to be read.
    OldRef old(int e) const {
        if (e < 0) return OldRef{};
        const int* off = cs_.sub_offset.data() + e + go_;
        return OldRef{static_cast<int>(e + gc_), static_cast<int>(off[0] + gk_), static_cast<int>(off[1] + gk_)};
    }
    // Old contacts e .. e + r - 1 next, as they are. Everything before them was written or
    // read already, so they only move down; they lie together, as they will once written, so
    // each array moves in one piece (on the threads when it is long: the same bytes).
    void put_kept(int e, int r) {
        offsets_room(e, 0);
        const OldRef o = old(e);
        const long k1 = cs_.sub_offset[e + r + go_] + gk_;
        const int threads = thread_count();
        if (o.c != wc_) {
            each_contact_array(cs_, [&](auto& v) { move_down(v, o.c, o.c + r, o.c - wc_, threads); });
        }
        if (o.k0 != wk_) {
            each_sub_array(cs_, tri_, dil_, [&](auto& v) { move_down(v, o.k0, k1, o.k0 - wk_, threads); });
        }
        // Each new offset goes below the old one it follows (wc + i + 1 < e + i + 1 + go).
        for (int i = 0; i < r; ++i) advance(cs_.sub_offset[e + i + 1 + go_] - cs_.sub_offset[e + i + go_]);
    }
    // Contact f of x next, with its id taken now when it is new; `next` is the first old
    // contact still to be read (-1: none), which it must not overwrite.
    void put_fresh(const ContactSet& x, int f, int next) {
        const int j0 = x.sub_offset[f], n = x.sub_offset[f + 1] - j0;
        if (!x.sub_tri.empty() && !tri_) {
            tri_ = true;
            cs_.sub_tri.assign(cs_.sub_code.size(), kNoTri);
        }
        if (!x.sub_udil.empty() && !dil_) {
            dil_ = true;
            cs_.sub_udil.assign(cs_.sub_code.size(), 0.0);
        }
        room(n, next);
        offsets_room(next, 1);
        const int c = wc_;
        cs_.id[c] = take_id(cs_, x.id[f]); cs_.block_a[c] = x.block_a[f]; cs_.block_b[c] = x.block_b[f];
        cs_.normal_code[c] = x.normal_code[f]; cs_.gap[c] = x.gap[f];
        cs_.joint[c] = x.joint[f]; cs_.free_motion[c] = x.free_motion[f];
        for (int i = 0; i < n; ++i) {
            const int j = j0 + i, k = wk_ + i;
            cs_.sub_code[k] = cs_.code_of_key(x.sub_key(j)); cs_.sub_area[k] = x.sub_area[j];
            cs_.sub_point[k] = x.sub_point[j]; cs_.sub_un[k] = x.sub_un[j]; // the point with its flags
            cs_.sub_us[k] = x.sub_us[j]; cs_.sub_ss[k] = x.sub_ss[j];
            if (tri_) cs_.sub_tri[k] = x.sub_triangle(j);
            if (dil_) cs_.sub_udil[k] = x.sub_dilation(j);
        }
        advance(n);
    }
    // The arrays cut to what was written. Their spare capacity is given back only when it is
    // large (a pass that dropped many contacts), so that passes do not reallocate step by step.
    void finish() {
        each_contact_array(cs_, [&](auto& v) { v.resize(wc_); trim(v); });
        each_sub_array(cs_, tri_, dil_, [&](auto& v) { v.resize(wk_); trim(v); });
        cs_.sub_offset.resize(wc_ + 1);
        trim(cs_.sub_offset);
        if (cs_.key_table.keys.size() > 2 * cs_.key_table.live + 1024) cs_.compact_key_table();
    }

private:
    void advance(int n) {
        ++wc_;
        wk_ += n;
        if (static_cast<size_t>(wc_) >= cs_.sub_offset.size()) cs_.sub_offset.push_back(wk_);
        else cs_.sub_offset[wc_] = wk_;
    }
    // Room below old contact `next`'s offset (next < 0: none is left to read) for the new
    // offsets of `extra` contacts more than wc + 1: the unread offsets moved up by a gap.
    void offsets_room(int next, int extra) {
        if (next < 0) return;
        const long lo = next + go_;
        if (wc_ + 1 + extra <= lo) return;
        const long p = static_cast<long>(cs_.sub_offset.size());
        const long g = wc_ + 1 + extra - lo + (p - lo) / 32 + 64;
        open(cs_.sub_offset, lo, g, false);
        go_ += g;
    }
    template <class V>
    static void trim(V& v) {
        if (v.capacity() > v.size() + v.size() / 8 + 1024) v.shrink_to_fit();
    }
    // The elements [from, to) of v moved down by `by`.
    template <class V>
    static void move_down(V& v, long from, long to, long by, int threads) {
        using T = typename V::value_type;
        static_assert(std::is_trivially_copyable_v<T> || std::is_same_v<T, Eigen::Vector3d> ||
                      std::is_same_v<T, Eigen::Vector2d>);
        move_bytes_down(reinterpret_cast<char*>(v.data()), from * sizeof(T), to * sizeof(T), by * sizeof(T), threads);
    }
    // v one longer by g elements inserted at `at`, what was there moved up.
    template <class V>
    static void open(V& v, std::size_t at, std::size_t g, bool appending) {
        const std::size_t p = v.size(), n = p + g;
        if (n > v.capacity()) v.reserve(std::max(n, v.capacity() + v.capacity() / (appending ? 2 : 8)));
        // The new elements are all written before they are read (moved up into, or written by
        // the pass), so their pages are not touched here.
        v.resize_for_overwrite(n);
        // Moved as bytes, on the threads when it is much: every array of the set holds plain
        // numbers (Eigen's 3-vectors are three doubles and nothing else).
        using T = typename V::value_type;
        static_assert(std::is_trivially_copyable_v<T> || std::is_same_v<T, Eigen::Vector3d> ||
                      std::is_same_v<T, Eigen::Vector2d>);
        if (at < p) {
            move_bytes_up(reinterpret_cast<char*>(v.data()), at * sizeof(T), p * sizeof(T), g * sizeof(T), thread_count());
        }
    }
    // Room for one more contact with nk sub-contacts before old contact `next`.
    void room(int nk, int next) {
        const long pc = static_cast<long>(cs_.id.size()), pk = static_cast<long>(cs_.sub_code.size());
        const long lc = next >= 0 ? next + gc_ : pc;
        const long lk = next >= 0 ? cs_.sub_offset[next + go_] + gk_ : pk;
        if (wc_ + 1 > lc) {
            // Past the end: grow by half again; before old state: a gap a 32nd of what follows.
            const long g = wc_ + 1 - lc + (next >= 0 ? (pc - lc) / 32 : pc / 2) + 64;
            each_contact_array(cs_, [&](auto& v) { open(v, lc, g, next < 0); });
            if (next >= 0) gc_ += g;
        }
        if (wk_ + nk > lk) {
            const long g = wk_ + nk - lk + (next >= 0 ? (pk - lk) / 32 : pk / 2) + 256;
            each_sub_array(cs_, tri_, dil_, [&](auto& v) { open(v, lk, g, next < 0); });
            if (next >= 0) gk_ += g;
        }
    }

    ContactSet& cs_;
    long gc_ = 0, gk_ = 0; // how far the unread old state has been moved up
    long go_ = 0;          // how far the unread old offsets have been moved up
    int wc_ = 0, wk_ = 0;  // contacts and sub-contacts written
    bool tri_;             // the set has triangles (sub_tri)
    bool dil_;             // the set has dilations (sub_udil)
};

// Carry a tangential vector onto the tangent plane of the new normal, keeping its length.
Vec3 retangent(const Vec3& t, const Vec3& n) {
    const double len = t.norm();
    if (!(len > 0)) return t;
    Vec3 r = t - t.dot(n) * n;
    const double rl = r.norm();
    return rl > 0 ? Vec3(r * (len / rl)) : Vec3(Vec3::Zero());
}

struct Detector {
    Model& m;
    ContactSet& cs;
    ContactSet& next;
    double tol;
    std::vector<Piece> pieces_a, pieces_b;
    std::vector<NewSub> subs;
    std::vector<double> face_area_a, face_area_b;
    std::vector<double> nodal_a, nodal_b; // (n_vertices) m^2, each vertex's own area facing the plane
    std::vector<GridpointSub> gsubs;

    BlockView view(int b) const {
        return BlockView{m.blocks.world_vertices.data() + m.blocks.vertex_offset[b], &m.blocks.shape[b]};
    }

    // For blocks that meet only along an edge or at a corner: the joint tag of the faces of
    // both blocks through the corners they share, when every such face lies on a joined
    // joint plane; 0 otherwise. Where pieces of one block cut apart by joined planes meet
    // only along a cut line or at a point, they touch on joined joints alone, and are glued
    // like the faces they share with their other neighbours. The shared corners are the
    // vertices of either block that lie on the other, to a hair: pieces cut from one block
    // share them exactly.
    int edge_tag(const BlockView& va, const BlockView& vb) const {
        if (va.topo->face_joint.empty() || vb.topo->face_joint.empty()) return 0;
        const double on = 1e-6 * tol;
        auto outside = [](const BlockView& t, const Vec3& x) {
            double most = -std::numeric_limits<double>::infinity();
            for (int f = 0; f < t.topo->n_faces(); ++f) {
                most = std::max(most, world_face_normal(t, f).dot(x - t.v[t.topo->face_vertex(f, 0)]));
            }
            return most;
        };
        std::vector<Vec3> shared;
        for (int i = 0; i < va.topo->n_vertices(); ++i) {
            if (std::abs(outside(vb, va.v[i])) <= on) shared.push_back(va.v[i]);
        }
        for (int i = 0; i < vb.topo->n_vertices(); ++i) {
            if (std::abs(outside(va, vb.v[i])) <= on) shared.push_back(vb.v[i]);
        }
        if (shared.empty()) return 0;
        int tag = 0;
        for (const BlockView* v : {&va, &vb}) {
            const Polyhedron& p = *v->topo;
            int found = 0;
            for (int f = 0; f < p.n_faces(); ++f) {
                const Vec3 nf = world_face_normal(*v, f);
                const Vec3& o = v->v[p.face_vertex(f, 0)];
                bool through = true;
                for (const Vec3& x : shared) through = through && std::abs(nf.dot(x - o)) <= on;
                if (!through) continue;
                const int t = p.face_joint.empty() ? 0 : p.face_joint[f];
                if (t <= 0 || t > static_cast<int>(m.joint_planes.size()) || !m.joint_planes[t - 1].joined) return 0;
                if (tag == 0) tag = t;
                ++found;
            }
            if (found == 0) return 0;
        }
        return tag;
    }

    // The dilation of the sub-contact just pushed to `next`: sub_udil is kept once some sub-contact
    // has one (then it has an entry for each).
    void push_dilation(double udil) {
        if (udil == 0 && next.sub_udil.empty()) return;
        next.sub_udil.resize(next.sub_code.size() - 1, 0.0);
        next.sub_udil.push_back(udil);
    }

    // The contact just built into `next`, from its sub-contact `first` on: those it took over
    // open (their closures as they are now: the old contact gave them so before the references
    // moved, detect_contacts) are held by the references as they are now (contact.h), when
    // its blocks are rigid and the contact set holds them so.
    void give_by_reference(int first) {
        const BlockSet& s = m.blocks;
        const int a = next.block_a.back(), b = next.block_b.back();
        if (!cs.open_by_reference || ((s.flags[a] | s.flags[b]) & kDeformable)) return;
        const Vec3 nrm = next.normal(next.size() - 1);
        for (int k = first; k < next.n_subs(); ++k) {
            if (!held_open(next.sub_flags(k))) continue;
            const int owner = next.sub_side(k) == 1 ? b : a;
            const Vec3 x = s.centroid[owner] + s.orientation[owner] * next.sub_point_local(k);
            next.sub_un[k] += reference_shift(m, a, b, x, nrm);
        }
    }

    // The history of the sub-contact just pushed to `next`: that of old sub-contact k (its
    // shear turned onto the new plane), or, for a new one (k < 0), the closure the geometry
    // shows. A point that slides with the overlap (`moving`) keeps no closure of its own.
    void push_history(int k, double closure, bool moving) {
        if (k >= 0) {
            // A contact whose plane turned (kTurned) changed what it is (an edge against an edge
            // become a face on a face): the closure its points gathered across the old plane
            // is not a closure across the new one; they take what the geometry shows.
            if (plane_turned) moving = true;
            next.sub_un.push_back(moving ? closure : cs.sub_un[k]);
            push_dilation(moving ? 0.0 : cs.sub_dilation(k));
            next.sub_us.push_back(turned(cs.sub_us[k]));
            next.sub_ss.push_back(turned(cs.sub_ss[k]));
            next.set_sub_flags(next.n_subs() - 1, cs.sub_flags(k) & ~(kSubNew | kSubFresh));
        } else {
            next.sub_un.push_back(closure);
            push_dilation(0);
            next.sub_us.push_back(Eigen::Vector2d::Zero());
            next.sub_ss.push_back(Eigen::Vector2d::Zero());
            next.set_sub_flags(next.n_subs() - 1, kSubNew);
        }
    }

    // A sub-contact new to a contact that was already carried: its closure is what the geometry
    // shows; its shear displacement and stress, dilation and whether the joint has failed are
    // those of old sub-contact k nearest it (the joint's state is continuous along it; starting
    // from nothing would drop what the shear springs held whenever the polygon's corners change;
    // build says when an old one hands its state on). One that the geometry shows open (its
    // joint would open at its first step) takes no shear stress: its spring would drop it at
    // once, and that energy was never put in.
    void push_inherited(int k, double closure) {
        next.sub_un.push_back(closure);
        push_dilation(cs.sub_dilation(k));
        next.sub_us.push_back(turned(cs.sub_us[k]));
        double kn = 0, ten = 0;
        if (const JointMaterial* jm = material()) {
            kn = jm->kn;
            ten = (cs.sub_flags(k) & kSubFailed) ? 0.0 : jm->tension;
        }
        const double sn = kn * (closure + cs.sub_dilation(k));
        const bool opens = !next.joined(next.size() - 1) && (sn < -ten || (sn <= 0 && ten <= 0));
        next.sub_ss.push_back(opens ? Eigen::Vector2d(Eigen::Vector2d::Zero()) : turned(cs.sub_ss[k]));
        next.set_sub_flags(next.n_subs() - 1, static_cast<std::uint8_t>((cs.sub_flags(k) & kSubFailed) | kSubFresh));
    }

    // The joint material of the contact being built, or null when it has none defined.
    const JointMaterial* material() const {
        return joint_material(m, next.jmat(next.size() - 1));
    }

    // Whether the contact being built turned its plane by more than kTurned since it was last
    // built (push_history).
    bool plane_turned = false;

    // The old sub-contact of old contact `old` (blocks a, b) nearest the world point x, or -1.
    // Slivers of the old polygon (under 1e-3 of its largest share: two corners all but
    // coinciding), whose histories need not be the joint's, hand nothing on.
    int nearest_old(const OldRef& old, int a, int b, const Vec3& x) const {
        int best = -1;
        double best_d = std::numeric_limits<double>::infinity();
        double hi = 0;
        for (int j = old.k0; j < old.k1; ++j) hi = std::max(hi, cs.sub_area[j]);
        for (int j = old.k0; j < old.k1; ++j) {
            if (cs.sub_side(j) > 2 || cs.sub_area[j] < 1e-3 * hi) continue;
            const int owner = cs.sub_side(j) == 1 ? b : a;
            const double d = (m.blocks.centroid[owner] + m.blocks.orientation[owner] * cs.sub_point_local(j) - x).squaredNorm();
            if (d < best_d) {
                best_d = d;
                best = j;
            }
        }
        return best;
    }

    // A shear vector of an old sub-contact of the contact being built (on the old contact's shear
    // axes) turned onto the new plane, keeping its length, and put on the new axes: the same
    // numbers when the plane did not turn.
    Eigen::Vector2d turned(const Eigen::Vector2d& v) const {
        if (same_axes) return v;
        const Vec3 t = retangent(v[0] * old_e1 + v[1] * old_e2, new_n);
        return Eigen::Vector2d(t.dot(new_e1), t.dot(new_e2));
    }

    // The contact's own entries in `next`: id, joint material and model (from the old
    // contact, else from the joint plane its faces lie on), blocks and plane.
    void push_header(int a, int b, int oc, const BlockView& va, const BlockView& vb, const CommonPlane& cp) {
        const BlockSet& s = m.blocks;
        new_n = cp.normal;
        shear_axes(new_n, new_e1, new_e2);
        const NormalCode code = encode_normal(cp.normal);
        same_axes = oc < 0 || cs.normal_code[oc] == code;
        if (!same_axes) shear_axes(cs.normal(oc), old_e1, old_e2);
        if (oc >= 0) {
            next.id.push_back(cs.id[oc]);
            next.joint.push_back(cs.joint[oc]);
        } else {
            next.id.push_back(0); // its id comes when it joins the contact set (take_id)
            int jmat = m.settings.default_jmat, jcons = m.settings.default_jcons;
            bool joined = false;
            // The joint plane the contact lies on, from the faces carrying most area.
            auto tag_of = [&](int blk, const std::vector<double>& fa) {
                const Polyhedron& p = s.shape[blk];
                int best = -1;
                double best_a = 0;
                for (int f = 0; f < static_cast<int>(fa.size()); ++f) {
                    if (fa[f] > best_a) { best_a = fa[f]; best = f; }
                }
                if (best < 0 || p.face_joint.empty()) return 0;
                return p.face_joint[best];
            };
            int tag = tag_of(a, face_area_a);
            if (tag == 0) tag = tag_of(b, face_area_b);
            // No tagged face carries the contact's area: the blocks may meet only along an
            // edge or at a corner (on a face that carries area, edge_tag finds that face).
            if (tag == 0) tag = edge_tag(va, vb);
            if (tag > 0 && tag <= static_cast<int>(m.joint_planes.size())) {
                const JointPlane& jp = m.joint_planes[tag - 1];
                if (jp.jmat > 0) jmat = jp.jmat;
                // Glued only where the blocks touch: two pieces of one joined mass with a thin
                // piece between them face each other across it, apart.
                joined = jp.joined && cp.gap <= 1e-3 * tol;
            }
            next.joint.push_back(ContactSet::joint_word(jmat, jcons, joined));
        }
        next.block_a.push_back(a);
        next.block_b.push_back(b);
        next.normal_code.push_back(code);
        next.gap.push_back(float_nearest(cp.gap));
        next.free_motion.push_back(bound16_not_above(-std::numeric_limits<double>::infinity()));
    }

    // Build contact (a, b), one of them deformable, from its gridpoints (contact_gridpoint.h).
    bool build_gridpoint(int a, int b, const OldRef& old, bool require_close) {
        const int oc = old.c;
        const BlockView va = view(a), vb = view(b);
        const Vec3 old_n = oc >= 0 ? cs.normal(oc) : Vec3::UnitZ();
        const CommonPlane cp = common_plane(va, vb, oc >= 0 ? &old_n : nullptr, oc >= 0 ? tol : 0.0, 0.1 * tol);
        if (require_close && cp.gap > tol) return false;
        plane_turned = oc >= 0 && old_n.dot(cp.normal) < kTurned;
        face_area_a.assign(m.blocks.shape[a].n_faces(), 0.0);
        face_area_b.assign(m.blocks.shape[b].n_faces(), 0.0);
        gridpoint_subcontacts(m, a, b, cp, tol, gsubs, face_area_a, face_area_b);
        push_header(a, b, oc, va, vb, cp);
        int k = old.k0;
        const int k_end = old.k1;
        for (const GridpointSub& gs : gsubs) {
            while (k < k_end && cs.sub_key(k) < gs.key) ++k;
            push_sub(next, gs.key, gs.area, gs.local, gs.tri);
            push_history(k < k_end && cs.sub_key(k) == gs.key ? k : -1, gs.closure, false);
        }
        next.sub_offset.push_back(next.n_subs());
        return true;
    }

    // Build contact (a, b) into `next`, carrying history from old contact oc (-1: new).
    // Returns false when the blocks are farther apart than ctol.
    bool build(int a, int b, const OldRef& old, bool require_close) {
        if ((m.blocks.flags[a] | m.blocks.flags[b]) & kDeformable) return build_gridpoint(a, b, old, require_close);
        const int oc = old.c;
        const BlockView va = view(a), vb = view(b);
        const Vec3 old_n = oc >= 0 ? cs.normal(oc) : Vec3::UnitZ();
        const CommonPlane cp = common_plane(va, vb, oc >= 0 ? &old_n : nullptr, oc >= 0 ? tol : 0.0, 0.1 * tol);
        if (require_close && cp.gap > tol) return false;
        plane_turned = false;
        if (oc >= 0 && cs.joined(oc) && old.k1 > old.k0) {
            // A glued joint is a bond between the material points it was glued over: it keeps
            // its sub-contacts, their places on their blocks and their areas, and only turns
            // with the common plane. Shared out anew as the blocks shear and bend on it, the
            // points' areas and places would change the energy its springs hold without work
            // (on joints of 1e8 Pa/m, a pendulum of glued blocks gained or lost 0.4 %).
            push_header(a, b, oc, va, vb, cp);
            const int first = next.n_subs();
            for (int k = old.k0; k < old.k1; ++k) {
                push_sub(next, cs.sub_key(k), cs.sub_area[k], cs.sub_point[k]);
                push_history(k, cs.sub_un[k], false);
            }
            give_by_reference(first);
            next.free_motion.back() = bound16_not_above(clearance(a, b, cp.normal, first));
            next.sub_offset.push_back(next.n_subs());
            return true;
        }
        plane_turned = oc >= 0 && old_n.dot(cp.normal) < kTurned;
        const Frame fr = make_frame(cp);
        present_faces(va, fr, 0, tol, pieces_a, nodal_a);
        present_faces(vb, fr, 1, tol, pieces_b, nodal_b);
        face_area_a.assign(m.blocks.shape[a].n_faces(), 0.0);
        face_area_b.assign(m.blocks.shape[b].n_faces(), 0.0);
        const double min_area = 1e-12 * tol * tol;
        polygon_subcontacts(fr, pieces_a, pieces_b, tol, 1e-9 * tol, min_area, subs, face_area_a, face_area_b, nodal_a,
                            nodal_b);

        const BlockSet& s = m.blocks;
        const Mat3 rot[2] = {s.orientation[a].toRotationMatrix(), s.orientation[b].toRotationMatrix()};
        push_header(a, b, oc, va, vb, cp);

        // Old sub-contact j hands its state on to a new one near it when the new one takes over
        // some of the area it held: it is gone (a corner that became a crossing of edges), or
        // its own area shrank (the polygon was shared out anew). One that keeps its area, as
        // a toe does when the other corner of its edge lands, hands nothing on: the new one
        // touches where nothing did, and a copy of the toe's shear stress would be energy the
        // springs never took up (that the joint would then dissipate as the copy slips).
        auto hands_on = [&](int j) {
            const std::int64_t key = cs.sub_key(j);
            const auto it = std::lower_bound(subs.begin(), subs.end(), key,
                                             [](const NewSub& x, std::int64_t kk) { return x.key < kk; });
            return it == subs.end() || it->key != key || it->area < cs.sub_area[j] * (1 - 1e-9);
        };
        // Merge with the old sub-contacts: both lists are in key order.
        int k = old.k0;
        const int k_end = old.k1;
        const int first = next.n_subs();
        born.clear();
        old_area.clear();
        for (const NewSub& ns : subs) {
            while (k < k_end && cs.sub_key(k) < ns.key) ++k;
            const int side = ContactSet::key_side(ns.key);
            const int owner = side == 1 ? b : a;
            const Vec3 local = rot[side == 1 ? 1 : 0].transpose() * (ns.x - s.centroid[owner]);
            push_sub(next, ns.key, ns.area, local);
            const bool moving = on_touch_line(ns.key);
            const bool kept = k < k_end && cs.sub_key(k) == ns.key; // the same point as before
            born.push_back(!kept || moving || plane_turned);
            old_area.push_back(kept ? cs.sub_area[k] : 0.0);
            if (kept) {
                push_history(k, ns.closure, moving);
            } else {
                const int j = moving || old.c < 0 ? -1 : nearest_old(old, a, b, ns.x);
                if (j >= 0 && hands_on(j)) push_inherited(j, ns.closure);
                else push_history(-1, ns.closure, moving);
            }
        }
        if (subs.empty()) {
            // A corner that still presses by its own closure, or has lifted by less than a
            // millionth of ctol, where the geometry finds no overlap at all, is kept as it is:
            // the closure is a step behind the geometry, and on stiff joints a toe that bounces
            // by a fraction of a micrometre is found just clear of the base now and then.
            // Dropped, its contact would touch nowhere, as blocks that meet along an edge do,
            // and be looked at again only once the toe had sunk a thousandth of ctol in unseen
            // (a kick). Kept, its own closure finds it landing again; a refresh drops it once it
            // has lifted clear.
            for (int j = old.k0; j < old.k1; ++j) {
                if (cs.sub_side(j) > 1 || !(cs.sub_un[j] + cs.sub_dilation(j) > -1e-6 * tol)) continue;
                push_sub(next, cs.sub_key(j), cs.sub_area[j], cs.sub_point[j]);
                push_history(j, cs.sub_un[j], false);
            }
        }
        if (m.settings.dynamic && oc >= 0) limit_rebuild_energy(old, first);
        give_by_reference(first);
        next.free_motion.back() = bound16_not_above(clearance(a, b, cp.normal, first));
        next.sub_offset.push_back(next.n_subs());
        return true;
    }

    // A rebuild is no event of the blocks' motion: in dynamic mode (where energy is real) the
    // energy the contact's springs hold may not jump by it. Areas and closures are made to
    // carry over smoothly (see the top), but where the geometry fails that (thin convex pieces
    // of blocks striking each other at speed, a corner that went in unseen), the springs born
    // or grown in area by this rebuild (`born`, `old_area`) would hold up to thousands of times
    // what the contact held: the collapsing corpus arch gained megajoules that way. When the
    // contact's springs would hold more than kRebuildGrowth times what they held, the closures
    // and shear stresses of those springs are scaled down so that it holds what it held (or
    // what its unchanged springs hold): the blocks overlap by the rest, unloaded, until they
    // part. Smaller changes, the rule's own, are left alone.
    void limit_rebuild_energy(const OldRef& old, int first) {
        const JointMaterial* jm = material();
        if (!jm) return;
        const double kn = jm->kn, ks = jm->ks;
        if (!(kn > 0 && ks > 0)) return;
        // Twice the energy of a spring of area `area`, normal closure `un`, shear stress `ss`.
        auto e = [&](double area, double un, const Eigen::Vector2d& ss) {
            return area * ((un > 0 ? kn * un * un : 0.0) + ss.squaredNorm() / ks);
        };
        // (The closures as they are now: the contact's open ones are held by reference only once
        // it is built, give_by_reference.)
        auto closure = [](const ContactSet& x, int k) { return x.sub_un[k] + x.sub_dilation(k); };
        double e_old = 0, e_keep = 0, e_changed = 0;
        for (int j = old.k0; j < old.k1; ++j) e_old += e(cs.sub_area[j], closure(cs, j), cs.sub_ss[j]);
        for (int i = 0; i < static_cast<int>(born.size()); ++i) {
            const int q = first + i;
            if (!born[i] && next.sub_area[q] > (1 + 1e-9) * old_area[i]) born[i] = 1;
            (born[i] ? e_changed : e_keep) += e(next.sub_area[q], closure(next, q), next.sub_ss[q]);
        }
        if (!(e_changed > 0 && e_keep + e_changed > kRebuildGrowth * e_old)) return;
        const double f = std::sqrt(std::max(0.0, e_old - e_keep) / e_changed);
        for (int i = 0; i < static_cast<int>(born.size()); ++i) {
            if (!born[i]) continue;
            const int q = first + i;
            const double c = closure(next, q);
            if (c > 0) next.sub_un[q] = f * c - next.sub_dilation(q);
            next.sub_ss[q] *= f;
        }
    }

    // How far blocks a and b may move, as `movement` measures it since their geometry
    // references, before a corner of either that carries none of the sub-contacts from `first`
    // on could have pressed into the other as the closing check looks for (detect_contacts):
    // the least distance of such a corner outside the other block (the largest of its distances
    // over the other's face planes, which a motion of either block changes by no more than the
    // motion), less the corner snap, less how far the blocks have moved since their references.
    // A corner over or under a corner of the other block that carries a sub-contact, as seen
    // along the normal, is carried by it (two blocks' corners meeting).
    double clearance(int a, int b, const Vec3& nrm, int first) {
        const BlockSet& s = m.blocks;
        const double snap = kCornerSnap * tol;
        const int off[2] = {s.vertex_offset[a], s.vertex_offset[b]};
        const int end[2] = {s.vertex_offset[a + 1], s.vertex_offset[b + 1]};
        const BlockView views[2] = {view(a), view(b)};
        auto tracked = [&](int side, int vertex) {
            return corner_carried(next, first, next.n_subs(), s.world_vertices, off, side, vertex, nrm, snap);
        };
        double clear = std::numeric_limits<double>::infinity();
        for (int side = 0; side < 2; ++side) {
            // The other block's face planes n.x = d, once.
            const BlockView& other = views[1 - side];
            const int nf = other.topo->n_faces();
            plane_n.resize(nf);
            plane_d.resize(nf);
            for (int f = 0; f < nf; ++f) {
                plane_n[f] = world_face_normal(other, f);
                plane_d[f] = plane_n[f].dot(other.v[other.topo->face_vertex(f, 0)]);
            }
            for (int i = off[side]; i < end[side]; ++i) {
                if (tracked(side, i - off[side])) continue;
                const Vec3& x = s.world_vertices[i];
                double outside = -std::numeric_limits<double>::infinity();
                for (int f = 0; f < nf; ++f) outside = std::max(outside, plane_n[f].dot(x) - plane_d[f]);
                clear = std::min(clear, outside);
            }
        }
        // A contact that carries nothing is watched from the moment its blocks could touch at
        // all: the gap across its plane, which a motion of either block closes by no more than
        // the motion. Two edges crossing (square prisms laid crosswise) touch with no corner in
        // the other block: watched by their corners alone, such blocks went ctol/10 into one
        // another before the next refresh (the upper prism sank 5 mm and was thrown off).
        if (first == next.n_subs()) clear = std::min(clear, static_cast<double>(next.gap.back()));
        return clear - snap - movement(cs, s, a, cs.geo_centroid, cs.geo_orientation) -
               movement(cs, s, b, cs.geo_centroid, cs.geo_orientation);
    }
    std::vector<Vec3> plane_n; // clearance's scratch: a block's face normals
    std::vector<double> plane_d;
    // Per sub-contact of the contact being built: its spring is new (born, or its closure taken
    // from the geometry), and the area it had before (0: none).
    std::vector<char> born;
    std::vector<double> old_area;
    // The shear axes of the contact being built and of its old contact (turned).
    Vec3 new_n = Vec3::UnitZ(), new_e1 = Vec3::UnitX(), new_e2 = Vec3::UnitY(); // of the contact being built
    Vec3 old_e1 = Vec3::UnitX(), old_e2 = Vec3::UnitY();                       // of its old contact
    bool same_axes = true;                                                     // its plane did not turn
};

// The contacts to (re)build in a pass, one int a job: its old contact (>= 0), whose blocks it is
// between and whose history it carries, or ~i for the i-th pair of blocks new to the set
// (Jobs::pairs, a < b). Four bytes a job: in a settling mass nearly
// every contact is rebuilt at a refresh pass, and the jobs are planned for the whole pass.
struct Jobs {
    std::vector<int> job;
    std::vector<std::array<int, 2>> pairs; // blocks a < b of the new pairs (full passes only)
    int size() const { return static_cast<int>(job.size()); }
    // The old contact of job j, or -1.
    int old(int j) const { return job[j] >= 0 ? job[j] : -1; }
    void clear() {
        job.clear();
        pairs.clear();
    }
    void add(int a, int b, int oc) {
        if (oc >= 0) {
            job.push_back(oc);
        } else {
            job.push_back(~static_cast<int>(pairs.size()));
            pairs.push_back({a, b});
        }
    }
};

// Jobs built at a time: the contacts of one window are all that a pass holds besides the set.
constexpr int kBuildWindow = 2048;

// Build jobs [j0, j1) into rb, on the threads, reading the old contacts where rw has them.
// fresh[j - j0] is the fresh index of job j's contact, or -1 when its blocks were farther apart
// than ctol. Each contact is built alone from the old set and the blocks, so the result is the
// same whatever the threads and the windows.
void build_jobs(Model& m, ContactSet& cs, const Jobs& jobs, int j0, int j1, const Rewrite& rw, Rebuilt& rb,
                std::vector<int>& fresh, std::vector<char>& carried) {
    const int nj = j1 - j0;
    const int threads = thread_count();
    const bool on_threads = threads > 1 && nj >= kParallelMinBuilds;
    const int n_parts = on_threads ? std::min(nj, 8 * threads) : 1;
    if (static_cast<int>(rb.parts.size()) < n_parts) rb.parts.resize(n_parts);
    for (ContactSet& x : rb.parts) clear_arrays(x);
    fresh.assign(nj, -1);
    carried.assign(nj, 0);
    ContactSet* parts = rb.parts.data();
    int* where = fresh.data();
    char* had = carried.data();
    const int* job = jobs.job.data() + j0;
    const std::array<int, 2>* new_pair = jobs.pairs.data();
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1) if (on_threads)
    for (int p = 0; p < n_parts; ++p) {
        const int i0 = static_cast<int>(static_cast<long>(nj) * p / n_parts);
        const int i1 = static_cast<int>(static_cast<long>(nj) * (p + 1) / n_parts);
        Detector d{m, cs, parts[p], cs.ctol, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}};
        for (int i = i0; i < i1; ++i) {
            // An old contact's blocks are read where the pass has it (not yet overwritten: its
            // window is being built).
            const int v = job[i];
            const OldRef o = rw.old(v >= 0 ? v : -1);
            had[i] = o.k1 > o.k0;
            const int a = v >= 0 ? cs.block_a[o.c] : new_pair[~v][0], b = v >= 0 ? cs.block_b[o.c] : new_pair[~v][1];
            if (d.build(a, b, o, true)) where[i] = parts[p].size() - 1;
        }
    }
    rb.part.clear();
    rb.local.clear();
    for (int p = 0; p < n_parts; ++p) {
        const int i0 = static_cast<int>(static_cast<long>(nj) * p / n_parts);
        const int i1 = static_cast<int>(static_cast<long>(nj) * (p + 1) / n_parts);
        for (int i = i0; i < i1; ++i) {
            if (fresh[i] < 0) continue;
            rb.part.push_back(p);
            rb.local.push_back(fresh[i]);
            fresh[i] = static_cast<int>(rb.part.size()) - 1;
        }
    }
}

// Candidate pairs (a < b) from the cell grid, sorted.
void broad_phase(const Model& m, double tol, std::vector<std::int64_t>& pairs) {
    const BlockSet& s = m.blocks;
    const int n = s.size();
    pairs.clear();
    // Buffers of this call only: the broad phase runs seldom, and kept they would hold about
    // 70 B a block between its runs.
    std::vector<Vec3> lo, hi;
    std::vector<int> active, cell_items;
    std::vector<long> cell_start; // block-cell memberships can pass INT_MAX
    lo.resize(n);
    hi.resize(n);
    active.clear();
    Vec3 glo = Vec3::Constant(std::numeric_limits<double>::infinity()), ghi = -glo;
    double size_sum = 0;
    for (int b = 0; b < n; ++b) {
        if (s.flags[b] & kExcavated) continue;
        const int o0 = s.vertex_offset[b], o1 = s.vertex_offset[b + 1];
        if (o1 == o0) continue;
        Vec3 l = s.world_vertices[o0], h = l;
        for (int i = o0 + 1; i < o1; ++i) {
            l = l.cwiseMin(s.world_vertices[i]);
            h = h.cwiseMax(s.world_vertices[i]);
        }
        lo[b] = l.array() - 0.5 * tol;
        hi[b] = h.array() + 0.5 * tol;
        glo = glo.cwiseMin(lo[b]);
        ghi = ghi.cwiseMax(hi[b]);
        size_sum += (hi[b] - lo[b]).maxCoeff();
        active.push_back(b);
    }
    const int na = static_cast<int>(active.size());
    if (na < 2) return;
    // Keep the grid to a few cells per block, however spread out the blocks are. The cell
    // counts are worked out in double and capped before anything becomes an integer, so no
    // spread of finite coordinates can overflow them (half spans: ghi - glo may exceed DBL_MAX).
    const double max_cells = 8.0 * na + 64;
    double cell = 2.0 * size_sum / na;
    if (!(cell > 0)) cell = 1; // zero-size (or non-finite) blocks: any cell will do
    auto cells_along = [&](int i) {
        const double r = (0.5 * ghi[i] - 0.5 * glo[i]) / cell * 2.0;
        if (!(r > 1)) return 1.0; // also NaN
        return std::min(std::ceil(r), max_cells + 1);
    };
    long dims[3];
    for (;;) {
        const double d0 = cells_along(0), d1 = cells_along(1), d2 = cells_along(2);
        if (d0 * d1 * d2 <= max_cells) { // each <= max_cells + 1: the product is exact enough
            dims[0] = static_cast<long>(d0);
            dims[1] = static_cast<long>(d1);
            dims[2] = static_cast<long>(d2);
            break;
        }
        cell *= 1.5; // an infinite cell gives one cell along every axis: the loop ends
    }
    // Monotonic in x, which is all the owner-cell test below needs; NaN and overflow clamp.
    auto cell_of = [&](double x, int i) {
        const double q = std::floor((x - glo[i]) / cell);
        if (!(q > 0)) return 0L;
        return q >= static_cast<double>(dims[i] - 1) ? dims[i] - 1 : static_cast<long>(q);
    };
    const long n_cells = dims[0] * dims[1] * dims[2]; // <= max_cells
    cell_start.assign(n_cells + 1, 0);
    auto for_cells = [&](int b, auto&& fn) {
        const long x0 = cell_of(lo[b].x(), 0), x1 = cell_of(hi[b].x(), 0);
        const long y0 = cell_of(lo[b].y(), 1), y1 = cell_of(hi[b].y(), 1);
        const long z0 = cell_of(lo[b].z(), 2), z1 = cell_of(hi[b].z(), 2);
        for (long z = z0; z <= z1; ++z)
            for (long y = y0; y <= y1; ++y)
                for (long x = x0; x <= x1; ++x) fn((z * dims[1] + y) * dims[0] + x);
    };
    for (int b : active) for_cells(b, [&](long c) { ++cell_start[c + 1]; });
    for (long c = 0; c < n_cells; ++c) cell_start[c + 1] += cell_start[c];
    cell_items.resize(cell_start[n_cells]);
    {
        std::vector<long> fill(cell_start.begin(), cell_start.end() - 1);
        for (int b : active) for_cells(b, [&](long c) { cell_items[fill[c]++] = b; });
    }
    for (long c = 0; c < n_cells; ++c) {
        for (long i = cell_start[c]; i < cell_start[c + 1]; ++i) {
            const int a = cell_items[i];
            for (long j = i + 1; j < cell_start[c + 1]; ++j) {
                const int b = cell_items[j];
                // Two held blocks need no contact, unless water flows in the joint between them (flow.h).
                if (!m.flow.on && (s.flags[a] & kFixed) && (s.flags[b] & kFixed) && !s.vel_bc[a] && !s.vel_bc[b]) continue;
                // The blocks of one continuum share their gridpoints: no contact between them.
                if ((s.flags[a] & s.flags[b] & kDeformable) && s.body[a] == s.body[b]) continue;
                // The pieces of one clump move as one rigid body: no contact between them.
                if (s.clump[a] != 0 && s.clump[a] == s.clump[b]) continue;
                if ((lo[a].array() > hi[b].array()).any() || (lo[b].array() > hi[a].array()).any()) continue;
                const Vec3 il = lo[a].cwiseMax(lo[b]);
                const long owner = (cell_of(il.z(), 2) * dims[1] + cell_of(il.y(), 1)) * dims[0] + cell_of(il.x(), 0);
                if (owner != c) continue;
                pairs.push_back(static_cast<std::int64_t>(a) * n + b); // a < b: items are in block order
            }
        }
    }
    std::sort(pairs.begin(), pairs.end());
}

} // namespace

void block_movements_for_test(const ContactSet& cs, const BlockSet& s, int b, const std::vector<Vec3>& ref_c,
                              const std::vector<Quat>& ref_q, double four[4], double one_by_one[4]) {
    movements4(cs, s, b, ref_c, ref_q, four);
    for (int l = 0; l < 4; ++l) one_by_one[l] = movement(cs, s, b + l, ref_c, ref_q);
}

double contact_tolerance(const Model& m) {
    if (m.settings.ctol > 0) return m.settings.ctol;
    const BlockSet& s = m.blocks;
    double sum = 0;
    int n = 0;
    for (int b = 0; b < s.size(); ++b) {
        if (s.flags[b] & kExcavated) continue;
        sum += std::cbrt(std::max(0.0, s.volume[b]));
        ++n;
    }
    return n > 0 && sum > 0 ? 0.05 * sum / n : 1e-3;
}

void renumber_contacts(Model& m, const std::vector<int>* new_block, const std::vector<int>* new_gp) {
    ContactSet& cs = m.contacts;
    const int nc = cs.size(), ns = cs.n_subs();
    // Geometry references that no longer fit the blocks are dropped below: the open closures
    // held by them are given as they are now first, which is what they are held by with no
    // references (reference_shift; the next refresh makes the references again).
    if (new_block != nullptr && (cs.geo_centroid.size() != new_block->size() || cs.geo_orientation.size() != new_block->size())) {
        for (int c = 0; c < nc; ++c) shift_open_closures(m, c, false);
    }
    auto mapped = [](const std::vector<int>* map, int i) {
        return map == nullptr ? i : (i >= 0 && i < static_cast<int>(map->size()) ? (*map)[i] : -1);
    };
    std::vector<char> keep_c(nc, 1), keep_s(ns, 1);
    for (int c = 0; c < nc; ++c) {
        keep_c[c] = mapped(new_block, cs.block_a[c]) >= 0 && mapped(new_block, cs.block_b[c]) >= 0;
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
            if (!keep_c[c]) {
                keep_s[k] = 0;
                continue;
            }
            if (cs.sub_side(k) < 3 || new_gp == nullptr) continue;
            const int g = mapped(new_gp, cs.sub_vertex(k));
            bool ok = g >= 0;
            if (ok) cs.set_key(k, gridpoint_sub_key(cs.sub_side(k) - 3, g));
            if (!cs.sub_tri.empty()) {
                for (int& q : cs.sub_tri[k]) {
                    if (q < 0) continue;
                    q = mapped(new_gp, q);
                    ok = ok && q >= 0;
                }
            }
            keep_s[k] = ok;
        }
    }
    // Compact, keeping the order (so a < b stays true of every pair).
    std::vector<int> offset(1, 0);
    for (int c = 0; c < nc; ++c) {
        if (!keep_c[c]) continue;
        int n = 0;
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) n += keep_s[k];
        offset.push_back(offset.back() + n);
    }
    each_contact_array(cs, [&](auto& v) {
        if (static_cast<int>(v.size()) != nc) {
            v.clear();
            return;
        }
        size_t w = 0;
        for (int c = 0; c < nc; ++c) {
            if (keep_c[c]) v[w++] = std::move(v[c]);
        }
        v.resize(w);
    });
    each_sub_array(cs, !cs.sub_tri.empty(), !cs.sub_udil.empty(), [&](auto& v) {
        size_t w = 0;
        for (int k = 0; k < ns; ++k) {
            if (keep_s[k]) v[w++] = std::move(v[k]);
        }
        v.resize(w);
    });
    cs.sub_offset.assign(offset.begin(), offset.end());
    if (new_block != nullptr) {
        for (int& b : cs.block_a) b = (*new_block)[b];
        for (int& b : cs.block_b) b = (*new_block)[b];
        const int nb = static_cast<int>(new_block->size());
        auto per_block = [&](auto& v) {
            if (static_cast<int>(v.size()) != nb) {
                v.clear();
                return;
            }
            size_t w = 0;
            for (int b = 0; b < nb; ++b) {
                if ((*new_block)[b] >= 0) v[w++] = std::move(v[b]);
            }
            v.resize(w);
        };
        per_block(cs.ref_centroid);
        per_block(cs.ref_orientation);
        per_block(cs.geo_centroid);
        per_block(cs.geo_orientation);
        per_block(cs.radius);
        per_block(cs.joint_kt);
        per_block(cs.joint_kr);
    }
    // What is derived from the contacts is made again.
    cs.surface_ready = false;
    cs.colored = false;
    cs.color_order.clear();
    cs.color_offset.clear();
    ++cs.revision;
    m.flow.invalidate();
}

void detect_contacts(Model& m) {
    // Unknown (a restored model, contacts made elsewhere): looked at every step until rebuilt.
    if (m.contacts.free_motion.size() != static_cast<size_t>(m.contacts.size())) {
        m.contacts.free_motion.assign(m.contacts.size(), bound16_not_above(-std::numeric_limits<double>::infinity()));
    }
    ContactSet& cs = m.contacts;
    BlockSet& s = m.blocks;
    const int n = s.size();
    cs.motion_fresh = false;
    if (static_cast<int>(s.vertex_offset.size()) != n + 1) return; // world vertices not refreshed yet
    const bool full_needed = !cs.detected || m.geometry_changed || static_cast<int>(cs.ref_centroid.size()) != n;
    if (full_needed) cs.surface_ready = false; // the zones may have changed
    refresh_contact_surface(m);

    thread_local Rebuilt rebuilt;
    thread_local Jobs jobs;
    thread_local std::vector<int> fresh; // per job of a window: its fresh contact, or -1
    thread_local std::vector<char> carried; // per job of a window: its old contact carried sub-contacts
    thread_local std::vector<std::int64_t> pairs;
    thread_local std::vector<char> moved;
    // Per contact: its overlap grew past its area, and then (the same bytes, once those are
    // applied) it touches nowhere and is now overlapping.
    thread_local std::vector<char> closing;
    std::vector<double>& motion = cs.block_motion; // m, movement since the last refresh
    // Per contact of the result: its old index, or ~job (full passes only: a refresh pass keeps
    // or rebuilds every old contact in order, so its plan is the old contacts with the jobs'
    // own in their places, read through plan_at without being written out).
    thread_local std::vector<int> plan;
    std::vector<Vec3>& geo_c = cs.geo_centroid;
    std::vector<Quat>& geo_q = cs.geo_orientation;

    bool full = full_needed;
    const int threads = thread_count();
    // Each block's movement since the last broad phase (kept for the refresh pass below: where a
    // block's geometry reference is that pose too, as it mostly is, it is the same movement).
    thread_local std::vector<double> since_broad;
    if (!full) {
        // On the threads in a large model.
        const double limit = 0.5 * cs.ctol;
        since_broad.resize(n);
        double* since_of = since_broad.data();
        // (Four blocks at a time, in chunks of fixed size on the threads; an excavated block's is
        // not kept.)
        constexpr int kChunk = 256;
        const int n_chunks = (n + kChunk - 1) / kChunk;
        const int far = parallel_or(n_chunks, threads, n >= kParallelMinBlocks, [&](int ch) {
            int out = 0;
            const int b1 = std::min(n, (ch + 1) * kChunk);
            int b = ch * kChunk;
            for (; b + 4 <= b1; b += 4) {
                double mv[4];
                movements4(cs, s, b, cs.ref_centroid, cs.ref_orientation, mv);
                for (int l = 0; l < 4; ++l) {
                    if (s.flags[b + l] & kExcavated) continue;
                    since_of[b + l] = mv[l];
                    out |= mv[l] > limit ? 1 : 0;
                }
            }
            for (; b < b1; ++b) {
                if (s.flags[b] & kExcavated) continue;
                since_of[b] = movement(cs, s, b, cs.ref_centroid, cs.ref_orientation);
                out |= since_of[b] > limit ? 1 : 0;
            }
            return out;
        });
        full = far != 0;
    }
    const double old_ctol = cs.ctol;
    if (full) {
        // What follows the broad check reads the blocks' world vertices: in step from here on.
        catch_up_world_vertices(m);
        cs.ctol = contact_tolerance(m);
        cs.radius.resize(n);
        for (int b = 0; b < n; ++b) {
            double r = 0;
            for (const Vec3& v : s.shape[b].vertices) r = std::max(r, v.norm());
            cs.radius[b] = r;
        }
    }
    plan.clear();
    jobs.clear();
    // Plan an old contact kept as it is, or a contact (re)built.
    auto rebuild = [&](int a, int b, int oc) {
        plan.push_back(~jobs.size());
        jobs.add(a, b, oc);
    };

    if (full) {
        // From scratch when the model changed or the caches do not fit; otherwise only the
        // contacts of blocks that moved since their last refresh are rebuilt (see the top).
        const bool scratch = full_needed || cs.ctol != old_ctol || static_cast<int>(geo_c.size()) != n ||
                             static_cast<int>(geo_q.size()) != n;
        moved.assign(n, 1);
        motion.assign(n, 0.0);
        if (!scratch) {
            const double limit = 0.1 * cs.ctol;
            for (int b = 0; b < n; ++b) {
                if (s.flags[b] & kExcavated) {
                    moved[b] = 0;
                    continue;
                }
                motion[b] = movement(cs, s, b, geo_c, geo_q);
                moved[b] = motion[b] > limit;
            }
        }
        broad_phase(m, cs.ctol, pairs);
        int oc = 0;
        const int n_old = cs.size();
        for (const std::int64_t key : pairs) {
            const int a = static_cast<int>(key / n), b = static_cast<int>(key % n);
            while (oc < n_old && (cs.block_a[oc] < a || (cs.block_a[oc] == a && cs.block_b[oc] < b))) ++oc;
            const bool have = oc < n_old && cs.block_a[oc] == a && cs.block_b[oc] == b;
            if (have && !moved[a] && !moved[b]) plan.push_back(oc);
            else rebuild(a, b, have ? oc : -1);
        }
        // The contacts rebuilt give their open sub-contacts' closures as they are now before the
        // references move (the rebuild gives them by the new references again: give_by_reference).
        for (int j = 0; j < static_cast<int>(jobs.size()); ++j) {
            if (jobs.old(j) >= 0) shift_open_closures(m, jobs.old(j), false);
        }
        cs.ref_centroid = s.centroid;
        cs.ref_orientation = s.orientation;
        if (scratch) {
            geo_c = s.centroid;
            geo_q = s.orientation;
            motion.assign(n, 0.0);
        } else {
            for (int b = 0; b < n; ++b) {
                if (moved[b]) { geo_c[b] = s.centroid[b]; geo_q[b] = s.orientation[b]; motion[b] = 0; }
            }
        }
        cs.detected = true;
        cs.change_seen = m.geometry_changed.count();
        ++cs.n_detections;
        // The candidate pairs are planned: their buffer, as large as all the pairs near one
        // another, is not kept (the broad phase runs seldom).
        std::vector<std::int64_t>().swap(pairs);
    } else {
        const double limit = 0.1 * cs.ctol;
        moved.assign(n, 0);
        motion.assign(n, 0.0);
        int bits;
        {
            char* mv_of = moved.data();
            double* motion_of = motion.data();
            const double* since_of = since_broad.data();
            // Bit 1: some block moved more than the limit; bit 2: more than 1e-3 ctol.
            bits = parallel_or(n, threads, n >= kParallelMinBlocks, [&](int b) {
                if (s.flags[b] & kExcavated) return 0;
                // (Coefficient by coefficient, as Eigen's == compares them, without its reduction.)
                const Vec3 &gc = geo_c[b], &rc = cs.ref_centroid[b];
                const Quat &gq = geo_q[b], &rq = cs.ref_orientation[b];
                const bool same = gc[0] == rc[0] && gc[1] == rc[1] && gc[2] == rc[2] && gq.x() == rq.x() &&
                                  gq.y() == rq.y() && gq.z() == rq.z() && gq.w() == rq.w();
                const double mv = same ? since_of[b] : movement(cs, s, b, geo_c, geo_q);
                motion_of[b] = mv;
                int out = 0;
                if (mv > limit) mv_of[b] = 1, out |= 1;
                if (mv > 1e-3 * cs.ctol) out |= 2;
                return out;
            });
        }
        bool any = (bits & 1) != 0;
        const bool any_motion = (bits & 2) != 0;
        // What the passes below look at, over all the contacts as the last refresh left them.
        if (cs.summary_revision != cs.revision || cs.free_motion.size() != static_cast<size_t>(cs.size())) {
            float least = std::numeric_limits<float>::infinity();
            bool unknown = cs.free_motion.size() != static_cast<size_t>(cs.size());
            for (size_t c = 0; c < cs.free_motion.size(); ++c) {
                const float v = bound16_value(cs.free_motion[c]);
                if (v != v) unknown = true;
                else least = std::min(least, v);
            }
            cs.least_free_motion = unknown ? -std::numeric_limits<float>::infinity() : least;
            // (Only a crossing, side 2, lies on one: the others' keys are not decoded.)
            bool touch = false;
            for (int k = 0; k < cs.n_subs() && !touch; ++k) {
                const std::uint32_t code = cs.sub_code[k];
                if (!key_code_in_table(code) && short_code_side(code) != 2) continue;
                touch = on_touch_line(cs.key_of_code(code));
            }
            cs.any_touch_line = touch;
            cs.summary_revision = cs.revision;
        }
        // The two blocks that moved most, together.
        // (Without branches, which random motions would mispredict, and in four interleaved
        // runs merged at the end, so that no step waits on the one before: the two largest of a
        // set are the same numbers in any order; a motion that is not a number is passed over.)
        double top[4] = {0, 0, 0, 0}, second[4] = {0, 0, 0, 0};
        auto take = [](double& most, double& next, double v) {
            next = std::max(next, std::min(v, most));
            most = std::max(most, v);
        };
        int b4 = 0;
        for (; b4 + 4 <= n; b4 += 4) {
            for (int i = 0; i < 4; ++i) take(top[i], second[i], motion[b4 + i]);
        }
        for (; b4 < n; ++b4) take(top[0], second[0], motion[b4]);
        double most = top[0], next_most = second[0];
        for (int i = 1; i < 4; ++i) {
            take(most, next_most, second[i]);
            take(most, next_most, top[i]);
        }
        // An edge or corner that presses into a face touches over an area that grows with
        // the overlap: its contact is rebuilt once its blocks have moved a quarter of that
        // overlap, so the area follows the penetration (a force that depended on the path
        // would make or lose energy), and both blocks take their pose as the new reference.
        if (any_motion && cs.any_touch_line) {
            // Marked on the threads, then applied in order (the same blocks whatever the threads).
            const int nc = cs.size();
            std::vector<char>& grown = closing;
            grown.assign(nc, 0);
            char* grown_of = grown.data();
            const double* motion_of = motion.data();
            parallel_for(nc, threads, nc >= kParallelMinItems, [&](int c) {
                const int a = cs.block_a[c], b = cs.block_b[c];
                bool tracked = false;
                for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1] && !tracked; ++k) tracked = on_touch_line(cs.sub_key(k));
                if (!tracked) return;
                double deepest = 0;
                for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
                    deepest = std::max(deepest, sub_closure(m, c, k) + cs.sub_dilation(k));
                }
                grown_of[c] = motion_of[a] + motion_of[b] > 0.25 * deepest + 1e-3 * cs.ctol;
            });
            for (int c = 0; c < nc; ++c) {
                if (grown[c]) moved[cs.block_a[c]] = moved[cs.block_b[c]] = any = 1;
            }
        }
        // A contact that touches nowhere has no sub-contacts to feel its blocks closing in
        // (blocks meeting along an edge or at a corner carry nothing while they only touch):
        // when it was built apart, it is rebuilt as soon as they overlap across its plane by a
        // millionth of ctol, rather than at the next refresh (ctol/10 of motion). Left to the
        // refresh, a toe that lifts off for a moment would sink back unseen, and its force
        // would start from the overlap it reached: on stiff joints a kick that throws the
        // block off its pivot.
        const double depth_min = kClosingDepth * cs.ctol;
        const int nc = cs.size();
        closing.assign(nc, 0);
        // No two blocks have moved as far as any contact's free motion: none is looked at (each
        // would end at its free motion below).
        const bool none_reached = most + next_most < cs.least_free_motion;
        const std::uint16_t* free_motion = cs.free_motion.data();
        if (!none_reached && nc > 0) catch_up_world_vertices(m); // (the look below reads them)
        // The threads reach these thread_local arrays through pointers (named in the loop, a
        // thread_local would be each worker's own).
        char* close_mark = closing.data();
        const double* mot = motion.data();
        parallel_for(none_reached ? 0 : nc, threads, nc >= kParallelMinItems, [&](int c) {
            const int k0 = cs.sub_offset[c], k1 = cs.sub_offset[c + 1];
            const int a = cs.block_a[c], b = cs.block_b[c];
            // A zoned block's faces on a face: the tracking rule above. Between rigid blocks, a
            // contact of more sub-contacts is looked at too: a hinge whose face closes onto the
            // other's, a corner that comes down beside a face on a face.
            if (k1 - k0 > 2 && ((s.flags[a] | s.flags[b]) & kDeformable)) return;
            if (!(mot[a] + mot[b] > 0)) return;
            if (mot[a] + mot[b] < bound16_value(free_motion[c])) return; // no corner could have reached in yet
            // Deeper than when it was built by depth_min; for a contact that touches nowhere and
            // was built touching (blocks cut from one another, meeting along an edge) or already
            // overlapping without area (edges along one line), by a thousandth of ctol: looking
            // again sooner would find the same.
            const double gap = cs.gap[c];
            const bool apart = gap > 1e-2 * depth_min;
            const double deeper = std::max(-gap, 0.0) + (k1 > k0 || apart ? depth_min : 1e-3 * cs.ctol);
            // Built -gap deep across its plane, and no point of either block has moved further
            // than its movement since: blocks that have not moved enough to go that much deeper
            // are not looked at (most contacts between blocks apart, each step).
            if (mot[a] + mot[b] - gap < 0.5 * deeper) return;
            const int a0 = s.vertex_offset[a], a1 = s.vertex_offset[a + 1];
            const int b0 = s.vertex_offset[b], b1 = s.vertex_offset[b + 1];
            double hi_a = -std::numeric_limits<double>::infinity(), lo_b = -hi_a;
            {
                // First along the normal's octahedral point, which is the normal times a length
                // (no root to take): most contacts end here, no deeper than they were built.
                const Vec3 dir = octahedral_point(cs.normal_code[c]);
                for (int i = a0; i < a1; ++i) hi_a = std::max(hi_a, dir.dot(s.world_vertices[i]));
                for (int i = b0; i < b1; ++i) lo_b = std::min(lo_b, dir.dot(s.world_vertices[i]));
                const double span = hi_a - lo_b;
                if (!(span > 0) || span * span <= deeper * deeper * dir.squaredNorm()) return;
            }
            const Vec3 nrm = cs.normal(c);
            hi_a = -std::numeric_limits<double>::infinity();
            lo_b = -hi_a;
            for (int i = a0; i < a1; ++i) hi_a = std::max(hi_a, nrm.dot(s.world_vertices[i]));
            for (int i = b0; i < b1; ++i) lo_b = std::min(lo_b, nrm.dot(s.world_vertices[i]));
            if (hi_a - lo_b <= deeper) return;
            if (k1 == k0) {
                close_mark[c] = 1;
                return;
            }
            // A vertex that carries no sub-contact and has gone into the other block (the other
            // corner of a toe coming down, the far edge of a hinge's face closing) counts as well;
            // one over or under a corner of the other block that carries one, as seen along the
            // normal, does not (two blocks' corners meeting, the sub-contact keyed by one of them).
            const int off[2] = {a0, b0};
            auto tracked = [&](int side, int vertex) {
                return corner_carried(cs, k0, k1, s.world_vertices, off, side, vertex, nrm, kCornerSnap * cs.ctol);
            };
            // How far x has gone into the block through its faces that face x's own block (those
            // whose outward normal points against `toward`, the normal from x's block to this
            // one), or -infinity when x is beside the block: outside one of its other faces by more
            // than the corner snap (kCornerSnap). A corner on the plane of a side face (blocks of
            // one thickness: every voussoir's corner of a plane arch lies on its neighbour's side
            // faces) presses in as far as it went through the facing faces.
            auto inside = [&](int blk, const Vec3& x, const Vec3& toward) {
                const BlockView view{s.world_vertices.data() + s.vertex_offset[blk], &s.shape[blk]};
                double depth = std::numeric_limits<double>::infinity();
                for (int f = 0; f < view.topo->n_faces(); ++f) {
                    const Vec3 nf = world_face_normal(view, f);
                    const double d = -nf.dot(x - view.v[view.topo->face_vertex(f, 0)]);
                    if (nf.dot(toward) < -1e-3) {
                        depth = std::min(depth, d);
                        if (depth <= deeper) return depth;
                    } else if (d < -kCornerSnap * cs.ctol) {
                        return -std::numeric_limits<double>::infinity();
                    }
                }
                return depth;
            };
            bool found = false;
            for (int i = a0; i < a1 && !found; ++i) {
                const Vec3& x = s.world_vertices[i];
                found = nrm.dot(x) - lo_b > deeper && !tracked(0, i - a0) && inside(b, x, nrm) > deeper;
            }
            for (int i = b0; i < b1 && !found; ++i) {
                const Vec3& x = s.world_vertices[i];
                found = hi_a - nrm.dot(x) > deeper && !tracked(1, i - b0) && inside(a, x, -nrm) > deeper;
            }
            close_mark[c] = found;
        });
        if (!any && (none_reached || std::find(closing.begin(), closing.end(), 1) == closing.end())) {
            cs.motion_fresh = true;
            return;
        }
        catch_up_world_vertices(m); // (the rebuild reads them)
        for (int c = 0; c < nc; ++c) {
            const int a = cs.block_a[c], b = cs.block_b[c];
            if (moved[a] || moved[b] || closing[c]) {
                jobs.add(a, b, c);
                shift_open_closures(m, c, false); // (see the full pass)
            }
        }
        for (int b = 0; b < n; ++b) {
            if (moved[b]) { geo_c[b] = s.centroid[b]; geo_q[b] = s.orientation[b]; motion[b] = 0; }
        }
    }
    // Build the jobs a window at a time, and after each window write the plan as far as it
    // reaches (Rewrite): a job whose blocks were too far apart drops out. The colouring of the
    // contact update holds while every old contact keeps its place and carries sub-contacts
    // or none as before.
    using Clock = std::chrono::steady_clock;
    const Clock::time_point pass_start = Clock::now();
    double build_time = 0;
    const int np = full ? static_cast<int>(plan.size()) : cs.size(), nj = static_cast<int>(jobs.size());
    bool colouring_holds = np == cs.size();
    // Entry q of the plan. The entries are read front to back, each reader with a cursor of
    // its own into the jobs (in a refresh pass, the first job whose old contact is not before q).
    auto plan_at = [&](int q, int& cursor) -> int {
        if (full) return plan[q];
        while (cursor < nj && jobs.old(cursor) < q) ++cursor;
        return cursor < nj && jobs.old(cursor) == q ? ~cursor : q;
    };
    {
        Rewrite rw(cs);
        int pi = 0;   // the next entry of the plan to write
        int pend = 0; // the first entry after it whose old contact is still to be read
        int at_pi = 0, at_pend = 0; // their cursors
        for (int j0 = 0;;) {
            const int j1 = std::min(nj, j0 + kBuildWindow);
            if (j1 > j0) {
                const Clock::time_point t0 = Clock::now();
                build_jobs(m, cs, jobs, j0, j1, rw, rebuilt, fresh, carried);
                build_time += std::chrono::duration<double>(Clock::now() - t0).count();
            }
            // Kept contacts are read as they are written, the old contacts of jobs when their
            // window is built.
            auto pending = [&](int q) {
                const int e = plan_at(q, at_pend);
                return e >= 0 || (~e >= j1 && jobs.old(~e) >= 0);
            };
            for (; pi < np && (plan_at(pi, at_pi) >= 0 || ~plan_at(pi, at_pi) < j1); ++pi) {
                const int e = plan_at(pi, at_pi);
                if (e >= 0) {
                    // A run of kept contacts, old contacts e, e + 1, ...: written in one move.
                    colouring_holds = colouring_holds && e == rw.written();
                    int r = 1;
                    while (pi + r < np && plan_at(pi + r, at_pi) == e + r) ++r;
                    rw.put_kept(e, r);
                    pi += r - 1;
                    continue;
                }
                const int f = fresh[~e - j0];
                if (f < 0) {
                    colouring_holds = false;
                    continue;
                }
                colouring_holds = colouring_holds && jobs.old(~e) == rw.written();
                // The colouring lists the contacts that carry sub-contacts: one that starts or
                // stops carrying any needs a new one (whether it carried any was seen when its
                // window was built: the writing may have overwritten its old offsets since).
                if (colouring_holds) {
                    const ContactSet& x = rebuilt.set(f);
                    const int lf = rebuilt.local[f];
                    colouring_holds = (carried[~e - j0] != 0) == (x.sub_offset[lf + 1] > x.sub_offset[lf]);
                }
                pend = std::max(pend, pi + 1);
                while (pend < np && !pending(pend)) ++pend;
                const int pe = pend < np ? plan_at(pend, at_pend) : -1;
                const int next = pend < np ? (pe >= 0 ? pe : jobs.old(~pe)) : -1;
                rw.put_fresh(rebuilt.set(f), rebuilt.local[f], next);
            }
            if (j1 >= nj) break;
            j0 = j1;
        }
        rw.finish();
    }
    cs.motion_fresh = static_cast<int>(motion.size()) == n;
    cs.build_seconds += build_time;
    cs.write_seconds += std::chrono::duration<double>(Clock::now() - pass_start).count() - build_time;
    ++cs.revision;
    if (!colouring_holds) cs.colored = false;
    // The parts are buffers for the contacts rebuilt in one window, kept so that passes allocate
    // nothing. So are the jobs and the plan, but after a full pass they are as large as all
    // the candidate pairs, most of which (blocks near one another without a contact) the
    // passes between two full ones never see: they are given back then.
    if (full) {
        std::vector<int>().swap(jobs.job);
        std::vector<std::array<int, 2>>().swap(jobs.pairs);
        std::vector<int>().swap(plan);
    }
    std::size_t held = 0;
    for (const ContactSet& x : rebuilt.parts) held += x.sub_code.capacity() + x.id.capacity();
    if (held > 8192 + (cs.sub_code.size() + cs.id.size()) / 8 + 4 * kBuildWindow) rebuilt = Rebuilt{};
}

double contact_touch_area(const Model& m, int c) {
    const ContactSet& cs = m.contacts;
    const BlockSet& s = m.blocks;
    const int a = cs.block_a[c], b = cs.block_b[c];
    const int k0 = cs.sub_offset[c], k1 = cs.sub_offset[c + 1];
    if ((s.flags[a] | s.flags[b]) & kDeformable) {
        // Gridpoints pressing on a surface: each carries its own share of it.
        double area = 0;
        for (int k = k0; k < k1; ++k) {
            if (!(cs.sub_flags(k) & kSubOpen)) area += cs.sub_area[k];
        }
        return area;
    }
    // The blocks as they are now (the world vertices may be a step old between commands).
    std::vector<Vec3> wv[2];
    const int blk[2] = {a, b};
    for (int i = 0; i < 2; ++i) {
        const Mat3 r = s.orientation[blk[i]].toRotationMatrix();
        for (const Vec3& v : s.shape[blk[i]].vertices) wv[i].push_back(s.centroid[blk[i]] + r * v);
    }
    const BlockView va{wv[0].data(), &s.shape[a]}, vb{wv[1].data(), &s.shape[b]};
    const double tol = cs.ctol > 0 ? cs.ctol : contact_tolerance(m);
    const Vec3 old_n = cs.normal(c);
    const CommonPlane cp = common_plane(va, vb, &old_n, tol, 0.1 * tol);
    const Frame fr = make_frame(cp);
    std::vector<Piece> pa, pb;
    std::vector<double> nodal;
    present_faces(va, fr, 0, tol, pa, nodal);
    present_faces(vb, fr, 1, tol, pb, nodal);
    // A face tilted to the plane touches only where the solids overlap: a strip as thin as the
    // penetration along an edge. The corners pressing into it carry that with their own spring
    // areas, which are not the area touched. Faces on the plane touch over the shares of their
    // closed sub-contacts (those that carry stress or are glued; one away from the other block
    // carries nothing and is open).
    const int nv_a = s.shape[a].n_vertices(), nv_b = s.shape[b].n_vertices();
    const double eps = 1e-9 * tol;
    std::vector<double> uv_a, uv_b;
    const PolygonKeys key_at(pa, pb, nv_a, nv_b, tol, uv_a, uv_b);
    double area = 0;
    std::vector<std::int64_t> pressing, on_plane;
    Poly q, tmp;
    for (const Piece& A : pa) {
        for (const Piece& B : pb) {
            clip_convex(A.poly, B.poly, B.orient, eps, q, tmp);
            if (q.n < 3) continue;
            if (A.flat && B.flat) {
                for (int i = 0; i < q.n; ++i) on_plane.push_back(key_at(q.vkey[i], q.u[i], q.v[i]));
                continue;
            }
            clip_step(q, [&](int i) { return A.height(q.u[i], q.v[i]) - B.height(q.u[i], q.v[i]); }, eps, 0, tmp);
            copy_poly(q, tmp);
            if (q.n < 3) continue;
            area += std::abs(signed_area(q));
            for (int i = 0; i < q.n; ++i) {
                const std::int64_t key = key_at(q.vkey[i], q.u[i], q.v[i]);
                if (ContactSet::key_side(key) < 2) pressing.push_back(key);
            }
        }
    }
    // A corner of a face on the plane that also presses into a tilted face keeps its share.
    std::sort(on_plane.begin(), on_plane.end());
    pressing.erase(std::remove_if(pressing.begin(), pressing.end(),
                                  [&](std::int64_t key) { return std::binary_search(on_plane.begin(), on_plane.end(), key); }),
                   pressing.end());
    std::sort(pressing.begin(), pressing.end());
    for (int k = k0; k < k1; ++k) {
        if (cs.sub_flags(k) & kSubOpen) continue;
        if (std::binary_search(pressing.begin(), pressing.end(), cs.sub_key(k))) continue;
        area += cs.sub_area[k];
    }
    return area;
}

} // namespace odec
