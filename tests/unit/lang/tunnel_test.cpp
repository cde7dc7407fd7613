// `poly tunnel`: a box of rock around a tunnel, made of convex blocks that share whole faces
// and are joined. Each test runs the real command and checks the geometry it leaves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/tunnel.h"
#include "test_util.h"

using odec::Model;
using odec::Polyhedron;
using odec::Vec3;
using odec::test::Session;

namespace {

constexpr double kPi = 3.14159265358979323846;

double total_volume(const Model& m, bool excavated_too = true) {
    double v = 0;
    for (int b = 0; b < m.blocks.size(); ++b) {
        if (excavated_too || !(m.blocks.flags[b] & odec::kExcavated)) v += m.blocks.volume[b];
    }
    return v;
}

std::vector<int> in_group(const Model& m, const std::string& name) {
    std::vector<int> out;
    for (int b = 0; b < m.blocks.size(); ++b) {
        const int g = m.blocks.group[b];
        if (g >= 0 && m.group_names[g] == name) out.push_back(b);
    }
    return out;
}

double model_scale(const Model& m) {
    double s = 0;
    for (int b = 0; b < m.blocks.size(); ++b) {
        for (const Vec3& v : odec::world_shape(m, b).vertices) s = std::max(s, v.cwiseAbs().maxCoeff());
    }
    return s;
}

// One face of one block, in world coordinates.
struct Face {
    int block = 0, face = 0, tag = 0;
    std::vector<Vec3> corners;
    Vec3 normal, centre;
};

std::vector<Face> all_faces(const Model& m) {
    std::vector<Face> out;
    for (int b = 0; b < m.blocks.size(); ++b) {
        const Polyhedron p = odec::world_shape(m, b);
        for (int f = 0; f < p.n_faces(); ++f) {
            Face x;
            x.block = b;
            x.face = f;
            x.tag = p.face_joint.empty() ? 0 : p.face_joint[f];
            x.normal = p.face_normal(f);
            x.centre = Vec3::Zero();
            for (int k = 0; k < p.face_size(f); ++k) {
                x.corners.push_back(p.vertices[p.face_vertex(f, k)]);
                x.centre += x.corners.back();
            }
            x.centre /= static_cast<double>(x.corners.size());
            out.push_back(x);
        }
    }
    return out;
}

// Same corners (in any order, within tol) and opposite normals.
bool same_face(const Face& a, const Face& b, double tol) {
    if (a.corners.size() != b.corners.size() || (a.centre - b.centre).norm() > tol) return false;
    if (a.normal.dot(b.normal) > -1 + 1e-9) return false;
    for (const Vec3& p : a.corners) {
        bool found = false;
        for (const Vec3& q : b.corners) found = found || (p - q).norm() <= tol;
        if (!found) return false;
    }
    return true;
}

struct FaceCheck {
    int shared = 0;     // pairs of faces that coincide
    int unmatched = 0;  // tagged (inner) faces with no partner
    int outer = 0;      // untagged faces (the box and the ends)
    std::set<std::pair<int, int>> neighbours; // block pairs sharing a face
};

// Every face with the tunnel's joint tag has exactly one partner on another block: the
// same polygon, facing the other way. Untagged faces are the outside of the box.
FaceCheck check_faces(const Model& m) {
    const std::vector<Face> faces = all_faces(m);
    const double tol = 1e-9 * std::max(1.0, model_scale(m));
    FaceCheck r;
    std::vector<int> partner(faces.size(), -1);
    for (size_t i = 0; i < faces.size(); ++i) {
        if (faces[i].tag == 0) {
            ++r.outer;
            continue;
        }
        int count = 0;
        for (size_t j = 0; j < faces.size(); ++j) {
            if (faces[j].block != faces[i].block && same_face(faces[i], faces[j], tol)) {
                ++count;
                partner[i] = static_cast<int>(j);
            }
        }
        if (count != 1) {
            ++r.unmatched;
        } else if (faces[partner[i]].tag != 0 && static_cast<int>(i) < partner[i]) {
            ++r.shared;
            r.neighbours.emplace(std::min(faces[i].block, faces[partner[i]].block),
                                 std::max(faces[i].block, faces[partner[i]].block));
        }
    }
    return r;
}

// What a failed command must leave as it was.
std::string state(const Model& m) {
    std::string s = std::to_string(m.blocks.size()) + " blocks, " + std::to_string(m.joint_planes.size()) +
                    " planes, " + std::to_string(m.n_joint_sets) + " sets, groups:";
    for (const auto& g : m.group_names) s += " " + g;
    for (int b = 0; b < m.blocks.size(); ++b) s += " " + std::to_string(m.blocks.centroid[b].sum());
    return s;
}

} // namespace

