// The in-situ stress state: zones and joints (see insitu.h).
#include "engine/insitu.h"

#include <algorithm>
#include <cmath>

#include "engine/blocks.h"
#include "engine/common_plane.h"
#include "engine/contact.h"
#include "engine/contact_gridpoint.h"
#include "engine/flow.h"
#include "engine/model.h"

namespace odec {

Sym6 StressField::at(const Vec3& x) const {
    Sym6 r;
    for (int k = 0; k < 6; ++k) r[k] = s[k] + x.x() * gx[k] + x.y() * gy[k] + x.z() * gz[k];
    return r;
}

InsituCount& InsituCount::operator+=(const InsituCount& o) {
    zones += o.zones;
    contacts += o.contacts;
    subs += o.subs;
    edge_subs += o.edge_subs;
    slipping += o.slipping;
    opened += o.opened;
    no_stiffness += o.no_stiffness;
    return *this;
}

namespace {

// A surface within 20 degrees of the contact plane lies flat on it (as contact detection
// judges a deformable block's surface triangles).

BlockView view_of(const Model& m, int b) {
    return BlockView{m.blocks.world_vertices.data() + m.blocks.vertex_offset[b], &m.blocks.shape[b]};
}

// The faces of a block whose outward normal lies within 20 degrees of `dir`, with their normals.
struct FlatFaces {
    BlockView view;
    std::vector<int> faces;
    std::vector<Vec3> normals;
};

FlatFaces flat_faces(const Model& m, int b, const Vec3& dir) {
    FlatFaces ff{view_of(m, b), {}, {}};
    for (int f = 0; f < m.blocks.shape[b].n_faces(); ++f) {
        const Vec3 nf = world_face_normal(ff.view, f);
        if (nf.dot(dir) >= kFlatToPlane) {
            ff.faces.push_back(f);
            ff.normals.push_back(nf);
        }
    }
    return ff;
}

// Whether the line through x along n meets one of these faces within `reach` of x, inside it
// (to `eps`).
bool over_faces(const FlatFaces& ff, const Vec3& x, const Vec3& n, double reach, double eps) {
    const Polyhedron& p = *ff.view.topo;
    for (size_t i = 0; i < ff.faces.size(); ++i) {
        const int f = ff.faces[i];
        const Vec3& nf = ff.normals[i];
        const double dn = nf.dot(n);
        if (!(std::abs(dn) > 0)) continue;
        const double s = nf.dot(ff.view.v[p.face_vertex(f, 0)] - x) / dn;
        if (!(std::abs(s) <= reach)) continue;
        const Vec3 y = x + s * n;
        const int k = p.face_size(f);
        bool inside = true;
        for (int j = 0; j < k && inside; ++j) {
            const Vec3& a = ff.view.v[p.face_vertex(f, j)];
            const Vec3 e = ff.view.v[p.face_vertex(f, (j + 1) % k)] - a;
            inside = e.cross(y - a).dot(nf) >= -eps * e.norm();
        }
        if (inside) return true;
    }
    return false;
}

// A convex polygon in the contact plane's coordinates.
using Poly2 = std::vector<Eigen::Vector2d>;

double signed_area(const Poly2& p) {
    double a2 = 0;
    for (size_t i = 0; i < p.size(); ++i) {
        const auto& u = p[i];
        const auto& v = p[(i + 1) % p.size()];
        a2 += u.x() * v.y() - v.x() * u.y();
    }
    return 0.5 * a2;
}

// p clipped by the convex polygon q (both counter-clockwise).
Poly2 clip(Poly2 p, const Poly2& q) {
    for (size_t i = 0; i < q.size() && !p.empty(); ++i) {
        const Eigen::Vector2d a = q[i], e = q[(i + 1) % q.size()] - a;
        auto side = [&](const Eigen::Vector2d& x) { return e.x() * (x.y() - a.y()) - e.y() * (x.x() - a.x()); };
        Poly2 out;
        for (size_t j = 0; j < p.size(); ++j) {
            const Eigen::Vector2d& u = p[j];
            const Eigen::Vector2d& v = p[(j + 1) % p.size()];
            const double su = side(u), sv = side(v);
            if (su >= 0) out.push_back(u);
            if ((su >= 0) != (sv >= 0)) out.push_back(u + (v - u) * (su / (su - sv)));
        }
        p = std::move(out);
    }
    return p;
}

// The faces of a block lying on the contact plane (within `tol` of it at every corner, within
// 20 degrees of it), projected on the plane's axes e1, e2, counter-clockwise.
std::vector<Poly2> faces_on_plane(const FlatFaces& ff, const Vec3& p0, const Vec3& n, const Vec3& e1, const Vec3& e2,
                                  double tol) {
    std::vector<Poly2> out;
    const Polyhedron& p = *ff.view.topo;
    for (int f : ff.faces) {
        Poly2 poly;
        bool on = true;
        for (int k = 0; k < p.face_size(f) && on; ++k) {
            const Vec3 d = ff.view.v[p.face_vertex(f, k)] - p0;
            on = std::abs(n.dot(d)) <= tol;
            poly.emplace_back(e1.dot(d), e2.dot(d));
        }
        if (!on) continue;
        if (signed_area(poly) < 0) std::reverse(poly.begin(), poly.end());
        out.push_back(std::move(poly));
    }
    return out;
}

bool inside(const Poly2& p, const Eigen::Vector2d& x, double eps) {
    for (size_t i = 0; i < p.size(); ++i) {
        const Eigen::Vector2d e = p[(i + 1) % p.size()] - p[i];
        const double len = e.norm();
        if (len > 0 && e.x() * (x.y() - p[i].y()) - e.y() * (x.x() - p[i].x()) < -eps * len) return false;
    }
    return true;
}

Mat3 tensor(const Sym6& t) {
    Mat3 s;
    s << t[0], t[3], t[4], t[3], t[1], t[5], t[4], t[5], t[2];
    return s;
}

// Surface triangles of the deformable blocks around each gridpoint (cs.surface_tri indices).
struct GridpointTriangles {
    std::vector<int> offset, items;
    void build(const Model& m) {
        const ContactSet& cs = m.contacts;
        const int ng = m.gridpoints.size();
        offset.assign(ng + 1, 0);
        for (const auto& t : cs.surface_tri)
            for (int q : t) ++offset[q + 1];
        for (int i = 0; i < ng; ++i) offset[i + 1] += offset[i];
        items.resize(offset[ng]);
        std::vector<int> fill(offset.begin(), offset.end() - 1);
        for (int t = 0; t < static_cast<int>(cs.surface_tri.size()); ++t)
            for (int q : cs.surface_tri[t]) items[fill[q]++] = t;
    }
};

// The joint law's limits for one contact's material (see joint_law.cpp).
struct Strength {
    double tan_phi = 0, coh = 0, ten = 0, tan_res = 0;
    bool model2 = false;
};

// Contact c's joint material when it has a normal stiffness to load, else null.
const JointMaterial* stiff_material(const Model& m, int c) {
    const JointMaterial* j = contact_joint_material(m, c);
    return j && j->kn > 0 ? j : nullptr;
}

// The limits of joint material j under joint model jcons.
Strength strength_of(const JointMaterial& j, int jcons) {
    const double deg = M_PI / 180.0;
    Strength st;
    st.tan_phi = std::tan(j.friction * deg);
    st.coh = j.cohesion;
    st.ten = j.tension;
    st.model2 = jcons == 2;
    st.tan_res = st.model2 ? std::tan(j.res_friction * deg) : st.tan_phi;
    return st;
}

// Load sub-contact k with the traction t on block b (scaled by the weight w of its area),
// capped by the joint's strength. Returns 1 when loaded as given, 2 capped in shear, 3 opened.
int load_sub(ContactSet& cs, int k, const Vec3& n, const Vec3& traction_on_b, double kn, bool joined,
             const Strength& st) {
    double sn = traction_on_b.dot(n);
    Vec3 ss = traction_on_b - sn * n;
    std::uint8_t flags = cs.sub_flags(k) & static_cast<std::uint8_t>(~(kSubOpen | kSubSlip | kSubNew | kSubFresh));
    int result = 1;
    if (!joined) {
        const bool failed = flags & kSubFailed;
        double coh = failed ? 0.0 : st.coh;
        const double ten = failed ? 0.0 : st.ten;
        double tan_phi = failed ? st.tan_res : st.tan_phi;
        const double scale = traction_on_b.norm();
        if (sn < -ten || (sn <= 0 && ten <= 0)) {
            // Pulled apart (or not pressed at all): the joint law opens it.
            if (sn < -ten && (coh > 0 || ten > 0)) flags |= kSubFailed;
            if (scale > 0) result = 3;
            sn = 0;
            ss.setZero();
            flags |= kSubOpen;
        } else {
            double tmax = std::max(0.0, coh + sn * tan_phi);
            const double t = ss.norm();
            if (t > tmax) {
                if (!failed && (coh > 0 || ten > 0 || st.model2)) {
                    flags |= kSubFailed;
                    tan_phi = st.tan_res;
                    tmax = std::max(0.0, sn * tan_phi);
                }
                ss *= tmax / t;
                flags |= kSubSlip;
                result = 2;
            }
        }
    }
    Vec3 e1, e2;
    shear_axes(n, e1, e2);
    cs.sub_ss[k] = Eigen::Vector2d(ss.dot(e1), ss.dot(e2));
    cs.sub_un[k] = sn / kn; // the closure that carries it (the springs' stress: effective)
    if (!cs.sub_udil.empty()) cs.sub_udil[k] = 0;
    cs.sub_us[k].setZero();
    cs.set_sub_flags(k, flags);
    return result;
}

void unload_sub(ContactSet& cs, int k) {
    cs.sub_ss[k].setZero();
    cs.sub_un[k] = 0;
    if (!cs.sub_udil.empty()) cs.sub_udil[k] = 0;
    cs.sub_us[k].setZero();
    cs.set_sub_flags(k, (cs.sub_flags(k) & kSubFailed) | kSubOpen);
}


void set_zone_stress(Model& m, const Range& r, const StressField& f, const std::vector<char>& only,
                     std::vector<std::uint8_t>& set) {
    ZoneSet& z = m.zones;
    set.resize(z.size(), 0);
    for (int i = 0; i < z.size(); ++i) {
        const int b = z.block[i];
        // Excavated blocks and null zones carry no stress.
        if ((m.blocks.flags[b] & kExcavated) || z.model[i] == kZoneNull) continue;
        if (!only.empty() && !only[b]) continue;
        const Vec3 c = zone_centroid(m, i);
        if (!r.contains_point(m, c, b)) continue;
        z.stress[i] = f.at(c);
        set[i] = 1;
    }
}

} // namespace

namespace {

// What happened to each sub-contact (SubResult), for the counts.
enum SubResult : std::uint8_t { kUntouched = 0, kLoaded = 1, kCapped = 2, kOpened = 3, kEdge = 4 };

// The contacts the range selects (with a block flagged in `only`, when given) take the field.
// Each sub-contact's outcome goes to result[k], each contact's to touched[c] (1 loaded,
// 2 no stiffness).
void load_contacts(Model& m, const Range& r, const StressField& f, const std::vector<char>& only,
                   std::vector<std::uint8_t>& result, std::vector<std::uint8_t>& touched) {
    ensure_contacts_current(m, true);
    refresh_contact_surface(m);
    ContactSet& cs = m.contacts;
    const BlockSet& s = m.blocks;
    const GridpointSet& g = m.gridpoints;
    result.resize(cs.n_subs(), kUntouched);
    touched.resize(cs.size(), 0);
    GridpointTriangles around;
    bool around_built = false;
    const double tol = cs.ctol > 0 ? cs.ctol : contact_tolerance(m);
    const double eps = 1e-3 * tol;
    std::vector<double> weight;
    // The joints' water pressures, when there is water (flow.h).
    const bool water = m.flow.configured && m.flow.on;
    if (water) flow_sync(m);
    for (int c = 0; c < cs.size(); ++c) {
        const int a = cs.block_a[c], b = cs.block_b[c];
        if ((s.flags[a] | s.flags[b]) & kExcavated) continue;
        if (!only.empty() && !only[a] && !only[b]) continue;
        if (!r.contains_contact(m, contact_centroid(m, c), a, b)) continue;
        const JointMaterial* jp = stiff_material(m, c);
        if (!jp) {
            if (cs.sub_offset[c + 1] > cs.sub_offset[c]) touched[c] = 2;
            continue;
        }
        const JointMaterial& j = *jp;
        const Strength st = strength_of(j, cs.jcons(c));
        const bool joined = cs.joined(c);
        const Vec3 n = cs.normal(c);
        // The flat faces of a facing b (+n) and of b facing a (-n).
        const FlatFaces fa = flat_faces(m, a, n), fb = flat_faces(m, b, -n);
        const int k0 = cs.sub_offset[c], k1 = cs.sub_offset[c + 1];
        const bool gridpoint_pair = (s.flags[a] | s.flags[b]) & kDeformable;
        // Between rigid blocks: where their faces on the plane overlap (with area).
        const Vec3 ref = std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
        const Vec3 e1 = (ref - ref.dot(n) * n).normalized(), e2 = n.cross(e1);
        const Vec3 p0 = contact_point(m, c);
        std::vector<Poly2> overlap;
        double overlap_area = 0;
        Eigen::Vector2d overlap_centre = Eigen::Vector2d::Zero();
        if (!gridpoint_pair) {
            for (const Poly2& pa : faces_on_plane(fa, p0, n, e1, e2, tol)) {
                for (const Poly2& pb : faces_on_plane(fb, p0, n, e1, e2, tol)) {
                    Poly2 q = clip(pa, pb);
                    if (q.size() < 3) continue;
                    const double area = signed_area(q);
                    if (!(area > 1e-9 * tol * tol)) continue;
                    Eigen::Vector2d cen = Eigen::Vector2d::Zero();
                    for (size_t i = 0; i < q.size(); ++i) {
                        const auto& u = q[i];
                        const auto& v = q[(i + 1) % q.size()];
                        cen += (u.x() * v.y() - v.x() * u.y()) * (u + v);
                    }
                    overlap_centre += cen / 6.0;
                    overlap_area += area;
                    overlap.push_back(std::move(q));
                }
            }
            if (overlap_area > 0) overlap_centre /= overlap_area;
        }
        // Per sub-contact: the share of its area to load (0: none) and where the field is taken.
        weight.assign(k1 - k0, 0.0);
        std::vector<Vec3> at(k1 - k0, Vec3::Zero());
        for (int k = k0; k < k1; ++k) {
            const Vec3 x = sub_point(m, c, k);
            at[k - k0] = x;
            if (!(cs.sub_area[k] > 0)) continue;
            if (cs.sub_side(k) < 3) {
                // A vertex of the contact polygon between rigid blocks: where their faces overlap.
                const Eigen::Vector2d u(e1.dot(x - p0), e2.dot(x - p0));
                for (const Poly2& q : overlap) {
                    if (inside(q, u, eps)) weight[k - k0] = 1.0;
                }
                continue;
            }
            // A gridpoint: its flat surface around it, over the other block's flat face. The
            // detection gave it its own area (halved against a deformable block) wherever its
            // surface lies over the other block's surface, flat or not.
            if (!around_built) {
                around.build(m);
                around_built = true;
            }
            const bool of_a = cs.sub_side(k) == 3;
            const int own = of_a ? a : b, other = of_a ? b : a;
            const Vec3 out = of_a ? n : Vec3(-n);
            const FlatFaces& partner = of_a ? fb : fa;
            const int gp = cs.sub_vertex(k);
            double covered = 0;
            Vec3 centre = Vec3::Zero();
            for (int i = around.offset[gp]; i < around.offset[gp + 1]; ++i) {
                const int t = around.items[i];
                if (t < cs.surface_offset[own] || t >= cs.surface_offset[own + 1]) continue;
                const auto& q = cs.surface_tri[t];
                const Vec3 nrm = (g.pos[q[1]] - g.pos[q[0]]).cross(g.pos[q[2]] - g.pos[q[0]]);
                const double twice = nrm.norm();
                if (!(twice > 0)) continue;
                const double cosine = nrm.dot(out) / twice;
                if (cosine < kFlatToPlane) continue;
                int me = 0;
                while (me < 3 && q[me] != gp) ++me;
                const Vec3& xi = g.pos[q[me]];
                const Vec3& xj = g.pos[q[(me + 1) % 3]];
                const Vec3& xk = g.pos[q[(me + 2) % 3]];
                // The centre of its third, as contact detection tests it.
                const Vec3 ct = (xi + xj + xk) / 3.0;
                const Vec3 third = 0.25 * (xi + 0.5 * (xi + xj) + 0.5 * (xi + xk) + ct);
                if (!over_faces(partner, third, n, tol, eps)) continue;
                const double area = 0.5 * twice * cosine / 3.0;
                covered += area;
                centre += area * 0.25 * (2.0 * xi + xj + xk);
            }
            if (!(covered > 0)) continue;
            at[k - k0] = centre / covered;
            const double own_share = (s.flags[other] & kDeformable) ? 0.5 * covered : covered;
            weight[k - k0] = std::min(1.0, own_share / cs.sub_area[k]);
        }
        // Rigid blocks: weights that give the loads the overlap's area and centroid (insitu.h).
        if (!gridpoint_pair && overlap_area > 0) {
            double total = 0;
            Eigen::Vector2d xq = Eigen::Vector2d::Zero();
            std::vector<Eigen::Vector2d> uv(k1 - k0, Eigen::Vector2d::Zero());
            for (int k = k0; k < k1; ++k) {
                if (weight[k - k0] <= 0) continue;
                uv[k - k0] = Eigen::Vector2d(e1.dot(at[k - k0] - p0), e2.dot(at[k - k0] - p0));
                total += cs.sub_area[k];
                xq += cs.sub_area[k] * uv[k - k0];
            }
            if (total > 0) {
                xq /= total;
                Eigen::Matrix2d J = Eigen::Matrix2d::Zero();
                for (int k = k0; k < k1; ++k) {
                    if (weight[k - k0] > 0) J += cs.sub_area[k] * (uv[k - k0] - xq) * (uv[k - k0] - xq).transpose();
                }
                // w_k = (1 + alpha . (x_k - xq)) A_total / sum A: the sum of w_k A_k is the
                // overlap's area and their centre its centroid.
                Eigen::Vector2d alpha = Eigen::Vector2d::Zero();
                if (std::abs(J.determinant()) > 1e-12 * J.squaredNorm()) alpha = J.inverse() * (total * (overlap_centre - xq));
                bool positive = true;
                for (int k = k0; k < k1; ++k) {
                    if (weight[k - k0] > 0) positive = positive && 1.0 + alpha.dot(uv[k - k0] - xq) > 0;
                }
                if (!positive) alpha.setZero();
                for (int k = k0; k < k1; ++k) {
                    if (weight[k - k0] > 0) weight[k - k0] = (1.0 + alpha.dot(uv[k - k0] - xq)) * overlap_area / total;
                }
            }
        }
        touched[c] = 1;
        for (int k = k0; k < k1; ++k) {
            const double w = weight[k - k0];
            if (!(w > 0)) {
                unload_sub(cs, k);
                result[k] = kEdge;
                continue;
            }
            // Block b lies on the +n side: the rock pulls on it through the plane with the
            // traction sigma (-n); the joint puts area (sn n + ss) on it. Water in the joint
            // carries its pressure: the springs the rest (the effective stress).
            Vec3 traction = -(tensor(f.at(at[k - k0])) * n) * w;
            if (water) {
                const int node = m.flow.sub_node[k];
                if (node >= 0) traction -= m.flow.pp[node] * m.flow.sub_wet[k] * n;
            }
            result[k] = static_cast<std::uint8_t>(load_sub(cs, k, n, traction, j.kn, joined, st));
        }
        // Those left open keep their closures by reference (contact.h).
        shift_open_closures(m, c, true);
    }
}

InsituCount counts(const std::vector<std::uint8_t>& zone_set, const std::vector<std::uint8_t>& result,
                   const std::vector<std::uint8_t>& touched) {
    InsituCount count;
    for (std::uint8_t z : zone_set) count.zones += z != 0;
    for (std::uint8_t t : touched) {
        count.contacts += t == 1;
        count.no_stiffness += t == 2;
    }
    for (std::uint8_t r : result) {
        count.subs += r >= kLoaded && r <= kOpened;
        count.slipping += r == kCapped;
        count.opened += r == kOpened;
        count.edge_subs += r == kEdge;
    }
    return count;
}

} // namespace

int shift_joint_water(Model& m, const std::vector<double>& old_pp) {
    ContactSet& cs = m.contacts;
    const FlowSet& f = m.flow;
    if (static_cast<int>(old_pp.size()) != f.n_nodes() || static_cast<int>(f.sub_node.size()) != cs.n_subs()) return 0;
    int shifted = 0;
    for (int c = 0; c < cs.size(); ++c) {
        const JointMaterial* j = stiff_material(m, c);
        if (!j) continue;
        const Strength st = strength_of(*j, cs.jcons(c));
        const Vec3 n = cs.normal(c);
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
            const int node = f.sub_node[k];
            const double sn = cs.sub_sn_for(c, k, j->kn);
            if (node < 0 || (cs.sub_flags(k) & kSubOpen) || !(sn > 0)) continue;
            const double dp = (f.pp[node] - old_pp[node]) * f.sub_wet[k];
            if (dp == 0) continue;
            // The total stress stays: the springs carry what the water no longer does.
            const Vec3 traction = (sn - dp) * n + cs.sub_shear_stress(c, k);
            load_sub(cs, k, n, traction, j->kn, cs.joined(c), st);
            if (cs.sub_flags(k) & kSubOpen) set_sub_closure(m, c, k, cs.sub_un[k]); // (contact.h)
            ++shifted;
        }
    }
    return shifted;
}

