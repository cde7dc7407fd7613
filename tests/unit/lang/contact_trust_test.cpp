// Contacts report what the blocks really do: blocks cut from one block start without
// force, edge and corner neighbours carry nothing through an area they do not have, and
// the joints of a stack carry the weight above them.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <sstream>

#include "engine/blocks.h"
#include "engine/contact.h"
#include "test_util.h"

using odec::test::Session;
using Vec3 = Eigen::Vector3d;

namespace {

// The model of the report: three joint sets, two of them not orthogonal to the others.
const char* kThreeSets =
    "poly brick 0 10 0 10 0 12\n"
    "jset dip 0 dd 0 origin 0,0,1 spacing 1.5 number 6\n"
    "jset dip 70 dd 90 origin 5,0,0 spacing 2 number 4\n"
    "jset dip 80 dd 10 origin 0,5,0 spacing 2.5 number 3\n"
    "prop mat=1 dens=2600\n"
    "prop jmat=1 jkn=5e9 jks=2e9 jfric=30\n"
    "fix range z 0 1\n"
    "grav 0 0 -10\n";

double largest_speed(const odec::Model& m) {
    double v = 0;
    for (int b = 0; b < m.blocks.size(); ++b) v = std::max(v, odec::velocity_at_t(m, b).norm());
    return v;
}

// Vertical force (N) that contact c passes from block a to block b, upward positive on the upper block.
double vertical_force(const odec::Model& m, int c) {
    const odec::ContactInfo ci = odec::contact_info(m, c);
    // Force on b: compression pushes b along the normal (from a to b), shear acts as stored.
    const Vec3 f = ci.area * (ci.normal_stress * ci.normal + ci.shear_stress_vec);
    const bool b_above = m.blocks.centroid[ci.block_b].z() > m.blocks.centroid[ci.block_a].z();
    return b_above ? f.z() : -f.z();
}

struct LevelLoad {
    double faces = 0;  // N carried by contacts whose normal is vertical
    double others = 0; // N carried vertically by every other contact (edges, corners, sides)
};

// Vertical load carried across each horizontal joint level z (rounded to mm).
std::map<long, LevelLoad> loads_by_level(const odec::Model& m) {
    std::map<long, LevelLoad> out;
    for (int c = 0; c < m.contacts.size(); ++c) {
        const odec::ContactInfo ci = odec::contact_info(m, c);
        const double za = m.blocks.centroid[ci.block_a].z(), zb = m.blocks.centroid[ci.block_b].z();
        if (std::abs(za - zb) < 1e-6) continue; // side by side: no joint level between them
        const long level = std::lround(1000 * ci.centroid.z());
        if (std::abs(ci.normal.z()) > 1 - 1e-6) out[level].faces += vertical_force(m, c);
        else out[level].others += vertical_force(m, c);
    }
    return out;
}

// A fixed base and a 1 m cube turned 45 degrees about x, standing exactly on one edge on it.
std::string cube_on_its_edge() {
    const double h = std::sqrt(0.5);
    std::ostringstream cube;
    cube << "poly brick -2 3 -2 2 -1 " << std::to_string(-h) << "\n";
    cube << "poly prism a (0,0," << h << ") (0," << h << ",0) (0,0,-" << h << ") (0,-" << h << ",0) b (1,0," << h
         << ") (1," << h << ",0) (1,0,-" << h << ") (1,-" << h << ",0)\n";
    return cube.str();
}

} // namespace

TEST(ContactTrust, CutBlocksStartWithoutForce) {
    Session s;
    ASSERT_TRUE(s.run(std::string(kThreeSets) + "step 1")) << s.error();
    const odec::ContactSet& cs = s.model.contacts;
    ASSERT_GT(cs.size(), 500);
    // After one step under gravity the joints have closed by g dt^2 at most: stresses of
    // kn g dt^2 / 2 (a few mPa), nowhere near the 7e8 Pa that a wrong plane gave.
    const double dt = s.model.dt, g = 10, kn = 5e9;
    for (int k = 0; k < cs.n_subs(); ++k) {
        EXPECT_LE(std::abs(odec::sub_normal_stress(s.model, k)), kn * g * dt * dt) << "sub-contact " << k;
        EXPECT_LE(cs.sub_un[k], g * dt * dt) << "sub-contact " << k;
    }
}