// The blocks fill the box exactly, the core has the area of the circle, and every block is a
// valid convex polyhedron, for square and oblong boxes, axes along the grid or askew, far from
// the origin, and numbers of sides that put box corners on rays, inside sectors, or two in one.
TEST(Tunnel, BlocksFillTheBoxAndTheCoreHasTheCircleArea) {
    struct Case {
        std::string cmd;
        Vec3 a, b;
        double r, hu, hv;
        int n, m, nseg;
    };
    const std::vector<Case> cases = {
        {"poly tunnel a (0,0,0) b (0,3,0) radius 1 box 6 nseg 3", {0, 0, 0}, {0, 3, 0}, 1, 6, 6, 16, 4, 3},
        {"poly tunnel a (0,0,0) b (0,2,0) radius 1 box 5 3 ntheta 12 nrad 3", {0, 0, 0}, {0, 2, 0}, 1, 5, 3, 12, 3, 1},
        {"poly tunnel a (1,2,3) b (4,6,8) radius 0.5 box 2 ntheta 8 nrad 2 ratio 1.5 nseg 2",
         {1, 2, 3}, {4, 6, 8}, 0.5, 2, 2, 8, 2, 2},
        {"poly tunnel a (0,0,0) b (0,0,-10) radius 2 box 8 ntheta 6 nrad 2", {0, 0, 0}, {0, 0, -10}, 2, 8, 8, 6, 2, 1},
        {"poly tunnel a (0,0,0) b (5,0,0) radius 1 box 4 ntheta 3 nrad 1", {0, 0, 0}, {5, 0, 0}, 1, 4, 4, 3, 1, 1},
        {"poly tunnel a (2e6,3e6,-500) b (2e6,3000040,-500) radius 3 box 30 20 ntheta 20 nrad 5 ratio 1.3 nseg 4",
         {2e6, 3e6, -500}, {2e6, 3e6 + 40, -500}, 3, 30, 20, 20, 5, 4},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.cmd);
        Session s;
        ASSERT_TRUE(s.run(c.cmd)) << s.error();
        const Model& m = s.model;
        const double length = (c.b - c.a).norm();
        ASSERT_EQ(m.blocks.size(), c.nseg * (1 + c.n * c.m));
        const double box = 4 * c.hu * c.hv * length;
        EXPECT_NEAR(total_volume(m), box, 1e-9 * box);
        const std::vector<int> core = in_group(m, "tunnel");
        ASSERT_EQ(static_cast<int>(core.size()), c.nseg);
        double core_volume = 0;
        for (int b : core) core_volume += m.blocks.volume[b];
        const double circle = kPi * c.r * c.r * length;
        EXPECT_NEAR(core_volume, circle, 1e-9 * circle);
        const double tol = 1e-9 * std::max(1.0, model_scale(m));
        for (int b = 0; b < m.blocks.size(); ++b) {
            std::string why;
            EXPECT_TRUE(odec::is_convex_polyhedron(odec::world_shape(m, b), tol, &why)) << "block " << b + 1 << ": " << why;
            EXPECT_GT(m.blocks.volume[b], 0);
        }
    }
}

// Neighbouring blocks share whole faces: each inner face is the same polygon as exactly one
// face of one other block (no face is cut across by a corner of its neighbour).
TEST(Tunnel, NeighboursShareWholeFaces) {
    for (const std::string cmd : {"poly tunnel a (0,0,0) b (0,2,0) radius 1 box 4 ntheta 16 nrad 3 nseg 2",
                                  "poly tunnel a (0,0,0) b (0,1,0) radius 1 box 5 3 ntheta 12 nrad 2",
                                  "poly tunnel a (1,2,3) b (4,6,8) radius 0.5 box 2 ntheta 7 nrad 2 nseg 2"}) {
        SCOPED_TRACE(cmd);
        Session s;
        ASSERT_TRUE(s.run(cmd)) << s.error();
        const FaceCheck r = check_faces(s.model);
        EXPECT_EQ(r.unmatched, 0);
        EXPECT_GT(r.shared, 0);
        // Every block touches another across a whole face; the core of each segment touches
        // the whole first ring.
        std::vector<int> touching(s.model.blocks.size(), 0);
        for (const auto& [a, b] : r.neighbours) {
            ++touching[a];
            ++touching[b];
        }
        for (int b = 0; b < s.model.blocks.size(); ++b) EXPECT_GE(touching[b], 3) << "block " << b + 1;
    }
    // The count for one segment of 16 sides and 3 rings: the core's 16 sides, 16 radial faces in
    // each ring, 16 faces between rings 1-2 and 2-3; with two segments, one face across the
    // middle per block of a segment.
    Session s;
    ASSERT_TRUE(s.run("poly tunnel a (0,0,0) b (0,2,0) radius 1 box 4 ntheta 16 nrad 3 nseg 2")) << s.error();
    const FaceCheck r = check_faces(s.model);
    EXPECT_EQ(r.shared, 2 * (16 + 3 * 16 + 2 * 16) + (1 + 3 * 16));
}

