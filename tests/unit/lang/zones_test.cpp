// Deformable blocks through the interpreter: zoning, continua of joined blocks, boundary
// conditions on gridpoints, stresses, histories, tables, and the errors of bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/zones.h"
#include "fish/runtime.h"
#include "test_util.h"

using odec::test::Session;
using namespace odec;

namespace {

const char* kCube = "poly brick 0 1 0 1 0 1\nprop mat=1 dens=2500 ymod=10e9 prat=0.25\n";

} // namespace

TEST(Zones, GenEdgeDividesABlockIntoGoodTetrahedra) {
    Session s;
    s.interp.quiet = false;
    ASSERT_TRUE(s.run(std::string(kCube) + "gen edge 0.25")) << s.error();
    const Model& m = s.model;
    EXPECT_TRUE(m.blocks.flags[0] & kDeformable);
    EXPECT_GT(m.zones.size(), 200);
    EXPECT_LT(m.zones.size(), 1000);
    // The zones fill the block: their volumes add up to it, none is flat.
    double volume = 0, smallest = 1;
    for (int z = 0; z < m.zones.size(); ++z) {
        const auto& q = m.zones.gp[z];
        const auto& x = m.gridpoints.pos;
        const double v = (x[q[1]] - x[q[0]]).dot((x[q[2]] - x[q[0]]).cross(x[q[3]] - x[q[0]])) / 6.0;
        volume += v;
        smallest = std::min(smallest, v);
    }
    EXPECT_NEAR(volume, 1.0, 1e-12);
    EXPECT_GT(smallest, 1e-5);
    // The report names the counts and the worst quality.
    const std::string out = s.out.str();
    EXPECT_NE(out.find("zoned 1 blocks: " + std::to_string(m.zones.size()) + " zones"), std::string::npos) << out;
    const size_t at = out.find("worst ");
    ASSERT_NE(at, std::string::npos);
    EXPECT_GT(std::stod(out.substr(at + 6)), 0.2) << out;
    // Gridpoint masses add up to the block's mass.
    double mass = 0;
    for (double g : m.gridpoints.mass) mass += g;
    EXPECT_NEAR(mass, 2500.0, 1e-9);
}

TEST(Zones, TheSameModelGetsTheSameZonesWhateverCameBefore) {
    Session a, b;
    ASSERT_TRUE(a.run(std::string(kCube) + "gen edge 0.2")) << a.error();
    ASSERT_TRUE(b.run("poly brick 0 9 0 9 0 9\njset dip 30 dd 20 spacing 0.7\ngroup 'x' range z 0 4\nnew\n" +
                      std::string(kCube) + "gen edge 0.2"))
        << b.error();
    ASSERT_EQ(a.model.zones.size(), b.model.zones.size());
    ASSERT_EQ(a.model.gridpoints.size(), b.model.gridpoints.size());
    EXPECT_TRUE(a.model.zones.gp == b.model.zones.gp);
    EXPECT_TRUE(a.model.gridpoints.pos == b.model.gridpoints.pos);
}

