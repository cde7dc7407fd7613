#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/jset.h"

using namespace odec;

namespace {

double total_volume(const Model& m) {
    double v = 0;
    for (int b = 0; b < m.blocks.size(); ++b) v += m.blocks.volume[b];
    return v;
}

Model ten_metre_cube() {
    Model m;
    m.materials.resize(2);
    m.materials[1].defined = true;
    m.materials[1].density = 2500;
    add_block(m, make_brick(0, 10, 0, 10, 0, 10), 1, -1, 1);
    return m;
}

// Faces of block b (world) carrying joint tag `tag`.
std::vector<int> tagged_faces(const Model& m, int b, int tag) {
    std::vector<int> out;
    const Polyhedron& s = m.blocks.shape[b];
    for (int f = 0; f < static_cast<int>(s.face_joint.size()); ++f) {
        if (s.face_joint[f] == tag) out.push_back(f);
    }
    return out;
}

} // namespace

TEST(PlaneNormal, DipAndDipDirection) {
    EXPECT_EQ(plane_normal(90, 90), Vec3(1, 0, 0));  // exactly: x = const
    EXPECT_EQ(plane_normal(90, 0), Vec3(0, 1, 0));   // y = const
    EXPECT_EQ(plane_normal(0, 123), Vec3(0, 0, 1));  // horizontal
    const Vec3 n = plane_normal(30, 0);
    EXPECT_NEAR((n - Vec3(0, 0.5, std::sqrt(3.0) / 2)).norm(), 0.0, 1e-15);
    // Dipping toward the east: the upward normal leans east.
    EXPECT_GT(plane_normal(45, 90).x(), 0.7);
}

TEST(JointSet, NumberAndSpacingOnATenMetreCube) {
    Model m = ten_metre_cube();
    JointSetSpec h;
    h.dip = 0;
    h.origin = Vec3(5, 5, 5);
    h.spacing = 2;
    h.number = 3; // z = 3, 5, 7
    const CutReport r1 = cut_joint_set(m, h, Range{}, 1e-3);
    EXPECT_EQ(r1.planes, 3);
    EXPECT_EQ(r1.blocks_cut, 3);
    EXPECT_EQ(m.blocks.size(), 4);
    JointSetSpec v;
    v.dip = 90;
    v.dd = 90;
    v.origin = Vec3(5, 5, 5);
    v.spacing = 2.5;
    v.number = 4; // x = 1.25, 3.75, 6.25, 8.75
    const CutReport r2 = cut_joint_set(m, v, Range{}, 1e-3);
    EXPECT_EQ(r2.blocks_cut, 16);
    EXPECT_EQ(m.blocks.size(), 20);
    EXPECT_NEAR(total_volume(m), 1000.0, 1e-9);
    EXPECT_EQ(m.n_joint_sets, 2);
    ASSERT_EQ(m.joint_planes.size(), 7u);
    EXPECT_EQ(m.joint_planes[2].set, 1);
    EXPECT_EQ(m.joint_planes[3].set, 2);
    EXPECT_TRUE(m.geometry_changed);
    // Ids stay unique and in index order; mass follows density.
    for (int b = 0; b < m.blocks.size(); ++b) {
        EXPECT_EQ(m.blocks.id[b], b + 1);
        EXPECT_NEAR(m.blocks.mass[b], 2500 * m.blocks.volume[b], 1e-6);
        EXPECT_EQ(m.blocks.region[b], 1);
        EXPECT_EQ(m.blocks.material[b], 1);
        EXPECT_EQ(m.blocks.shape[b].face_joint.size(), static_cast<size_t>(m.blocks.shape[b].n_faces()));
        std::string why;
        EXPECT_TRUE(is_convex_polyhedron(m.blocks.shape[b], 1e-9, &why)) << why;
        EXPECT_LT(m.blocks.shape[b].vertices.size(), 9u);
    }
    // Slab thicknesses in z are 3, 2, 2, 3 and in x 1.25, 2.5, 2.5, 2.5, 1.25.
    std::multiset<long> vols;
    for (int b = 0; b < m.blocks.size(); ++b) vols.insert(std::lround(m.blocks.volume[b] * 1000));
    EXPECT_EQ(vols.count(std::lround(1.25 * 3 * 10 * 1000)), 4u);
    EXPECT_EQ(vols.count(std::lround(2.5 * 2 * 10 * 1000)), 6u);
}