// The rays at the mid-planes lie exactly on them, the box's sides are exactly where asked,
// and a quarter model cut along the mid-planes keeps whole blocks (the core aside).
TEST(Tunnel, MidPlanesAndBoxSidesAreExact) {
    Session s;
    ASSERT_TRUE(s.run("poly tunnel a (0,0,0) b (0,1,0) radius 1 box 10 ntheta 16 nrad 8")) << s.error();
    const Model& m = s.model;
    double lo_x = 0, hi_x = 0, lo_z = 0, hi_z = 0;
    for (int b = 0; b < m.blocks.size(); ++b) {
        const Polyhedron p = odec::world_shape(m, b);
        double bx_lo = 1e9, bx_hi = -1e9, bz_lo = 1e9, bz_hi = -1e9;
        for (const Vec3& v : p.vertices) {
            bx_lo = std::min(bx_lo, v.x());
            bx_hi = std::max(bx_hi, v.x());
            bz_lo = std::min(bz_lo, v.z());
            bz_hi = std::max(bz_hi, v.z());
        }
        lo_x = std::min(lo_x, bx_lo);
        hi_x = std::max(hi_x, bx_hi);
        lo_z = std::min(lo_z, bz_lo);
        hi_z = std::max(hi_z, bz_hi);
        if (m.group_names[m.blocks.group[b]] == "tunnel") continue;
        // No ring block crosses x = 0 or z = 0 (to round-off of the centroid shift).
        EXPECT_TRUE(bx_lo >= -1e-12 || bx_hi <= 1e-12) << "block " << b + 1;
        EXPECT_TRUE(bz_lo >= -1e-12 || bz_hi <= 1e-12) << "block " << b + 1;
    }
    EXPECT_NEAR(lo_x, -10, 1e-12);
    EXPECT_NEAR(hi_x, 10, 1e-12);
    EXPECT_NEAR(lo_z, -10, 1e-12);
    EXPECT_NEAR(hi_z, 10, 1e-12);
    // A quarter: delete below z = 0 and west of x = 0.
    Session q;
    ASSERT_TRUE(q.run("poly tunnel a (0,0,0) b (0,1,0) radius 1 box 10 ntheta 16 nrad 8\n"
                      "delete range group tunnel\n"
                      "delete range plane dip 0 dd 0 origin 0,0,0 below\n"
                      "delete range plane dip 90 dd 90 origin 0,0,0 below"))
        << q.error();
    EXPECT_EQ(q.model.blocks.size(), 16 * 8 / 4);
    EXPECT_NEAR(total_volume(q.model), (400.0 - kPi) / 4, 1e-9 * 100);
}

// The rings and the outer region can be selected: ring k is group tunnel_ring<k> and region
// base + k; the core is the group given (default 'tunnel') and region base.
TEST(Tunnel, GroupsAndRegionsSelectCoreAndRings) {
    Session s;
    ASSERT_TRUE(s.run("poly tunnel a (0,0,0) b (0,2,0) radius 1 box 6 ntheta 8 nrad 3 nseg 2 region 10 group 'drift'"))
        << s.error();
    const Model& m = s.model;
    ASSERT_EQ(in_group(m, "drift").size(), 2u);
    for (int b : in_group(m, "drift")) EXPECT_EQ(m.blocks.region[b], 10);
    for (int k = 1; k <= 3; ++k) {
        const std::vector<int> ring = in_group(m, "drift_ring" + std::to_string(k));
        ASSERT_EQ(ring.size(), 16u) << k;
        for (int b : ring) EXPECT_EQ(m.blocks.region[b], 10 + k);
    }
    // The outermost ring holds the blocks on the box: each has a face on it (x or z = +-6).
    for (int b : in_group(m, "drift_ring3")) {
        double far = 0;
        for (const Vec3& v : odec::world_shape(m, b).vertices) far = std::max({far, std::abs(v.x()), std::abs(v.z())});
        EXPECT_NEAR(far, 6, 1e-12);
    }
    // Ring radii grow geometrically by default: equal ratios of corner distances.
    std::vector<double> reach(4, 0);
    for (int b = 0; b < m.blocks.size(); ++b) {
        const int k = m.blocks.region[b] - 10;
        for (const Vec3& v : odec::world_shape(m, b).vertices) {
            const double d = std::hypot(v.x(), v.z());
            if (k < 3) reach[k] = std::max(reach[k], d);
        }
    }
    const double r0 = odec::equal_area_circumradius(1, 8);
    EXPECT_NEAR(reach[0], r0, 1e-12);
    const double q = std::cbrt(6 / r0);
    EXPECT_NEAR(reach[1] / reach[0], q, 1e-12);
    EXPECT_NEAR(reach[2] / reach[1], q, 1e-12);
}

