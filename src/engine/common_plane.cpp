// The common plane between two convex blocks.
//
// For a unit normal n pointing from block a to block b, the widest gap a plane with that
// normal can leave on both sides is
//     gap(n) = min over b's vertices of n.x  -  max over a's vertices of n.x,
// and the plane sits midway. The common plane is the n that makes gap(n) largest
// (Cundall 1988). gap(n) is minus the support function of the Minkowski difference
// a - b, so the question has two well-known faces:
//   * apart (largest gap > 0): the largest gap is the distance between the blocks, taken
//     along the line joining their closest points. It moves continuously as the blocks
//     move: a vertex passing over an edge sees the normal swing smoothly round the edge,
//     which is exactly the rounding that keeps contact forces from jumping.
//   * overlapping (largest gap < 0): the smallest overlap is reached on a face of a - b,
//     whose normal is a face normal of a, a face normal of b, or the cross product of an
//     edge of a with an edge of b. These cover the six contact types: face-face,
//     edge-face and vertex-face take a face normal; edge-edge takes the cross product;
//     vertex-edge and vertex-vertex, when overlapping, fall on whichever of those gives
//     the smaller overlap.
// The search therefore evaluates gap() on the candidate directions, and when the best is
// positive refines it to the exact closest-feature direction.
//
// Speed (after Nezami et al. 2004): only features near the previous plane can decide the
// new one when blocks have moved little, so with a warm start the candidates come from the
// faces and edges having a vertex within `band` of the last plane. Parallel edges give one
// direction, so a brick contributes three edge directions, not twelve. The previous normal
// is itself a candidate and is kept through ties, so a face-face contact between two equal
// face normals does not flip from one to the other from step to step.
#include "engine/common_plane.h"
#include "engine/normal_code.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace odec {

namespace {

constexpr int kMaxDirs = 64;

struct Extent {
    double lo, hi;
};

// Smallest and largest n.x over the vertices.
inline Extent extent(const BlockView& s, const Vec3& n) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    const int nv = s.n_vertices();
    for (int i = 0; i < nv; ++i) {
        const double d = n.dot(s.v[i]);
        lo = std::min(lo, d);
        hi = std::max(hi, d);
    }
    return {lo, hi};
}

inline double gap_along(const BlockView& a, const BlockView& b, const Vec3& n) {
    return extent(b, n).lo - extent(a, n).hi;
}

// Unit edge directions of s having an end marked near, one per parallel family.
int edge_directions(const BlockView& s, const std::vector<char>& near, Vec3* out, int cap) {
    int n = 0;
    const Polyhedron& p = *s.topo;
    for (int f = 0; f < p.n_faces(); ++f) {
        const int m = p.face_size(f);
        for (int k = 0; k < m; ++k) {
            const int i = p.face_vertex(f, k), j = p.face_vertex(f, (k + 1) % m);
            if (i > j) continue; // each edge is seen once with i < j
            if (!near.empty() && !near[i] && !near[j]) continue;
            Vec3 d = s.v[j] - s.v[i];
            const double len = d.norm();
            if (!(len > 0)) continue;
            d /= len;
            bool seen = false;
            for (int q = 0; q < n && !seen; ++q) seen = std::abs(out[q].dot(d)) > 1 - 1e-10;
            if (!seen && n < cap) out[n++] = d;
        }
    }
    return n;
}

// Closest points of segments p0-p1 and q0-q1.
double segment_distance2(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1, Vec3& cp, Vec3& cq) {
    const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
    const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
    double s = 0, t = 0;
    if (a <= 1e-300 && e <= 1e-300) {
        s = t = 0;
    } else if (a <= 1e-300) {
        t = std::clamp(f / e, 0.0, 1.0);
    } else {
        const double c = d1.dot(r);
        if (e <= 1e-300) {
            s = std::clamp(-c / a, 0.0, 1.0);
        } else {
            const double b = d1.dot(d2), denom = a * e - b * b;
            s = denom > 1e-14 * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
            t = (b * s + f) / e;
            if (t < 0) {
                t = 0;
                s = std::clamp(-c / a, 0.0, 1.0);
            } else if (t > 1) {
                t = 1;
                s = std::clamp((b - c) / a, 0.0, 1.0);
            }
        }
    }
    cp = p0 + s * d1;
    cq = q0 + t * d2;
    return (cp - cq).squaredNorm();
}

