// `insitu`: a jointed model whose in-situ stress is in equilibrium with gravity and its
// boundaries starts at rest, its joints (contacts and their sub-contacts) loaded from the
// stress field as its zones are, in deformable and rigid blocks alike; zones made after
// 'insitu' take the field too, also across save and restore; contacts found later do not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <unistd.h>

#include "engine/contact.h"
#include "engine/cycle.h"
#include "engine/insitu.h"
#include "engine/zones.h"
#include "test_util.h"

using namespace odec;
using odec::test::Session;

namespace {

// The fastest motion in the model: gridpoints, and rigid blocks (translation, and rotation at
// their farthest vertex), m/s.
double fastest(const Model& m) {
    double v = 0;
    for (int i = 0; i < m.gridpoints.size(); ++i) {
        if (m.gridpoints.mass[i] > 0) v = std::max(v, m.gridpoints.vel[i].norm());
    }
    const BlockSet& s = m.blocks;
    for (int b = 0; b < s.size(); ++b) {
        if (s.flags[b] & (kDeformable | kExcavated)) continue;
        double r = 0;
        for (const Vec3& x : s.shape[b].vertices) r = std::max(r, x.norm());
        v = std::max(v, s.vel[b].norm() + s.ang_vel[b].norm() * r);
    }
    return v;
}

struct Rest {
    double first_ratio = 1;  // unbalanced-force ratio after the first step
    double fastest = 1;      // m/s, fastest motion over the steps
};

// Steps the model one step at a time, watching it.
Rest watch(Session& s, int steps = 100) {
    Rest r;
    r.fastest = 0;
    for (int k = 0; k < steps; ++k) {
        if (!s.run("step 1")) {
            ADD_FAILURE() << s.error();
            return r;
        }
        if (k == 0) r.first_ratio = unbalanced_ratio(s.model);
        r.fastest = std::max(r.fastest, fastest(s.model));
    }
    return r;
}

// The stress on the plane of normal n (from a to b) on block b: sn (compression positive) and
// the shear stress vector.
void traction(const Sym6& t, const Vec3& n, double& sn, Vec3& ss) {
    Mat3 s;
    s << t[0], t[3], t[4], t[3], t[1], t[5], t[4], t[5], t[2];
    const Vec3 on_b = -(s * n);
    sn = on_b.dot(n);
    ss = on_b - sn * n;
}

// 'bound stress' with this tensor on the six faces of the box x0..x1, y0..y1, z0..z1.
std::string box_stress(const std::string& tensor, double x0, double x1, double y0, double y1, double z0, double z1) {
    std::string out;
    char buf[200];
    const double lo[3] = {x0, y0, z0}, hi[3] = {x1, y1, z1};
    const char* axis[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) {
        for (double c : {lo[i], hi[i]}) {
            std::snprintf(buf, sizeof buf, "bound stress %s range %s %.6g %.6g\n", tensor.c_str(), axis[i], c - 1e-3,
                          c + 1e-3);
            out += buf;
        }
    }
    return out;
}

const char* kRock = "prop mat=1 dens=2500 ymod=10e9 prat=0.25\n"
                    "prop jmat=1 jkn=2e11 jks=1e11 jfric=40\nset jmat 1\nchange jmat=1\n";

} // namespace