InsituCount set_insitu_contact_stress(Model& m, const Range& r, const StressField& f, const std::vector<char>& only) {
    std::vector<std::uint8_t> result, touched;
    load_contacts(m, r, f, only, result, touched);
    return counts({}, result, touched);
}

InsituCount apply_insitu(Model& m, const Range& r, const StressField& f) {
    std::vector<std::uint8_t> zone_set, result, touched;
    set_zone_stress(m, r, f, {}, zone_set);
    load_contacts(m, r, f, {}, result, touched);
    m.insitu.push_back(InsituRecord{r, f});
    return counts(zone_set, result, touched);
}

InsituCount apply_kept_insitu(Model& m, const std::vector<int>& blocks) {
    if (m.insitu.empty() || blocks.empty()) return {};
    std::vector<char> only(m.blocks.size(), 0);
    for (int b : blocks) {
        if (b >= 0 && b < m.blocks.size()) only[b] = 1;
    }
    // Each field in turn, as each command set it: the last one to select a zone or a
    // sub-contact sets it.
    std::vector<std::uint8_t> zone_set, result, touched;
    for (const InsituRecord& rec : m.insitu) {
        set_zone_stress(m, rec.range, rec.field, only, zone_set);
        load_contacts(m, rec.range, rec.field, only, result, touched);
    }
    return counts(zone_set, result, touched);
}

} // namespace odec
