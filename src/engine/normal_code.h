// A unit normal in eight bytes: the octahedral code (the normal's point on the octahedron
// |x| + |y| + |z| = 1, its lower half folded over the upper, as two coordinates of 2^-30), to
// within 1.5e-9 rad of the normal it was made from. The contact set keeps its normals so; the
// common plane of two blocks is made with the normal as kept (snap_normal), so that the contact
// acts along the very normal its geometry was measured on. A code decodes to the same bits every
// time, and a decoded normal codes to the same code again.
#pragma once

#include <cmath>
#include <cstdint>

#include <Eigen/Dense>

namespace odec {

struct NormalCode {
    std::int32_t u = 0, v = 0; // (0, 0): +z
    bool operator==(const NormalCode& o) const { return u == o.u && v == o.v; }
};

// The largest |u| or |v| of a code (2^30): the edge of the folded octahedron.
constexpr std::int32_t kNormalCodeLimit = std::int32_t{1} << 30;

namespace normal_code_detail {
constexpr double kScale = kNormalCodeLimit; // steps from the centre of the code to its edge
inline double sign_of(double x) { return x < 0 ? -1.0 : 1.0; }
} // namespace normal_code_detail

// The code of the direction of n (not null, finite; else +z's).
inline NormalCode encode_normal(const Eigen::Vector3d& n) {
    using namespace normal_code_detail;
    const double l1 = std::abs(n.x()) + std::abs(n.y()) + std::abs(n.z());
    if (!(l1 > 0) || !std::isfinite(l1)) return NormalCode{};
    double u = n.x() / l1, v = n.y() / l1;
    if (n.z() < 0) {
        const double fu = (1 - std::abs(v)) * sign_of(u), fv = (1 - std::abs(u)) * sign_of(v);
        u = fu;
        v = fv;
    }
    return NormalCode{static_cast<std::int32_t>(std::lround(u * kScale)), static_cast<std::int32_t>(std::lround(v * kScale))};
}

// The point of code c on the octahedron: along its normal, between 1/sqrt(3) and 1 long (never
// null). A code out of the octahedron's range (which no encode_normal makes) gives a point
// outside it, still a direction.
[[gnu::always_inline]] inline Eigen::Vector3d octahedral_point(NormalCode c) {
    using namespace normal_code_detail;
    double u = c.u / kScale, v = c.v / kScale;
    const double z = 1 - std::abs(u) - std::abs(v);
    if (z < 0) {
        const double fu = (1 - std::abs(v)) * sign_of(u), fv = (1 - std::abs(u)) * sign_of(v);
        u = fu;
        v = fv;
    }
    return Eigen::Vector3d(u, v, z);
}

// The unit normal of code c.
[[gnu::always_inline]] inline Eigen::Vector3d decode_normal(NormalCode c) {
    const Eigen::Vector3d p = octahedral_point(c);
    const double r = 1 / std::sqrt(p.squaredNorm());
    return Eigen::Vector3d(p[0] * r, p[1] * r, p[2] * r);
}

// n as the contact set keeps it.
inline Eigen::Vector3d snap_normal(const Eigen::Vector3d& n) { return decode_normal(encode_normal(n)); }

} // namespace odec
