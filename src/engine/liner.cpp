#include "engine/liner.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/mass_scaling.h"
#include "engine/model.h"
#include "engine/range.h"
#include "engine/stages.h"

namespace odec {

namespace {

using Mat18 = Eigen::Matrix<double, 18, 18>;
using Vec18 = Eigen::Matrix<double, 18, 1>;

// The drilling penalty: this fraction of E t A ties each node's rotation about the element's
// normal to the element's in-plane rotation.
constexpr double kDrilling = 1e-3;

// The element in its own frame: rows of `r` are x (along its first edge), y and its normal.
struct ElementFrame {
    Mat3 r;
    double x[3], y[3];
    double area = 0;
};

ElementFrame element_frame(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
    ElementFrame f;
    const Vec3 a = p1 - p0, b = p2 - p0;
    Vec3 n = a.cross(b);
    f.area = 0.5 * n.norm();
    n.normalize();
    const Vec3 ex = a.normalized();
    const Vec3 ey = n.cross(ex);
    f.r.row(0) = ex;
    f.r.row(1) = ey;
    f.r.row(2) = n;
    f.x[0] = 0; f.y[0] = 0;
    f.x[1] = a.dot(ex); f.y[1] = 0;
    f.x[2] = b.dot(ex); f.y[2] = b.dot(ey);
    return f;
}

// CST strain-displacement matrix (dofs u1 v1 u2 v2 u3 v3), and the in-plane rotation row.
Eigen::Matrix<double, 3, 6> membrane_b(const ElementFrame& f, Eigen::Matrix<double, 1, 6>* omega = nullptr) {
    Eigen::Matrix<double, 3, 6> bm = Eigen::Matrix<double, 3, 6>::Zero();
    const double inv = 1.0 / (2.0 * f.area);
    Eigen::Matrix<double, 1, 6> w = Eigen::Matrix<double, 1, 6>::Zero();
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3, k = (i + 2) % 3;
        const double bi = (f.y[j] - f.y[k]) * inv; // dN_i/dx
        const double ci = (f.x[k] - f.x[j]) * inv; // dN_i/dy
        bm(0, 2 * i) = bi;
        bm(1, 2 * i + 1) = ci;
        bm(2, 2 * i) = ci;
        bm(2, 2 * i + 1) = bi;
        w(2 * i + 1) = 0.5 * bi;  // omega = (v,x - u,y) / 2
        w(2 * i) = -0.5 * ci;
    }
    if (omega) *omega = w;
    return bm;
}

// DKT curvature-displacement matrix at (xi, eta) (area coordinates L2, L3), plate dofs
// w, theta_x, theta_y of the three corners. The rotations beta (u = z beta) are beta_x =
// theta_y, beta_y = -theta_x; they vary quadratically between their values at the corners and
// the mid-sides, where the tangential one follows the cubic w along the side and the normal one
// is the mean of the corners'.
Eigen::Matrix<double, 3, 9> plate_b(const ElementFrame& f, double xi, double eta) {
    // g: beta (x, y) at the 6 points as rows (2 per point) of a 12 x 9 map from the dofs.
    Eigen::Matrix<double, 12, 9> g = Eigen::Matrix<double, 12, 9>::Zero();
    for (int a = 0; a < 3; ++a) {
        g(2 * a, 3 * a + 2) = 1.0;   // beta_x = theta_y
        g(2 * a + 1, 3 * a + 1) = -1.0; // beta_y = -theta_x
    }
    const int side_i[3] = {1, 2, 0}, side_j[3] = {2, 0, 1}; // mid-sides 4, 5, 6: sides 2-3, 3-1, 1-2
    for (int k = 0; k < 3; ++k) {
        const int i = side_i[k], j = side_j[k];
        const double dx = f.x[j] - f.x[i], dy = f.y[j] - f.y[i];
        const double l = std::sqrt(dx * dx + dy * dy);
        const double sx = dx / l, sy = dy / l, nx = -sy, ny = sx;
        Eigen::Matrix<double, 1, 9> bs_i = sx * g.row(2 * i) + sy * g.row(2 * i + 1);
        Eigen::Matrix<double, 1, 9> bs_j = sx * g.row(2 * j) + sy * g.row(2 * j + 1);
        Eigen::Matrix<double, 1, 9> bn_i = nx * g.row(2 * i) + ny * g.row(2 * i + 1);
        Eigen::Matrix<double, 1, 9> bn_j = nx * g.row(2 * j) + ny * g.row(2 * j + 1);
        Eigen::Matrix<double, 1, 9> bs = -0.25 * (bs_i + bs_j);
        bs(3 * j) += -1.5 / l;
        bs(3 * i) += 1.5 / l;
        const Eigen::Matrix<double, 1, 9> bn = 0.5 * (bn_i + bn_j);
        g.row(2 * (3 + k)) = sx * bs + nx * bn;
        g.row(2 * (3 + k) + 1) = sy * bs + ny * bn;
    }
    const double l1 = 1.0 - xi - eta;
    const double dxi[6] = {-(4 * l1 - 1), 4 * xi - 1, 0, 4 * eta, -4 * eta, 4 * l1 - 4 * xi};
    const double deta[6] = {-(4 * l1 - 1), 0, 4 * eta - 1, 4 * xi, 4 * l1 - 4 * eta, -4 * xi};
    Eigen::Matrix2d j;
    j << f.x[1] - f.x[0], f.y[1] - f.y[0], f.x[2] - f.x[0], f.y[2] - f.y[0];
    const Eigen::Matrix2d ji = j.inverse();
    Eigen::Matrix<double, 3, 9> b = Eigen::Matrix<double, 3, 9>::Zero();
    for (int a = 0; a < 6; ++a) {
        const double ddx = ji(0, 0) * dxi[a] + ji(0, 1) * deta[a];
        const double ddy = ji(1, 0) * dxi[a] + ji(1, 1) * deta[a];
        b.row(0) += ddx * g.row(2 * a);
        b.row(1) += ddy * g.row(2 * a + 1);
        b.row(2) += ddy * g.row(2 * a) + ddx * g.row(2 * a + 1);
    }
    return b;
}

Mat3 plane_stress(double e, double nu) {
    Mat3 d;
    d << 1, nu, 0, nu, 1, 0, 0, 0, 0.5 * (1 - nu);
    return d * (e / (1 - nu * nu));
}

// The element's stiffness in world axes, dofs (u, theta) of its three nodes in turn.
Mat18 element_stiffness(const Vec3& p0, const Vec3& p1, const Vec3& p2, const LinerMaterial& p) {
    const ElementFrame f = element_frame(p0, p1, p2);
    const Mat3 d = plane_stress(p.e, p.nu);
    Mat18 kl = Mat18::Zero();
    // Membrane.
    Eigen::Matrix<double, 1, 6> omega;
    const Eigen::Matrix<double, 3, 6> bm = membrane_b(f, &omega);
    const Eigen::Matrix<double, 6, 6> km = p.thick * f.area * bm.transpose() * d * bm;
    const int mi[6] = {0, 1, 6, 7, 12, 13};
    for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 6; ++c) kl(mi[r], mi[c]) += km(r, c);
    // Bending, at the three mid-sides.
    const Mat3 db = d * (p.thick * p.thick * p.thick / 12.0);
    const double pts[3][2] = {{0.5, 0.0}, {0.5, 0.5}, {0.0, 0.5}};
    Eigen::Matrix<double, 9, 9> kb = Eigen::Matrix<double, 9, 9>::Zero();
    for (const auto& q : pts) {
        const Eigen::Matrix<double, 3, 9> bb = plate_b(f, q[0], q[1]);
        kb += (f.area / 3.0) * bb.transpose() * db * bb;
    }
    const int bi[9] = {2, 3, 4, 8, 9, 10, 14, 15, 16};
    for (int r = 0; r < 9; ++r)
        for (int c = 0; c < 9; ++c) kl(bi[r], bi[c]) += kb(r, c);
    // Drilling.
    const double kd = kDrilling * p.e * p.thick * f.area;
    for (int a = 0; a < 3; ++a) {
        Vec18 c = Vec18::Zero();
        c(6 * a + 5) = 1.0;
        for (int q = 0; q < 6; ++q) c(mi[q]) -= omega(q);
        kl += kd * c * c.transpose();
    }
    Mat18 t = Mat18::Zero();
    for (int k = 0; k < 6; ++k) t.block<3, 3>(3 * k, 3 * k) = f.r;
    return t.transpose() * kl * t;
}