// Excavating the core opens exactly the hole: the core blocks and nothing else.
TEST(Tunnel, ExcavatingTheGroupRemovesExactlyTheCore) {
    Session s;
    ASSERT_TRUE(s.run("poly tunnel a (0,0,0) b (0,3,0) radius 1.5 box 9 ntheta 16 nrad 5 nseg 3\n"
                      "excavate range group 'tunnel'"))
        << s.error();
    const Model& m = s.model;
    int excavated = 0;
    for (int b = 0; b < m.blocks.size(); ++b) {
        const bool gone = m.blocks.flags[b] & odec::kExcavated;
        excavated += gone;
        const Vec3 c = m.blocks.centroid[b];
        // The core's centroids are on the axis; every other block's is outside the wall.
        EXPECT_EQ(gone, std::hypot(c.x(), c.z()) < 1e-9) << "block " << b + 1;
    }
    EXPECT_EQ(excavated, 3);
    const double left = 18 * 18 * 3 - kPi * 1.5 * 1.5 * 3;
    EXPECT_NEAR(total_volume(m, false), left, 1e-9 * left);
}

// The blocks are joined: every contact between two of them is glued, and there is one for
// every shared face; a block put against the box touches it through an ordinary contact.
TEST(Tunnel, ContactsBetweenTheBlocksAreJoined) {
    Session s;
    ASSERT_TRUE(s.run("poly tunnel a (0,0,0) b (0,2,0) radius 1 box 4 ntheta 8 nrad 2 nseg 2 jmat 2\n"
                      "poly brick -4 4 0 2 4 5\n"
                      "prop mat=1 dens=2000\nprop jmat=1 jkn=1e9 jks=1e9\nprop jmat=2 jkn=2e9 jks=2e9"))
        << s.error();
    Model& m = s.model;
    const int brick = m.blocks.size() - 1;
    const FaceCheck faces = check_faces(m);
    ASSERT_EQ(faces.unmatched, 0);
    odec::refresh_world_vertices(m);
    odec::detect_contacts(m);
    const odec::ContactSet& cs = m.contacts;
    std::set<std::pair<int, int>> joined_pairs;
    int with_brick = 0;
    for (int c = 0; c < cs.size(); ++c) {
        const int a = cs.block_a[c], b = cs.block_b[c];
        if (a == brick || b == brick) {
            ++with_brick;
            EXPECT_FALSE(cs.joined(c)) << "contact with the brick";
            EXPECT_EQ(cs.jmat(c), 1);
            continue;
        }
        // Blocks sharing a face, and blocks meeting only along an edge or at a corner.
        EXPECT_TRUE(cs.joined(c)) << "blocks " << a + 1 << " and " << b + 1;
        EXPECT_EQ(cs.jmat(c), 2);
        joined_pairs.emplace(std::min(a, b), std::max(a, b));
    }
    for (const auto& pair : faces.neighbours) EXPECT_EQ(joined_pairs.count(pair), 1u);
    EXPECT_GT(joined_pairs.size(), faces.neighbours.size()); // the edge contacts
    EXPECT_GT(with_brick, 0);
}