TEST(ContactTrust, NoBlockOutrunsFreeFall) {
    Session s;
    ASSERT_TRUE(s.run("config dyn\n" + std::string(kThreeSets) + "step 200")) << s.error();
    // Joints only hold blocks back: nothing may move faster than a block falling freely.
    EXPECT_LE(largest_speed(s.model), 10.0 * s.model.time);
}

TEST(ContactTrust, StackJointsCarryTheWeightAbove) {
    // 1 m cubes, 3 x 3 in plan and 3 high, on a fixed base.
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 3 0 3 -1 3\n"
                      "jset dip 0 dd 0 origin 0,0,1 spacing 1 number 3\n"
                      "jset dip 90 dd 90 origin 1.5,0,0 spacing 1 number 2\n"
                      "jset dip 90 dd 0 origin 0,1.5,0 spacing 1 number 2\n"
                      "prop mat=1 dens=2000\nprop jmat=1 jkn=1e9 jks=1e9 jfric=30\ngrav 0 0 -10\n"
                      "fix range z -1 0\nsolve ratio 1e-6"))
        << s.error();
    ASSERT_EQ(s.model.blocks.size(), 36);
    const double rho_g = 2000 * 10.0;
    // Every face contact of a horizontal joint at z carries rho g (3 - z) on its 1 m^2.
    int n_faces = 0;
    for (int c = 0; c < s.model.contacts.size(); ++c) {
        const odec::ContactInfo ci = odec::contact_info(s.model, c);
        if (std::abs(ci.normal.z()) < 1 - 1e-6 || ci.area < 0.5) continue;
        const double z = std::round(ci.centroid.z());
        EXPECT_NEAR(ci.normal_stress, rho_g * (3 - z), 0.005 * rho_g * (3 - z)) << "contact " << ci.id;
        EXPECT_NEAR(ci.area, 1.0, 1e-9);
        ++n_faces;
    }
    EXPECT_EQ(n_faces, 27);
    // Edge and corner neighbours carry nothing of the load.
    for (const auto& [level, load] : loads_by_level(s.model)) {
        EXPECT_LE(std::abs(load.others), 0.005 * std::abs(load.faces)) << "level z " << level / 1000.0;
    }
}

TEST(ContactTrust, RunningBondJointsCarryTheWeightAbove) {
    // A wall of 2 x 1 x 1 m bricks laid in running bond, four courses on a fixed base.
    std::ostringstream script;
    script << "poly brick 0 6 0 1 -1 0\n";
    for (int course = 0; course < 4; ++course) {
        const double z0 = course, z1 = course + 1;
        std::vector<double> x = course % 2 == 0 ? std::vector<double>{0, 2, 4, 6} : std::vector<double>{0, 1, 3, 5, 6};
        for (size_t i = 0; i + 1 < x.size(); ++i) {
            script << "poly brick " << x[i] << " " << x[i + 1] << " 0 1 " << z0 << " " << z1 << "\n";
        }
    }
    script << "prop mat=1 dens=2500\nprop jmat=1 jkn=2e9 jks=1e9 jfric=35\ngrav 0 0 -10\nfix range z -1 0\n"
              "solve ratio 1e-6";
    Session s;
    ASSERT_TRUE(s.run(script.str())) << s.error();
    const double weight_per_course = 2500 * 10.0 * 6.0; // N: 6 m^3 a course
    const auto loads = loads_by_level(s.model);
    ASSERT_EQ(loads.size(), 4u);
    for (const auto& [level, load] : loads) {
        const double above = weight_per_course * (4 - level / 1000.0);
        EXPECT_NEAR(load.faces, above, 0.005 * above) << "level z " << level / 1000.0;
        EXPECT_LE(std::abs(load.others), 0.005 * above) << "level z " << level / 1000.0;
    }
}