// (a) Two deformable blocks across an inclined joint under a general stress tensor (no
// gravity): the joint takes the traction of the tensor on its plane at every sub-contact,
// and nothing moves.
TEST(Insitu, AJointBetweenDeformableBlocksStartsAtRest) {
    const std::string t = "-6e6 -4e6 -8e6 1e6 -5e5 8e5";
    Session s;
    ASSERT_TRUE(s.run(std::string("poly brick 0 2 0 1 0 1\njset dip 50 dd 70 origin 1,0.5,0.5\n") + kRock +
                      "gen edge 0.25\ninsitu stress " + t + "\n" + box_stress(t, 0, 2, 0, 1, 0, 1)))
        << s.error();
    const Model& m = s.model;
    ASSERT_EQ(m.contacts.size(), 1);
    const Sym6 tensor = {-6e6, -4e6, -8e6, 1e6, -5e5, 8e5};
    double sn = 0;
    Vec3 ss;
    traction(tensor, m.contacts.normal(0), sn, ss);
    ASSERT_GT(sn, 0);
    int loaded = 0;
    for (int k = m.contacts.sub_offset[0]; k < m.contacts.sub_offset[1]; ++k) {
        // Every sub-contact carries the field's traction (weighted by the share of its area on
        // the joint face, 1 here), and the closure that carries it.
        EXPECT_NEAR(sub_normal_stress(m, k), sn, 1e-9 * sn);
        EXPECT_NEAR((m.contacts.sub_shear_stress(0, k) - ss).norm(), 0.0, 1e-9 * sn);
        EXPECT_NEAR(m.contacts.sub_un[k], sn / 2e11, 1e-9 * sn / 2e11);
        ++loaded;
    }
    EXPECT_GT(loaded, 20);
    const Rest r = watch(s);
    EXPECT_LT(r.first_ratio, 1e-6);
    EXPECT_LT(r.fastest, 1e-6);
    // Without the joint's share (its sub-contacts unloaded, as before 'insitu' loaded joints)
    // the same model jolts: the zones push into an unloaded joint.
    Session bare;
    ASSERT_TRUE(bare.run(std::string("poly brick 0 2 0 1 0 1\njset dip 50 dd 70 origin 1,0.5,0.5\n") + kRock +
                         "gen edge 0.25\ninsitu stress " + t + "\n" + box_stress(t, 0, 2, 0, 1, 0, 1)))
        << bare.error();
    ContactSet& cs = bare.model.contacts;
    for (int k = 0; k < cs.n_subs(); ++k) {
        cs.sub_un[k] = 0;
        cs.sub_ss[k].setZero();
    }
    EXPECT_GT(watch(bare, 1).first_ratio, 1e-3);
}

// 'bound stress' with no range loads the model's outer faces only: the faces of a joint
// between zoned blocks, and of a zoned block against a rigid one, are covered by the other
// block and take no boundary traction (they used to, and the joint lost three quarters of its
// normal stress within 20 steps). The model of (a), and a zoned block on a rigid one.
TEST(Insitu, BoundStressWithoutARangeLoadsOnlyTheOuterFaces) {
    const std::string t = "-6e6 -4e6 -8e6 1e6 -5e5 8e5";
    Session s;
    ASSERT_TRUE(s.run(std::string("poly brick 0 2 0 1 0 1\njset dip 50 dd 70 origin 1,0.5,0.5\n") + kRock +
                      "gen edge 0.25\ninsitu stress " + t + "\nbound stress " + t))
        << s.error();
    const Model& m = s.model;
    // The loaded faces cover the box's surface, 2 (2 + 2 + 1) = 10 m^2, and nothing more.
    auto loaded_area = [](const Model& mm) {
        double area = 0;
        for (const BoundaryFace& f : mm.stress_boundary.faces) {
            const Vec3& p0 = mm.gridpoints.pos[f.gp[0]];
            area += 0.5 * (mm.gridpoints.pos[f.gp[1]] - p0).cross(mm.gridpoints.pos[f.gp[2]] - p0).norm();
        }
        return area;
    };
    EXPECT_NEAR(loaded_area(m), 10.0, 1e-9);
    const Rest r = watch(s);
    EXPECT_LT(r.first_ratio, 1e-6);
    EXPECT_LT(r.fastest, 1e-6);
    double sn = 0;
    Vec3 ss;
    traction({-6e6, -4e6, -8e6, 1e6, -5e5, 8e5}, s.model.contacts.normal(0), sn, ss);
    for (int k = 0; k < s.model.contacts.n_subs(); ++k) EXPECT_NEAR(sub_normal_stress(s.model, k), sn, 1e-6 * sn);

    // A zoned cube on a rigid base: its top and sides are loaded (5 m^2), not its base, which
    // stands on the rigid block.
    Session r2;
    ASSERT_TRUE(r2.run(std::string("poly brick -1 2 -1 2 -1 0\npoly brick 0 1 0 1 0 1\n") + kRock +
                       "gen edge 0.25 range z 0 1\nfix range z -1 0\nbound stress 0 0 -1e6 0 0 0"))
        << r2.error();
    EXPECT_NEAR(loaded_area(r2.model), 5.0, 1e-9);
}