// The 3DEC-like form (dip, dd, origin, length) makes the same blocks as the two points.
TEST(Tunnel, AxisByDirectionAndLengthIsTheSameAsByPoints) {
    Session p, d;
    ASSERT_TRUE(p.run("poly tunnel a (1,2,3) b (1,7,3) radius 1 box 10 nrad 10 ratio 1.4")) << p.error();
    ASSERT_TRUE(d.run("poly tunnel dip 0 dd 0 origin 1,2,3 length 0 5 radius 1 box 10 nrad 10 ratio 1.4")) << d.error();
    ASSERT_EQ(p.model.blocks.size(), d.model.blocks.size());
    for (int b = 0; b < p.model.blocks.size(); ++b) {
        EXPECT_LT((p.model.blocks.centroid[b] - d.model.blocks.centroid[b]).norm(), 1e-12) << b;
    }
    // A plunging axis: dip 90 points straight down.
    Session v;
    ASSERT_TRUE(v.run("poly tunnel dip 90 dd 0 length 0 4 radius 1 box 3 nrad 1 ntheta 4")) << v.error();
    for (int b : in_group(v.model, "tunnel")) EXPECT_NEAR(v.model.blocks.centroid[b].z(), -2, 1e-12);
    // Ring thicknesses grow by the ratio given: 10 rings of ratio 1.4 from the wall to the box.
    const double r0 = odec::equal_area_circumradius(1, 16);
    const double t1 = (10 - r0) * 0.4 / (std::pow(1.4, 10) - 1);
    double inner = 1e9;
    for (int b : in_group(p.model, "tunnel_ring1")) {
        for (const Vec3& x : odec::world_shape(p.model, b).vertices) {
            const double dist = std::hypot(x.x() - 1, x.z() - 3);
            if (dist > r0 + 1e-9) inner = std::min(inner, dist);
        }
    }
    EXPECT_NEAR(inner, r0 + t1, 1e-12);
}

// A tunnel cycles as one mass: held at its base under gravity, the joined blocks settle
// without opening or slipping, to a small displacement.
TEST(Tunnel, JoinedBlocksCycleAsOneMass) {
    Session s;
    ASSERT_TRUE(s.run("poly tunnel a (0,0,0) b (0,1,0) radius 1 box 3 ntheta 8 nrad 2\n"
                      "prop mat=1 dens=2000\nprop jmat=1 jkn=1e10 jks=1e10\ngrav 0 0 -10\n"
                      "fix range z -3 -2\nstep 300"))
        << s.error();
    double most = 0;
    for (int b = 0; b < s.model.blocks.size(); ++b) most = std::max(most, s.model.blocks.disp[b].norm());
    EXPECT_LT(most, 1e-4);
    EXPECT_GT(most, 0);
}