void gather(const LinerSet& ls, int e, Vec18& d) {
    for (int a = 0; a < 3; ++a) {
        const int i = ls.elem[e][a];
        d.segment<3>(6 * a) = ls.u[i];
        d.segment<3>(6 * a + 3) = ls.rot[i];
    }
}

const LinerMaterial& material_of_node(const LinerSet& ls, int i) { return ls.materials[ls.material[ls.liner_of_node(i)]]; }

bool stiffness_fresh(const LinerSet& ls) {
    return static_cast<int>(ls.k.size()) == ls.n_elements() && static_cast<int>(ls.stiff_t.size()) == ls.n_nodes();
}

void ensure_stiffness(LinerSet& ls) {
    if (!stiffness_fresh(ls)) build_liner_stiffness(ls);
}

} // namespace

int LinerSet::index(int liner_id) const {
    const auto it = std::lower_bound(id.begin(), id.end(), liner_id);
    return it != id.end() && *it == liner_id ? static_cast<int>(it - id.begin()) : -1;
}

int LinerSet::liner_of_element(int e) const {
    const auto it = std::upper_bound(elem_offset.begin(), elem_offset.end(), e);
    return static_cast<int>(it - elem_offset.begin()) - 1;
}

int LinerSet::liner_of_node(int i) const {
    const auto it = std::upper_bound(node_offset.begin(), node_offset.end(), i);
    return static_cast<int>(it - node_offset.begin()) - 1;
}

