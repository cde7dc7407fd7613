// Contacts of deformable blocks: gridpoints against rigid faces and against the surface
// triangles of other deformable blocks, checked against the statics and the friction law.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <unistd.h>

#include "engine/contact.h"
#include "engine/zones.h"
#include "test_util.h"

using namespace odec;
using odec::test::Session;

namespace {

// Sum of the normal forces a contact carries, N.
double normal_force(const Model& m, int c) {
    const ContactSet& cs = m.contacts;
    double f = 0;
    for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) f += cs.sub_area[k] * odec::sub_normal_stress(m, c, k);
    return f;
}

int contact_between(const Model& m, int block_a_id, int block_b_id) {
    const int a = m.block_index(block_a_id), b = m.block_index(block_b_id);
    for (int c = 0; c < m.contacts.size(); ++c) {
        if (m.contacts.block_a[c] == std::min(a, b) && m.contacts.block_b[c] == std::max(a, b)) return c;
    }
    return -1;
}

const char* kBlockOnBase =
    "poly brick 0 1 0 1 -1 0\n"
    "poly brick 0 1 0 1 0 1\n"
    "prop mat=1 dens=2500 ymod=10e9 prat=0.25\n"
    "prop jmat=1 jkn=1e11 jks=1e11 jfric=30\n"
    "set jmat 1\n"
    "fix range z -1 0\n"
    "gen edge 0.25 range z 0 1\n";

} // namespace

// A 1 m elastic cube resting on a fixed rigid base through a joint. At rest the joint carries
// the weight, rho g H = 25 kPa over the face, closed by sigma / kn; the top settles by the
// column's own shortening rho g H^2 / (2 E) plus that closure.
TEST(ZoneContacts, RigidBaseCarriesADeformableBlock) {
    Session s;
    ASSERT_TRUE(s.run(std::string(kBlockOnBase) + "grav 0 0 -10\nsolve ratio 1e-7")) << s.error();
    const Model& m = s.model;
    ASSERT_EQ(m.contacts.size(), 1);
    const ContactInfo ci = contact_info(m, 0);
    const double sigma = 2500.0 * 10.0 * 1.0;
    EXPECT_NEAR(ci.area, 1.0, 1e-9);                      // the gridpoints' areas tile the face
    EXPECT_NEAR(ci.normal_stress, sigma, 1e-3 * sigma);   // 0.1 %
    EXPECT_NEAR(ci.normal_disp, sigma / 1e11, 1e-3 * sigma / 1e11);
    // Every sub-contact is a gridpoint of the deformable block pressing on the rigid face.
    for (int k = 0; k < m.contacts.n_subs(); ++k) {
        EXPECT_EQ(m.contacts.sub_side(k), 4);
        EXPECT_EQ(m.contacts.sub_triangle(k)[0], -1);
    }
    const int top = find_gridpoint_near(m, Vec3(0.5, 0.5, 1.0));
    ASSERT_GE(top, 0);
    const double expected = 2500.0 * 10.0 * 1.0 / (2.0 * 10e9) + sigma / 1e11;
    EXPECT_NEAR(-m.gridpoints.disp[top].z(), expected, 0.02 * expected); // 2 %: tetrahedra, base friction
    // The reaction read at the fixed base is the force the model puts on it, its own weight
    // and the block's through the joint: 2 x 25 kN, downward.
    ASSERT_TRUE(s.run("hist zreaction range z -1 0\nstep 10")) << s.error();
    ASSERT_FALSE(s.model.histories.items.back().values.empty());
    EXPECT_NEAR(s.model.histories.items.back().values.back(), -50000.0, 50.0);
}