TEST(Zones, JoinedBlocksShareGridpointsAndOthersDoNot) {
    Session joined;
    ASSERT_TRUE(joined.run("poly brick 0 1 0 1 0 1\npoly brick 0 1 0 1 1 2\nprop mat=1 dens=2500 k=5e9 g=3e9\n"
                           "join\ngen edge 0.3"))
        << joined.error();
    const Model& m = joined.model;
    EXPECT_EQ(m.blocks.body[0], m.blocks.body[1]);
    // Gridpoints on the shared face z = 1 belong to zones of both blocks.
    int shared = 0;
    std::vector<int> owners(m.gridpoints.size(), 0);
    for (int z = 0; z < m.zones.size(); ++z) {
        for (int g : m.zones.gp[z]) owners[g] |= 1 << m.zones.block[z];
    }
    for (int g = 0; g < m.gridpoints.size(); ++g) {
        if (owners[g] == 3) {
            ++shared;
            EXPECT_NEAR(m.gridpoints.pos[g].z(), 1.0, 1e-12);
        }
    }
    EXPECT_GE(shared, 9);
    // The continuum cycles: joined blocks need no contact between them.
    ASSERT_TRUE(joined.run("grav 0 0 -10\nfix range z -0.01 0.01\nsolve")) << joined.error();
    double top = 0;
    for (int g = 0; g < m.gridpoints.size(); ++g) top = std::min(top, m.gridpoints.disp[g].z());
    EXPECT_LT(top, 0.0);

    Session apart;
    ASSERT_TRUE(apart.run("poly brick 0 1 0 1 0 1\npoly brick 0 1 0 1 1 2\nprop mat=1 dens=2500 k=5e9 g=3e9\n"
                          "gen edge 0.3"))
        << apart.error();
    EXPECT_NE(apart.model.blocks.body[0], apart.model.blocks.body[1]);
    // Zoned apart, they meet through a contact at their gridpoints, which carries the top
    // block's weight: 2500 x 10 x 1 m = 25 kPa over the whole face once at rest.
    ASSERT_TRUE(apart.run("prop jmat=1 jkn=1e11 jks=1e11 jfric=30\nset jmat 1\ngrav 0 0 -10\n"
                          "fix range z -0.01 0.01\nsolve ratio 1e-6"))
        << apart.error();
    ASSERT_EQ(apart.model.contacts.size(), 1);
    const ContactInfo ci = contact_info(apart.model, 0);
    EXPECT_NEAR(ci.area, 1.0, 1e-9);
    EXPECT_NEAR(ci.normal_stress, 25000.0, 25.0);
}