void build_liner_stiffness(LinerSet& ls) {
    ls.k.assign(ls.n_elements(), {});
    ls.stiff_t.assign(ls.n_nodes(), 0.0);
    ls.stiff_r.assign(ls.n_nodes(), 0.0);
    for (int c = 0; c < ls.size(); ++c) {
        const LinerMaterial& p = ls.materials[ls.material[c]];
        for (int e = ls.elem_offset[c]; e < ls.elem_offset[c + 1]; ++e) {
            const auto& n = ls.elem[e];
            const Mat18 k = element_stiffness(ls.pos0[n[0]], ls.pos0[n[1]], ls.pos0[n[2]], p);
            for (int r = 0; r < 18; ++r)
                for (int q = 0; q < 18; ++q) ls.k[e][18 * r + q] = k(r, q);
            for (int a = 0; a < 3; ++a) {
                double kt = 0, kr = 0;
                for (int r = 0; r < 3; ++r) {
                    kt = std::max(kt, k.row(6 * a + r).cwiseAbs().sum());
                    kr = std::max(kr, k.row(6 * a + 3 + r).cwiseAbs().sum());
                }
                ls.stiff_t[n[a]] += kt;
                ls.stiff_r[n[a]] += kr;
            }
        }
    }
}

void refresh_liner_stiffness(LinerSet& ls) { ensure_stiffness(ls); }

