#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "engine/polyhedron.h"

using namespace odec;

namespace {

std::vector<Vec3> reversed(std::vector<Vec3> v) {
    std::reverse(v.begin(), v.end());
    return v;
}

// Unit cube faces as loops, in mixed windings.
std::vector<std::vector<Vec3>> cube_faces() {
    return {
        {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}},  // bottom, wound inward
        {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},  // top
        {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}},  // y = 0
        {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}},  // y = 1
        {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}},  // x = 0
        {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}},  // x = 1
    };
}

double max_abs(const Mat3& m) { return m.cwiseAbs().maxCoeff(); }

} // namespace

TEST(MakeFromFaces, TetrahedronMassPropertiesMatchClosedForm) {
    // Right-corner tetrahedron with legs a=2, b=3, c=4 along the axes, moved off the origin.
    const Vec3 o(10, -5, 3);
    const Vec3 p0 = o, p1 = o + Vec3(2, 0, 0), p2 = o + Vec3(0, 3, 0), p3 = o + Vec3(0, 0, 4);
    const std::vector<std::vector<Vec3>> faces{{p0, p1, p2}, {p0, p1, p3}, {p3, p2, p0}, {p1, p2, p3}};
    Polyhedron p;
    std::string err;
    ASSERT_TRUE(make_from_faces(faces, 1e-9, p, err)) << err;
    EXPECT_EQ(p.n_vertices(), 4);
    EXPECT_EQ(p.n_faces(), 4);
    EXPECT_TRUE(is_convex_polyhedron(p, 1e-9));
    const MassProperties mp = mass_properties(p);
    EXPECT_NEAR(mp.volume, 4.0, 1e-12);
    EXPECT_NEAR((mp.centroid - (o + Vec3(0.5, 0.75, 1.0))).norm(), 0.0, 1e-12);
    // I_xx = 3V(b^2+c^2)/80, products of inertia V a b / 80 (tensor entry -(-Vab/80)).
    Mat3 expect;
    expect << 3.75, 0.3, 0.4,
              0.3, 3.0, 0.6,
              0.4, 0.6, 1.95;
    EXPECT_LT(max_abs(mp.inertia - expect), 1e-11);
}

TEST(MakeFromFaces, TriangularPrismMassPropertiesMatchClosedForm) {
    // Right triangle legs 3 (x) and 4 (y), height 2 (z); faces in mixed windings.
    const Vec3 a0(0, 0, 0), a1(3, 0, 0), a2(0, 4, 0);
    const Vec3 h(0, 0, 2);
    const std::vector<std::vector<Vec3>> faces{
        {a0, a1, a2}, {a0 + h, a2 + h, a1 + h}, {a0, a1, a1 + h, a0 + h},
        reversed({a1, a2, a2 + h, a1 + h}), {a2, a0, a0 + h, a2 + h}};
    Polyhedron p;
    std::string err;
    ASSERT_TRUE(make_from_faces(faces, 1e-9, p, err)) << err;
    EXPECT_EQ(p.n_vertices(), 6);
    EXPECT_EQ(p.n_faces(), 5);
    const MassProperties mp = mass_properties(p);
    EXPECT_NEAR(mp.volume, 12.0, 1e-12);
    EXPECT_NEAR((mp.centroid - Vec3(1.0, 4.0 / 3.0, 1.0)).norm(), 0.0, 1e-12);
    // Second moments about the centroid: triangle var x = a^2/18, var y = b^2/18,
    // cov = -ab/36 (times area and height), z: A h^3 / 12.
    Mat3 expect;
    expect << 32.0 / 3.0 + 4.0, 4.0, 0.0,
              4.0, 6.0 + 4.0, 0.0,
              0.0, 0.0, 6.0 + 32.0 / 3.0;
    EXPECT_LT(max_abs(mp.inertia - expect), 1e-11);
}

TEST(MakeFromFaces, FacesComeOutCounterClockwiseFromOutside) {
    Polyhedron p;
    std::string err;
    ASSERT_TRUE(make_from_faces(cube_faces(), 1e-9, p, err)) << err;
    EXPECT_EQ(p.n_vertices(), 8);
    EXPECT_TRUE(p.face_joint.empty());
    const Vec3 c(0.5, 0.5, 0.5);
    for (int f = 0; f < p.n_faces(); ++f) {
        EXPECT_GT(p.face_normal(f).dot(p.vertices[p.face_vertex(f, 0)] - c), 0.4) << "face " << f;
    }
    EXPECT_NEAR(mass_properties(p).volume, 1.0, 1e-14);
}