TEST(ContactTrust, JointedCubeContactsAreConsistent) {
    // The tutorial's jointed block, settled for a while.
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 6 0 6 -2 6\n"
                      "jset dip 0 dd 0 origin 0,0,2 spacing 2 number 3\n"
                      "jset dip 75 dd 90 origin 3,0,0 spacing 2 number 3\n"
                      "jset dip 80 dd 0 origin 0,3,0 spacing 3 number 1\n"
                      "prop mat=1 dens=2600\nprop jmat=1 jkn=5e9 jks=2e9 jfric=35 jcoh=0 jten=0\n"
                      "grav 0 0 -10\nfix range z -2 0\ndelete range x 4.5 6 z 2 6\n"
                      "solve ratio 1e-4 cycles 3000"))
        << s.error();
    const odec::Model& m = s.model;
    const odec::ContactSet& cs = m.contacts;
    const double kn = 5e9;
    ASSERT_GT(cs.size(), 50);
    for (int c = 0; c < cs.size(); ++c) {
        const odec::ContactInfo ci = odec::contact_info(m, c);
        EXPECT_NEAR(ci.normal.norm(), 1.0, 1e-12) << "contact " << ci.id;
        if (ci.area == 0) {
            // No touching area: nothing to carry (its sub-contacts, if any, are all open).
            for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
                EXPECT_TRUE(cs.sub_flags(k) & odec::kSubOpen) << "contact " << ci.id;
            }
            EXPECT_EQ(ci.normal_stress, 0) << "contact " << ci.id;
            EXPECT_EQ(ci.shear_stress, 0) << "contact " << ci.id;
        }
        bool all_closed = ci.n_subs > 0;
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
            const double closure = odec::sub_closure(m, c, k) + cs.sub_dilation(k);
            if (cs.sub_flags(k) & odec::kSubOpen) {
                EXPECT_EQ(odec::sub_normal_stress(s.model, c, k), 0) << "open sub-contact " << k << " of contact " << ci.id;
                EXPECT_EQ(cs.sub_ss[k].norm(), 0) << "open sub-contact " << k << " of contact " << ci.id;
                EXPECT_LE(closure, 0) << "open sub-contact " << k << " of contact " << ci.id;
                all_closed = false;
            } else {
                // No cohesion, no tension: a stressed point is closed, by sn / kn exactly.
                EXPECT_NEAR(odec::sub_normal_stress(s.model, c, k), kn * closure, 1e-9 * kn * std::abs(closure) + 1e-9)
                    << "sub-contact " << k << " of contact " << ci.id;
            }
        }
        if (all_closed) {
            EXPECT_NEAR(ci.normal_stress, kn * ci.normal_disp, 1e-9 * std::abs(ci.normal_stress) + 1e-6)
                << "contact " << ci.id;
        }
        // Closures are a fraction of a millimetre here: nothing like the tolerance band.
        EXPECT_LT(std::abs(ci.normal_disp), 1e-3) << "contact " << ci.id;
    }
}

TEST(ContactTrust, PrintMaxIgnoresContactsWithoutArea) {
    // Two cubes side by side and one diagonal to them, all resting on a base: the diagonal
    // pair touches along an edge only, and must not be where any maximum is reported.
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 -1 0\npoly brick 0 1 0 1 0 1\npoly brick 1 2 1 2 0 1\n"
                      "poly brick 1 2 1 2 -1 0\nprop mat=1 dens=2000\nprop jmat=1 jkn=1e9 jks=1e9 jfric=30\n"
                      "grav 0 0 -10\nfix range z -1 0\nsolve ratio 1e-6\nprint max"))
        << s.error();
    const std::string out = s.out.str();
    int n_without_area = 0;
    for (int c = 0; c < s.model.contacts.size(); ++c) {
        const odec::ContactInfo ci = odec::contact_info(s.model, c);
        if (ci.area > 0) continue;
        ++n_without_area;
        EXPECT_EQ(out.find("at contact " + std::to_string(ci.id) + " "), std::string::npos) << out;
    }
    EXPECT_GT(n_without_area, 0);
    EXPECT_NE(out.find("joint normal stress  20000 Pa"), std::string::npos) << out;
}