int add_liner(Model& m, const Range& range, int mat, const Vec3& axis_in, std::string& why) {
    LinerSet& ls = m.liners;
    if (mat < 1 || mat >= static_cast<int>(ls.materials.size()) || !ls.materials[mat].defined) {
        why = "liner material " + std::to_string(mat) + " is not defined: give it with 'prop mat=" + std::to_string(mat) +
              " li_e ... li_nu ... li_thick ... li_kn ... li_ks ...'";
        return -1;
    }
    const LinerMaterial& p = ls.materials[mat];
    if (!(p.e > 0) || !(p.thick > 0)) {
        why = "liner material " + std::to_string(mat) + " needs a Young's modulus (li_e) and a thickness (li_thick) above 0";
        return -1;
    }
    const BlockSet& s = m.blocks;
    const ZoneSet& z = m.zones;
    const GridpointSet& g = m.gridpoints;
    // The faces of the zones of standing deformable blocks; those met once are on the surface.
    struct Face {
        std::array<int, 3> key;
        int zone, opposite;
    };
    std::vector<Face> faces;
    for (int q = 0; q < z.size(); ++q) {
        const int b = z.block[q];
        if ((s.flags[b] & kExcavated) || !(s.flags[b] & kDeformable)) continue;
        for (int k = 0; k < 4; ++k) {
            std::array<int, 3> key;
            int n = 0;
            for (int r = 0; r < 4; ++r)
                if (r != k) key[n++] = z.gp[q][r];
            std::sort(key.begin(), key.end());
            faces.push_back({key, q, k});
        }
    }
    std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) {
        return a.key != b.key ? a.key < b.key : a.zone < b.zone;
    });
    std::vector<std::array<int, 3>> tri;  // gridpoints, counter-clockwise seen from outside
    std::vector<int> tri_block;
    int covered = 0;
    for (size_t i = 0; i < faces.size();) {
        size_t j = i + 1;
        while (j < faces.size() && faces[j].key == faces[i].key) ++j;
        if (j - i == 1) {
            const Face& f = faces[i];
            const int b = z.block[f.zone];
            bool in = true;
            for (int gp : f.key) in = in && range.contains_point(m, g.pos[gp], b);
            if (in) {
                std::array<int, 3> t = f.key;
                const Vec3 nrm = (g.pos[t[1]] - g.pos[t[0]]).cross(g.pos[t[2]] - g.pos[t[0]]);
                if ((g.pos[z.gp[f.zone][f.opposite]] - g.pos[t[0]]).dot(nrm) > 0) std::swap(t[1], t[2]);
                // Free: no other standing block just outside it.
                const Vec3 c = (g.pos[t[0]] + g.pos[t[1]] + g.pos[t[2]]) / 3.0;
                const Vec3 outward = (g.pos[t[1]] - g.pos[t[0]]).cross(g.pos[t[2]] - g.pos[t[0]]);
                const double a = 0.5 * outward.norm();
                const Vec3 out = c + outward.normalized() * (1e-3 * std::sqrt(a));
                bool free = a > 0;
                for (int o = 0; o < s.size() && free; ++o) {
                    if (o == b || (s.flags[o] & kExcavated)) continue;
                    if (contains_point(s.shape[o], s.orientation[o].conjugate() * (out - s.centroid[o]), 0.0)) free = false;
                }
                if (free) {
                    tri.push_back(t);
                    tri_block.push_back(b);
                } else {
                    ++covered;
                }
            }
        }
        i = j;
    }
    if (tri.empty()) {
        why = "no free face of a zoned block has its three corners in the range" +
              std::string(covered > 0 ? " (" + std::to_string(covered) + " faces in it are covered by another block)" : "") +
              ": a liner is laid on the zone faces of deformable blocks ('gen edge') that face a void";
        return -1;
    }
    // Axis of the report frame.
    Vec3 axis = axis_in;
    if (!(axis.norm() > 0)) {
        axis = Vec3::UnitZ();
        for (const Filter& f : range.filters) {
            if (f.kind == FilterKind::Cylinder && !f.negate && (f.b - f.a).norm() > 0) {
                axis = (f.b - f.a).normalized();
                break;
            }
        }
    }
    axis.normalize();
    LinerSet out = ls;
    const int c = out.size();
    out.id.push_back(out.next_id++);
    out.material.push_back(mat);
    out.axis.push_back(axis);
    if (out.node_offset.empty()) out.node_offset.push_back(0);
    if (out.elem_offset.empty()) out.elem_offset.push_back(0);
    const int first = out.n_nodes();
    std::vector<int> node_of_gp;
    std::vector<int> gps;
    for (const auto& t : tri)
        for (int gp : t) gps.push_back(gp);
    std::sort(gps.begin(), gps.end());
    gps.erase(std::unique(gps.begin(), gps.end()), gps.end());
    auto node_of = [&](int gp) { return first + static_cast<int>(std::lower_bound(gps.begin(), gps.end(), gp) - gps.begin()); };
    for (int gp : gps) {
        const Vec3 x = g.pos[gp];
        out.pos0.push_back(x); out.pos.push_back(x);
        out.vel.push_back(Vec3::Zero()); out.spin.push_back(Vec3::Zero());
        out.u.push_back(Vec3::Zero()); out.rot.push_back(Vec3::Zero()); out.disp.push_back(Vec3::Zero());
        out.force.push_back(Vec3::Zero()); out.moment.push_back(Vec3::Zero()); out.force_scale.push_back(0);
        out.area.push_back(0); out.normal.push_back(Vec3::Zero());
        out.mass.push_back(0); out.inertial_mass.push_back(0); out.inertial_moment.push_back(0);
        out.host_block.push_back(0); out.host_lever.push_back(Vec3::Zero());
        out.host_gp.push_back({-1, -1, -1, -1}); out.host_w.push_back({0, 0, 0, 0});
        out.bond_n.push_back(0); out.bond_s.push_back(Vec3::Zero()); out.state.push_back(0);
    }
    for (size_t e = 0; e < tri.size(); ++e) {
        const std::array<int, 3> n = {node_of(tri[e][0]), node_of(tri[e][1]), node_of(tri[e][2])};
        out.elem.push_back(n);
        const Vec3 nrm = 0.5 * (out.pos0[n[1]] - out.pos0[n[0]]).cross(out.pos0[n[2]] - out.pos0[n[0]]);
        const double a = nrm.norm();
        for (int i : n) {
            out.area[i] += a / 3.0;
            out.normal[i] += nrm;
        }
    }
    // Each node is tied to the zone it is a corner of (of the face's block).
    std::vector<char> tied(gps.size(), 0);
    for (size_t e = 0; e < tri.size(); ++e) {
        for (int a = 0; a < 3; ++a) {
            const int gp = tri[e][a];
            const int i = node_of(gp);
            if (tied[i - first]) continue;
            tied[i - first] = 1;
            const int b = tri_block[e];
            for (int q = 0; q < z.size(); ++q) {
                if (z.block[q] != b) continue;
                int r = 0;
                while (r < 4 && z.gp[q][r] != gp) ++r;
                if (r == 4) continue;
                out.host_block[i] = s.id[b];
                out.host_gp[i] = z.gp[q];
                out.host_w[i] = {0, 0, 0, 0};
                out.host_w[i][r] = 1.0;
                break;
            }
        }
    }
    for (int i = first; i < out.n_nodes(); ++i) {
        out.normal[i].normalize();
        out.mass[i] = out.inertial_mass[i] = p.density * p.thick * out.area[i];
    }
    out.node_offset.push_back(out.n_nodes());
    out.elem_offset.push_back(out.n_elements());
    build_liner_stiffness(out);
    ls = std::move(out);
    m.geometry_changed = true; // masses and timestep follow
    return c;
}

