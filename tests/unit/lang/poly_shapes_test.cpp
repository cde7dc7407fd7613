// 'poly' for shapes beyond convex solids with planar faces: tapered prisms, prism sides that
// are not planar, solids that are not convex (made of joined convex blocks); and the overlap
// tolerance that refuses to cycle blocks made overlapping ('set ovtol').
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "engine/polyhedron.h"
#include "test_util.h"

using odec::test::Session;
using namespace odec;

namespace {

std::string tmp_path(const std::string& name) {
    return std::string(access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp") + "/odec_poly_shapes_" +
           std::to_string(getpid()) + "_" + name;
}

std::string save_bytes(const Model& m) {
    const std::string path = tmp_path("m.sav");
    std::string error;
    EXPECT_TRUE(save_model(m, path, error)) << error;
    const std::string bytes = odec::test::read_bytes(path);
    std::remove(path.c_str());
    return bytes;
}

// The deepest overlap between blocks, from the contacts' gaps (after a step), m.
double deepest_overlap(const Model& m) {
    double deepest = 0;
    for (double gap : m.contacts.gap) deepest = std::max(deepest, -gap);
    return deepest;
}

// Two halves of a tapered column drum, as a survey wrote them (to 0.01 mm): the side they
// share, the chord from (1.80331, 1.25698) to (0.72715, 1.79702) at the bottom, is not
// planar (its corners are 12 mm off one plane). As convex hulls they overlapped by 10.1 mm.
const char* kHalfDrum1 =
    "poly region 6 prism &\n"
    "a (1.80331,1.25698,4.32560) (1.90060,1.55673,4.32560) (1.79990,1.86342,4.32560) &\n"
    "  (1.56182,2.08473,4.32560) (1.24181,2.14816,4.32560) (0.95125,2.01764,4.32560) (0.72715,1.79702,4.32560) &\n"
    "b (1.69394,1.22596,4.73297) (1.75518,1.47421,4.73297) (1.69131,1.72329,4.73297) &\n"
    "  (1.50944,1.91039,4.73297) (1.25466,1.97185,4.73297) (1.00913,1.89066,4.73297) (0.82910,1.70864,4.73297)\n";
const char* kHalfDrum2 =
    "poly region 6 prism &\n"
    "a (0.72715,1.79702,4.32560) (0.58315,1.47958,4.32560) (0.61956,1.08657,4.32560) &\n"
    "  (0.95996,0.88538,4.32560) (1.31358,0.92248,4.32560) (1.60887,1.01846,4.32560) (1.80331,1.25698,4.32560) &\n"
    "b (0.82910,1.70864,4.73297) (0.74214,1.45947,4.73297) (0.80051,1.19156,4.73297) &\n"
    "  (1.00423,1.00518,4.73297) (1.26931,0.96451,4.73297) (1.51692,1.03997,4.73297) (1.69394,1.22596,4.73297)\n";

} // namespace

TEST(PolyShapes, TaperedPrismWithPlanarSidesIsExact) {
    // A frustum of a square pyramid: 2 x 2 m at z = 0, 1 x 1 m at z = 1. Volume
    // h (A1 + A2 + sqrt(A1 A2)) / 3 = 7/3 m^3, centroid h (A1 + 2 sqrt(A1 A2) + 3 A2) /
    // (4 (A1 + sqrt(A1 A2) + A2)) = 11/28 m above the base.
    Session s;
    ASSERT_TRUE(s.run("poly prism a (-1,-1,0) (1,-1,0) (1,1,0) (-1,1,0) b (-0.5,-0.5,1) (0.5,-0.5,1) (0.5,0.5,1) "
                      "(-0.5,0.5,1)"))
        << s.error();
    ASSERT_EQ(s.model.blocks.size(), 1);
    EXPECT_NEAR(s.model.blocks.volume[0], 7.0 / 3, 1e-14);
    EXPECT_LT((s.model.blocks.centroid[0] - Vec3(0, 0, 11.0 / 28)).norm(), 1e-14);
    EXPECT_EQ(s.error(), "");
}

TEST(PolyShapes, TaperedPrismWrittenTo5DecimalsIsMadeExactlyPlanar) {
    // A hexagonal frustum, radius 1 m at z = 0 and 0.8 m at z = 1.2, its corners written to
    // 5 decimals: each side is planar only within that rounding. It is one block, without a
    // warning, every face planar to round-off, no corner moved by more than the rounding
    // (sqrt(3) 1e-5 m), the volume that of the frustum within the rounding.
    std::string a = " a", b = " b";
    std::vector<Vec3> given;
    char buf[80];
    for (int k = 0; k < 6; ++k) {
        const double t = k * M_PI / 3 + 0.3;
        std::snprintf(buf, sizeof buf, " (%.5f,%.5f,0)", std::cos(t), std::sin(t));
        a += buf;
        given.emplace_back(std::round(1e5 * std::cos(t)) / 1e5, std::round(1e5 * std::sin(t)) / 1e5, 0);
    }
    for (int k = 0; k < 6; ++k) {
        const double t = k * M_PI / 3 + 0.3;
        std::snprintf(buf, sizeof buf, " (%.5f,%.5f,1.2)", 0.8 * std::cos(t), 0.8 * std::sin(t));
        b += buf;
        given.emplace_back(std::round(0.8e5 * std::cos(t)) / 1e5, std::round(0.8e5 * std::sin(t)) / 1e5, 1.2);
    }
    Session s;
    ASSERT_TRUE(s.run("poly prism" + a + b)) << s.error();
    EXPECT_EQ(s.error(), "");
    ASSERT_EQ(s.model.blocks.size(), 1);
    const Polyhedron& p = s.model.blocks.shape[0];
    EXPECT_EQ(p.n_faces(), 8);
    for (int f = 0; f < p.n_faces(); ++f) {
        const Vec3 n = p.face_normal(f);
        const Vec3& o = p.vertices[p.face_vertex(f, 0)];
        for (int k = 0; k < p.face_size(f); ++k) EXPECT_LT(std::abs(n.dot(p.vertices[p.face_vertex(f, k)] - o)), 1e-14);
    }
    for (const Vec3& v : p.vertices) {
        const Vec3 x = v + s.model.blocks.centroid[0];
        double nearest = 1;
        for (const Vec3& g : given) nearest = std::min(nearest, (x - g).norm());
        EXPECT_LE(nearest, std::sqrt(3.0) * 1e-5);
    }
    const double a1 = 1.5 * std::sqrt(3.0), a2 = a1 * 0.64;
    EXPECT_NEAR(s.model.blocks.volume[0], 1.2 * (a1 + a2 + std::sqrt(a1 * a2)) / 3, 5e-5);
}

TEST(PolyShapes, SidesThatAreNotPlanarAreSplitWithAWarning) {
    // A unit square turned by 10 degrees between its ends: no side is planar. Each is taken
    // as two triangles along the diagonal that keeps the block convex, so the block is the
    // convex hull of its 8 corners; the warning says how far the corners are off a plane.
    std::string a = " a", b = " b";
    std::vector<Vec3> corners;
    char buf[80];
    for (int k = 0; k < 4; ++k) {
        const double t = k * M_PI / 2, u = t + 10 * M_PI / 180;
        std::snprintf(buf, sizeof buf, " (%.17g,%.17g,0)", std::cos(t), std::sin(t));
        a += buf;
        corners.emplace_back(std::cos(t), std::sin(t), 0);
        std::snprintf(buf, sizeof buf, " (%.17g,%.17g,1)", std::cos(u), std::sin(u));
        b += buf;
        corners.emplace_back(std::cos(u), std::sin(u), 1);
    }
    Session s;
    ASSERT_TRUE(s.run("poly prism" + a + b)) << s.error();
    ASSERT_EQ(s.model.blocks.size(), 1);
    EXPECT_NE(s.error().find("t.dat:1:12: warning: prism: 4 of its 4 sides are not planar (their corners up to "),
              std::string::npos)
        << s.error();
    EXPECT_NE(s.error().find("each is taken as two triangles, split along the diagonal that keeps the block convex"),
              std::string::npos)
        << s.error();
    Polyhedron hull;
    std::string err;
    ASSERT_TRUE(make_convex_hull(corners, 1e-12, hull, err)) << err;
    EXPECT_NEAR(s.model.blocks.volume[0], mass_properties(hull).volume, 1e-13);
    EXPECT_EQ(s.model.blocks.shape[0].n_faces(), 10);
}

TEST(PolyShapes, HalvesOfADrumShareTheirSkewSideWithoutOverlap) {
    for (int order = 0; order < 2; ++order) {
        SCOPED_TRACE(order);
        Session s;
        s.interp.quiet = false;
        ASSERT_TRUE(s.run(std::string(order == 0 ? kHalfDrum1 : kHalfDrum2) + (order == 0 ? kHalfDrum2 : kHalfDrum1)))
            << s.error();
        // The second takes the first one's diagonal on the side they share, and is not convex
        // there: it is made of convex blocks, one rigid body.
        EXPECT_NE(s.error().find("or along the one the neighbouring block already has (side 7 as block 1)"),
                  std::string::npos)
            << s.error();
        EXPECT_NE(s.out.str().find("poly: the solid is not convex: made of 2 convex blocks, ids 2 to 3, one rigid body "
                                   "(clump 2); the faces between them are joint set 1, joined"),
                  std::string::npos)
            << s.out.str();
        ASSERT_EQ(s.model.blocks.size(), 3);
        s.interp.quiet = true;
        ASSERT_TRUE(s.run("prop mat=1 dens=2625\nprop jmat=1 jkn=2.95e9 jks=1.47e9 jfric=35\ngrav 0 0 -10\nstep 1"))
            << s.error();
        EXPECT_LT(deepest_overlap(s.model), 1e-9);
        EXPECT_EQ(s.model.step, 1);
    }
}

TEST(PolyShapes, SolidThatIsNotConvexIsMadeOfBlocksMovingAsOne) {
    // An L-shaped block 1 m thick: the boxes [0,2]x[0,1] and [0,1]x[1,2].
    Session s;
    s.interp.quiet = false;
    ASSERT_TRUE(s.run("config dyn\n"
                      "poly region 4 group 'ell' mat 2 face (0,0,0) (2,0,0) (2,1,0) (1,1,0) (1,2,0) (0,2,0) &\n"
                      "  face (0,0,1) (2,0,1) (2,1,1) (1,1,1) (1,2,1) (0,2,1) &\n"
                      "  face (0,0,0) (2,0,0) (2,0,1) (0,0,1)  face (2,0,0) (2,1,0) (2,1,1) (2,0,1) &\n"
                      "  face (2,1,0) (1,1,0) (1,1,1) (2,1,1)  face (1,1,0) (1,2,0) (1,2,1) (1,1,1) &\n"
                      "  face (1,2,0) (0,2,0) (0,2,1) (1,2,1)  face (0,2,0) (0,0,0) (0,0,1) (0,2,1)\n"))
        << s.error();
    EXPECT_NE(s.out.str().find("poly: the solid is not convex: made of 2 convex blocks, ids 1 to 2, one rigid body "
                               "(clump 1); the faces between them are joint set 1, joined, should the clump end "
                               "('jset', 'gen edge')\n"),
              std::string::npos)
        << s.out.str();
    EXPECT_EQ(s.error(), "");
    const BlockSet& b = s.model.blocks;
    ASSERT_EQ(b.size(), 2);
    double volume = 0;
    Vec3 moment = Vec3::Zero();
    for (int i = 0; i < 2; ++i) {
        EXPECT_EQ(b.region[i], 4);
        EXPECT_EQ(b.material[i], 2);
        EXPECT_EQ(s.model.group_names.at(b.group[i]), "ell");
        volume += b.volume[i];
        moment += b.volume[i] * b.centroid[i];
    }
    EXPECT_NEAR(volume, 3.0, 1e-13);
    EXPECT_LT((moment / volume - Vec3(2.5 / 3, 2.5 / 3, 0.5)).norm(), 1e-13);
    // They are one rigid body (a clump, clump.h): a velocity given to block 2, away from block 1
    // across the face between them, is the clump's; both move with it, and no contact forms
    // between them.
    const Vec3 away = (b.centroid[1] - b.centroid[0]).normalized() * 0.014;
    s.interp.quiet = true;
    char ini[160];
    std::snprintf(ini, sizeof ini, "ini xvel %.17g yvel %.17g range id 2", away.x(), away.y());
    ASSERT_TRUE(s.run("prop mat=2 dens=2500\nprop jmat=1 jkn=1e9 jks=1e9 jfric=30\ndamp off\n" + std::string(ini) +
                      "\nstep time 0.1"))
        << s.error();
    const ContactSet& cs = s.model.contacts;
    EXPECT_EQ(cs.size(), 0);
    EXPECT_EQ(b.clump[0], 1);
    EXPECT_EQ(b.clump[1], 1);
    EXPECT_NEAR(b.mass[0] + b.mass[1], 2500 * 3.0, 1e-9);
    const double t = s.model.time;
    for (int i = 0; i < 2; ++i) EXPECT_LT((b.disp[i] - away * t).norm(), 1e-12);
}

TEST(PolyShapes, OverlapBeyondTheToleranceStopsTheFirstStep) {
    Session s;
    ASSERT_TRUE(s.run("prop mat=1 dens=2500\nprop jmat=1 jkn=1e9 jks=1e9 jfric=30\n"
                      "poly brick 0 1 0 1 0 1\npoly brick 0 1 0 1 0.99 2\n"  // 10 mm deep
                      "poly brick 2 3 0 1 0 1\npoly brick 2 3 0 1 0.996 2\n" // 4 mm: under 0.5 % of 1 m
                      "fix range z 0 0.5\ngrav 0 0 -10"))
        << s.error();
    const std::string before = save_bytes(s.model);
    EXPECT_FALSE(s.run("step 10"));
    EXPECT_EQ(s.error(),
              "t.dat:1:1: error: 1 pair of blocks overlap deeper than the overlap tolerance (0.5 % of the smaller "
              "block's size, the cube root of its volume) where they carry no stress yet, and their joints would "
              "throw them apart at the first step (correct their coordinates, or let the joints push them apart "
              "with a larger 'set ovtol'):\n"
              "    blocks 1 and 2 overlap 0.01 m deep near (0.5,0.5,0.995) (tolerance 0.005 m)\n"
              "    step 10\n"
              "    ^~~~\n"
              "  see 'help step'\n");
    // Refused before any step: the model is as it was.
    EXPECT_EQ(s.model.step, 0);
    EXPECT_EQ(save_bytes(s.model), before);
    // Allowed, the joints push the pair apart (block 2 leaves at metres a second).
    s.err.str("");
    ASSERT_TRUE(s.run("set ovtol 0.02\nstep 10")) << s.error();
    EXPECT_EQ(s.model.settings.ovtol, 0.02);
    EXPECT_GT(s.model.blocks.vel[1].z(), 1.0);
    // Cycled on, the overlaps carry stress: new blocks elsewhere do not bring the check back
    // to them, while a new overlap is named alone.
    ASSERT_TRUE(s.run("set ovtol 0\npoly brick 5 6 0 1 0 1\nstep 1")) << s.error();
    EXPECT_FALSE(s.run("poly brick 5 6 0 1 0.98 2\nstep 1"));
    EXPECT_NE(s.error().find("blocks 5 and 6 overlap 0.02 m deep"), std::string::npos) << s.error();
    EXPECT_EQ(s.error().find("blocks 1 and 2"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("set ovtol -1"));
}

TEST(PolyShapes, OverlapToleranceIsSavedAndShown) {
    Session s;
    s.interp.quiet = false;
    ASSERT_TRUE(s.run("print info")) << s.error();
    EXPECT_NE(s.out.str().find("overlap:    at most 0.5 % of the smaller block's size (automatic) where unstressed\n"),
              std::string::npos)
        << s.out.str();
    const std::string path = tmp_path("ovtol");
    ASSERT_TRUE(s.run("set ovtol 0.003\nsave '" + path + "'\nnew\nrestore '" + path + "'\nprint info")) << s.error();
    std::remove((path + ".sav").c_str());
    EXPECT_EQ(s.model.settings.ovtol, 0.003);
    EXPECT_NE(s.out.str().find("overlap:    at most 0.003 m (set ovtol) where unstressed\n"), std::string::npos)
        << s.out.str();
}