TEST(Zones, BadInputIsRefusedAndChangesNothing) {
    Session s;
    ASSERT_TRUE(s.run(kCube)) << s.error();
    EXPECT_FALSE(s.run("gen edge 0"));
    EXPECT_NE(s.error().find("'edge' must be > 0 (got 0)"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("gen edge -1"));
    EXPECT_FALSE(s.run("gen edge 1e-4"));
    EXPECT_NE(s.error().find("zones in 1 blocks"), std::string::npos) << s.error();
    EXPECT_NE(s.error().find("give a larger edge"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("gen"));
    EXPECT_NE(s.error().find("'generate' needs one of: edge, model"), std::string::npos) << s.error();
    EXPECT_EQ(s.model.zones.size(), 0);
    EXPECT_FALSE(s.model.blocks.flags[0] & kDeformable);
    // A lone rigid block has no joint to take an in-situ stress: the model keeps it for the
    // zones the block gets later.
    ASSERT_TRUE(s.run("insitu stress -1e6 -1e6 -1e6 0 0 0")) << s.error();
    EXPECT_EQ(s.model.insitu.size(), 1u);
    // 'bound stress' on a rigid block: the traction of its free faces in the range, a force at
    // the face's centroid.
    ASSERT_TRUE(s.run("bound stress 0 0 -1e6 0 0 0 range z 0.99 1.01")) << s.error();
    ASSERT_EQ(s.model.blocks.loads[0].size(), 1u);
    EXPECT_NEAR(s.model.blocks.loads[0][0].force.z(), -1e6 * 1.0, 1e-6);
    EXPECT_NEAR(s.model.blocks.loads[0][0].force.x(), 0, 1e-6);
    // A model whose zones lack elastic moduli, or a material, cannot cycle, and says which.
    Session t;
    ASSERT_TRUE(t.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2500\ngen edge 0.5")) << t.error();
    EXPECT_FALSE(t.run("step 1"));
    EXPECT_NE(t.error().find("the zones of block 1 have no stiffness: material 1 needs a bulk and a shear modulus"),
              std::string::npos)
        << t.error();
    EXPECT_EQ(t.model.step, 0);
    Session u;
    ASSERT_TRUE(u.run("poly brick 0 1 0 1 0 1 material 3\ngen edge 0.5")) << u.error();
    EXPECT_FALSE(u.run("step 1"));
    EXPECT_NE(u.error().find("material 3 is not defined"), std::string::npos) << u.error();
    // An excavated block is not zoned; the range selects nothing, and says so.
    Session v;
    ASSERT_TRUE(v.run(std::string(kCube) + "excavate range id 1\ngen edge 0.5")) << v.error();
    EXPECT_EQ(v.model.zones.size(), 0);
    EXPECT_NE(v.error().find("the range selects no blocks"), std::string::npos) << v.error();
}

TEST(Zones, InsituStressWithGradientAndChangeCons) {
    Session s;
    ASSERT_TRUE(s.run(std::string(kCube) + "gen edge 0.3\ninsitu stress -1e6 -2e6 -3e6 1e5 0 0 zgrad 0 0 1e4 0 0 0\n"
                                           "change cons=2 range z 0 0.5"))
        << s.error();
    const Model& m = s.model;
    int mc = 0;
    for (int z = 0; z < m.zones.size(); ++z) {
        const Vec3 c = zone_centroid(m, z);
        EXPECT_DOUBLE_EQ(m.zones.stress[z][0], -1e6);
        EXPECT_DOUBLE_EQ(m.zones.stress[z][3], 1e5);
        EXPECT_NEAR(m.zones.stress[z][2], -3e6 + 1e4 * c.z(), 1e-6);
        mc += m.zones.model[z] == kZoneMohrCoulomb;
        EXPECT_EQ(m.zones.model[z] == kZoneMohrCoulomb, c.z() <= 0.5 + 1e-9);
    }
    EXPECT_GT(mc, 0);
}

TEST(Zones, GravityLoadsTheBaseWithTheWeightAndStressGrowsWithDepth) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 2\nprop mat=1 dens=2000 k=5e9 g=3e9\ngen edge 0.25\ngrav 0 0 -10\n"
                      "bound zvel 0 range z -0.001 0.001\nbound xvel 0 range x -0.001 0.001\n"
                      "bound xvel 0 range x 0.999 1.001\nbound yvel 0 range y -0.001 0.001\n"
                      "bound yvel 0 range y 0.999 1.001\n"
                      "hist zreaction range z -0.001 0.001\nhist szz 0.5,0.5,0.5\nsolve ratio 1e-7"))
        << s.error();
    const Model& m = s.model;
    // The base carries the weight, 2000 kg/m^3 x 2 m^3 x 10 m/s^2, pushing down on its support.
    EXPECT_NEAR(m.histories.items[0].values.back(), -40000.0, 40.0);
    // Zones: szz = -rho g (2 - z). Each uniform-strain zone has one stress for a field that
    // varies across it, so the check is on the fit over all zones: the slope (rho g) within 2 %,
    // the stress at the top within 2 % of the base stress, and the volume-weighted mean (the
    // weight over the area, averaged over the height) within 0.5 %.
    double sv = 0, sz = 0, ss = 0, szz2 = 0, szs = 0, vol = 0, mean = 0;
    for (int z = 0; z < m.zones.size(); ++z) {
        const double zc = zone_centroid(m, z).z(), st = m.zones.stress[z][2];
        sv += 1;
        sz += zc;
        ss += st;
        szz2 += zc * zc;
        szs += zc * st;
        vol += m.zones.volume[z];
        mean += m.zones.volume[z] * st;
    }
    const double slope = (sv * szs - sz * ss) / (sv * szz2 - sz * sz);
    const double at_top = (ss - slope * sz) / sv + slope * 2.0;
    EXPECT_NEAR(slope, 2e4, 0.02 * 2e4);
    EXPECT_NEAR(at_top, 0.0, 0.02 * 4e4);
    EXPECT_NEAR(mean / vol, -2e4, 0.005 * 2e4);
    // print lists zones and gridpoints; print max names the most compressive stress.
    s.interp.quiet = false;
    ASSERT_TRUE(s.run("print zone range z 0 0.3\nprint gp range z 1.99 2.01\nprint max\nprint info")) << s.error();
    const std::string out = s.out.str();
    EXPECT_NE(out.find("zones (x, y, z: centroid; stresses in Pa, tension positive"), std::string::npos) << out;
    EXPECT_NE(out.find("gridpoints (m, m/s; held"), std::string::npos) << out;
    EXPECT_NE(out.find("smin (most compressive)"), std::string::npos) << out;
    EXPECT_NE(out.find("zones:      " + std::to_string(m.zones.size()) + " in 1 deformable blocks"), std::string::npos)
        << out;
    // Every line fits a terminal of 100 columns.
    size_t start = 0;
    while (start < out.size()) {
        const size_t end = std::min(out.find('\n', start), out.size());
        EXPECT_LE(end - start, 100u) << out.substr(start, end - start);
        start = end + 1;
    }
}