void remove_liners(Model& m, std::vector<int> liners) {
    LinerSet& ls = m.liners;
    std::sort(liners.begin(), liners.end());
    liners.erase(std::unique(liners.begin(), liners.end()), liners.end());
    if (liners.empty()) return;
    LinerSet out;
    out.next_id = ls.next_id;
    out.materials = ls.materials;
    out.node_offset.push_back(0);
    out.elem_offset.push_back(0);
    size_t r = 0;
    for (int c = 0; c < ls.size(); ++c) {
        if (r < liners.size() && liners[r] == c) {
            ++r;
            continue;
        }
        out.id.push_back(ls.id[c]);
        out.material.push_back(ls.material[c]);
        out.axis.push_back(ls.axis[c]);
        const int shift = out.n_nodes() - ls.node_offset[c];
        for (int i = ls.node_offset[c]; i < ls.node_offset[c + 1]; ++i) {
            out.pos0.push_back(ls.pos0[i]); out.pos.push_back(ls.pos[i]); out.vel.push_back(ls.vel[i]);
            out.spin.push_back(ls.spin[i]); out.u.push_back(ls.u[i]); out.rot.push_back(ls.rot[i]);
            out.disp.push_back(ls.disp[i]); out.force.push_back(ls.force[i]); out.moment.push_back(ls.moment[i]);
            out.force_scale.push_back(ls.force_scale[i]); out.area.push_back(ls.area[i]);
            out.normal.push_back(ls.normal[i]); out.mass.push_back(ls.mass[i]);
            out.inertial_mass.push_back(ls.inertial_mass[i]); out.inertial_moment.push_back(ls.inertial_moment[i]);
            out.host_block.push_back(ls.host_block[i]); out.host_lever.push_back(ls.host_lever[i]);
            out.host_gp.push_back(ls.host_gp[i]); out.host_w.push_back(ls.host_w[i]);
            out.bond_n.push_back(ls.bond_n[i]); out.bond_s.push_back(ls.bond_s[i]); out.state.push_back(ls.state[i]);
        }
        for (int e = ls.elem_offset[c]; e < ls.elem_offset[c + 1]; ++e) {
            std::array<int, 3> n = ls.elem[e];
            for (int& i : n) i += shift;
            out.elem.push_back(n);
        }
        out.node_offset.push_back(out.n_nodes());
        out.elem_offset.push_back(out.n_elements());
    }
    if (out.size() == 0) {
        out.node_offset.clear();
        out.elem_offset.clear();
    }
    ls = std::move(out);
    build_liner_stiffness(ls);
    m.geometry_changed = true;
}

std::string liners_problem(const Model& m) {
    const LinerSet& ls = m.liners;
    for (int c = 0; c < ls.size(); ++c) {
        const int mat = ls.material[c];
        if (mat < 1 || mat >= static_cast<int>(ls.materials.size()) || !ls.materials[mat].defined ||
            !(ls.materials[mat].e > 0) || !(ls.materials[mat].thick > 0)) {
            return "liner " + std::to_string(ls.id[c]) + ": its material " + std::to_string(mat) +
                   " has no Young's modulus (li_e) or thickness (li_thick)";
        }
        if (m.settings.dynamic && !(ls.materials[mat].density > 0)) {
            return "liner " + std::to_string(ls.id[c]) + ": its material " + std::to_string(mat) +
                   " has no density (li_dens), which dynamic mode needs for the nodes' masses";
        }
    }
    return "";
}

void attach_liner_nodes(Model& m) {
    LinerSet& ls = m.liners;
    // As cables' grout (attach_cable_nodes): the bond of a node whose rock is gone (deleted or
    // excavated) starts again from nothing; one whose block was only zoned again keeps it.
    for (int i = 0; i < ls.n_nodes(); ++i) {
        if (ls.host_block[i] > 0 && rock_tie_holds(m, ls.host_block[i], ls.host_lever[i], ls.host_gp[i])) continue;
        const int was = ls.host_block[i];
        find_rock_tie(m, ls.pos[i], ls.host_block[i], ls.host_lever[i], ls.host_gp[i], ls.host_w[i]);
        if (!rock_tie_kept(m, was, ls.host_block[i])) {
            ls.bond_n[i] = 0;
            ls.bond_s[i].setZero();
            ls.state[i] = 0;
        }
    }
    build_liner_stiffness(ls);
}