TEST(JointSet, VerticalEastDippingPlaneIsXConstant) {
    Model m = ten_metre_cube();
    JointSetSpec s;
    s.dip = 90;
    s.dd = 90;
    s.origin = Vec3(4, 0, 0);
    cut_joint_set(m, s, Range{}, 1e-3);
    ASSERT_EQ(m.blocks.size(), 2);
    // Block 1 (kept index) is the part below the plane, i.e. x < 4 (normal +x).
    EXPECT_NEAR(m.blocks.volume[0], 400.0, 1e-9);
    EXPECT_NEAR(m.blocks.centroid[0].x(), 2.0, 1e-12);
    EXPECT_NEAR(m.blocks.centroid[1].x(), 7.0, 1e-12);
    for (int b = 0; b < 2; ++b) {
        const std::vector<int> caps = tagged_faces(m, b, 1);
        ASSERT_EQ(caps.size(), 1u);
        const Polyhedron w = world_shape(m, b);
        for (int k = 0; k < w.face_size(caps[0]); ++k) EXPECT_EQ(w.vertices[w.face_vertex(caps[0], k)].x(), 4.0);
        EXPECT_NEAR(std::abs(w.face_normal(caps[0]).x()), 1.0, 1e-15);
    }
}

TEST(JointSet, PersistenceIsDeterministicAndSeedDependent) {
    auto run = [](std::uint64_t seed) {
        Model m = ten_metre_cube();
        JointSetSpec cols;
        cols.dip = 90;
        cols.dd = 90;
        cols.origin = Vec3(5, 5, 5);
        cols.spacing = 1;
        cols.number = 9; // ten slabs
        cut_joint_set(m, cols, Range{}, 1e-3);
        JointSetSpec p;
        p.origin = Vec3(5, 5, 5);
        p.spacing = 1.5;
        p.number = 5;
        p.persistence = 0.5;
        p.seed = seed;
        cut_joint_set(m, p, Range{}, 1e-3);
        return m;
    };
    const Model a = run(42), b = run(42), c = run(43);
    ASSERT_EQ(a.blocks.size(), b.blocks.size());
    for (int i = 0; i < a.blocks.size(); ++i) {
        EXPECT_EQ(a.blocks.centroid[i], b.blocks.centroid[i]);
        EXPECT_EQ(a.blocks.volume[i], b.blocks.volume[i]);
    }
    // Some but not all of the 50 crossings cut.
    EXPECT_GT(a.blocks.size(), 10 + 5);
    EXPECT_LT(a.blocks.size(), 10 + 50);
    EXPECT_NEAR(total_volume(a), 1000.0, 1e-9);
    bool differ = a.blocks.size() != c.blocks.size();
    for (int i = 0; !differ && i < a.blocks.size(); ++i) differ = a.blocks.centroid[i] != c.blocks.centroid[i];
    EXPECT_TRUE(differ);
}

TEST(JointSet, HiddenAndExcavatedBlocksStayWhole) {
    Model m;
    add_block(m, make_brick(0, 1, 0, 1, 0, 1), 1, -1, 0);
    add_block(m, make_brick(1, 2, 0, 1, 0, 1), 1, -1, 0);
    add_block(m, make_brick(2, 3, 0, 1, 0, 1), 1, -1, 0);
    m.blocks.flags[0] |= kHidden;
    m.blocks.flags[2] |= kExcavated;
    const Polyhedron before = m.blocks.shape[0];
    JointSetSpec s;
    s.origin = Vec3(0, 0, 0.5);
    const CutReport r = cut_joint_set(m, s, Range{}, 1e-3);
    EXPECT_EQ(r.blocks_cut, 1);
    ASSERT_EQ(m.blocks.size(), 4);
    EXPECT_EQ(m.blocks.volume[0], 1.0);
    EXPECT_EQ(m.blocks.shape[0].vertices, before.vertices);
    EXPECT_EQ(m.blocks.volume[2], 1.0);
    EXPECT_NEAR(m.blocks.volume[1], 0.5, 1e-14);
    EXPECT_NEAR(m.blocks.volume[3], 0.5, 1e-14);
    EXPECT_EQ(m.blocks.id[3], 4);
}