TEST(MakeFromFaces, HealsPointOnAnEdgeOfOneFace) {
    // The top face lists the midpoint of an edge that the side face y=0 does not.
    auto faces = cube_faces();
    faces[1] = {{0, 0, 1}, {0.5, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    Polyhedron p;
    std::string err;
    ASSERT_TRUE(make_from_faces(faces, 1e-9, p, err)) << err;
    EXPECT_EQ(p.n_vertices(), 8);
    EXPECT_NEAR(mass_properties(p).volume, 1.0, 1e-14);
}

TEST(MakeFromFaces, RejectsNonPlanarFaceByIndex) {
    auto faces = cube_faces();
    faces[1][2] = Vec3(1, 1, 1.2);
    Polyhedron p;
    std::string err;
    EXPECT_FALSE(make_from_faces(faces, 1e-9, p, err));
    EXPECT_EQ(err, "face 2 is not planar");
    EXPECT_EQ(p.n_faces(), 0); // untouched
}

TEST(MakeFromFaces, RejectsNonConvexSolidByIndex) {
    // Unit cube whose top is a pyramid pushed inward to (0.5, 0.5, 0.5).
    auto faces = cube_faces();
    const Vec3 apex(0.5, 0.5, 0.5);
    faces.erase(faces.begin() + 1);
    faces.push_back({{0, 0, 1}, {1, 0, 1}, apex});
    faces.push_back({{1, 0, 1}, {1, 1, 1}, apex});
    faces.push_back({{1, 1, 1}, {0, 1, 1}, apex});
    faces.push_back({{0, 1, 1}, {0, 0, 1}, apex});
    Polyhedron p;
    std::string err;
    EXPECT_FALSE(make_from_faces(faces, 1e-9, p, err));
    EXPECT_EQ(err, "face 6 has vertices on both sides of its plane: the solid is not convex");
}

TEST(MakeFromFaces, RejectsNonConvexFaceByIndex) {
    // An L-shaped prism: its end faces are non-convex polygons.
    const std::vector<Vec3> l{{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
    std::vector<std::vector<Vec3>> faces{l};
    std::vector<Vec3> top;
    for (const Vec3& v : l) top.push_back(v + Vec3(0, 0, 1));
    faces.push_back(top);
    for (size_t i = 0; i < l.size(); ++i) {
        const size_t j = (i + 1) % l.size();
        faces.push_back({l[i], l[j], top[j], top[i]});
    }
    Polyhedron p;
    std::string err;
    EXPECT_FALSE(make_from_faces(faces, 1e-9, p, err));
    EXPECT_NE(err.find("not convex"), std::string::npos) << err;
    EXPECT_EQ(err.rfind("face ", 0), 0u) << err;
}

TEST(MakeFromFaces, RejectsOpenSolid) {
    auto faces = cube_faces();
    faces.pop_back(); // no x = 1 face
    Polyhedron p;
    std::string err;
    EXPECT_FALSE(make_from_faces(faces, 1e-9, p, err));
    EXPECT_NE(err.find("has an edge that no other face shares: the solid is not closed"), std::string::npos) << err;
    EXPECT_EQ(err.rfind("face ", 0), 0u) << err;
}

TEST(MakeFromFaces, RejectsTooFewFacesAndFlatSolids) {
    Polyhedron p;
    std::string err;
    auto faces = cube_faces();
    faces.resize(3);
    EXPECT_FALSE(make_from_faces(faces, 1e-9, p, err));
    EXPECT_EQ(err, "a closed solid needs at least 4 faces (got 3)");
    // Four triangles all in the plane z = 0.
    const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0), d(1, 1, 0);
    EXPECT_FALSE(make_from_faces({{a, b, c}, {a, b, d}, {a, c, d}, {b, c, d}}, 1e-9, p, err));
    EXPECT_NE(err.find("no volume"), std::string::npos) << err;
}

TEST(MakeTetra, VolumeAndFlatRejection) {
    Polyhedron p;
    std::string err;
    ASSERT_TRUE(make_tetra({0, 0, 0}, {0, 0, 6}, {0, 1, 0}, {1, 0, 0}, 1e-9, p, err)) << err;
    EXPECT_NEAR(mass_properties(p).volume, 1.0, 1e-14);
    EXPECT_TRUE(is_convex_polyhedron(p, 1e-9));
    EXPECT_FALSE(make_tetra({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, 1e-9, p, err));
    EXPECT_EQ(err.rfind("tetra: ", 0), 0u) << err;
}

TEST(MakePrism, TranslatedCopyListedFromAnotherVertexBackwards) {
    const std::vector<Vec3> a{{0, 0, 0}, {4, 0, 0}, {4, 1, 0}, {0, 3, 0}};
    const Vec3 t(0.5, 0.25, 2); // oblique
    const std::vector<Vec3> b{a[2] + t, a[1] + t, a[0] + t, a[3] + t};
    Polyhedron p;
    std::string err;
    ASSERT_TRUE(make_prism(a, b, 1e-9, p, err)) << err;
    EXPECT_EQ(p.n_faces(), 6);
    EXPECT_EQ(p.n_vertices(), 8);
    // Base area 4*1 + 4*2/2 = 8 (trapezoid 4 wide, 1 and 3 high), height 2.
    EXPECT_NEAR(mass_properties(p).volume, 16.0, 1e-12);
    EXPECT_TRUE(is_convex_polyhedron(p, 1e-9));
}

TEST(MakePrism, RejectsFrustumAndMismatchedCounts) {
    const std::vector<Vec3> a{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
    const std::vector<Vec3> b{{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
    Polyhedron p;
    std::string err;
    EXPECT_FALSE(make_prism(a, b, 1e-9, p, err));
    EXPECT_EQ(err, "prism: polygon b is not a translated copy of polygon a");
    EXPECT_FALSE(make_prism(a, {{0, 0, 1}, {1, 0, 1}}, 1e-9, p, err));
    EXPECT_EQ(err, "prism: polygons a and b have different numbers of vertices (3 and 2)");
}

TEST(ConvexHull, CubeCornersWithInteriorAndBoundaryPointsGiveSixQuads) {
    std::vector<Vec3> pts;
    // Interior and on-face/on-edge points first, so they are seen before the corners.
    std::uint64_t x = 12345;
    auto next = [&]() {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        return static_cast<double>(x % 1000000) / 1000000.0;
    };
    for (int i = 0; i < 100; ++i) pts.push_back(Vec3(0.05 + 0.9 * next(), 0.05 + 0.9 * next(), 0.05 + 0.9 * next()));
    pts.push_back({0.5, 0.5, 0});  // face centre
    pts.push_back({0.5, 0, 0});    // edge midpoint
    pts.push_back({1, 0.3, 1});    // on an edge
    pts.push_back({0.2, 1, 0.7});  // on a face
    for (int k = 0; k < 8; ++k) pts.push_back(Vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1));
    Polyhedron p;
    std::string err;
    ASSERT_TRUE(make_convex_hull(pts, 1e-9, p, err)) << err;
    EXPECT_EQ(p.n_faces(), 6);
    EXPECT_EQ(p.n_vertices(), 8);
    for (int f = 0; f < p.n_faces(); ++f) EXPECT_EQ(p.face_size(f), 4) << "face " << f;
    EXPECT_NEAR(mass_properties(p).volume, 1.0, 1e-12);
    EXPECT_TRUE(is_convex_polyhedron(p, 1e-9));
}

TEST(ConvexHull, PointsOnASphere) {
    // 300 points on a Fibonacci sphere: the hull holds them all and approaches the ball.
    std::vector<Vec3> pts;
    const int n = 300;
    const double golden = M_PI * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
        const double z = 1.0 - 2.0 * (i + 0.5) / n;
        const double r = std::sqrt(1.0 - z * z);
        pts.push_back(Vec3(r * std::cos(golden * i), r * std::sin(golden * i), z) * 5.0 + Vec3(100, 200, -50));
    }
    Polyhedron p;
    std::string err;
    ASSERT_TRUE(make_convex_hull(pts, 1e-9, p, err)) << err;
    EXPECT_EQ(p.n_vertices(), n);
    std::string why;
    EXPECT_TRUE(is_convex_polyhedron(p, 1e-8, &why)) << why;
    for (const Vec3& x : pts) EXPECT_TRUE(contains_point(p, x, 1e-8));
    const double ball = 4.0 / 3.0 * M_PI * 125.0;
    const double v = mass_properties(p).volume;
    EXPECT_LT(v, ball);
    EXPECT_GT(v, 0.97 * ball);
}

TEST(ConvexHull, RejectsDegenerateInput) {
    Polyhedron p;
    std::string err;
    EXPECT_FALSE(make_convex_hull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, 1e-9, p, err));
    EXPECT_EQ(err, "a convex hull needs at least 4 points (got 3)");
    EXPECT_FALSE(make_convex_hull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.3, 0.2, 0}}, 1e-9, p, err));
    EXPECT_EQ(err, "the points are coplanar");
    EXPECT_FALSE(make_convex_hull({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}}, 1e-9, p, err));
    EXPECT_EQ(err, "the points are collinear");
}

