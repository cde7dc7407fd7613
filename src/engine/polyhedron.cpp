#include "engine/polyhedron.h"

#include <algorithm>
#include <limits>

namespace odec {

Vec3 Polyhedron::face_normal(int f) const {
    Vec3 n = Vec3::Zero();
    const int m = face_size(f);
    for (int k = 0; k < m; ++k) {
        const Vec3& a = vertices[face_vertex(f, k)];
        const Vec3& b = vertices[face_vertex(f, (k + 1) % m)];
        n += a.cross(b);
    }
    const double len = n.norm();
    return len > 0 ? Vec3(n / len) : Vec3(Vec3::Zero());
}

double Polyhedron::face_area(int f) const {
    Vec3 n = Vec3::Zero();
    const int m = face_size(f);
    for (int k = 0; k < m; ++k) {
        n += vertices[face_vertex(f, k)].cross(vertices[face_vertex(f, (k + 1) % m)]);
    }
    return 0.5 * n.norm();
}

void Polyhedron::bounds(Vec3& lo, Vec3& hi) const {
    const double inf = std::numeric_limits<double>::infinity();
    lo = Vec3(inf, inf, inf);
    hi = -lo;
    for (const Vec3& v : vertices) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
    }
}

void Polyhedron::translate(const Vec3& d) {
    for (Vec3& v : vertices) v += d;
}

// Each triangle (a, b, c) of a face with the origin spans a tetrahedron of signed volume
// det[a b c]/6. Its second moments about the origin are
//   integral x_i x_j dV = V/20 (sum_k a_i a_j ... ) written as V/20 (S_i S_j + sum_v v_i v_j)
// with S = a + b + c, the closed form for a tetrahedron with one vertex at the origin.
MassProperties mass_properties(const Polyhedron& p) {
    MassProperties mp;
    if (p.n_vertices() == 0) return mp;
    // Work relative to a vertex-average reference point to limit round-off far from the origin.
    Vec3 ref = Vec3::Zero();
    for (const Vec3& v : p.vertices) ref += v;
    ref /= static_cast<double>(p.n_vertices());

    double vol = 0;
    Vec3 first = Vec3::Zero();
    Mat3 second = Mat3::Zero(); // integral of x x^T dV about ref
    for (int f = 0; f < p.n_faces(); ++f) {
        const int m = p.face_size(f);
        const Vec3 a = p.vertices[p.face_vertex(f, 0)] - ref;
        for (int k = 1; k + 1 < m; ++k) {
            const Vec3 b = p.vertices[p.face_vertex(f, k)] - ref;
            const Vec3 c = p.vertices[p.face_vertex(f, k + 1)] - ref;
            const double v = a.dot(b.cross(c)) / 6.0;
            const Vec3 s = a + b + c;
            vol += v;
            first += v * s / 4.0;
            second += v / 20.0 * (s * s.transpose() + a * a.transpose() + b * b.transpose() + c * c.transpose());
        }
    }
    mp.volume = vol;
    if (vol <= 0) return mp;
    const Vec3 cr = first / vol; // centroid relative to ref
    mp.centroid = ref + cr;
    // Second moment about the centroid (parallel-axis theorem), then the inertia tensor.
    const Mat3 sc = second - vol * cr * cr.transpose();
    mp.inertia = sc.trace() * Mat3::Identity() - sc;
    return mp;
}

Polyhedron make_brick(double x1, double x2, double y1, double y2, double z1, double z2) {
    Polyhedron p;
    p.vertices = {{x1, y1, z1}, {x2, y1, z1}, {x2, y2, z1}, {x1, y2, z1},
                  {x1, y1, z2}, {x2, y1, z2}, {x2, y2, z2}, {x1, y2, z2}};
    // Counter-clockwise seen from outside.
    const int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                             {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
    p.face_offsets.push_back(0);
    for (const auto& f : faces) {
        for (int k = 0; k < 4; ++k) p.face_vertices.push_back(f[k]);
        p.face_offsets.push_back(static_cast<int>(p.face_vertices.size()));
    }
    return p;
}

bool contains_point(const Polyhedron& p, const Vec3& x, double tol) {
    for (int f = 0; f < p.n_faces(); ++f) {
        const Vec3 n = p.face_normal(f);
        if (n.dot(x - p.vertices[p.face_vertex(f, 0)]) > tol) return false;
    }
    return p.n_faces() > 0;
}

} // namespace odec