// True when x projects inside convex face f of s (normal nf).
bool projects_inside(const BlockView& s, int f, const Vec3& nf, const Vec3& x) {
    const Polyhedron& p = *s.topo;
    const int m = p.face_size(f);
    for (int k = 0; k < m; ++k) {
        const Vec3& a = s.v[p.face_vertex(f, k)];
        const Vec3& b = s.v[p.face_vertex(f, (k + 1) % m)];
        if ((b - a).cross(x - a).dot(nf) < 0) return false;
    }
    return true;
}

bool face_has_near(const Polyhedron& p, int f, const std::vector<char>& near) {
    if (near.empty()) return true;
    for (int k = 0; k < p.face_size(f); ++k) {
        if (near[p.face_vertex(f, k)]) return true;
    }
    return false;
}

// Closest points between the near features of two separated convex blocks: vertex-face
// both ways and edge-edge (which also covers vertex-edge and vertex-vertex).
double closest_points(const BlockView& a, const BlockView& b, const std::vector<char>& near_a,
                      const std::vector<char>& near_b, Vec3& pa, Vec3& pb) {
    double best = std::numeric_limits<double>::infinity();
    auto vertex_face = [&](const BlockView& s, const std::vector<char>& ns, const BlockView& t,
                           const std::vector<char>& nt, bool s_is_a) {
        const Polyhedron& pt = *t.topo;
        for (int f = 0; f < pt.n_faces(); ++f) {
            if (!face_has_near(pt, f, nt)) continue;
            const Vec3 nf = world_face_normal(t, f);
            const Vec3& o = t.v[pt.face_vertex(f, 0)];
            for (int i = 0; i < s.n_vertices(); ++i) {
                if (!ns.empty() && !ns[i]) continue;
                const double h = nf.dot(s.v[i] - o);
                if (h < 0 || h * h >= best) continue;
                const Vec3 q = s.v[i] - h * nf;
                if (!projects_inside(t, f, nf, q)) continue;
                best = h * h;
                if (s_is_a) { pa = s.v[i]; pb = q; } else { pb = s.v[i]; pa = q; }
            }
        }
    };
    vertex_face(a, near_a, b, near_b, true);
    vertex_face(b, near_b, a, near_a, false);
    const Polyhedron& ta = *a.topo;
    const Polyhedron& tb = *b.topo;
    for (int fa = 0; fa < ta.n_faces(); ++fa) {
        const int ma = ta.face_size(fa);
        for (int ka = 0; ka < ma; ++ka) {
            const int i0 = ta.face_vertex(fa, ka), i1 = ta.face_vertex(fa, (ka + 1) % ma);
            if (i0 > i1 || (!near_a.empty() && !near_a[i0] && !near_a[i1])) continue;
            for (int fb = 0; fb < tb.n_faces(); ++fb) {
                const int mb = tb.face_size(fb);
                for (int kb = 0; kb < mb; ++kb) {
                    const int j0 = tb.face_vertex(fb, kb), j1 = tb.face_vertex(fb, (kb + 1) % mb);
                    if (j0 > j1 || (!near_b.empty() && !near_b[j0] && !near_b[j1])) continue;
                    Vec3 cp, cq;
                    const double d2 = segment_distance2(a.v[i0], a.v[i1], b.v[j0], b.v[j1], cp, cq);
                    if (d2 < best) {
                        best = d2;
                        pa = cp;
                        pb = cq;
                    }
                }
            }
        }
    }
    return std::sqrt(best);
}