// Two deformable blocks zoned apart (different sizes, so their gridpoints do not line up):
// the upper one's weight crosses the deformable-deformable joint, and both weights the base.
TEST(ZoneContacts, DeformableBlocksCarryEachOther) {
    Session s;
    ASSERT_TRUE(s.run(std::string(kBlockOnBase) +
                      "poly brick 0.2 0.8 0.2 0.8 1 1.5\n"
                      "gen edge 0.15 range z 1 1.5\n"
                      "grav 0 0 -10\nsolve ratio 1e-7"))
        << s.error();
    const Model& m = s.model;
    const int upper = contact_between(m, 2, 3), lower = contact_between(m, 1, 2);
    ASSERT_GE(upper, 0);
    ASSERT_GE(lower, 0);
    const double w_top = 2500.0 * 10.0 * 0.6 * 0.6 * 0.5, w_mid = 2500.0 * 10.0 * 1.0;
    EXPECT_NEAR(normal_force(m, upper), w_top, 1e-3 * w_top);
    EXPECT_NEAR(normal_force(m, lower), w_top + w_mid, 1e-3 * (w_top + w_mid));
    // Both blocks' gridpoints press on the other's surface triangles.
    bool side3 = false, side4 = false;
    for (int k = m.contacts.sub_offset[upper]; k < m.contacts.sub_offset[upper + 1]; ++k) {
        side3 |= m.contacts.sub_side(k) == 3;
        side4 |= m.contacts.sub_side(k) == 4;
        EXPECT_GE(m.contacts.sub_triangle(k)[0], 0);
        EXPECT_NEAR(m.contacts.sub_point_local(k).sum(), 1.0, 1e-9); // weights of a point in its triangle
    }
    EXPECT_TRUE(side3 && side4);
}

// Gravity tilted 40 degrees on a joint of friction 30: the block slides, undamped, at
// a = g (sin 40 - cos 40 tan 30) = 2.005 m/s^2. Tilted 20 degrees and damped to rest, it stays
// put, the joint carrying rho g H (cos 20, sin 20). (Undamped, a block dropped on an unloaded
// joint bounces: each time the joint opens it loses its grip and creeps down the slope.)
TEST(ZoneContacts, FrictionHoldsOrLetsGoAsCoulombSays) {
    const double g = 10.0, phi = 30.0 * M_PI / 180.0;
    for (const double deg : {40.0, 20.0}) {
        const double th = deg * M_PI / 180.0;
        Session s;
        char grav[96];
        std::snprintf(grav, sizeof grav, "grav %.12g 0 %.12g\n", g * std::sin(th), -g * std::cos(th));
        // Sliding is timed: real masses (the holding case is the same equilibrium either way).
        ASSERT_TRUE(s.run("config dyn\npoly brick -1 3 -1 2 -1 0\npoly brick 0 1 0 1 0 1\n"
                          "prop mat=1 dens=2500 ymod=10e9 prat=0.25\nprop jmat=1 jkn=1e10 jks=1e10 jfric=30\n"
                          "set jmat 1\nfix range z -1 0\ngen edge 0.25 range z 0 1\n" +
                          std::string(grav) + (deg > 30 ? "damp off\nsolve time 0.2" : "solve ratio 1e-6")))
            << s.error();
        const Model& m = s.model;
        // Mean velocity of the block's gridpoints (its centre of mass moves with it).
        double vx = 0;
        for (int i = 0; i < m.gridpoints.size(); ++i) vx += m.gridpoints.vel[i].x();
        vx /= m.gridpoints.size();
        const double a = g * (std::sin(th) - std::cos(th) * std::tan(phi));
        if (a > 0) {
            EXPECT_NEAR(vx, a * m.time, 0.02 * a * m.time) << deg; // 2 %: elastic ringing, undamped
        } else {
            const ContactInfo ci = contact_info(m, 0);
            EXPECT_LT(ci.shear_disp, 1e-5) << deg; // elastic shear only
            EXPECT_NEAR(ci.normal_stress, 25000.0 * std::cos(th), 0.01 * 25000.0 * std::cos(th));
            EXPECT_NEAR(ci.shear_stress, 25000.0 * std::sin(th), 0.01 * 25000.0 * std::sin(th));
        }
    }
}

