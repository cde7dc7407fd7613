// The common plane for each contact type, and its continuity.
#include <gtest/gtest.h>

#include <cmath>

#include "contact_test_util.h"
#include "engine/range.h"

using namespace odec;
using namespace odec::test;

namespace {

Polyhedron cube(double x, double y, double z, double a = 1) { return make_brick(x, x + a, y, y + a, z, z + a); }

// A unit cube standing on one vertex: rotated so its body diagonal points along `up`,
// that vertex at `tip`.
Polyhedron cube_on_vertex(const Vec3& tip, const Vec3& up = Vec3::UnitZ()) {
    Polyhedron p = cube(-0.5, -0.5, -0.5);
    const Vec3 diag = Vec3(1, 1, 1).normalized();
    const Mat3 r = Eigen::Quaterniond::FromTwoVectors(diag, up.normalized()).toRotationMatrix();
    for (Vec3& v : p.vertices) v = r * v;
    p.translate(tip - r * Vec3(-0.5, -0.5, -0.5));
    return p;
}

} // namespace

TEST(ContactPlane, FaceFaceGapAndOverlap) {
    const Polyhedron a = cube(0, 0, 0);
    for (double g : {0.05, 0.0, -0.01}) {
        const CommonPlane cp = find_common_plane(a, cube(0.3, 0.2, 1 + g), nullptr);
        EXPECT_NEAR(cp.gap, g, 1e-12);
        EXPECT_NEAR(cp.normal.z(), 1.0, 1e-12);
        EXPECT_NEAR(cp.point.z(), 1 + 0.5 * g, 1e-12);
    }
}

TEST(ContactPlane, VertexFace) {
    const Polyhedron base = make_brick(-2, 2, -2, 2, -1, 0);
    for (double g : {0.02, -0.005}) {
        const CommonPlane cp = find_common_plane(base, cube_on_vertex(Vec3(0.1, 0.2, g)), nullptr);
        EXPECT_NEAR(cp.normal.z(), 1.0, 1e-9) << g;
        EXPECT_NEAR(cp.gap, g, 1e-9);
    }
}

TEST(ContactPlane, EdgeEdge) {
    // Two long bars crossing at right angles, one edge of each facing the other: the
    // normal is the cross product of the edges (vertical here), the gap their distance.
    const Vec3 x = Vec3::UnitX();
    const Polyhedron lower = rotated(make_brick(-3, 3, -0.5, 0.5, -0.5, 0.5), Vec3::Zero(), x, M_PI / 4);
    const double top = std::sqrt(0.5);
    for (double g : {0.03, -0.004}) {
        Polyhedron upper = rotated(make_brick(-0.5, 0.5, -3, 3, -0.5, 0.5), Vec3::Zero(), Vec3::UnitY(), M_PI / 4);
        upper.translate(Vec3(0, 0, 2 * top + g));
        const CommonPlane cp = find_common_plane(lower, upper, nullptr);
        EXPECT_NEAR(cp.normal.z(), 1.0, 1e-9);
        EXPECT_NEAR(cp.gap, g, 1e-9);
        EXPECT_NEAR(cp.point.z(), top + 0.5 * g, 1e-9);
    }
}

TEST(ContactPlane, EdgeFaceAndVertexVertexApart) {
    // A cube lying on an edge above a face: normal up, gap to the edge.
    const Polyhedron base = make_brick(-2, 2, -2, 2, -1, 0);
    Polyhedron edge = rotated(cube(-0.5, -0.5, -0.5), Vec3::Zero(), Vec3::UnitX(), M_PI / 4);
    edge.translate(Vec3(0, 0, std::sqrt(0.5) + 0.01));
    const CommonPlane ef = find_common_plane(base, edge, nullptr);
    EXPECT_NEAR(ef.normal.z(), 1.0, 1e-9);
    EXPECT_NEAR(ef.gap, 0.01, 1e-9);
    // Two cubes corner to corner along the diagonal: the plane is normal to the line
    // joining the corners, the gap is their distance.
    const Polyhedron c1 = cube(0, 0, 0);
    const double d = 0.02;
    const Polyhedron c2 = cube(1 + d, 1 + d, 1 + d);
    const CommonPlane vv = find_common_plane(c1, c2, nullptr);
    EXPECT_NEAR(vv.normal.dot(Vec3(1, 1, 1).normalized()), 1.0, 1e-9);
    EXPECT_NEAR(vv.gap, d * std::sqrt(3.0), 1e-9);
}