TEST(ContactTrust, AnEdgeThatPressesInIsFeltAtOnce) {
    // A cube standing exactly on one edge (turned 45 degrees about x) on a fixed base: the
    // contact starts with no area; as the edge presses in, sub-contacts appear while the
    // overlap is still a small fraction of the contact tolerance, not after ctol/10 of motion.
    Session s;
    ASSERT_TRUE(s.run(cube_on_its_edge() + "prop mat=1 dens=2600\nprop jmat=1 jkn=1e10 jks=1e10 jfric=30\ngrav 0 0 -10\n"
                      "fix range z -1 -0.8\nset dt 1e-5"))
        << s.error();
    const odec::ContactSet& cs = s.model.contacts;
    double worst = 0;
    for (int k = 0; k < 3000; ++k) {
        ASSERT_TRUE(s.run("step 1")) << s.error();
        for (int j = 0; j < cs.n_subs(); ++j) {
            if (cs.sub_flags(j) & odec::kSubNew) worst = std::max(worst, cs.sub_un[j]);
        }
    }
    ASSERT_GT(cs.n_subs(), 0); // the edge does press in
    EXPECT_LT(worst, 0.02 * cs.ctol) << "ctol " << cs.ctol;
}

TEST(ContactTrust, ACubeRockingOnItsEdgeMakesNoEnergy) {
    // Undamped, a cube set down exactly on one edge oscillates on it: its centroid may never
    // rise above where it started, and the swing must not grow (a force that stiffened as
    // the edge pressed in, with its area updated in jumps, made energy here).
    Session s;
    ASSERT_TRUE(s.run(cube_on_its_edge() + "prop mat=1 dens=2600\nprop jmat=1 jkn=1e9 jks=1e9 jfric=30\ngrav 0 0 -10\n"
                      "fix range z -1 -0.8\nset dt 1e-5\ndamp off\nhist ncyc 10\nhist zdis 0.5,0,0\nhist zvel 0.5,0,0\n"
                      "step 60000"))
        << s.error();
    const auto& z = s.model.histories.items[0].values;
    const auto& v = s.model.histories.items[1].values;
    ASSERT_EQ(z.size(), 6000u);
    double first = 0, last = 0;
    for (size_t i = 0; i < z.size(); ++i) {
        EXPECT_LE(z[i], 1e-7) << "sample " << i;
        (i < z.size() / 4 ? first : last) = std::max(i < z.size() / 4 ? first : last, i >= 3 * z.size() / 4 || i < z.size() / 4 ? std::abs(v[i]) : 0.0);
    }
    EXPECT_GT(first, 0.0);
    EXPECT_LE(last, 1.02 * first);
}

TEST(ContactTrust, AContactMadeWithoutJointPropertiesStopsTheRun) {
    // A block dropped 0.2 m onto another: the joint material given is 2, but contacts made while
    // cycling take 'set jmat' (1, never given). Where they meet, the run stops and says so,
    // instead of letting the block fall through unheld.
    const std::string model = "config dyn\npoly brick 0 1 0 1 0 1\npoly brick 0 1 0 1 1.2 2.2\nprop mat=1 dens=2000\n"
                              "prop jmat=2 jkn=1e9 jks=1e9 jfric=30\ngrav 0 0 -10\nfix range z 0 1\n";
    {
        Session s;
        s.check_save_at_end = false;
        EXPECT_FALSE(s.run(model + "solve time 0.5"));
        EXPECT_NE(s.error().find("has joint material 1, which has no properties"), std::string::npos) << s.error();
        EXPECT_NE(s.error().find("set jmat n"), std::string::npos) << s.error();
        // It stopped as the block reached the base, not after it had sunk in.
        EXPECT_GT(s.model.blocks.centroid[1].z(), 1.5 - 0.01);
    }
    {
        Session s;
        ASSERT_TRUE(s.run(model + "set jmat 2\nsolve time 0.5")) << s.error();
        // Landed and held: it bounces on the joint, by at most v sqrt(m / k) = 2.8 mm.
        EXPECT_NEAR(s.model.blocks.centroid[1].z(), 1.5, 5e-3);
    }
}

