// Solids that are not convex, built as convex pieces (make_convex_pieces): the pieces are
// convex, fill the solid exactly (volume, centroid and inertia add up to closed forms computed
// here independently), are stout rather than slivers, and tag the faces between them.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "engine/polyhedron.h"

using namespace odec;

namespace {

constexpr int kInner = 7; // the tag asked for on the faces between pieces

using Faces = std::vector<std::vector<Vec3>>;

// The faces of the prism that extrudes the 2D polygon `p` (x, y; any winding) from z0 to z1.
Faces extrusion(const std::vector<Eigen::Vector2d>& p, double z0, double z1) {
    Faces faces(2);
    for (const auto& q : p) {
        faces[0].emplace_back(q.x(), q.y(), z0);
        faces[1].emplace_back(q.x(), q.y(), z1);
    }
    for (size_t k = 0; k < p.size(); ++k) {
        const auto& a = p[k];
        const auto& b = p[(k + 1) % p.size()];
        faces.push_back({{a.x(), a.y(), z0}, {b.x(), b.y(), z0}, {b.x(), b.y(), z1}, {a.x(), a.y(), z1}});
    }
    return faces;
}

struct Sums {
    double volume = 0;
    Vec3 centroid = Vec3::Zero();
    Mat3 inertia = Mat3::Zero();     // about the centroid of the whole, per unit density
    double surface_area = 0;         // faces tagged 0
    double inner_area = 0;           // faces tagged kInner (each interface counted from both sides)
    double smallest = 0;             // smallest piece's volume over the whole's
};

Sums add_up(const SolidPieces& sp) {
    Sums s;
    std::vector<MassProperties> mp;
    for (const Polyhedron& p : sp.pieces) {
        mp.push_back(mass_properties(p));
        s.volume += mp.back().volume;
        s.centroid += mp.back().volume * mp.back().centroid;
        for (int f = 0; f < p.n_faces(); ++f) {
            const int tag = p.face_joint.empty() ? 0 : p.face_joint[f];
            EXPECT_TRUE(tag == 0 || tag == kInner) << tag;
            (tag == 0 ? s.surface_area : s.inner_area) += p.face_area(f);
        }
    }
    s.centroid /= s.volume;
    s.smallest = 1;
    for (const MassProperties& m : mp) {
        const Vec3 d = m.centroid - s.centroid;
        s.inertia += m.inertia + m.volume * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
        s.smallest = std::min(s.smallest, m.volume / s.volume);
    }
    return s;
}

void expect_convex(const SolidPieces& sp) {
    for (const Polyhedron& p : sp.pieces) {
        std::string why;
        EXPECT_TRUE(is_convex_polyhedron(p, 1e-9, &why)) << why;
    }
}

// Inertia tensor per unit density of the box [x0,x1] x [y0,y1] x [z0,z1] about the point o.
Mat3 box_inertia(const Vec3& lo, const Vec3& hi, const Vec3& o) {
    const Vec3 e = hi - lo;
    const double v = e.prod();
    Mat3 i = Mat3::Zero();
    i(0, 0) = v * (e.y() * e.y() + e.z() * e.z()) / 12;
    i(1, 1) = v * (e.x() * e.x() + e.z() * e.z()) / 12;
    i(2, 2) = v * (e.x() * e.x() + e.y() * e.y()) / 12;
    const Vec3 d = 0.5 * (lo + hi) - o;
    return i + v * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
}

} // namespace