// Bad input is refused with the word it concerns, and the model stays as it was.
TEST(Tunnel, BadInputIsRefusedAndChangesNothing) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"poly tunnel a (0,0,0) b (0,1,0) radius 0", "t.dat:1:40: error: 'radius' must be > 0 (got 0)"},
        {"poly tunnel a (0,0,0) b (0,1,0) radius -1", "error: 'radius' must be > 0 (got -1)"},
        {"poly tunnel a (0,0,0) b (0,1,0) radius 1e999", "error: 'radius' must be a finite number > 0"},
        {"poly tunnel a (0,0,0) b (0,1,0) radius nan", "'nan' is not a number"},
        {"poly tunnel a (0,0,0) b (0,1,0) radius 1 box 1",
         "t.dat:1:42: error: the box (half-size 1 m) must reach beyond the tunnel wall, whose corners lie 1.013 m from the "
         "axis (a polygon of 16 sides with the area of the circle)"},
        {"poly tunnel a (0,0,0) b (0,1,0) radius 1 box 0.5 10", "error: the box (half-size 0.5 m) must reach beyond"},
        {"poly tunnel a (0,0,0) b (0,1,0) radius 1 ntheta 2", "t.dat:1:49: error: 'ntheta' must be 3 to 720 (got 2)"},
        {"poly tunnel a (0,0,0) b (0,1,0) radius 1 nrad 0", "error: 'nrad' must be 1 to 1000 (got 0)"},
        {"poly tunnel a (0,0,0) b (0,1,0) radius 1 nseg 0", "error: 'nseg' must be 1 to 10000 (got 0)"},
        {"poly tunnel a (0,0,0) b (0,1,0) radius 1 ratio 0", "error: 'ratio' must be > 0 (got 0)"},
        {"poly tunnel a (1,1,1) b (1,1,1) radius 1", "t.dat:1:23: error: the tunnel's axis has no length"},
        {"poly tunnel length 2 2 radius 1", "t.dat:1:13: error: the tunnel's axis has no length"},
        {"poly tunnel a (0,0,0) b (0,1,0)", "t.dat:1:6: error: 'tunnel' needs 'radius r'"},
        {"poly tunnel radius 1", "t.dat:1:6: error: the tunnel needs its axis: 'a (x,y,z) b (x,y,z)'"},
        {"poly tunnel dip 30 radius 1", "t.dat:1:13: error: the tunnel needs its axis"},
        {"poly tunnel a (0,0,0) radius 1", "error: the tunnel needs both ends of its axis"},
        {"poly tunnel a (0,0,0) (1,0,0) b (0,1,0) radius 1",
         "t.dat:1:23: error: 'a' takes one point here, an end of the tunnel's axis (got 2)"},
        {"poly tunnel a (0,0,0) b (0,1,0) dip 0 length 0 1 radius 1", "t.dat:1:33: error: give the tunnel's axis either"},
        {"poly brick 0 1 0 1 0 1 radius 1", "t.dat:1:24: error: 'radius' goes with 'tunnel'"},
        {"poly tetra (0,0,0) (1,0,0) (0,1,0) (0,0,1) nseg 2", "error: 'nseg' goes with 'tunnel'"},
        {"poly tunnel a (0,0,0) b (0,1,0) radius 1 nrad 50 ratio 3", "error: with 50 rings and ratio 3 the thinnest ring"},
        {"poly tunnel a (0,0,0) b (0,1,0) radius 1 nrad 1000 ratio 0.5", "error: with 1000 rings and ratio 0.5"},
        {"poly tunnel a (0,0,0) b (0,1,0) radius 2e9", "error: size 2e+09 is too large: poly takes sizes within 1e+09 m"},
        {"poly tunnel a (0,0,0) b (0,1,0) radius 1 box 1e50", "error: size 1e+50 is too large"},
        {"poly tunnel a (0,0,0) b (0,1,0) radius 1 box 1e300", "t.dat:1:46: error: 'box' w must be a number of magnitude at most 1e100"},
        {"poly tunnel a (0,0,0) b (0,1e-300,0) radius 1", "error: the tunnel's axis has no length"},
        {"poly tunnel a (1e8,0,0) b (1e8,1,0) radius 1e-3 box 1e-2", "error: the smallest block edge"},
        {"poly tunnel a (0,0,0) b (0,1,0) radius 1 box 10 ntheta 720 nrad 1000 nseg 10",
         "error: this tunnel would make 7200010 blocks; one 'poly tunnel' makes at most 100000"},
        {"poly tunnel a (0,0,0) b (0,1,0) radius 1 region 2000000000 nrad 200000000",
         "error: 'nrad' must be 1 to 1000 (got 200000000)"},
        {"prop mat=1 dens=1e300\npoly tunnel a (0,0,0) b (0,1e8,0) radius 1e8 box 1e9",
         "t.dat:1:17: error: 'density' must be a number of magnitude at most 1e100 (got 1e300)"},
    };
    for (const auto& [cmd, expected] : cases) {
        SCOPED_TRACE(cmd);
        Session s;
        ASSERT_TRUE(s.run("poly brick 20 21 0 1 0 1\ngroup 'rock'")) << s.error();
        const std::string before = state(s.model);
        EXPECT_FALSE(s.run(cmd));
        EXPECT_NE(s.error().find(expected), std::string::npos) << s.error();
        EXPECT_EQ(state(s.model), before);
        EXPECT_EQ(s.model.blocks.size(), 1);
        EXPECT_EQ(s.model.n_joint_sets, 0);
    }
}

// A session with a block limit refuses a tunnel that would pass it, before making any.
TEST(Tunnel, SessionBlockLimitIsKept) {
    Session s;
    s.interp.limits.max_blocks = 300;
    ASSERT_TRUE(s.run("poly tunnel a (0,0,0) b (0,1,0) radius 1 box 5")) << s.error(); // 65 blocks
    EXPECT_FALSE(s.run("poly tunnel a (0,10,0) b (0,11,0) radius 1 box 5 nrad 20"));
    EXPECT_NE(s.error().find("this session allows at most 300 blocks: the tunnel would make 321 more"), std::string::npos)
        << s.error();
    EXPECT_EQ(s.model.blocks.size(), 65);
}

// ---- 'tunnel': the same pattern cut into blocks that exist ----