// (b) A tunnel's rings and radial cuts before excavation, under a far-field stress with its
// traction on the outer faces and plane strain along the axis. First as 'poly tunnel' makes
// them, joined and zoned as one continuum; then as separate deformable blocks with real
// joints between them (prisms: the core, two rings and the rock out to the box, in 8
// sectors), every joint loaded.
TEST(Insitu, TunnelRingsAndRadialCutsStartAtRest) {
    const std::string t = "-5e6 -3.25e6 -8e6 0 1.5e6 0";
    const std::string bounds = "bound stress " + t + " range x 3.999 4.001\nbound stress " + t +
                               " range x -4.001 -3.999\nbound stress " + t + " range z 3.999 4.001\nbound stress " + t +
                               " range z -4.001 -3.999\nbound yvel 0 range y -0.001 0.001\n"
                               "bound yvel 0 range y 0.999 1.001\n";
    {
        Session s;
        ASSERT_TRUE(s.run(std::string("poly tunnel a (0,0,0) b (0,1,0) radius 1 box 4 ntheta 8 nrad 2\n") + kRock +
                          "gen edge 0.5\ninsitu stress " + t + "\n" + bounds))
            << s.error();
        EXPECT_EQ(s.model.contacts.size(), 0); // one continuum
        const Rest r = watch(s);
        EXPECT_LT(r.first_ratio, 1e-6);
        EXPECT_LT(r.fastest, 1e-6);
    }
    // The same pattern as separate blocks: 8 sectors, a core, rings to radii 1, 2 and 3 (the
    // octagons' corners on those circles) and the rock out to the box's half-width 4.
    std::string blocks;
    const double radii[3] = {1, 2, 3};
    auto corner = [&](int ring, int k) { // ring 3: the box
        const double a = k * M_PI / 4;
        if (ring < 3) return std::make_pair(radii[ring] * std::cos(a), radii[ring] * std::sin(a));
        const double c = std::cos(a), sn = std::sin(a);
        const double f = 4.0 / std::max(std::abs(c), std::abs(sn));
        return std::make_pair(f * c, f * sn);
    };
    auto prism = [&](const std::vector<std::pair<double, double>>& p) {
        std::string a = "poly prism a", b = " b";
        char buf[80];
        for (const auto& [x, z] : p) {
            std::snprintf(buf, sizeof buf, " (%.12g,0,%.12g)", x, z);
            a += buf;
            std::snprintf(buf, sizeof buf, " (%.12g,1,%.12g)", x, z);
            b += buf;
        }
        blocks += a + b + "\n";
    };
    for (int k = 0; k < 8; ++k) {
        prism({{0.0, 0.0}, corner(0, k), corner(0, k + 1)});
        for (int ring = 0; ring < 3; ++ring) prism({corner(ring, k), corner(ring + 1, k), corner(ring + 1, k + 1), corner(ring, k + 1)});
    }
    for (const char* zoning : {"gen edge 0.5", "group 'rigid' range cylinder (0,0,0) (0,1,0) 2\n"
                                               "gen edge 0.5 range not group 'rigid'"}) {
        SCOPED_TRACE(zoning);
        Session s;
        ASSERT_TRUE(s.run(blocks + kRock + zoning + "\ninsitu stress " + t + "\n" + bounds)) << s.error();
        const Model& m = s.model;
        EXPECT_EQ(m.blocks.size(), 32);
        int face_contacts = 0;
        for (int c = 0; c < m.contacts.size(); ++c) {
            EXPECT_FALSE(m.contacts.joined(c));
            if (contact_info(m, c).normal_stress > 1e6) ++face_contacts;
        }
        EXPECT_EQ(face_contacts, 8 + 8 * 3 + 8 * 3); // core-ring, ring-ring and ring-box; radial cuts
        const Rest r = watch(s);
        EXPECT_LT(r.first_ratio, 1e-6);
        EXPECT_LT(r.fastest, 1e-6);
    }
}

