#include "engine/range.h"

#include "engine/model.h"

namespace odec {

// Filters that test a location (a block centroid or a contact point).
static bool test_point_filter(const Vec3& c, const Filter& f) {
    auto within = [](double v, double lo, double hi) {
        const double eps = 1e-9 * (1.0 + std::abs(lo) + std::abs(hi));
        return v >= lo - eps && v <= hi + eps;
    };
    switch (f.kind) {
    case FilterKind::X: return within(c.x(), f.lo, f.hi);
    case FilterKind::Y: return within(c.y(), f.lo, f.hi);
    case FilterKind::Z: return within(c.z(), f.lo, f.hi);
    case FilterKind::Sphere: return (c - f.a).norm() <= f.radius;
    case FilterKind::Cylinder: {
        const Vec3 axis = f.b - f.a;
        const double len2 = axis.squaredNorm();
        if (len2 == 0) return false;
        const double t = (c - f.a).dot(axis) / len2;
        if (t < 0 || t > 1) return false;
        return (c - (f.a + t * axis)).norm() <= f.radius;
    }
    case FilterKind::PlaneAbove: return (c - f.a).dot(f.b) >= 0;
    case FilterKind::PlaneBelow: return (c - f.a).dot(f.b) <= 0;
    default: return false;
    }
}

static bool test_filter(const Model& m, int b, const Filter& f) {
    switch (f.kind) {
    case FilterKind::Region: return m.blocks.region[b] == static_cast<int>(f.lo);
    case FilterKind::Group: {
        const int g = m.blocks.group[b];
        return g >= 0 && m.group_names[g] == f.name;
    }
    case FilterKind::Id: return m.blocks.id[b] >= f.lo && m.blocks.id[b] <= f.hi;
    case FilterKind::AnyOf:
        for (const Range& r : f.any_of) {
            if (r.contains_block(m, b)) return true;
        }
        return false;
    default: return test_point_filter(m.blocks.centroid[b], f);
    }
}

bool Range::contains_block(const Model& m, int b) const {
    for (const Filter& f : filters) {
        if (test_filter(m, b, f) == f.negate) return false;
    }
    return true;
}


bool Range::contains_contact(const Model& m, const Vec3& point, int a, int b) const {
    for (const Filter& f : filters) {
        bool pass;
        switch (f.kind) {
        case FilterKind::Region:
        case FilterKind::Group:
        case FilterKind::Id: pass = test_filter(m, a, f) || test_filter(m, b, f); break;
        case FilterKind::AnyOf:
            pass = false;
            for (const Range& r : f.any_of) pass = pass || r.contains_contact(m, point, a, b);
            break;
        default: pass = test_point_filter(point, f); break;
        }
        if (pass == f.negate) return false;
    }
    return true;
}

bool Range::contains_point(const Model& m, const Vec3& point, int b) const {
    for (const Filter& f : filters) {
        bool pass;
        switch (f.kind) {
        case FilterKind::Region:
        case FilterKind::Group:
        case FilterKind::Id: pass = test_filter(m, b, f); break;
        case FilterKind::AnyOf:
            pass = false;
            for (const Range& r : f.any_of) pass = pass || r.contains_point(m, point, b);
            break;
        default: pass = test_point_filter(point, f); break;
        }
        if (pass == f.negate) return false;
    }
    return true;
}

std::vector<int> select_blocks(const Model& m, const Range& r, bool include_excavated) {
    std::vector<int> out;
    for (int b = 0; b < m.blocks.size(); ++b) {
        if (!include_excavated && (m.blocks.flags[b] & kExcavated)) continue;
        if (r.contains_block(m, b)) out.push_back(b);
    }
    return out;
}

} // namespace odec