TEST(Zones, FixAndFreeActOnGridpointsByPosition) {
    Session s;
    s.interp.quiet = false;
    ASSERT_TRUE(s.run(std::string(kCube) + "gen edge 0.5\nfix range z -0.01 0.01")) << s.error();
    const Model& m = s.model;
    int held = 0;
    for (int g = 0; g < m.gridpoints.size(); ++g) {
        EXPECT_EQ(m.gridpoints.vel_bc[g] == 7, m.gridpoints.pos[g].z() < 1e-9);
        held += m.gridpoints.vel_bc[g] == 7;
    }
    EXPECT_NE(s.out.str().find("0 blocks fixed, " + std::to_string(held) + " gridpoints fixed"), std::string::npos)
        << s.out.str();
    ASSERT_TRUE(s.run("free range z -0.01 0.01")) << s.error();
    for (int g = 0; g < m.gridpoints.size(); ++g) EXPECT_EQ(m.gridpoints.vel_bc[g], 0);
}

// UDEC's form: 'zone model elastic|mohr|null density ... bulk ... shear ...' gives the blocks
// of the range a zone model and a material of those values (the same values, the same number).
TEST(Zones, UdecZoneModelFormSetsModelAndMaterial) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\npoly brick 0 1 0 1 1 2\npoly brick 0 1 0 1 2 3\ngen edge 0.5\n"
                      "zone model elastic density 2700 bulk 3.6e10 shear 2.7e10 range z 0 1\n"
                      "zone model mohr density 2700 bulk 3.6e10 shear 2.7e10 friction 51 cohesion 5.5e7 "
                      "tension 1.17e7 range z 1 3"))
        << s.error();
    const Model& m = s.model;
    EXPECT_EQ(m.blocks.material[0], 1);
    EXPECT_EQ(m.blocks.material[1], 2);
    EXPECT_EQ(m.blocks.material[2], 2);
    EXPECT_EQ(m.blocks.cons[0], kZoneElastic);
    EXPECT_EQ(m.blocks.cons[2], kZoneMohrCoulomb);
    for (int z = 0; z < m.zones.size(); ++z) {
        EXPECT_EQ(m.zones.model[z], m.zones.block[z] == 0 ? kZoneElastic : kZoneMohrCoulomb);
    }
    const Material& mc = m.materials[2];
    EXPECT_EQ(mc.density, 2700);
    EXPECT_EQ(mc.friction, 51);
    EXPECT_EQ(mc.cohesion, 5.5e7);
    EXPECT_EQ(mc.tension, 1.17e7);
    EXPECT_NEAR(m.blocks.mass[0], 2700.0, 1e-9); // the block's mass follows
    // Young's modulus and Poisson's ratio in place of K and G; a refused form changes nothing.
    ASSERT_TRUE(s.run("zone model elastic young 10e9 poisson 0.25 range z 0 1")) << s.error();
    EXPECT_NEAR(m.materials[m.blocks.material[0]].bulk, 10e9 / 1.5, 1.0);
    EXPECT_NEAR(m.materials[m.blocks.material[0]].shear, 10e9 / 2.5, 1.0);
    const size_t n_materials = m.materials.size();
    EXPECT_FALSE(s.run("zone model mohr friction 30 dilation 40"));
    EXPECT_NE(s.error().find("may not exceed the friction angle"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("zone model mohr young 1e9"));
    EXPECT_EQ(m.materials.size(), n_materials);
    EXPECT_EQ(m.blocks.cons[0], kZoneElastic);
    // It cycles: the zones have what they need.
    ASSERT_TRUE(s.run("grav 0 0 -10\nbound zvel 0 range z -0.01 0.01\nstep 20")) << s.error();
}