// Between rigid blocks the sub-contacts sit at the corners of the contact polygon, whose own
// shares of its area place their centre off the polygon's centroid on a face that is neither
// a triangle nor symmetric: the loads 'insitu' gives them put the field's resultant at the
// centroid, so that a uniform field turns no block.
TEST(Insitu, RigidJointResultantActsAtItsCentroid) {
    const char* quad = "(0,0,0) (4,0,0) (3,2,0) (0.5,1,0)";
    const char* quad1 = "(0,0,1) (4,0,1) (3,2,1) (0.5,1,1)";
    const char* quad2 = "(0,0,2) (4,0,2) (3,2,2) (0.5,1,2)";
    Session s;
    ASSERT_TRUE(s.run(std::string("poly prism a ") + quad + " b " + quad1 + "\npoly prism a " + quad1 + " b " + quad2 +
                      "\n" + kRock + "insitu stress -2e6 -3e6 -5e6 4e5 -3e5 2e5"))
        << s.error();
    const Model& m = s.model;
    ASSERT_EQ(m.contacts.size(), 1);
    // The quadrilateral's area and centroid.
    const double xs[4] = {0, 4, 3, 0.5}, ys[4] = {0, 0, 2, 1};
    double a2 = 0, cx = 0, cy = 0;
    for (int i = 0; i < 4; ++i) {
        const int j = (i + 1) % 4;
        const double w = xs[i] * ys[j] - xs[j] * ys[i];
        a2 += w;
        cx += w * (xs[i] + xs[j]);
        cy += w * (ys[i] + ys[j]);
    }
    const Vec3 centroid(cx / (3 * a2), cy / (3 * a2), 1.0);
    Vec3 force = Vec3::Zero(), moment = Vec3::Zero();
    const ContactSet& cs = m.contacts;
    for (int k = cs.sub_offset[0]; k < cs.sub_offset[1]; ++k) {
        const Vec3 f = cs.sub_area[k] * (sub_normal_stress(m, 0, k) * cs.normal(0) + cs.sub_shear_stress(0, k));
        force += f;
        moment += (sub_point(m, 0, k) - centroid).cross(f);
    }
    const Sym6 tensor = {-2e6, -3e6, -5e6, 4e5, -3e5, 2e5};
    double sn = 0;
    Vec3 ss;
    traction(tensor, cs.normal(0), sn, ss);
    const double area = 0.5 * a2;
    EXPECT_NEAR((force - area * (sn * cs.normal(0) + ss)).norm(), 0.0, 1e-9 * area * sn);
    EXPECT_LT(moment.norm(), 1e-9 * area * sn);
}

// (c) A wall of blocks, rigid ones among deformable ones, under gravity with the in-situ
// stress of its own weight (szz = rho g (z - 4), sxx = syy = szz / 2, free top), on rollers.
// Rigid blocks take their joints' forces from the field too: their weight is carried and
// they neither drop nor turn.
TEST(Insitu, RigidAndDeformableBlocksUnderGravityStartAtRest) {
    Session s;
    ASSERT_TRUE(s.run(std::string("poly brick 0 3 0 1 0 4\njset dip 90 dd 90 origin 1,0,0\njset dip 90 dd 90 origin 2,0,0\n"
                                  "jset dip 0 dd 0 origin 0,0,1\njset dip 0 dd 0 origin 0,0,2\njset dip 0 dd 0 origin 0,0,3\n") +
                      kRock +
                      "group 'rigid' range x 1 2 z 1 3\ngen edge 0.25 range not group 'rigid'\ngrav 0 0 -10\n"
                      "insitu stress -50000 -50000 -100000 0 0 0 zgrad 12500 12500 25000 0 0 0\n"
                      "bound zvel 0 range z -0.001 0.001\nbound xvel 0 range x -0.001 0.001\n"
                      "bound xvel 0 range x 2.999 3.001\nbound yvel 0 range y -0.001 0.001\n"
                      "bound yvel 0 range y 0.999 1.001\n"))
        << s.error();
    const Model& m = s.model;
    int rigid = 0;
    for (int b = 0; b < m.blocks.size(); ++b) rigid += !(m.blocks.flags[b] & kDeformable);
    ASSERT_EQ(rigid, 2);
    // The joint between the two rigid blocks (z = 2) carries the weight of the column above it.
    bool found = false;
    for (int c = 0; c < m.contacts.size(); ++c) {
        const int a = m.contacts.block_a[c], b = m.contacts.block_b[c];
        if ((m.blocks.flags[a] | m.blocks.flags[b]) & kDeformable) continue;
        found = true;
        EXPECT_NEAR(contact_info(m, c).normal_stress, 2500.0 * 10.0 * 2.0, 1e-9 * 5e4);
    }
    EXPECT_TRUE(found);
    const Rest r = watch(s);
    EXPECT_LT(r.first_ratio, 1e-6);
    EXPECT_LT(r.fastest, 1e-6);
    // Unloaded joints under the same field: the rigid blocks drop.
    Session bare;
    ASSERT_TRUE(bare.run(std::string("poly brick 0 3 0 1 0 4\njset dip 90 dd 90 origin 1,0,0\njset dip 90 dd 90 origin 2,0,0\n"
                                     "jset dip 0 dd 0 origin 0,0,1\njset dip 0 dd 0 origin 0,0,2\njset dip 0 dd 0 origin 0,0,3\n") +
                         kRock + "group 'rigid' range x 1 2 z 1 3\ngen edge 0.25 range not group 'rigid'\ngrav 0 0 -10\n"
                                 "bound zvel 0 range z -0.001 0.001\n"))
        << bare.error();
    EXPECT_GT(watch(bare, 20).fastest, 1e-4);
}