namespace {

double bond_stiffness(const LinerSet& ls, int i) {
    if (ls.host_block[i] <= 0) return 0.0;
    const LinerMaterial& p = material_of_node(ls, i);
    return std::max(p.kn, p.ks) * ls.area[i];
}

} // namespace

double liner_critical_timestep(const Model& m) {
    const LinerSet& ls = m.liners;
    if (!stiffness_fresh(ls)) return 0.0;
    double dt = 0;
    for (int i = 0; i < ls.n_nodes(); ++i) {
        const double k = ls.stiff_t[i] + bond_stiffness(ls, i);
        if (!(ls.mass[i] > 0) || !(k > 0)) continue;
        const double d = std::sqrt(ls.mass[i] / k);
        if (dt == 0 || d < dt) dt = d;
    }
    return dt;
}

std::string choose_liner_masses(Model& m, double raise_to) {
    LinerSet& ls = m.liners;
    if (ls.n_nodes() == 0) return "";
    ensure_stiffness(ls);
    const double dt2 = m.dt * m.dt;
    for (int i = 0; i < ls.n_nodes(); ++i) {
        const double kt = ls.stiff_t[i] + bond_stiffness(ls, i);
        // The own step of a node is sqrt(m / kt) (liner_critical_timestep).
        const double mass = !m.settings.dynamic ? kt * dt2
                            : raise_to > 0      ? std::max(ls.mass[i], kt * raise_to * raise_to)
                                                : ls.mass[i];
        const double moment = ls.stiff_r[i] * dt2;
        if (!(mass > 0) || !std::isfinite(mass) || !(moment > 0) || !std::isfinite(moment)) {
            const int c = ls.liner_of_node(i);
            return "node " + std::to_string(i - ls.node_offset[c] + 1) + " of liner " + std::to_string(ls.id[c]) +
                   " gets no usable mass (" + num_text(mass) + " kg): give its material a density (li_dens), "
                   "a modulus (li_e) and a thickness (li_thick) of sensible size";
        }
        ls.vel[i] *= velocity_factor(ls.inertial_mass[i], mass);
        ls.spin[i] *= velocity_factor(ls.inertial_moment[i], moment);
        ls.inertial_mass[i] = mass;
        ls.inertial_moment[i] = moment;
    }
    return "";
}

void add_liner_gridpoint_stiffness(const Model& m, std::vector<double>& k) {
    const LinerSet& ls = m.liners;
    for (int i = 0; i < ls.n_nodes(); ++i) {
        if (ls.host_block[i] <= 0 || ls.host_gp[i][0] < 0) continue;
        const double kb = bond_stiffness(ls, i);
        for (int q = 0; q < 4; ++q) {
            const int g = ls.host_gp[i][q];
            if (g < static_cast<int>(k.size())) k[g] += ls.host_w[i][q] * kb;
        }
    }
}

void add_liner_block_stiffness(const Model& m, std::vector<double>& kt, std::vector<double>& kr) {
    const LinerSet& ls = m.liners;
    for (int i = 0; i < ls.n_nodes(); ++i) {
        if (ls.host_block[i] <= 0 || ls.host_gp[i][0] >= 0) continue;
        const int b = m.block_index(ls.host_block[i]);
        if (b < 0 || b >= static_cast<int>(kt.size())) continue;
        const double k = bond_stiffness(ls, i);
        kt[b] += k;
        kr[b] += k * ls.host_lever[i].squaredNorm();
    }
}