TEST(JointSet, RangeLimitsTheCut) {
    Model m;
    add_block(m, make_brick(0, 1, 0, 1, 0, 1), 1, -1, 0);
    add_block(m, make_brick(1, 2, 0, 1, 0, 1), 2, -1, 0);
    Range r;
    Filter f;
    f.kind = FilterKind::Region;
    f.lo = 2;
    r.filters.push_back(f);
    JointSetSpec s;
    s.origin = Vec3(0, 0, 0.5);
    EXPECT_EQ(cut_joint_set(m, s, r, 1e-3).blocks_cut, 1);
    ASSERT_EQ(m.blocks.size(), 3);
    EXPECT_EQ(m.blocks.volume[0], 1.0);
    EXPECT_EQ(m.blocks.region[2], 2);
}

TEST(JointSet, SliversAreSkippedAndCounted) {
    Model m = ten_metre_cube();
    JointSetSpec s;
    s.origin = Vec3(0, 0, 9.995); // 5 mm below the top
    s.join = true;
    const CutReport r = cut_joint_set(m, s, Range{}, 0.01);
    EXPECT_EQ(r.blocks_cut, 0);
    EXPECT_EQ(r.slivers_skipped, 1);
    EXPECT_EQ(m.slivers_skipped, 1);
    EXPECT_EQ(m.blocks.size(), 1);
    ASSERT_EQ(m.joint_planes.size(), 1u);
    EXPECT_TRUE(m.joint_planes[0].joined);
    // A plane along a face is no sliver, and no cut.
    s.origin = Vec3(0, 0, 10);
    const CutReport r2 = cut_joint_set(m, s, Range{}, 0.01);
    EXPECT_EQ(r2.slivers_skipped, 0);
    EXPECT_EQ(m.slivers_skipped, 1);
    EXPECT_EQ(m.blocks.size(), 1);
    // With a finer tolerance the 5 mm slab is cut off.
    s.origin = Vec3(0, 0, 9.995);
    EXPECT_EQ(cut_joint_set(m, s, Range{}, 1e-3).blocks_cut, 1);
    EXPECT_EQ(m.blocks.size(), 2);
}

TEST(JointSet, RotatedSpinningBlockIsCutInTheWorldFrame) {
    Model m;
    add_block(m, make_brick(-2, 2, -1, 1, -1, 1), 1, -1, 0);
    // Turn it a quarter turn about z: it now spans x in [-1, 1], y in [-2, 2].
    m.blocks.orientation[0] = Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()));
    m.blocks.ang_vel[0] = Vec3(0, 0, 1);
    m.blocks.vel[0] = Vec3(3, 0, 0);
    m.blocks.disp[0] = Vec3(0.1, 0.2, 0.3);
    m.blocks.flags[0] |= kFixed;
    // The displacement since 'reset disp' of two material points (the block was made unturned).
    const Vec3 points[2] = {Vec3(-0.5, -1.5, -0.5), Vec3(0.5, 1.5, 0.5)};
    Vec3 moved[2];
    for (int k = 0; k < 2; ++k) {
        moved[k] = point_displacement(m, 0, m.blocks.orientation[0].conjugate() * (points[k] - m.blocks.centroid[0]));
    }
    JointSetSpec s;
    s.dip = 90;
    s.dd = 0; // y = const
    s.origin = Vec3(0, 1, 0);
    ASSERT_EQ(cut_joint_set(m, s, Range{}, 1e-3).blocks_cut, 1);
    ASSERT_EQ(m.blocks.size(), 2);
    EXPECT_NEAR(m.blocks.volume[0], 12.0, 1e-12); // y in [-2, 1]
    EXPECT_NEAR(m.blocks.volume[1], 4.0, 1e-12);  // y in [1, 2]
    for (int b = 0; b < 2; ++b) {
        EXPECT_TRUE(m.blocks.orientation[b].isApprox(Quat::Identity()));
        Vec3 lo, hi;
        world_shape(m, b).bounds(lo, hi);
        EXPECT_NEAR(lo.x(), -1.0, 1e-12);
        EXPECT_NEAR(hi.x(), 1.0, 1e-12);
        // Each piece's centroid is displaced as the block's material point there: it was where
        // the quarter turn back takes it (about the block's centroid, at the origin).
        const Vec3 c = m.blocks.centroid[b];
        const Vec3 was = Eigen::AngleAxisd(-M_PI / 2, Vec3::UnitZ()) * c - Vec3(0.1, 0.2, 0.3);
        EXPECT_NEAR((m.blocks.disp[b] - (c - was)).norm(), 0.0, 1e-15);
        // And every material point keeps its displacement (points[b] is in piece b).
        EXPECT_NEAR((point_displacement(m, b, points[b] - c) - moved[b]).norm(), 0.0, 1e-15);
        EXPECT_TRUE(m.blocks.flags[b] & kFixed);
        // Rigid motion carried over: v = v0 + w x (c - c0).
        const Vec3 expect = Vec3(3, 0, 0) + Vec3(0, 0, 1).cross(m.blocks.centroid[b]);
        EXPECT_NEAR((m.blocks.vel[b] - expect).norm(), 0.0, 1e-12);
    }
    EXPECT_NEAR(m.blocks.centroid[0].y(), -0.5, 1e-12);
    EXPECT_NEAR(m.blocks.centroid[1].y(), 1.5, 1e-12);
}