// A model with deformable contacts saved in the middle of a run continues to the same bits.
TEST(ZoneContacts, SaveAndRestoreContinueToTheSameBits) {
    char dir[] = "/tmp/odec-zc-XXXXXX";
    ASSERT_NE(mkdtemp(dir), nullptr);
    const std::string path = std::string(dir) + "/drop.sav";
    const std::string script = std::string(kBlockOnBase) + "poly brick 0.2 0.8 0.2 0.8 1 1.5\n"
                               "gen edge 0.2 range z 1 1.5\ngrav 0 0 -10\ndamp off\nstep 150\n";
    Session a, b;
    ASSERT_TRUE(a.run(script + "save '" + path + "'\nstep 150")) << a.error();
    ASSERT_TRUE(b.run("restore '" + path + "'\nstep 150")) << b.error();
    const GridpointSet& ga = a.model.gridpoints;
    const GridpointSet& gb = b.model.gridpoints;
    ASSERT_EQ(ga.size(), gb.size());
    for (int i = 0; i < ga.size(); ++i) {
        ASSERT_EQ(ga.pos[i], gb.pos[i]) << i;
        ASSERT_EQ(ga.vel[i], gb.vel[i]) << i;
    }
    ASSERT_EQ(a.model.contacts.sub_un, b.model.contacts.sub_un);
    // The upper block presses on the middle one: their contact carries load.
    const int c = contact_between(a.model, 2, 3);
    ASSERT_GE(c, 0);
    EXPECT_GT(normal_force(a.model, c), 0.0);
    std::remove(path.c_str());
    rmdir(dir);
}

// Taking the base away lets the block fall freely: its contact goes with it.
TEST(ZoneContacts, RemovingTheBaseLetsTheBlockFall) {
    Session s;
    // The fall is timed: real masses.
    ASSERT_TRUE(s.run("config dyn\n" + std::string(kBlockOnBase) + "grav 0 0 -10\nsolve ratio 1e-6\n"
                      "delete range z -1 0\ndamp off\nini zvel 0\nreset disp"))
        << s.error();
    const double t0 = s.model.time;
    ASSERT_TRUE(s.run("solve time 0.05")) << s.error();
    const Model& m = s.model;
    const double t = m.time - t0;
    EXPECT_EQ(m.contacts.size(), 0);
    const int top = find_gridpoint_near(m, Vec3(0.5, 0.5, 1.0));
    // Free fall from rest, less the small rebound of the column released from its weight.
    EXPECT_NEAR(m.gridpoints.disp[top].z(), -0.5 * 10.0 * t * t, 2e-3 * 0.5 * 10.0 * t * t);
}

// Two blocks zoned apart, confined on rollers, given the in-situ stress of their own weight
// (szz = -rho g (2 - z), sxx = syy = nu / (1 - nu) szz): 'insitu' loads the joint between them
// too, so gravity finds everything in equilibrium and nothing moves. Without the joint's
// share the upper block would drop onto an unloaded joint.
TEST(ZoneContacts, InsituStressLoadsTheJointsToo) {
    const std::string model =
        "poly brick 0 1 0 1 0 1\npoly brick 0 1 0 1 1 2\n"
        "prop mat=1 dens=2500 ymod=10e9 prat=0.25\nprop jmat=1 jkn=1e11 jks=1e11 jfric=30\nset jmat 1\n"
        "gen edge 0.25\nbound zvel 0 range z -0.001 0.001\n"
        "bound xvel 0 range x -0.001 0.001\nbound xvel 0 range x 0.999 1.001\n"
        "bound yvel 0 range y -0.001 0.001\nbound yvel 0 range y 0.999 1.001\ngrav 0 0 -10\n";
    const std::string insitu = "insitu stress -16666.6667 -16666.6667 -50000 0 0 0 zgrad 8333.33333 8333.33333 25000 0 0 0\n";
    Session s;
    ASSERT_TRUE(s.run(model + insitu)) << s.error();
    ASSERT_EQ(s.model.contacts.size(), 1);
    const double sigma = 2500.0 * 10.0 * 1.0; // the upper block's weight over its base
    EXPECT_NEAR(contact_info(s.model, 0).normal_stress, sigma, 1e-6 * sigma);
    EXPECT_NEAR(contact_info(s.model, 0).normal_disp, sigma / 1e11, 1e-6 * sigma / 1e11);
    ASSERT_TRUE(s.run("damp off\nstep 300")) << s.error();
    double most = 0;
    for (const Vec3& d : s.model.gridpoints.disp) most = std::max(most, d.norm());
    // Dropped onto an unloaded joint it would close by sigma / kn = 2.5e-7 m: a million times more.
    EXPECT_LT(most, 1e-13);
    EXPECT_NEAR(contact_info(s.model, 0).normal_stress, sigma, 1e-6 * sigma);
}

