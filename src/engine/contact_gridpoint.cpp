// Sub-contacts at the surface gridpoints of deformable blocks (see contact_gridpoint.h).
#include "engine/contact_gridpoint.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/zones.h"

namespace odec {

namespace {

BlockView view_of(const Model& m, int b) {
    return BlockView{m.blocks.world_vertices.data() + m.blocks.vertex_offset[b], &m.blocks.shape[b]};
}

// In-plane axes of the common plane, by a fixed rule (as the rigid contacts use).
struct PlaneFrame {
    Vec3 p, e1, e2, n;
    explicit PlaneFrame(const CommonPlane& cp) : p(cp.point), n(cp.normal) {
        const Vec3 ref = std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
        e1 = (ref - ref.dot(n) * n).normalized();
        e2 = n.cross(e1);
    }
    void to_plane(const Vec3& x, double& u, double& v, double& h) const {
        const Vec3 d = x - p;
        u = e1.dot(d);
        v = e2.dot(d);
        h = n.dot(d);
    }
};

// A surface triangle of a deformable block facing the plane, projected on it.
struct FlatTri {
    int t = 0;                      // index into cs.surface_tri
    double u[3], v[3], h[3];
    bool in[3];                     // corner within ctol of the plane
    bool flat = false;              // within 20 degrees of the plane
    double area = 0;                // m^2, projected on the plane
    double lo_u, hi_u, lo_v, hi_v;  // footprint bounds
};

// A face of a rigid block facing the plane, projected on it.
struct FlatFace {
    std::vector<double> u, v;
    double orient = 1;
    double h0 = 0, hu = 0, hv = 0;  // height of the face over (u, v)
    double height(double uu, double vv) const { return h0 + hu * uu + hv * vv; }
};

// A surface triangle within 20 degrees of the common plane lies flat on it (a face-to-face
// contact); one more tilted belongs to an edge or a corner of its block near the plane.

bool inside_face(const FlatFace& f, double u, double v, double eps) {
    const int n = static_cast<int>(f.u.size());
    for (int k = 0; k < n; ++k) {
        const int j = (k + 1) % n;
        const double eu = f.u[j] - f.u[k], ev = f.v[j] - f.v[k];
        const double len = std::sqrt(eu * eu + ev * ev);
        if (!(len > 0)) continue;
        if (f.orient * (eu * (v - f.v[k]) - ev * (u - f.u[k])) < -eps * len) return false;
    }
    return true;
}

// Barycentric weights of (u, v) in tri, true when inside (to a relative hair).
bool weights_in(const FlatTri& t, double u, double v, Vec3& w) {
    const double d = (t.u[1] - t.u[0]) * (t.v[2] - t.v[0]) - (t.u[2] - t.u[0]) * (t.v[1] - t.v[0]);
    if (!(std::abs(d) > 0)) return false;
    const double w1 = ((u - t.u[0]) * (t.v[2] - t.v[0]) - (t.u[2] - t.u[0]) * (v - t.v[0])) / d;
    const double w2 = ((t.u[1] - t.u[0]) * (v - t.v[0]) - (u - t.u[0]) * (t.v[1] - t.v[0])) / d;
    const double w0 = 1.0 - w1 - w2;
    constexpr double hair = 1e-7;
    if (w0 < -hair || w1 < -hair || w2 < -hair) return false;
    w = Vec3(w0, w1, w2);
    return true;
}

// A coarse grid over the triangles' footprints, so that finding the triangle under a point
// costs a few tests, not one per triangle. Cells list triangles in their order, so the
// first one found is the same every run.
struct TriGrid {
    double u0 = 0, v0 = 0, cell = 1;
    int nu = 1, nv = 1;
    std::vector<int> start, items;
    void build(const std::vector<FlatTri>& tris) {
        start.assign(2, 0);
        items.clear();
        nu = nv = 1;
        if (tris.empty()) return;
        double lu = tris[0].lo_u, hu = tris[0].hi_u, lv = tris[0].lo_v, hv = tris[0].hi_v;
        for (const FlatTri& t : tris) {
            lu = std::min(lu, t.lo_u); hu = std::max(hu, t.hi_u);
            lv = std::min(lv, t.lo_v); hv = std::max(hv, t.hi_v);
        }
        const double span = std::max(hu - lu, hv - lv);
        const int per = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(tris.size()) / 2.0)));
        cell = span > 0 ? span / per : 1.0;
        u0 = lu;
        v0 = lv;
        nu = std::clamp(static_cast<int>((hu - lu) / cell) + 1, 1, per + 1);
        nv = std::clamp(static_cast<int>((hv - lv) / cell) + 1, 1, per + 1);
        start.assign(static_cast<size_t>(nu) * nv + 1, 0);
        auto span_of = [&](const FlatTri& t, int& i0, int& i1, int& j0, int& j1) {
            i0 = index(t.lo_u - u0, nu); i1 = index(t.hi_u - u0, nu);
            j0 = index(t.lo_v - v0, nv); j1 = index(t.hi_v - v0, nv);
        };
        int i0, i1, j0, j1;
        for (const FlatTri& t : tris) {
            span_of(t, i0, i1, j0, j1);
            for (int j = j0; j <= j1; ++j)
                for (int i = i0; i <= i1; ++i) ++start[j * nu + i + 1];
        }
        for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
        items.resize(start.back());
        std::vector<int> fill(start.begin(), start.end() - 1);
        for (int k = 0; k < static_cast<int>(tris.size()); ++k) {
            span_of(tris[k], i0, i1, j0, j1);
            for (int j = j0; j <= j1; ++j)
                for (int i = i0; i <= i1; ++i) items[fill[j * nu + i]++] = k;
        }
    }
    int index(double d, int n) const {
        const double q = std::floor(d / cell);
        if (!(q > 0)) return 0;
        return q >= n - 1 ? n - 1 : static_cast<int>(q);
    }
    // The first triangle whose footprint holds (u, v), or -1.
    int find(const std::vector<FlatTri>& tris, double u, double v, Vec3& w) const {
        if (tris.empty()) return -1;
        const int c = index(v - v0, nv) * nu + index(u - u0, nu);
        for (int i = start[c]; i < start[c + 1]; ++i) {
            if (weights_in(tris[items[i]], u, v, w)) return items[i];
        }
        return -1;
    }
};

} // namespace