TEST(SplitByPlane, ObliquePlaneConservesVolumeAndMakesClosedConvexParts) {
    const Polyhedron brick = make_brick(0, 2, 0, 3, 0, 1);
    const Vec3 n = Vec3(1, 2, 3).normalized();
    const double d = n.dot(Vec3(1, 1.5, 0.5)) + 0.1;
    Polyhedron lo, hi;
    SplitOutcome why = SplitOutcome::Missed;
    ASSERT_TRUE(split_by_plane(brick, n, d, 1e-6, 7, lo, hi, &why));
    EXPECT_EQ(why, SplitOutcome::Split);
    const MassProperties m0 = mass_properties(brick), ml = mass_properties(lo), mh = mass_properties(hi);
    EXPECT_LT(std::abs(ml.volume + mh.volume - m0.volume) / m0.volume, 1e-12);
    EXPECT_LT((ml.volume * ml.centroid + mh.volume * mh.centroid - m0.volume * m0.centroid).norm(), 1e-12);
    std::string w1, w2;
    EXPECT_TRUE(is_convex_polyhedron(lo, 1e-12, &w1)) << w1;
    EXPECT_TRUE(is_convex_polyhedron(hi, 1e-12, &w2)) << w2;
    for (const Vec3& v : lo.vertices) EXPECT_LE(n.dot(v) - d, 1e-12);
    for (const Vec3& v : hi.vertices) EXPECT_GE(n.dot(v) - d, -1e-12);
    // The cap is the last face of both, tagged 7, facing out of each part.
    ASSERT_EQ(lo.face_joint.size(), static_cast<size_t>(lo.n_faces()));
    ASSERT_EQ(hi.face_joint.size(), static_cast<size_t>(hi.n_faces()));
    EXPECT_EQ(lo.face_joint.back(), 7);
    EXPECT_EQ(hi.face_joint.back(), 7);
    EXPECT_EQ(std::count(lo.face_joint.begin(), lo.face_joint.end(), 7), 1);
    EXPECT_NEAR((lo.face_normal(lo.n_faces() - 1) - n).norm(), 0.0, 1e-12);
    EXPECT_NEAR((hi.face_normal(hi.n_faces() - 1) + n).norm(), 0.0, 1e-12);
    EXPECT_NEAR(lo.face_area(lo.n_faces() - 1), hi.face_area(hi.n_faces() - 1), 1e-12);
}