Vec3 mean_vertex(const BlockView& s) {
    Vec3 c = Vec3::Zero();
    for (int i = 0; i < s.n_vertices(); ++i) c += s.v[i];
    return c / std::max(1, s.n_vertices());
}

} // namespace

Vec3 world_face_normal(const BlockView& s, int f, double* area) {
    const Polyhedron& p = *s.topo;
    const int m = p.face_size(f);
    Vec3 n = Vec3::Zero();
    const Vec3& o = s.v[p.face_vertex(f, 0)];
    for (int k = 1; k + 1 < m; ++k) {
        n += (s.v[p.face_vertex(f, k)] - o).cross(s.v[p.face_vertex(f, k + 1)] - o);
    }
    const double len = n.norm();
    if (area) *area = 0.5 * len;
    return len > 0 ? Vec3(n / len) : Vec3(Vec3::Zero());
}

CommonPlane common_plane(const BlockView& a, const BlockView& b, const Vec3* warm, double band,
                         double prefer_joint) {
    const Vec3 ca = mean_vertex(a), cb = mean_vertex(b);
    Vec3 n0 = warm ? *warm : Vec3(cb - ca);
    if (!(n0.norm() > 0)) n0 = Vec3::UnitZ();
    n0.normalize();

    // Features near the warm plane (all of them without a warm start).
    thread_local std::vector<char> near_a, near_b;
    near_a.clear();
    near_b.clear();
    if (warm && band > 0) {
        const Extent ea = extent(a, n0), eb = extent(b, n0);
        const double g0 = eb.lo - ea.hi;
        const double w = band + std::max(0.0, -g0);
        near_a.resize(a.n_vertices());
        near_b.resize(b.n_vertices());
        for (int i = 0; i < a.n_vertices(); ++i) near_a[i] = n0.dot(a.v[i]) >= ea.hi - w;
        for (int i = 0; i < b.n_vertices(); ++i) near_b[i] = n0.dot(b.v[i]) <= eb.lo + w;
    }

    Vec3 best_n = n0;
    double best_gap = gap_along(a, b, n0);
    // Ties keep the earlier (warm) choice: a later candidate must be better by a hair.
    const double tie = 1e-12 * (1.0 + (cb - ca).norm());
    auto consider = [&](Vec3 n) {
        const double g = gap_along(a, b, n);
        if (g > best_gap + tie) {
            best_gap = g;
            best_n = n;
        }
    };
    const Polyhedron& ta = *a.topo;
    const Polyhedron& tb = *b.topo;
    thread_local std::vector<Vec3> normals_a, normals_b;
    normals_a.clear();
    normals_b.clear();
    for (int f = 0; f < ta.n_faces(); ++f) {
        if (!face_has_near(ta, f, near_a)) continue;
        normals_a.push_back(world_face_normal(a, f));
        consider(normals_a.back());
    }
    for (int f = 0; f < tb.n_faces(); ++f) {
        if (!face_has_near(tb, f, near_b)) continue;
        normals_b.push_back(-world_face_normal(b, f));
        consider(normals_b.back());
    }
    // Shared planes: a face of a facing a face of b across one plane (a joint). Either
    // face's normal may serve; the one leaving the larger gap does.
    Vec3 joint_n = Vec3::Zero();
    double joint_gap = -std::numeric_limits<double>::infinity();
    auto consider_joint = [&](const Vec3& n, const std::vector<Vec3>& others) {
        bool shared = false;
        for (const Vec3& o : others) shared = shared || o.dot(n) > 1 - 1e-6;
        if (!shared) return;
        const double g = gap_along(a, b, n);
        if (g > joint_gap + tie || (g > joint_gap - tie && n.dot(n0) > joint_n.dot(n0))) {
            joint_gap = g;
            joint_n = n;
        }
    };
    for (const Vec3& n : normals_a) consider_joint(n, normals_b);
    for (const Vec3& n : normals_b) consider_joint(n, normals_a);
    Vec3 da[kMaxDirs], db[kMaxDirs];
    const int n_da = edge_directions(a, near_a, da, kMaxDirs);
    const int n_db = edge_directions(b, near_b, db, kMaxDirs);
    for (int i = 0; i < n_da; ++i) {
        for (int j = 0; j < n_db; ++j) {
            Vec3 c = da[i].cross(db[j]);
            const double len = c.norm();
            if (len < 1e-6) continue;
            c /= len;
            if (c.dot(n0) < 0) c = -c;
            consider(c);
        }
    }

    if (best_gap > 0) {
        // Apart: the exact largest gap is the distance, along the closest points. The
        // closest points lie within (distance - best_gap) of the best candidate plane, so
        // widen the feature band accordingly.
        const Extent ea = extent(a, best_n), eb = extent(b, best_n);
        const double w = std::max(band, 2.0 * best_gap) + best_gap;
        if (band > 0) {
            near_a.assign(a.n_vertices(), 0);
            near_b.assign(b.n_vertices(), 0);
            for (int i = 0; i < a.n_vertices(); ++i) near_a[i] = best_n.dot(a.v[i]) >= ea.hi - w;
            for (int i = 0; i < b.n_vertices(); ++i) near_b[i] = best_n.dot(b.v[i]) <= eb.lo + w;
        }
        // Blocks that touch (cut from one block, or resting on each other) have a gap of
        // round-off size: the direction between their closest points is then noise, and
        // the candidate plane is already the answer. The refined plane is taken only where
        // it is meaningful and never when it leaves a smaller gap than the candidate.
        Vec3 pa, pb;
        const double d = closest_points(a, b, near_a, near_b, pa, pb);
        const double noise = 1e-9 * (1.0 + (cb - ca).norm());
        if (d > noise && d < std::numeric_limits<double>::infinity() && d >= best_gap - tie) {
            const Vec3 n = (pb - pa) / d;
            const double g = gap_along(a, b, n);
            if (g >= best_gap) {
                best_n = n;
                best_gap = g;
            }
        }
    }

    // Two blocks on either side of one plane (cut by it, or laid face to face) that meet
    // only along an edge or at a corner of it: the gap is nearly as large across that
    // plane as along any other direction, and the plane is the joint they can act
    // through. Taking it keeps the normal on the joint as the blocks settle by small
    // amounts, where the exact largest-gap direction would swing to a diagonal that reads
    // settlement as closure.
    // Only for blocks that do not cross the joint: where they overlap across it by more than
    // a hair, the plane of least overlap is the one to push them apart along (a block
    // pressed sideways into its neighbour must be pushed sideways, not up).
    if (joint_gap > -std::numeric_limits<double>::infinity() && best_gap - joint_gap <= prefer_joint &&
        joint_gap >= -0.01 * prefer_joint) {
        best_n = joint_n;
        best_gap = joint_gap;
    }

    // The normal as the contact set keeps it (normal_code.h), and the gap across the plane of
    // that normal: the contact acts along the normal its geometry is measured on.
    best_n = snap_normal(best_n);
    best_gap = gap_along(a, b, best_n);
    CommonPlane cp;
    cp.normal = best_n;
    cp.gap = best_gap;
    cp.point = plane_point(a, b, best_n);
    return cp;
}

Vec3 plane_point(const BlockView& a, const BlockView& b, const Vec3& n) {
    const Extent ea = extent(a, n), eb = extent(b, n);
    const double s = 0.5 * (ea.hi + eb.lo);
    const Vec3 mid = 0.5 * (mean_vertex(a) + mean_vertex(b));
    return mid + (s - n.dot(mid)) * n;
}

CommonPlane find_common_plane(const Polyhedron& a, const Polyhedron& b, const Vec3* warm, double band,
                              double prefer_joint) {
    BlockView va{a.vertices.data(), &a};
    BlockView vb{b.vertices.data(), &b};
    return common_plane(va, vb, warm, band, prefer_joint);
}

} // namespace odec