// A 2 x 2 x 2 stack of deformable blocks (three joint sets, zoned apart) on rollers: the joint
// at mid-height carries the whole weight of the upper layer, and the blocks that meet only
// along an edge or at a corner carry nothing, however they settle.
TEST(ZoneContacts, ARegularStackLosesNoLoadToEdgeAndCornerContacts) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 2 0 2 0 2\njset dip 0 dd 0 origin 0,0,1\njset dip 90 dd 90 origin 1,0,0\n"
                      "jset dip 90 dd 0 origin 0,1,0\nprop mat=1 dens=2500 ymod=10e9 prat=0.25\n"
                      "prop jmat=1 jkn=1e10 jks=1e10 jfric=30\nset jmat 1\ngen edge 0.25\n"
                      "bound zvel 0 range z -0.001 0.001\nbound xvel 0 range x -0.001 0.001\n"
                      "bound xvel 0 range x 1.999 2.001\nbound yvel 0 range y -0.001 0.001\n"
                      "bound yvel 0 range y 1.999 2.001\ngrav 0 0 -10\nsolve ratio 1e-6"))
        << s.error();
    const Model& m = s.model;
    double mid = 0;
    int faces = 0, others = 0;
    for (int c = 0; c < m.contacts.size(); ++c) {
        const ContactInfo ci = contact_info(m, c);
        if (ci.area > 0.5) {
            ++faces;
            if (std::abs(ci.normal.z()) > 0.99) mid += normal_force(m, c);
        } else {
            ++others;
            EXPECT_EQ(normal_force(m, c), 0.0) << "contact " << ci.id;
        }
    }
    EXPECT_EQ(faces, 12);  // 4 horizontal, 8 vertical
    EXPECT_EQ(others, 16); // 12 pairs across an edge, 4 across a corner
    const double upper_weight = 4 * 2500.0 * 10.0 * 1.0;
    EXPECT_NEAR(mid, upper_weight, 1e-3 * upper_weight);
}

namespace {

// Zoning a block whose joints carry shear: its gridpoints' sub-contacts start from their own
// closures, not from the history of the block vertex that has the same number. The middle block
// is a prism whose vertices 0-3 are on its top face; Gmsh numbers a gridpoint in that face 2,
// and before the gridpoints' keys were marked apart it took over vertex 2's closure and its
// shear stress of 5 kPa, at a point 0.76 m from that corner.
TEST(ZoneContacts, ZoningStartsTheGridpointsFromTheirOwnClosures) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 2 0 2 -2 -1\n"
                      "poly prism a (0,0,0) (1,0,0) (1,1,0) (0,1,0) b (0,0,-1) (1,0,-1) (1,1,-1) (0,1,-1)\n"
                      "poly brick 0 1 0 1 0 1\nprop mat=1 dens=2000 ymod=1e9 prat=0.25\n"
                      "prop jmat=1 jkn=1e9 jks=1e9 jfric=40\nfix range z -2 -1\ngrav 0 0 -10\n"
                      "bound xload 5000 range z 0 1\nsolve ratio 1e-6"))
        << s.error();
    const ContactSet& cs = s.model.contacts;
    double sheared = 0;
    for (int k = 0; k < cs.n_subs(); ++k) sheared = std::max(sheared, cs.sub_ss[k].norm());
    ASSERT_GT(sheared, 4000);
    ASSERT_TRUE(s.run("gen edge 0.5 range z -1 0")) << s.error();
    ensure_contacts_current(s.model, true);
    int gridpoint_subs = 0;
    for (int k = 0; k < cs.n_subs(); ++k) {
        if (cs.sub_side(k) < 3) continue;
        ++gridpoint_subs;
        EXPECT_EQ(cs.sub_ss[k].norm(), 0.0) << "gridpoint " << cs.sub_vertex(k) + 1;
        EXPECT_EQ(cs.sub_us[k].norm(), 0.0) << "gridpoint " << cs.sub_vertex(k) + 1;
    }
    EXPECT_GT(gridpoint_subs, 12);
}