void liner_forces(Model& m, double dt) {
    LinerSet& ls = m.liners;
    if (ls.size() == 0) return;
    ensure_stiffness(ls);
    BlockSet& s = m.blocks;
    GridpointSet& g = m.gridpoints;
    if (!m.settings.dynamic && static_cast<int>(m.contacts.joint_kt.size()) == s.size() &&
        static_cast<int>(m.contacts.joint_kr.size()) == s.size()) {
        add_liner_block_stiffness(m, m.contacts.joint_kt, m.contacts.joint_kr);
    }
    for (int i = 0; i < ls.n_nodes(); ++i) {
        ls.force[i] = ls.mass[i] * m.gravity;
        ls.moment[i].setZero();
        ls.force_scale[i] = ls.force[i].norm();
    }
    // Elements.
    Vec18 d, f;
    for (int e = 0; e < ls.n_elements(); ++e) {
        gather(ls, e, d);
        const Eigen::Map<const Eigen::Matrix<double, 18, 18, Eigen::RowMajor>> k(ls.k[e].data());
        f.noalias() = k * d;
        for (int a = 0; a < 3; ++a) {
            const int i = ls.elem[e][a];
            const Vec3 fa = f.segment<3>(6 * a);
            ls.force[i] -= fa;
            ls.moment[i] -= f.segment<3>(6 * a + 3);
            ls.force_scale[i] += fa.norm();
        }
    }
    // Bond.
    for (int c = 0; c < ls.size(); ++c) {
        const LinerMaterial& p = ls.materials[ls.material[c]];
        const double tanf = std::tan(p.sfric * M_PI / 180.0);
        for (int i = ls.node_offset[c]; i < ls.node_offset[c + 1]; ++i) {
            if (ls.host_block[i] <= 0) continue;
            int b = -1;
            const Vec3 vh = rock_tie_velocity(m, ls.host_block[i], ls.host_lever[i], ls.host_gp[i], ls.host_w[i], b);
            if (b < 0 || (s.flags[b] & kExcavated)) continue;
            const Vec3& n = ls.normal[i];
            const Vec3 du = (ls.vel[i] - vh) * dt;
            const double dun = du.dot(n);
            const double a = ls.area[i];
            double fn = ls.bond_n[i] - p.kn * a * dun;
            Vec3 fs = ls.bond_s[i] - p.ks * a * (du - dun * n);
            std::uint8_t st = ls.state[i] & (kBondBrokenTension | kBondBrokenShear);
            if (!st && p.ncut >= 0 && -fn > p.ncut * a) st |= kBondBrokenTension;
            double cap = std::numeric_limits<double>::infinity();
            if (st) {
                if (fn < 0) {
                    fn = 0;
                    fs.setZero();
                    st |= kBondOpen;
                }
                cap = tanf * std::max(fn, 0.0);
            } else if (p.scoh >= 0) {
                cap = p.scoh * a + tanf * std::max(fn, 0.0);
            }
            const double fsn = fs.norm();
            if (fsn > cap) {
                fs *= fsn > 0 ? cap / fsn : 0.0;
                st |= kBondSlipNow;
                if (!(st & (kBondBrokenTension | kBondBrokenShear))) st |= kBondBrokenShear;
            }
            ls.bond_n[i] = fn;
            ls.bond_s[i] = fs;
            ls.state[i] = st;
            const Vec3 on_liner = fn * n + fs;
            ls.force[i] += on_liner;
            ls.force_scale[i] += on_liner.norm();
            const Vec3 on_rock = -on_liner;
            if (ls.host_gp[i][0] >= 0) {
                for (int q = 0; q < 4; ++q) {
                    const int gp = ls.host_gp[i][q];
                    const Vec3 share = ls.host_w[i][q] * on_rock;
                    g.force[gp] += share;
                    g.force_scale[gp] += share.norm();
                }
            } else {
                const Vec3 lever = s.orientation[b] * ls.host_lever[i];
                s.force[b] += on_rock;
                s.moment[b] += lever.cross(on_rock);
                s.force_scale[b] += on_rock.norm();
            }
        }
    }
}

int integrate_liners(Model& m, double dt, AutoDampingSums* sums) {
    LinerSet& ls = m.liners;
    const Damping& d = m.damping;
    int bad = -1;
    for (int i = 0; i < ls.n_nodes(); ++i) {
        const double mass = ls.inertial_mass[i], inertia = ls.inertial_moment[i];
        if (!(mass > 0) || !(inertia > 0)) continue;
        for (int k = 0; k < 3; ++k) {
            const double v0 = ls.vel[i][k], w0 = ls.spin[i][k];
            ls.vel[i][k] += damped_force(d, ls.force[i][k], v0, mass, dt) / mass * dt;
            ls.spin[i][k] += damped_force(d, ls.moment[i][k], w0, inertia, dt) / inertia * dt;
            if (sums) {
                sums->add(mass, ls.force[i][k], v0, ls.vel[i][k]);
                sums->add(inertia, ls.moment[i][k], w0, ls.spin[i][k]);
            }
        }
        const Vec3 dx = ls.vel[i] * dt;
        ls.pos[i] += dx;
        ls.u[i] += dx;
        ls.disp[i] += dx;
        ls.rot[i] += ls.spin[i] * dt;
        if (bad < 0 && !std::isfinite(ls.pos[i].squaredNorm() + ls.rot[i].squaredNorm())) bad = i;
    }
    return bad;
}