// (d) 'insitu' given to rigid blocks, which are zoned afterwards (and saved and restored in
// between): the model keeps the field, the zones and the joints of the zoned blocks take it
// when they are made, and the model starts at rest.
TEST(Insitu, ZonesMadeAfterInsituTakeTheField) {
    const std::string t = "-6e6 -4e6 -8e6 1e6 -5e5 8e5";
    const std::string dir = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    const std::string file = dir + "/odec-insitu-" + std::to_string(getpid()) + ".sav";
    {
        Session s;
        s.interp.quiet = false;
        ASSERT_TRUE(s.run(std::string("poly brick 0 2 0 1 0 1\njset dip 50 dd 70 origin 1,0.5,0.5\n"
                                      "jset dip 80 dd 200 origin 1,0.5,0.5\n") +
                          kRock + "insitu stress " + t + "\nsave '" + file + "'"))
            << s.error();
        EXPECT_NE(s.out.str().find("kept for the zones"), std::string::npos) << s.out.str();
        ASSERT_EQ(s.model.insitu.size(), 1u);
    }
    Session s;
    s.interp.quiet = false;
    ASSERT_TRUE(s.run("restore '" + file + "'\ngen edge 0.25\n" + box_stress(t, 0, 2, 0, 1, 0, 1))) << s.error();
    std::remove(file.c_str());
    ASSERT_EQ(s.model.insitu.size(), 1u);
    EXPECT_NE(s.out.str().find("in-situ stress given before:"), std::string::npos) << s.out.str();
    const Sym6 tensor = {-6e6, -4e6, -8e6, 1e6, -5e5, 8e5};
    for (const Sym6& z : s.model.zones.stress) EXPECT_EQ(z, tensor);
    EXPECT_GE(s.model.contacts.size(), 3);
    const Rest r = watch(s);
    EXPECT_LT(r.first_ratio, 1e-6);
    EXPECT_LT(r.fastest, 1e-6);
}

// A contact found after 'insitu' (a block placed on the model afterwards) starts unloaded:
// only the joints there when the field was given, and those of blocks zoned later, take it.
TEST(Insitu, ContactsFoundLaterStartUnloaded) {
    const std::string t = "-1e6 -1e6 -1e6 0 0 0";
    Session s;
    ASSERT_TRUE(s.run(std::string("poly brick 0 1 0 1 0 1\npoly brick 0 1 0 1 1 2\n") + kRock + "gen edge 0.5\ninsitu stress " +
                      t + "\n" + box_stress(t, 0, 1, 0, 1, 0, 2) + "poly brick 0 1 0 1 2 3\nstep 1"))
        << s.error();
    const Model& m = s.model;
    ASSERT_EQ(m.contacts.size(), 2);
    for (int c = 0; c < m.contacts.size(); ++c) {
        const ContactInfo ci = contact_info(m, c);
        if (ci.centroid.z() < 1.5) EXPECT_NEAR(ci.normal_stress, 1e6, 1e-3);
        else EXPECT_LT(std::abs(ci.normal_stress), 1e-3); // the new block's joint
    }
    EXPECT_LT(unbalanced_ratio(m), 1e-6);
}