// A dam on a foundation cut every metre, its reservoir pushing it and its base's water lifting it,
// slides when its friction is cut below its limit: its toe passes onto the block beyond, whose end
// face stood in one plane with the dam's. Their contact was an edge against an edge across that
// upright plane and turns into a face on a face. Its points take the closure the geometry shows,
// not the one gathered across the upright plane as the toe went through it (9.9 mm, 98 MPa
// holding the toe up, and the dam stood where it should slide).
TEST(ContactTrust, AContactThatTurnsKeepsNoClosureFromItsOldPlane) {
    std::string script = "config flow\nfluid density 1000 viscosity 1e-3 bulk 2e9\ngrav 0 0 -9.81\npoly brick -10 0 0 2 -10 0\n";
    for (int x = 0; x < 10; ++x) script += "poly brick " + std::to_string(x) + " " + std::to_string(x + 1) + " 0 2 -10 0\n";
    script += "poly brick 10 30 0 2 -10 0\npoly brick 0 10 0 2 0 20\nprop mat=1 dens=2400\n"
              "prop jmat=1 jkn=1e10 jks=1e10 jfric=35 azero=1e-4 ares=1e-5\nfix range z -10 0\n"
              "bound pp 196200 range x -0.01 0.01 z -0.01 0.01\nbound pp 19620 range x 9.99 10.01 z -0.01 0.01\n"
              "bound stress -196200 0 0 0 0 0 zgrad 9810 0 0 0 0 0 range x -0.01 0.01 z 0 20\nsolve\n"
              "prop jmat=1 jfric=25.03\nstep 1500\n";
    Session s;
    ASSERT_TRUE(s.run(script)) << s.error();
    const odec::ContactSet& cs = s.model.contacts;
    const int dam = s.model.block_index(13), beyond = s.model.block_index(12);
    ASSERT_GT(s.model.blocks.disp[dam].x(), 0.02); // the toe is on the block beyond
    bool found = false;
    for (int c = 0; c < cs.size(); ++c) {
        if (cs.block_a[c] != beyond || cs.block_b[c] != dam) continue;
        found = true;
        EXPECT_GT(cs.normal(c).z(), 0.999) << "the contact is a face on a face now";
        // The dam's base is flat and hardly turned: its points' closures differ by little.
        double lo = 1e9, hi = -1e9;
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
            lo = std::min(lo, cs.sub_un[k]);
            hi = std::max(hi, cs.sub_un[k]);
        }
        EXPECT_LT(hi - lo, 1e-3) << "closures from " << lo << " to " << hi << " m";
    }
    EXPECT_TRUE(found);
}

// Two pieces of neighbouring voussoirs of the collapsing corpus arch as they stood at 1.02 s: an
// edge of the first crosses an edge of the second 0.7 mm deep (the common plane's overlap), while
// the corner at the end of that edge grazes in by nanometres. The crossing carries the contact
// with its closure. Before, the grazing corner alone carried it with its own (large) area, the
// crossing's overlap was unfelt, and as the corner lifted out and in again at every refresh the
// contact flipped between the two, its springs born again each time: the pieces sank 3 to 57 mm
// into each other.
TEST(ContactTrust, ACrossingDeeperThanAGrazingCornerCarriesTheContact) {
    Session s;
    ASSERT_TRUE(s.interp.run_file(std::string(ODEC_SOURCE_DIR) + "/tests/scripts/arch-pieces-crossing.dat")) << s.error();
    ASSERT_TRUE(s.run("prop mat=1 dens=1220.5\nprop jmat=1 jkn=2e11 jks=8e10 jfric=43\nset ctol 0.03459\n"
                      "set ovtol 0.01\nconfig dyn\nstep 1")) << s.error();
    const odec::ContactSet& cs = s.model.contacts;
    ASSERT_EQ(cs.size(), 1);
    double deepest = 0, deepest_corner = -1;
    for (int k = cs.sub_offset[0]; k < cs.sub_offset[1]; ++k) {
        const double closure = cs.sub_un[k] + cs.sub_dilation(k);
        deepest = std::max(deepest, closure);
        if (cs.sub_side(k) < 2) deepest_corner = std::max(deepest_corner, closure);
    }
    EXPECT_NEAR(deepest, -cs.gap[0], 0.05 * -cs.gap[0]);
    EXPECT_GT(deepest, 5e-4);
    EXPECT_LT(deepest_corner, 0.01 * deepest); // the corner only grazes
}