LinerResultants liner_resultants(const LinerSet& ls, int e) {
    LinerResultants out;
    const int c = ls.liner_of_element(e);
    const LinerMaterial& p = ls.materials[ls.material[c]];
    const auto& n = ls.elem[e];
    const ElementFrame f = element_frame(ls.pos0[n[0]], ls.pos0[n[1]], ls.pos0[n[2]]);
    Eigen::Matrix<double, 6, 1> um;
    Eigen::Matrix<double, 9, 1> ub;
    for (int a = 0; a < 3; ++a) {
        const Vec3 ul = f.r * ls.u[n[a]];
        const Vec3 rl = f.r * ls.rot[n[a]];
        um(2 * a) = ul.x();
        um(2 * a + 1) = ul.y();
        ub(3 * a) = ul.z();
        ub(3 * a + 1) = rl.x();
        ub(3 * a + 2) = rl.y();
    }
    const Mat3 d = plane_stress(p.e, p.nu);
    const Vec3 nm = p.thick * d * (membrane_b(f) * um);
    const Vec3 mm = d * (p.thick * p.thick * p.thick / 12.0) * (plate_b(f, 1.0 / 3.0, 1.0 / 3.0) * ub);
    const Vec3 nz = f.r.row(2).transpose();
    Vec3 hx = ls.axis[c].cross(nz);
    if (hx.norm() < 1e-6) hx = Vec3::UnitX() - Vec3::UnitX().dot(nz) * nz;
    if (hx.norm() < 1e-6) hx = Vec3::UnitY() - Vec3::UnitY().dot(nz) * nz;
    hx.normalize();
    const Vec3 hy = nz.cross(hx);
    Eigen::Matrix2d q;
    q << hx.dot(f.r.row(0)), hx.dot(f.r.row(1)), hy.dot(f.r.row(0)), hy.dot(f.r.row(1));
    Eigen::Matrix2d tn, tm;
    tn << nm.x(), nm.z(), nm.z(), nm.y();
    tm << mm.x(), mm.z(), mm.z(), mm.y();
    tn = q * tn * q.transpose();
    tm = q * tm * q.transpose();
    out.nx = tn(0, 0); out.ny = tn(1, 1); out.nxy = tn(0, 1);
    out.mx = tm(0, 0); out.my = tm(1, 1); out.mxy = tm(0, 1);
    out.centroid = (ls.pos[n[0]] + ls.pos[n[1]] + ls.pos[n[2]]) / 3.0;
    out.x_dir = hx;
    out.normal = nz;
    return out;
}

double liner_strain_energy(const Model& m) {
    const LinerSet& ls = m.liners;
    if (!stiffness_fresh(ls)) return 0.0;
    double en = 0;
    Vec18 d;
    for (int e = 0; e < ls.n_elements(); ++e) {
        gather(ls, e, d);
        const Eigen::Map<const Eigen::Matrix<double, 18, 18, Eigen::RowMajor>> k(ls.k[e].data());
        en += 0.5 * d.dot(k * d);
    }
    for (int i = 0; i < ls.n_nodes(); ++i) {
        if (ls.host_block[i] <= 0) continue;
        const LinerMaterial& p = material_of_node(ls, i);
        const double a = ls.area[i];
        if (p.kn > 0) en += 0.5 * ls.bond_n[i] * ls.bond_n[i] / (p.kn * a);
        if (p.ks > 0) en += 0.5 * ls.bond_s[i].squaredNorm() / (p.ks * a);
    }
    return en;
}

double liner_max_unbalanced(const Model& m) {
    const LinerSet& ls = m.liners;
    double f = 0;
    for (int i = 0; i < ls.n_nodes(); ++i) f = std::max(f, ls.force[i].norm());
    return f;
}

void liner_unbalanced_sums(const Model& m, double& unbal, double& total) {
    const LinerSet& ls = m.liners;
    for (int i = 0; i < ls.n_nodes(); ++i) {
        unbal += ls.force[i].norm();
        total += ls.force_scale[i];
    }
}

int nearest_liner_element(const Model& m, const Vec3& x) {
    const LinerSet& ls = m.liners;
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (int e = 0; e < ls.n_elements(); ++e) {
        const auto& n = ls.elem[e];
        const double d = ((ls.pos[n[0]] + ls.pos[n[1]] + ls.pos[n[2]]) / 3.0 - x).stableNorm();
        if (d < best_d) {
            best = e;
            best_d = d;
        }
    }
    return best;
}

int nearest_liner_node(const Model& m, const Vec3& x) {
    const LinerSet& ls = m.liners;
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (int i = 0; i < ls.n_nodes(); ++i) {
        const double d = (ls.pos[i] - x).stableNorm();
        if (d < best_d) {
            best = i;
            best_d = d;
        }
    }
    return best;
}

void reset_liner_displacements(Model& m) {
    for (Vec3& d : m.liners.disp) d.setZero();
}

} // namespace odec
