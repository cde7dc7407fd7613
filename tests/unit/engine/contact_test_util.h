// Small builders shared by the contact tests: models made straight through the engine API.
#pragma once

#include <cmath>

#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/cycle.h"
#include "engine/model.h"

namespace odec::test {

inline void set_material(Model& m, int n, double density) {
    if (static_cast<int>(m.materials.size()) <= n) m.materials.resize(n + 1);
    m.materials[n].defined = true;
    m.materials[n].density = density;
}

inline JointMaterial& set_joint(Model& m, int n, double kn, double ks, double friction) {
    if (static_cast<int>(m.joint_materials.size()) <= n) m.joint_materials.resize(n + 1);
    JointMaterial& j = m.joint_materials[n];
    j = JointMaterial{};
    j.defined = true;
    j.kn = kn;
    j.ks = ks;
    j.friction = friction;
    return j;
}

// Rotate every vertex of p about the point o by `angle` (rad) around `axis`.
inline Polyhedron rotated(Polyhedron p, const Vec3& o, const Vec3& axis, double angle) {
    const Mat3 r = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
    for (Vec3& v : p.vertices) v = o + r * (v - o);
    return p;
}

inline int add_fixed(Model& m, const Polyhedron& p) {
    const int b = add_block(m, p, 0, -1, 1);
    m.blocks.flags[b] |= kFixed;
    return b;
}

// Index of the contact between blocks a and b, or -1.
inline int contact_between(const Model& m, int a, int b) {
    if (a > b) std::swap(a, b);
    for (int c = 0; c < m.contacts.size(); ++c) {
        if (m.contacts.block_a[c] == a && m.contacts.block_b[c] == b) return c;
    }
    return -1;
}

inline CycleResult run_steps(Model& m, long n) {
    CycleLimits lim;
    lim.max_steps = n;
    return cycle(m, lim);
}

inline CycleResult run_time(Model& m, double t) {
    CycleLimits lim;
    lim.max_time = t;
    return cycle(m, lim);
}

} // namespace odec::test