void refresh_contact_surface(Model& m) {
    ContactSet& cs = m.contacts;
    if (cs.surface_ready) return;
    const BlockSet& s = m.blocks;
    const ZoneSet& z = m.zones;
    const GridpointSet& g = m.gridpoints;
    const int n = s.size();
    cs.surface_tri.clear();
    cs.surface_face.clear();
    cs.surface_offset.assign(n + 1, 0);
    cs.surface_ready = true;
    if (z.size() == 0) return;
    const auto faces = boundary_faces(m);
    for (const auto& f : faces) ++cs.surface_offset[z.block[f.first] + 1];
    for (int b = 0; b < n; ++b) cs.surface_offset[b + 1] += cs.surface_offset[b];
    cs.surface_tri.resize(faces.size());
    cs.surface_face.assign(faces.size(), -1);
    std::vector<int> fill(cs.surface_offset.begin(), cs.surface_offset.end() - 1);
    for (const auto& [zi, k] : faces) {
        const auto& q = z.gp[zi];
        std::array<int, 3> t;
        int j = 0;
        for (int c = 0; c < 4; ++c) {
            if (c != k) t[j++] = q[c];
        }
        const Vec3& x0 = g.pos[t[0]];
        const Vec3 nrm = (g.pos[t[1]] - x0).cross(g.pos[t[2]] - x0);
        if (nrm.dot(g.pos[q[k]] - x0) > 0) std::swap(t[1], t[2]); // outward: away from the zone
        const int b = z.block[zi];
        const int slot = fill[b]++;
        cs.surface_tri[slot] = t;
        // The block face it lies on: the one its centre is nearest, among those facing its way.
        const BlockView bv = view_of(m, b);
        const Vec3 centre = (g.pos[t[0]] + g.pos[t[1]] + g.pos[t[2]]) / 3.0;
        const Vec3 tn = (g.pos[t[1]] - g.pos[t[0]]).cross(g.pos[t[2]] - g.pos[t[0]]).normalized();
        double best = std::numeric_limits<double>::infinity();
        for (int f = 0; f < s.shape[b].n_faces(); ++f) {
            const Vec3 nf = world_face_normal(bv, f);
            if (nf.dot(tn) < 0.5) continue;
            const double d = std::abs(nf.dot(centre - bv.v[s.shape[b].face_vertex(f, 0)]));
            if (d < best) {
                best = d;
                cs.surface_face[slot] = f;
            }
        }
    }
}