// Where the field exceeds a joint's strength, the joint starts at its strength, as the joint
// law would cap it, and 'insitu' says how many sub-contacts: slipping under too much shear
// (Coulomb), open under tension beyond the tensile strength.
TEST(Insitu, JointsBeyondTheirStrengthAreCappedWithAWarning) {
    Session s;
    // The joint z = 1 under sxz = 1 MPa and szz = -1 MPa: its friction carries tan 30 MPa.
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 2\njset dip 0 dd 0 origin 0,0,1\nprop mat=1 dens=2500 ymod=10e9 prat=0.25\n"
                      "prop jmat=1 jkn=1e11 jks=1e11 jfric=30\nset jmat 1\nchange jmat=1\ngen edge 0.5\n"
                      "insitu stress -1e6 -1e6 -1e6 0 1e6 0"))
        << s.error();
    const Model& m = s.model;
    ASSERT_EQ(m.contacts.size(), 1);
    const int n = m.contacts.sub_offset[1] - m.contacts.sub_offset[0];
    EXPECT_NE(s.error().find("warning: " + std::to_string(n) + " of " + std::to_string(n) +
                             " sub-contacts cannot carry the in-situ shear stress"),
              std::string::npos)
        << s.error();
    for (int k = m.contacts.sub_offset[0]; k < m.contacts.sub_offset[1]; ++k) {
        EXPECT_NEAR(sub_normal_stress(m, k), 1e6, 1e-3);
        EXPECT_NEAR(m.contacts.sub_ss[k].norm(), 1e6 * std::tan(M_PI / 6), 1e-3);
        EXPECT_TRUE(m.contacts.sub_flags(k) & kSubSlip);
    }
    // Tension across it, with no tensile strength: open and unloaded.
    ASSERT_TRUE(s.run("insitu stress -1e6 -1e6 2e5 0 0 0")) << s.error();
    EXPECT_NE(s.error().find("sub-contacts are pulled apart by the in-situ stress"), std::string::npos) << s.error();
    for (int k = m.contacts.sub_offset[0]; k < m.contacts.sub_offset[1]; ++k) {
        EXPECT_EQ(sub_normal_stress(m, k), 0.0);
        EXPECT_TRUE(m.contacts.sub_flags(k) & kSubOpen);
    }
    // A joined joint has no limits: it carries both.
    ASSERT_TRUE(s.run("join\ninsitu stress -1e6 -1e6 2e5 0 1e6 0")) << s.error();
    for (int k = m.contacts.sub_offset[0]; k < m.contacts.sub_offset[1]; ++k) {
        EXPECT_NEAR(sub_normal_stress(m, k), -2e5, 1e-3);
        EXPECT_NEAR(m.contacts.sub_ss[k].norm(), 1e6, 1e-3);
    }
}

// 'insitu' with nothing to take it is refused, and the model keeps no field.
TEST(Insitu, NothingToTakeTheStressIsRefused) {
    Session s;
    EXPECT_FALSE(s.run("insitu stress -1e6 -1e6 -1e6 0 0 0"));
    EXPECT_NE(s.error().find("there are no blocks"), std::string::npos) << s.error();
    s.all_succeeded = true;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2500 ymod=10e9 prat=0.25\ngen edge 0.5")) << s.error();
    EXPECT_FALSE(s.run("insitu stress -1e6 -1e6 -1e6 0 0 0 range x 5 6"));
    EXPECT_NE(s.error().find("the range selects no zone"), std::string::npos) << s.error();
    EXPECT_TRUE(s.model.insitu.empty());
    s.all_succeeded = true;
}