TEST(JointSet, FarFromTheOriginKeepsItsDigits) {
    // A block at survey coordinates: the cut is made about the centroid, so the pieces'
    // volumes still add up to round-off of the block's size, not of its position.
    Model m;
    const Vec3 o(3.2e6, 5.7e6, 120);
    add_block(m, make_brick(-3, 4, -2, 5, -1, 2), 1, -1, 0);
    m.blocks.centroid[0] += o;
    JointSetSpec s;
    s.dip = 37;
    s.dd = 211;
    s.origin = o + Vec3(0.3, 0.2, 0.1);
    s.spacing = 0.7;
    s.number = 7;
    const CutReport r = cut_joint_set(m, s, Range{}, 1e-3);
    EXPECT_EQ(r.blocks_cut, 7);
    EXPECT_LT(std::abs(total_volume(m) - 147.0) / 147.0, 1e-13);
    Vec3 first = Vec3::Zero();
    for (int b = 0; b < m.blocks.size(); ++b) first += m.blocks.volume[b] * (m.blocks.centroid[b] - o);
    EXPECT_NEAR((first / 147.0 - Vec3(0.5, 1.5, 0.5)).norm(), 0.0, 1e-9);
}

// Blocks that meet only along an edge are glued when every face through that edge lies on a
// joined joint, as where two joined joint sets cross; not when one of the sets is free.
TEST(JointSet, EdgeContactsAcrossJoinedCutsAreJoined) {
    for (const bool second_joined : {true, false}) {
        SCOPED_TRACE(second_joined);
        Model m;
        add_block(m, make_brick(0, 2, 0, 1, 0, 2), 0, -1, 1);
        JointSetSpec vertical;
        vertical.dip = 90;
        vertical.dd = 90;
        vertical.origin = Vec3(1, 0, 0);
        vertical.join = true;
        JointSetSpec horizontal;
        horizontal.origin = Vec3(0, 0, 1);
        horizontal.join = second_joined;
        cut_joint_set(m, vertical, Range{}, 1e-6);
        cut_joint_set(m, horizontal, Range{}, 1e-6);
        ASSERT_EQ(m.blocks.size(), 4);
        refresh_world_vertices(m);
        detect_contacts(m);
        int diagonal = 0, joined = 0;
        for (int c = 0; c < m.contacts.size(); ++c) {
            const Vec3 d = m.blocks.centroid[m.contacts.block_a[c]] - m.blocks.centroid[m.contacts.block_b[c]];
            const bool edge = std::abs(d.x()) > 0.5 && std::abs(d.z()) > 0.5;
            diagonal += edge;
            if (edge) {
                EXPECT_EQ(m.contacts.joined(c), second_joined);
            }
            joined += m.contacts.joined(c);
        }
        EXPECT_EQ(diagonal, 2);
        // Two face contacts across the vertical plane; two more across the horizontal one and
        // the two along the edge where the planes cross, when that one is joined too.
        EXPECT_EQ(joined, second_joined ? 6 : 2);
    }
}