// A brick crossed by a tunnel: the pieces fill it, those inside the wall have the circle's
// area times the length inside the brick, every piece is convex, and they keep the brick's
// region, material and group (but the core's).
TEST(TunnelCut, PiecesFillTheBlockAndTheCoreHasTheCircleArea) {
    struct Case {
        std::string cmd;
        double r, inside;
    };
    const std::vector<Case> cases = {
        {"tunnel a (0,-1,0) b (0,9,0) radius 2 outer 6 nrad 3", 2, 8},
        {"tunnel a (0,-1,0) b (0,9,0) radius 1 ntheta 12 nrad 2 ratio 1.5 nseg 3", 1, 8},
        {"tunnel a (1,2,0.5) b (1,6,0.5) radius 1.5 ntheta 8 nrad 2", 1.5, 4},      // ends inside the brick
        {"tunnel a (0,-1,0) b (0,9,0) radius 1 ntheta 7 nrad 1", 1, 8},              // odd number of sides
        {"tunnel dip 0 dd 0 origin 0,4,0 length -10 10 radius 2 nrad 2", 2, 8},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.cmd);
        Session s;
        ASSERT_TRUE(s.run("prop mat=3 dens=2500\npoly brick -10 10 0 8 -10 10 region 4 group rock mat 3\n" + c.cmd))
            << s.error();
        const Model& m = s.model;
        EXPECT_GT(m.blocks.size(), 10);
        EXPECT_NEAR(total_volume(m), 20 * 8 * 20, 1e-9 * 3200);
        double core = 0;
        for (int b : in_group(m, "tunnel")) core += m.blocks.volume[b];
        const double circle = kPi * c.r * c.r * c.inside;
        EXPECT_NEAR(core, circle, 1e-9 * circle);
        EXPECT_EQ(in_group(m, "tunnel").size() + in_group(m, "rock").size(), static_cast<size_t>(m.blocks.size()));
        for (int b = 0; b < m.blocks.size(); ++b) {
            std::string why;
            EXPECT_TRUE(odec::is_convex_polyhedron(odec::world_shape(m, b), 1e-9 * 20, &why)) << "block " << b + 1 << ": " << why;
            EXPECT_EQ(m.blocks.region[b], 4);
            EXPECT_EQ(m.blocks.material[b], 3);
            EXPECT_NEAR(m.blocks.mass[b], 2500 * m.blocks.volume[b], 1e-9 * m.blocks.mass[b]);
        }
        EXPECT_EQ(m.n_joint_sets, 1);
    }
}

// Excavating the pieces inside the wall opens exactly the hole.
TEST(TunnelCut, ExcavatingTheCoreOpensTheHole) {
    Session s;
    ASSERT_TRUE(s.run("poly brick -10 10 0 8 -10 10\ntunnel a (0,-1,0) b (0,9,0) radius 2 nseg 2\n"
                      "excavate range group tunnel"))
        << s.error();
    const Model& m = s.model;
    const double wall = odec::equal_area_circumradius(2, 16);
    for (int b = 0; b < m.blocks.size(); ++b) {
        const bool gone = m.blocks.flags[b] & odec::kExcavated;
        double far = 0;
        for (const Vec3& v : odec::world_shape(m, b).vertices) far = std::max(far, std::hypot(v.x(), v.z()));
        EXPECT_EQ(gone, far <= wall * (1 + 1e-12)) << "block " << b + 1;
    }
    const double left = 20 * 8 * 20 - kPi * 4 * 8;
    EXPECT_NEAR(total_volume(m, false), left, 1e-9 * left);
    EXPECT_EQ(in_group(m, "tunnel").size(), 2u * 16u);
}

// Blocks across an existing joint are cut alike on both sides, so their faces still match
// across it; the new cuts are joined, the old joint is not; blocks beyond the rings are left
// as they were.
TEST(TunnelCut, OldJointsStayFreeNewCutsAreJoinedFacesMatch) {
    Session s;
    ASSERT_TRUE(s.run("poly brick -10 10 0 8 -10 10\njset dip 90 dd 0 origin 0,4,0\npoly brick 30 31 0 1 0 1\n"
                      "tunnel a (0,-1,0) b (0,9,0) radius 1 outer 4 ntheta 8 nrad 2 jmat 2\n"
                      "prop mat=1 dens=2000\nprop jmat=1 jkn=1e9 jks=1e9\nprop jmat=2 jkn=2e9 jks=2e9"))
        << s.error();
    Model& m = s.model;
    // The far brick: untouched, still block 3.
    ASSERT_EQ(m.block_index(3), 2);
    EXPECT_NEAR(m.blocks.volume[2], 1, 1e-12);
    EXPECT_EQ(m.blocks.shape[2].n_faces(), 6);
    // Every face with a joint tag (the old joint at y = 4 and the new cuts) has exactly one
    // partner, the same polygon.
    const FaceCheck faces = check_faces(m);
    EXPECT_EQ(faces.unmatched, 0);
    EXPECT_GT(faces.shared, 0);
    odec::refresh_world_vertices(m);
    odec::detect_contacts(m);
    int across_joint = 0, joined = 0;
    for (int c = 0; c < m.contacts.size(); ++c) {
        const int a = m.contacts.block_a[c], b = m.contacts.block_b[c];
        if (a == 2 || b == 2) continue;
        if ((m.blocks.centroid[a].y() < 4) != (m.blocks.centroid[b].y() < 4)) {
            // Across the old joint, face to face or along an edge of it.
            ++across_joint;
            EXPECT_FALSE(m.contacts.joined(c));
            EXPECT_EQ(m.contacts.jmat(c), 1);
        } else {
            // Pieces of one block: across the new cuts only.
            EXPECT_TRUE(m.contacts.joined(c)) << "contact " << c + 1;
            EXPECT_EQ(m.contacts.jmat(c), 2);
            ++joined;
        }
    }
    EXPECT_GT(across_joint, 16);
    EXPECT_GT(joined, 32);
}