TEST(ContactPlane, NormalTurnsSmoothlyOverAnEdge) {
    // A vertex passes over the edge of a block at a constant small clearance: the normal
    // must swing from the top face's normal to the side face's without a jump.
    const Polyhedron base = make_brick(-2, 0, -1, 1, -1, 0);
    const double clearance = 0.01;
    Vec3 prev_n = Vec3::Zero();
    double largest_turn = 0;
    Vec3 warm = Vec3::UnitZ();
    const int n = 400;
    for (int i = 0; i <= n; ++i) {
        const double t = -0.5 * M_PI * i / n; // walk round the edge on a circle
        const Vec3 radial(std::sin(-t), 0, std::cos(t));
        const CommonPlane cp = find_common_plane(base, cube_on_vertex(clearance * radial, radial), &warm, 0.05);
        warm = cp.normal;
        EXPECT_NEAR(cp.gap, clearance, 1e-9) << i;
        if (i > 0) largest_turn = std::max(largest_turn, std::acos(std::min(1.0, prev_n.dot(cp.normal))));
        prev_n = cp.normal;
    }
    EXPECT_NEAR(prev_n.x(), 1.0, 1e-6);
    // 90 degrees over 400 steps: no step may turn much more than its share.
    EXPECT_LT(largest_turn, 3 * (0.5 * M_PI / n));
}

TEST(ContactPlane, AreaChangesSmoothlyOverAnEdge) {
    // A block slides off the edge of another: the contact area falls linearly, without
    // jumps, and the forces stay inside the shrinking contact.
    Model m;
    set_material(m, 1, 2000);
    set_joint(m, 1, 1e7, 1e7, 30);
    add_fixed(m, make_brick(-3, 0, -1, 1, -1, 0));
    const int b = add_block(m, cube(-1, -0.5, -0.001), 0, -1, 1);
    double prev_area = 0;
    for (int i = 0; i <= 18; ++i) {
        m.blocks.centroid[b] = Vec3(-0.5 + 0.05 * i, 0, 0.499);
        m.geometry_changed = true;
        refresh_world_vertices(m);
        detect_contacts(m);
        ASSERT_EQ(m.contacts.size(), 1);
        const ContactInfo info = contact_info(m, 0);
        EXPECT_NEAR(info.area, 1.0 - 0.05 * i, 1e-9) << i;
        EXPECT_NEAR(info.normal.z(), 1.0, 1e-12);
        EXPECT_LE(info.centroid.x(), 1e-12);
        if (i > 0) {
            EXPECT_NEAR(prev_area - info.area, 0.05, 1e-9);
        }
        prev_area = info.area;
    }
}

TEST(ContactPlane, JoinAndAssignMaterial) {
    Model m;
    set_material(m, 1, 2000);
    set_joint(m, 1, 1e7, 1e7, 30);
    set_joint(m, 2, 1e8, 1e8, 10);
    add_fixed(m, make_brick(-1, 2, -1, 2, -1, 0));
    add_block(m, cube(0, 0, 0), 0, -1, 1);
    add_block(m, cube(0, 0, 1), 0, -1, 1);
    Range r;
    Filter f;
    f.kind = FilterKind::Z;
    f.lo = 0.5;
    f.hi = 1.5;
    r.filters.push_back(f);
    EXPECT_EQ(assign_joint_material(m, r, 2, 2), 1);
    const int upper = contact_between(m, 1, 2);
    EXPECT_EQ(m.contacts.jmat(upper), 2);
    EXPECT_EQ(m.contacts.jcons(upper), 2);
    EXPECT_EQ(m.contacts.jmat(contact_between(m, 0, 1)), 1);
    EXPECT_EQ(join_blocks(m, {1, 2}), 1);
    EXPECT_TRUE(m.contacts.joined(upper));
    EXPECT_EQ(find_contact_at(m, Vec3(0.5, 0.5, 1.1)), upper);
    // Joined: the upper block hangs from the lower one when gravity turns upward.
    m.gravity = Vec3(0, 0, 10);
    m.joint_materials[1].friction = 0;
    run_steps(m, 2000);
    EXPECT_LT(std::abs(m.blocks.disp[2].z() - m.blocks.disp[1].z()), 1e-2);
    EXPECT_GT(m.blocks.disp[1].z(), 0.1); // the lower one, not glued to the base, lifts off
}

TEST(ContactTimestep, FromStiffestContactAndLightestBlock) {
    Model m;
    set_material(m, 1, 2000);
    set_joint(m, 1, 1e7, 2e7, 30);
    add_fixed(m, make_brick(-1, 2, -1, 2, -1, 0));
    add_block(m, cube(0, 0, 0), 0, -1, 1);
    // Before detection: estimated from the stiffest joint and the largest face (3 x 3 m).
    EXPECT_NEAR(contact_critical_timestep(m), 0.1 * 2 * std::sqrt(2000 / (2e7 * 9)), 1e-12);
    ASSERT_EQ(prepare_cycle(m), "");
    EXPECT_NEAR(m.dt, 0.1 * 2 * std::sqrt(2000 / 2e7), 1e-12);
}