TEST(ConvexPieces, LShapedBlockIsFilledExactly) {
    // The L of the boxes [0,2]x[0,1]x[0,1] and [0,1]x[1,2]x[0,1]: one reflex edge, at x = y = 1.
    const Faces faces = extrusion({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, 0, 1);
    SolidPieces sp;
    std::string err;
    ASSERT_TRUE(make_convex_pieces(faces, 1e-9, kInner, sp, err)) << err;
    EXPECT_EQ(sp.pieces.size(), 2u);
    expect_convex(sp);
    const Sums s = add_up(sp);
    // Volume 3; centroid ((2 x 1 + 1 x 0.5) / 3, (2 x 0.5 + 1 x 1.5) / 3, 0.5).
    const Vec3 c(2.5 / 3, 2.5 / 3, 0.5);
    EXPECT_NEAR(s.volume, 3.0, 1e-13);
    EXPECT_LT((s.centroid - c).norm(), 1e-13);
    const Mat3 expect = box_inertia({0, 0, 0}, {2, 1, 1}, c) + box_inertia({0, 1, 0}, {1, 2, 1}, c);
    EXPECT_LT((s.inertia - expect).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_NEAR(sp.whole.volume, 3.0, 1e-13);
    EXPECT_LT((sp.whole.centroid - c).norm(), 1e-13);
    // The surface keeps tag 0 (two L faces of 3 m^2 and sides 8 m long and 1 m tall); the one
    // interface between the pieces is tagged on both.
    EXPECT_NEAR(s.surface_area, 14.0, 1e-12);
    EXPECT_GT(s.inner_area, 2.0);
    EXPECT_GT(s.smallest, 0.25);
}

TEST(ConvexPieces, VoussoirWithAPolygonalIntradosIsFilledExactly) {
    // A voussoir of an arch: between radii 2 and 3 m from 0 to 40 degrees in the x-z plane,
    // both arcs as 4 facets, 1 m thick along y. The intrados facets fold inward at 3 edges.
    std::vector<Eigen::Vector2d> profile; // (x, z)
    for (int k = 0; k <= 4; ++k) {
        const double a = k * 10.0 * M_PI / 180;
        profile.emplace_back(3 * std::cos(a), 3 * std::sin(a));
    }
    for (int k = 4; k >= 0; --k) {
        const double a = k * 10.0 * M_PI / 180;
        profile.emplace_back(2 * std::cos(a), 2 * std::sin(a));
    }
    Faces faces(2);
    const size_t n = profile.size();
    for (const auto& q : profile) {
        faces[0].emplace_back(q.x(), 0, q.y());
        faces[1].emplace_back(q.x(), 1, q.y());
    }
    for (size_t k = 0; k < n; ++k) {
        const auto& a = profile[k];
        const auto& b = profile[(k + 1) % n];
        faces.push_back({{a.x(), 0, a.y()}, {b.x(), 0, b.y()}, {b.x(), 1, b.y()}, {a.x(), 1, a.y()}});
    }
    // The profile's area and centroid by the shoelace formula.
    double area = 0, cx = 0, cz = 0;
    for (size_t k = 0; k < n; ++k) {
        const auto& a = profile[k];
        const auto& b = profile[(k + 1) % n];
        const double w = a.x() * b.y() - b.x() * a.y();
        area += 0.5 * w;
        cx += (a.x() + b.x()) * w / 6;
        cz += (a.y() + b.y()) * w / 6;
    }
    EXPECT_NEAR(area, 4 * 0.5 * std::sin(10 * M_PI / 180) * (9 - 4), 1e-14);
    SolidPieces sp;
    std::string err;
    ASSERT_TRUE(make_convex_pieces(faces, 1e-9, kInner, sp, err)) << err;
    expect_convex(sp);
    EXPECT_GE(sp.pieces.size(), 2u);
    EXPECT_LE(sp.pieces.size(), 4u);
    const Sums s = add_up(sp);
    EXPECT_NEAR(s.volume, area, 1e-13);
    EXPECT_LT((s.centroid - Vec3(cx / area, 0.5, cz / area)).norm(), 1e-13);
    // No sliver among the pieces.
    EXPECT_GT(s.smallest, 0.1);
}

TEST(ConvexPieces, CubeWithASunkenRoof) {
    // A unit cube whose top is four triangles meeting at (0.5, 0.5, 0.5): the cube less a
    // square pyramid of height 0.5, volume 1 - 1/6, centroid at z = (0.5 - 0.875 / 6) / (5 / 6).
    const Vec3 apex(0.5, 0.5, 0.5);
    const Faces faces{{{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}},
                      {{0, 0, 1}, {1, 0, 1}, apex},
                      {{1, 0, 1}, {1, 1, 1}, apex},
                      {{1, 1, 1}, {0, 1, 1}, apex},
                      {{0, 1, 1}, {0, 0, 1}, apex},
                      {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}},
                      {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}},
                      {{1, 1, 0}, {0, 1, 0}, {0, 1, 1}, {1, 1, 1}},
                      {{0, 1, 0}, {0, 0, 0}, {0, 0, 1}, {0, 1, 1}}};
    SolidPieces sp;
    std::string err;
    ASSERT_TRUE(make_convex_pieces(faces, 1e-9, kInner, sp, err)) << err;
    expect_convex(sp);
    EXPECT_GE(sp.pieces.size(), 2u);
    const Sums s = add_up(sp);
    EXPECT_NEAR(s.volume, 5.0 / 6, 1e-14);
    EXPECT_LT((s.centroid - Vec3(0.5, 0.5, (0.5 - 0.875 / 6) / (5.0 / 6))).norm(), 1e-13);
    EXPECT_NEAR(s.surface_area, 5 + 4 * 0.5 * std::sqrt(0.5), 1e-12); // 5 squares, 4 valley faces
}