// Bad input is refused with the word it concerns, and the model stays as it was; a tunnel
// that reaches no block changes nothing and says so.
TEST(TunnelCut, BadInputIsRefusedAndChangesNothing) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"tunnel a (0,-1,0) b (0,9,0)", "t.dat:1:1: error: 'tunnel' needs 'radius r'"},
        {"tunnel a (0,-1,0) b (0,9,0) radius 0", "t.dat:1:36: error: 'radius' must be > 0 (got 0)"},
        {"tunnel a (0,-1,0) b (0,9,0) radius 2 outer 2",
         "t.dat:1:38: error: the outermost ring (radius 2 m) must be larger than the tunnel (radius 2 m)"},
        {"tunnel a (0,-1,0) b (0,9,0) radius 2 outer 1", "error: the outermost ring (radius 1 m) must be larger"},
        {"tunnel a (0,1,0) b (0,1,0) radius 1", "t.dat:1:18: error: the tunnel's axis has no length"},
        {"tunnel radius 1", "t.dat:1:1: error: the tunnel needs its axis"},
        {"tunnel a (0,0,0) b (0,1,0) length 0 1 radius 1", "t.dat:1:28: error: give the tunnel's axis either"},
        {"tunnel a (0,0,0) radius 1", "error: the tunnel needs both ends of its axis"},
        {"tunnel a (0,-1,0) b (0,9,0) radius 1 ntheta 2", "error: 'ntheta' must be 3 to 720 (got 2)"},
        {"tunnel a (0,-1,0) b (0,9,0) radius 1 nrad 60 ratio 2", "error: with 60 rings and ratio 2 the thinnest ring"},
        {"tunnel a (0,-1,0) b (0,9,0) radius 1 outer 2e9", "error: 2e+09 is too large"},
        {"tunnel a (0,-1,0) b (0,9,0) radius 1 ntheta 720 nrad 1000 nseg 100", "error: this tunnel could cut"},
        {"tunnel a (0,-1,0) b (0,9,0) radius nan", "'nan' is not a number"},
    };
    for (const auto& [cmd, expected] : cases) {
        SCOPED_TRACE(cmd);
        Session s;
        ASSERT_TRUE(s.run("poly brick -10 10 0 8 -10 10\ngroup 'rock'")) << s.error();
        const std::string before = state(s.model);
        EXPECT_FALSE(s.run(cmd));
        EXPECT_NE(s.error().find(expected), std::string::npos) << s.error();
        EXPECT_EQ(state(s.model), before);
    }
    Session s;
    ASSERT_TRUE(s.run("poly brick -10 10 0 8 -10 10")) << s.error();
    const std::string before = state(s.model);
    EXPECT_TRUE(s.run("tunnel a (50,-1,0) b (50,9,0) radius 1")) << s.error();
    EXPECT_NE(s.error().find("t.dat:1:1: warning: the tunnel reaches no block, nothing changed"), std::string::npos)
        << s.error();
    EXPECT_EQ(state(s.model), before);
    EXPECT_TRUE(s.run("tunnel a (0,-1,0) b (0,9,0) radius 1 range x 20 30")) << s.error();
    EXPECT_NE(s.error().find("warning: the tunnel reaches no block of the range, nothing changed"), std::string::npos)
        << s.error();
    EXPECT_EQ(state(s.model), before);
    // A session with a block limit refuses a cut that would pass it.
    Session t;
    t.interp.limits.max_blocks = 300;
    ASSERT_TRUE(t.run("poly brick -10 10 0 8 -10 10")) << t.error();
    EXPECT_FALSE(t.run("tunnel a (0,-1,0) b (0,9,0) radius 1 nseg 4"));
    EXPECT_NE(t.error().find("this session allows at most 300 blocks: the tunnel would leave"), std::string::npos)
        << t.error();
    // and refuses work that could pass it many times over before doing it.
    EXPECT_FALSE(t.run("tunnel a (0,-1,0) b (0,9,0) radius 1 nseg 100"));
    EXPECT_NE(t.error().find("this session allows at most 300 blocks: the tunnel could cut 1 blocks into up to 8002 "
                             "pieces each"),
              std::string::npos)
        << t.error();
    EXPECT_EQ(t.model.blocks.size(), 1);
}