void gridpoint_subcontacts(const Model& m, int a, int b, const CommonPlane& cp, double tol,
                           std::vector<GridpointSub>& out, std::vector<double>& face_area_a,
                           std::vector<double>& face_area_b) {
    out.clear();
    const BlockSet& s = m.blocks;
    const ContactSet& cs = m.contacts;
    const GridpointSet& g = m.gridpoints;
    const PlaneFrame fr(cp);
    const int blk[2] = {a, b};
    const bool deformable[2] = {(s.flags[a] & kDeformable) != 0, (s.flags[b] & kDeformable) != 0};
    std::vector<double>* face_area[2] = {&face_area_a, &face_area_b};
    thread_local std::vector<FlatTri> tris[2];
    thread_local std::vector<FlatFace> faces[2];
    // (gridpoint, area on triangles flat to the plane, area on tilted ones)
    thread_local std::vector<std::array<double, 3>> nodal[2];
    thread_local TriGrid grid[2];
    double flat_area[2] = {0, 0};
    for (int side = 0; side < 2; ++side) {
        const double sign = side == 0 ? 1.0 : -1.0; // a faces +n, b faces -n
        const int bk = blk[side];
        tris[side].clear();
        faces[side].clear();
        nodal[side].clear();
        if (deformable[side]) {
            if (static_cast<int>(cs.surface_offset.size()) != s.size() + 1) continue;
            for (int t = cs.surface_offset[bk]; t < cs.surface_offset[bk + 1]; ++t) {
                const auto& q = cs.surface_tri[t];
                FlatTri ft;
                ft.t = t;
                bool any_in = false, in[3];
                for (int i = 0; i < 3; ++i) {
                    fr.to_plane(g.pos[q[i]], ft.u[i], ft.v[i], ft.h[i]);
                    in[i] = sign * ft.h[i] >= -tol;
                    any_in |= in[i];
                }
                if (!any_in) continue;
                const Vec3& x0 = g.pos[q[0]];
                const Vec3 nrm = (g.pos[q[1]] - x0).cross(g.pos[q[2]] - x0); // twice the area, outward
                const double twice = nrm.norm();
                if (!(twice > 0)) continue;
                const double c = sign * nrm.dot(fr.n) / twice;
                if (c < 0.01) continue; // edge-on or facing away
                ft.area = 0.5 * twice * c;
                ft.flat = c >= kFlatToPlane;
                for (int i = 0; i < 3; ++i) ft.in[i] = in[i];
                const int f = cs.surface_face[t];
                if (f >= 0 && f < static_cast<int>(face_area[side]->size())) (*face_area[side])[f] += ft.area;
                ft.lo_u = std::min({ft.u[0], ft.u[1], ft.u[2]});
                ft.hi_u = std::max({ft.u[0], ft.u[1], ft.u[2]});
                ft.lo_v = std::min({ft.v[0], ft.v[1], ft.v[2]});
                ft.hi_v = std::max({ft.v[0], ft.v[1], ft.v[2]});
                tris[side].push_back(ft);
            }
            grid[side].build(tris[side]);
        } else {
            const BlockView bv = view_of(m, bk);
            const Polyhedron& p = s.shape[bk];
            for (int f = 0; f < p.n_faces(); ++f) {
                const Vec3 nf = world_face_normal(bv, f);
                const double nn = nf.dot(fr.n);
                if (sign * nn < 0.01) continue;
                FlatFace ff;
                const int k = p.face_size(f);
                ff.u.resize(k);
                ff.v.resize(k);
                double area2 = 0, h = 0;
                for (int i = 0; i < k; ++i) fr.to_plane(bv.v[p.face_vertex(f, i)], ff.u[i], ff.v[i], h);
                for (int i = 0; i < k; ++i) {
                    const int j = (i + 1) % k;
                    area2 += ff.u[i] * ff.v[j] - ff.u[j] * ff.v[i];
                }
                if (area2 == 0) continue;
                ff.orient = area2 > 0 ? 1.0 : -1.0;
                double u0, v0, h0;
                fr.to_plane(bv.v[p.face_vertex(f, 0)], u0, v0, h0);
                ff.h0 = h0 + (nf.dot(fr.e1) * u0 + nf.dot(fr.e2) * v0) / nn;
                ff.hu = -nf.dot(fr.e1) / nn;
                ff.hv = -nf.dot(fr.e2) / nn;
                faces[side].push_back(std::move(ff));
            }
        }
    }
    // Each gridpoint's area: its third of each surface triangle around it that faces the plane,
    // where that third lies over the other block (tested at its centre), so that a gridpoint
    // on the edge of the other block's footprint takes only the part of its area inside it,
    // and blocks that meet only along an edge or at a corner carry nothing while they touch.
    auto covered = [&](int other, double u, double v) {
        if (deformable[other]) {
            Vec3 w;
            return grid[other].find(tris[other], u, v, w) >= 0;
        }
        for (const FlatFace& ff : faces[other]) {
            if (inside_face(ff, u, v, 0.0)) return true;
        }
        return false;
    };
    for (int side = 0; side < 2; ++side) {
        if (!deformable[side]) continue;
        auto& nd = nodal[side];
        for (const FlatTri& ft : tris[side]) {
            const auto& q = cs.surface_tri[ft.t];
            const double cu = (ft.u[0] + ft.u[1] + ft.u[2]) / 3.0, cv = (ft.v[0] + ft.v[1] + ft.v[2]) / 3.0;
            for (int i = 0; i < 3; ++i) {
                if (!ft.in[i]) continue;
                const int j = (i + 1) % 3, k = (i + 2) % 3;
                // Centre of the corner's third: the quadrilateral corner, mid-edges, centroid.
                const double u = 0.25 * (ft.u[i] + 0.5 * (ft.u[i] + ft.u[j]) + 0.5 * (ft.u[i] + ft.u[k]) + cu);
                const double v = 0.25 * (ft.v[i] + 0.5 * (ft.v[i] + ft.v[j]) + 0.5 * (ft.v[i] + ft.v[k]) + cv);
                if (!covered(1 - side, u, v)) continue;
                const double third = ft.area / 3.0;
                nd.push_back({static_cast<double>(q[i]), ft.flat ? third : 0.0, ft.flat ? 0.0 : third});
            }
        }
        std::stable_sort(nd.begin(), nd.end(), [](const auto& x, const auto& y) { return x[0] < y[0]; });
        int w = 0;
        for (int r = 0; r < static_cast<int>(nd.size()); ++r) {
            if (w > 0 && nd[w - 1][0] == nd[r][0]) {
                nd[w - 1][1] += nd[r][1];
                nd[w - 1][2] += nd[r][2];
            } else {
                nd[w++] = nd[r];
            }
        }
        nd.resize(w);
        for (const auto& e : nd) flat_area[side] += e[1];
    }
    // Between two deformable blocks each side presses with half its area, unless only one
    // side lies flat on the plane (an edge or corner of the other pressing into its face).
    const bool both = deformable[0] && deformable[1] && flat_area[0] > 0 && flat_area[1] > 0;
    const double min_area = 1e-12 * tol * tol;
    const double eps = 1e-7 * tol;
    for (int side = 0; side < 2; ++side) {
        if (!deformable[side]) continue;
        const int other = 1 - side;
        const double other_sign = other == 0 ? 1.0 : -1.0;
        const int ob = blk[other];
        const Mat3 rot_t = s.orientation[ob].toRotationMatrix().transpose();
        for (const auto& e : nodal[side]) {
            const int gp = static_cast<int>(e[0]);
            // Only a gridpoint on the block's surface flat to the plane carries the contact; one
            // on tilted surfaces only (an edge or a corner) carries it with its own area where it
            // presses into a rigid block's face, and nothing while it only touches.
            const bool on_flat = e[1] > min_area;
            const double area = on_flat ? e[1] : e[2];
            if (!(area > min_area) || (!on_flat && deformable[other])) continue;
            double u, v, h;
            fr.to_plane(g.pos[gp], u, v, h);
            GridpointSub sub;
            double ho = 0;
            bool found = false;
            if (deformable[other]) {
                Vec3 w;
                const int t = grid[other].find(tris[other], u, v, w);
                if (t >= 0) {
                    const FlatTri& ft = tris[other][t];
                    ho = w[0] * ft.h[0] + w[1] * ft.h[1] + w[2] * ft.h[2];
                    sub.local = w;
                    sub.tri = cs.surface_tri[ft.t];
                    found = true;
                }
            } else {
                for (const FlatFace& ff : faces[other]) {
                    if (!inside_face(ff, u, v, eps)) continue;
                    ho = ff.height(u, v);
                    const Vec3 x = fr.p + u * fr.e1 + v * fr.e2 + ho * fr.n;
                    sub.local = rot_t * (x - s.centroid[ob]);
                    found = true;
                    break;
                }
            }
            // The partner point must lie near the plane too: beyond ctol the surfaces are apart.
            if (!found || other_sign * ho < -tol) continue;
            const double closure = side == 0 ? h - ho : ho - h;
            if (!on_flat && !(closure > 0)) continue;
            sub.side = 3 + side;
            sub.gp = gp;
            sub.key = gridpoint_sub_key(side, gp);
            sub.area = both ? 0.5 * area : area;
            sub.closure = closure;
            out.push_back(sub);
        }
    }
    std::sort(out.begin(), out.end());
}

} // namespace odec