// A block zoned again, or deleted, renumbers the gridpoints of the other zoned blocks: their
// sub-contacts keep their histories, carried to the new numbers. A joint between two zoned
// blocks under an in-situ stress that grows along x (each gridpoint sub-contact its own normal
// stress), then the lower block zoned again, then a third block deleted: the upper block's
// gridpoints still carry the stress of the field where they are.
TEST(ZoneContacts, GridpointHistoriesFollowTheirGridpointsWhenOthersAreRenumbered) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 3 4 0 1 0 1\npoly brick 0 2 0 1 0 1\npoly brick 0 2 0 1 1 2\n"
                      "prop mat=1 dens=2500 k=1e10 g=1e10\nprop jmat=1 jkn=1e10 jks=1e10 jfric=40\nset jmat 1\n"
                      "gen edge 0.25 range x 3 4\ngen edge 0.125 range x 0 2 z 0 1\ngen edge 0.25 range x 0 2 z 1 2\ninsitu stress 0 0 -1e6 0 0 0 xgrad 0 0 -5e5 0 0 0\n"))
        << s.error();
    const ContactSet& cs = s.model.contacts;
    // The normal stress of each upper-block gridpoint on the joint (side 4: gridpoints of block
    // b), by where it stands (the upper block is not zoned again, its gridpoints do not move).
    auto stresses = [&]() {
        ensure_contacts_current(s.model, true);
        std::vector<std::pair<Vec3, double>> out;
        for (int k = 0; k < cs.n_subs(); ++k) {
            if (cs.sub_side(k) == 4) out.emplace_back(s.model.gridpoints.pos[cs.sub_vertex(k)], odec::sub_normal_stress(s.model, k));
        }
        std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
            return std::lexicographical_compare(a.first.data(), a.first.data() + 3, b.first.data(), b.first.data() + 3);
        });
        return out;
    };
    const auto loaded = stresses();
    ASSERT_GT(loaded.size(), 20u);
    double lo = 1e300, hi = 0;
    for (const auto& e : loaded) {
        lo = std::min(lo, e.second);
        hi = std::max(hi, e.second);
    }
    EXPECT_GT(hi - lo, 5e5);  // the field varies along the joint
    for (const char* step : {"gen edge 0.5 range z 0 1 x 0 2", "delete range x 3 4"}) {
        ASSERT_TRUE(s.run(step)) << s.error();
        // Savable as it stands, before any step (after 'gen' a model whose other zoned blocks had
        // more gridpoints used to be refused: "a sub-contact gridpoint is out of range").
        const std::string file = ::testing::TempDir() + "odec-renumbered-" + std::to_string(getpid()) + ".sav";
        EXPECT_TRUE(s.run("save '" + file + "'")) << step << ": " << s.error();
        std::remove(file.c_str());
        s.check_round_trip();
        const auto now = stresses();
        ASSERT_EQ(now.size(), loaded.size()) << step;
        for (size_t i = 0; i < now.size(); ++i) {
            EXPECT_EQ(now[i].first, loaded[i].first) << step;
            EXPECT_NEAR(now[i].second, loaded[i].second, 1e-9 * loaded[i].second)
                << step << ": gridpoint at " << now[i].first.transpose();
        }
    }
    // Without 'insitu' (which finds the contacts again when zones are made): a block zoned
    // again with fewer gridpoints, then saved at once.
    Session g;
    ASSERT_TRUE(g.run("poly brick 0 1 0 1 1 2\npoly brick 0 1 0 1 0 1\nprop mat=1 dens=2500 k=1e10 g=1e10\n"
                      "prop jmat=1 jkn=1e10 jks=1e10 jfric=30\nset jmat 1\ngrav 0 0 -10\ngen edge 0.1 range z 0 1\n"
                      "gen edge 0.2 range z 1 2\nfix range z 0 0.01\nstep 20\ngen edge 0.5 range z 0 1"))
        << g.error();
    const std::string file = ::testing::TempDir() + "odec-rezoned-" + std::to_string(getpid()) + ".sav";
    EXPECT_TRUE(g.run("save '" + file + "'")) << g.error();
    std::remove(file.c_str());
    g.check_round_trip();
}

} // namespace