TEST(SplitByPlane, PlaneThroughCornersAndTagsOfEarlierCutsSurvive) {
    // x + y + z = 1 passes through three corners of the unit cube: 1/6 below, 5/6 above.
    const Vec3 n = Vec3(1, 1, 1).normalized();
    Polyhedron lo, hi;
    ASSERT_TRUE(split_by_plane(make_brick(0, 1, 0, 1, 0, 1), n, 1.0 / std::sqrt(3.0), 1e-6, 3, lo, hi));
    EXPECT_NEAR(mass_properties(lo).volume, 1.0 / 6.0, 1e-14);
    EXPECT_NEAR(mass_properties(hi).volume, 5.0 / 6.0, 1e-14);
    EXPECT_EQ(lo.n_vertices(), 4);
    EXPECT_EQ(hi.n_vertices(), 7);
    EXPECT_TRUE(is_convex_polyhedron(lo, 1e-12));
    EXPECT_TRUE(is_convex_polyhedron(hi, 1e-12));
    // Cut the big part again; the first cap keeps tag 3, the new one gets 5.
    Polyhedron lo2, hi2;
    ASSERT_TRUE(split_by_plane(hi, Vec3(0, 0, 1), 0.5, 1e-6, 5, lo2, hi2));
    for (const Polyhedron* q : {&lo2, &hi2}) {
        ASSERT_EQ(q->face_joint.size(), static_cast<size_t>(q->n_faces()));
        EXPECT_EQ(std::count(q->face_joint.begin(), q->face_joint.end(), 5), 1);
    }
    EXPECT_EQ(std::count(lo2.face_joint.begin(), lo2.face_joint.end(), 3), 1);
    EXPECT_NEAR(mass_properties(lo2).volume + mass_properties(hi2).volume, 5.0 / 6.0, 1e-14);
}