TEST(ConvexPieces, NearlyOppositeFoldsOfADrumMakeNoThinWedge) {
    // A 12-sided drum whose outline is pushed in a little at two opposite corners (3 and 9), as
    // a drum's outline rounded from a survey is: the planes through the two folds would cross in
    // a thin wedge if both went through one point. Every piece is stout.
    std::vector<Eigen::Vector2d> p;
    for (int k = 0; k < 12; ++k) {
        const double a = k * M_PI / 6 + 0.01;
        const double r = (k == 3 || k == 9) ? 0.42 : 0.5; // inside the chord of its neighbours (0.433)
        p.emplace_back(r * std::cos(a), r * std::sin(a) + (k == 9 ? 0.01 : 0.0));
    }
    SolidPieces sp;
    std::string err;
    ASSERT_TRUE(make_convex_pieces(extrusion(p, 0, 0.4), 1e-9, kInner, sp, err)) << err;
    expect_convex(sp);
    double area = 0;
    for (size_t k = 0; k < p.size(); ++k) area += 0.5 * (p[k].x() * p[(k + 1) % 12].y() - p[(k + 1) % 12].x() * p[k].y());
    const Sums s = add_up(sp);
    EXPECT_NEAR(s.volume, 0.4 * area, 1e-13);
    EXPECT_GE(sp.pieces.size(), 3u);
    EXPECT_GT(s.smallest, 0.05) << sp.pieces.size() << " pieces";
}

TEST(ConvexPieces, ConvexSolidIsOnePieceWithItsFacesUntagged) {
    const Faces faces = extrusion({{0, 0}, {2, 0}, {2, 1}, {0, 1}}, 0, 3);
    SolidPieces sp;
    std::string err;
    ASSERT_TRUE(make_convex_pieces(faces, 1e-9, kInner, sp, err)) << err;
    ASSERT_EQ(sp.pieces.size(), 1u);
    for (int t : sp.pieces[0].face_joint) EXPECT_EQ(t, 0);
    EXPECT_NEAR(mass_properties(sp.pieces[0]).volume, 6.0, 1e-13);
}

TEST(ConvexPieces, CornersAreMovedOntoTheirPlanesWithinTheTolerance) {
    // An L whose top corners were rounded to 1e-5 m: the top face is planar only within that,
    // and comes out planar to round-off (every face of every piece), the volume within the
    // rounding times the area.
    Faces faces = extrusion({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, 0, 1);
    const double bumps[6] = {4e-6, -3e-6, 5e-6, -2e-6, 0, 3e-6};
    for (int k = 0; k < 6; ++k) faces[1][k].z() += bumps[k];
    for (size_t f = 2; f < faces.size(); ++f) {
        for (Vec3& v : faces[f]) {
            for (int k = 0; k < 6; ++k) {
                if (v.z() == 1 && (v - faces[1][k]).head<2>().norm() == 0) v = faces[1][k];
            }
        }
    }
    SolidPieces sp;
    std::string err;
    ASSERT_TRUE(make_convex_pieces(faces, 1e-5, kInner, sp, err)) << err;
    for (const Polyhedron& p : sp.pieces) {
        for (int f = 0; f < p.n_faces(); ++f) {
            const Vec3 n = p.face_normal(f);
            const Vec3 o = p.vertices[p.face_vertex(f, 0)];
            for (int k = 0; k < p.face_size(f); ++k) EXPECT_LT(std::abs(n.dot(p.vertices[p.face_vertex(f, k)] - o)), 1e-13);
        }
    }
    EXPECT_NEAR(add_up(sp).volume, 3.0, 1e-5 * 3);
}

TEST(ConvexPieces, RejectsWhatBoundsNoSolid) {
    SolidPieces sp;
    std::string err;
    // An L with its top left off: open.
    Faces open = extrusion({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, 0, 1);
    open.erase(open.begin() + 1);
    EXPECT_FALSE(make_convex_pieces(open, 1e-9, kInner, sp, err));
    EXPECT_NE(err.find("not closed"), std::string::npos) << err;
    // A face whose outline crosses itself (a bow tie).
    Faces bow = extrusion({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, 0, 1);
    std::swap(bow[0][1], bow[0][2]);
    EXPECT_FALSE(make_convex_pieces(bow, 1e-9, kInner, sp, err));
    EXPECT_EQ(err, "face 1 crosses itself");
    // A face that is not planar.
    Faces warped = extrusion({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, 0, 1);
    warped[0][3].z() = 0.1;
    EXPECT_FALSE(make_convex_pieces(warped, 1e-9, kInner, sp, err));
    EXPECT_EQ(err, "face 1 is not planar");
    EXPECT_TRUE(sp.pieces.empty());
}