namespace {

// In large strain a zone keeps the mass it was zoned with, however its volume changes: masses
// chosen again after a 'prop' (the same density) still add up to rho times the block's volume.
// They were taken from the deformed zones, so a block squeezed by 5 % lost 5 % of its weight.
TEST(Zones, AZoneKeepsItsMassWhenItsVolumeChanges) {
    Session s;
    ASSERT_TRUE(s.run("config dyn\npoly brick 0 1 0 1 0 1\nprop mat=1 dens=2000 ymod=1e8 prat=0.25\ngen edge 0.5\n"
                      "bound zvel 0 range z -0.001 0.001\nbound zvel -1 range z 0.999 1.001\nstep 400\n"))
        << s.error();
    auto total = [&] {
        double sum = 0;
        for (int i = 0; i < s.model.gridpoints.size(); ++i) sum += s.model.gridpoints.mass[i];
        return sum;
    };
    double top = 0;
    for (int i = 0; i < s.model.gridpoints.size(); ++i) top = std::max(top, s.model.gridpoints.pos[i].z());
    ASSERT_LT(top, 0.97) << "the block is squeezed";
    ASSERT_TRUE(s.run("prop mat=1 dens=2000\nstep 1")) << s.error();
    EXPECT_NEAR(total(), 2000.0, 1e-9 * 2000.0);
}

} // namespace

// A null zone ('change cons=0') carries no stress: its stress and plastic state go to 0, 'insitu'
// leaves it alone, and given a model again it starts unstressed. A filled block ('excavate',
// then 'fill') is new material: its zones start unstressed too. Before, both came back with the
// stress they had when they were removed.
TEST(Zones, NullZonesAndFilledBlocksStartUnstressed) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\npoly brick 0 1 0 1 1 2\nprop mat=1 dens=2500 k=1e10 g=1e10\n"
                      "gen edge 0.5\ninsitu stress 0 0 -5e6 0 0 0\nchange cons=0 range z 0.5 1\n"))
        << s.error();
    const ZoneSet& z = s.model.zones;
    auto upper = [&](int i) { return zone_centroid(s.model, i).z() > 1; };
    auto nulled = [&](int i) {
        const double c = zone_centroid(s.model, i).z();
        return c > 0.5 && c < 1;
    };
    int n_null = 0;
    for (int i = 0; i < z.size(); ++i) {
        if (nulled(i)) {
            ++n_null;
            EXPECT_EQ(z.stress[i][2], 0.0);
        } else {
            EXPECT_EQ(z.stress[i][2], -5e6);
        }
    }
    EXPECT_GT(n_null, 0);
    ASSERT_TRUE(s.run("insitu stress 0 0 -7e6 0 0 0\nchange cons=1\nexcavate range z 1 2\nfill range z 1 2")) << s.error();
    for (int i = 0; i < z.size(); ++i) {
        const double want = nulled(i) || upper(i) ? 0.0 : -7e6;
        EXPECT_EQ(z.stress[i][2], want) << "zone " << i;
        EXPECT_EQ(z.model[i], kZoneElastic);
    }
}

// A zoned block's velocity (print block, FISH b_vel, the export, plots) is that of its gridpoints,
// as its displacement is: a zoned cube falling freely moves at g t (it read 0 in 'print block'
// and b_vel while the export gave the gridpoints' mean).
TEST(Zones, AZonedBlockMovesWithItsGridpoints) {
    Session s;
    ASSERT_TRUE(s.run("config dynamic\npoly brick 0 1 0 1 0 1\nprop mat=1 dens=2500 k=1e10 g=1e10\ngen edge 0.5\n"
                      "grav 0 0 -10\ndamp off\nset dt 2e-5\nstep 500\n"
                      "def v\n  v = b_zvel(b_near(0.5,0.5,0.5))\nend\n@v"))
        << s.error();
    const double t = s.model.time;
    EXPECT_NEAR(t, 0.01, 1e-12);
    EXPECT_NEAR(velocity_at_t(s.model, 0).z(), -10 * t, 1e-9);
    const odec::fish::Symbol* v = s.interp.fish().find("v");
    ASSERT_NE(v, nullptr);
    EXPECT_NEAR(v->value.number(), -10 * t, 1e-9);
}