TEST(SplitByPlane, MissesAndSliversLeaveOutputsUntouched) {
    const Polyhedron cube = make_brick(0, 1, 0, 1, 0, 1);
    Polyhedron lo = make_brick(5, 6, 5, 6, 5, 6), hi = lo;
    SplitOutcome why = SplitOutcome::Split;
    // Through a face.
    EXPECT_FALSE(split_by_plane(cube, Vec3(0, 0, 1), 1.0, 1e-3, 1, lo, hi, &why));
    EXPECT_EQ(why, SplitOutcome::Missed);
    // Clear of the cube.
    EXPECT_FALSE(split_by_plane(cube, Vec3(0, 0, 1), 2.0, 1e-3, 1, lo, hi, &why));
    EXPECT_EQ(why, SplitOutcome::Missed);
    // Crossing, but a piece would be 0.5 mm thick with a 1 mm sliver tolerance, either side.
    EXPECT_FALSE(split_by_plane(cube, Vec3(0, 0, 1), 0.9995, 1e-3, 1, lo, hi, &why));
    EXPECT_EQ(why, SplitOutcome::Sliver);
    EXPECT_FALSE(split_by_plane(cube, Vec3(0, 0, 1), 0.0005, 1e-3, 1, lo, hi, &why));
    EXPECT_EQ(why, SplitOutcome::Sliver);
    EXPECT_DOUBLE_EQ(lo.vertices[0].x(), 5.0);
    EXPECT_DOUBLE_EQ(hi.vertices[0].x(), 5.0);
    // The same plane with a finer tolerance does cut.
    EXPECT_TRUE(split_by_plane(cube, Vec3(0, 0, 1), 0.9995, 1e-4, lo, hi));
    EXPECT_NEAR(mass_properties(hi).volume, 0.0005, 1e-15);
    EXPECT_TRUE(lo.face_joint.empty()); // untagged source, untagged cap
}

TEST(ConvexHull, LatticeWithManyCoplanarAndCollinearPoints) {
    // A 6 x 6 x 6 grid: every face and edge is crowded with points that must merge away.
    std::vector<Vec3> pts;
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            for (int k = 0; k < 6; ++k) pts.push_back(Vec3(i, j, k) * 0.2 + Vec3(-3, 7, 1));
    Polyhedron p;
    std::string err;
    ASSERT_TRUE(make_convex_hull(pts, 1e-9, p, err)) << err;
    EXPECT_EQ(p.n_faces(), 6);
    EXPECT_EQ(p.n_vertices(), 8);
    EXPECT_NEAR(mass_properties(p).volume, 1.0, 1e-12);
}

TEST(ConvexHull, OctahedronFacesAreTriangles) {
    const std::vector<Vec3> pts{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, 0, 0}};
    Polyhedron p;
    std::string err;
    ASSERT_TRUE(make_convex_hull(pts, 1e-9, p, err)) << err;
    EXPECT_EQ(p.n_faces(), 8);
    EXPECT_EQ(p.n_vertices(), 6);
    EXPECT_NEAR(mass_properties(p).volume, 4.0 / 3.0, 1e-14);
}

TEST(SplitByPlane, RepeatedObliqueCutsStayConvexAndConserveVolume) {
    // Cut a brick by many planes of three oblique families; every piece stays a closed
    // convex polyhedron and the pieces' volumes add up to the brick's.
    std::vector<Polyhedron> pieces{make_brick(0, 7, 0, 5, 0, 3)};
    const Vec3 normals[3] = {Vec3(1, 2, 3).normalized(), Vec3(-2, 1, 0.5).normalized(), Vec3(0.3, -1, 2).normalized()};
    int tag = 0;
    for (const Vec3& n : normals) {
        for (int k = -8; k <= 8; ++k) {
            ++tag;
            std::vector<Polyhedron> next;
            for (const Polyhedron& q : pieces) {
                Polyhedron lo, hi;
                if (split_by_plane(q, n, 0.37 * k + n.dot(Vec3(3.5, 2.5, 1.5)), 1e-3, tag, lo, hi)) {
                    next.push_back(std::move(lo));
                    next.push_back(std::move(hi));
                } else {
                    next.push_back(q);
                }
            }
            pieces = std::move(next);
        }
    }
    EXPECT_GT(pieces.size(), 200u);
    double v = 0;
    for (const Polyhedron& q : pieces) {
        std::string why;
        EXPECT_TRUE(is_convex_polyhedron(q, 1e-9, &why)) << why;
        v += mass_properties(q).volume;
    }
    EXPECT_LT(std::abs(v - 105.0) / 105.0, 1e-12);
}
