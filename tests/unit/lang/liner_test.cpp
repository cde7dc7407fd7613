// Liners (liner.h, 'liner'): a lined circular tunnel in elastic ground against the closed form
// of a thin ring in an elastic plane (full slip), bonds that break, and what the commands refuse.
#include <gtest/gtest.h>

#include <stdlib.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "engine/liner.h"
#include "render/scene_builder.h"
#include "test_util.h"

using namespace odec;
using namespace odec::test;

namespace {

// A zoned brick 0..2 x 0..1 x 0..1 whose base is held, and liner material 2.
const char* kBrick =
    "new\n"
    "poly brick 0 2 0 1 0 1\n"
    "prop mat=1 dens=2500 ymod=10e9 prat=0.25\n"
    "gen edge 0.25\n"
    "bound xvel 0 yvel 0 zvel 0 range z -0.01 0.01\n"
    "prop mat=2 li_e=30e9 li_nu=0.2 li_thick=0.2 li_dens=2500 li_kn=1e10 li_ks=1e10\n";

} // namespace

// A circular tunnel of radius R = 1 m in elastic ground (E 5 GPa, nu 0.25) under a vertical
// in-situ stress P = 10 MPa and a horizontal one K P, K = 0.5, in plane strain (a slice 0.1 m
// thick along the axis y, held at both faces; the full ring, out to 20 R, loaded by the far-field
// stress on its outer faces). The lining (E_s 25 GPa, t 0.2 m, nu_s 0, so that plane stress and
// plane strain agree) is laid at once on the wall as the tunnel is excavated: no relaxation.
// It may slide on the rock (li_ks 0: full slip) and is pressed onto it by stiff springs (li_kn).
//
// Closed form (Einstein and Schwartz 1979, full slip; the thin ring's equations kept whole): with
// S = P (1 + K) / 2, D = P (1 - K) / 2, G the ground's shear modulus, EA = E_s t, EI = E_s t^3 / 12,
// the contact pressure p0 + p2 cos 2 theta (theta from the springline) is
//   p0 = S / (1 + 2G/(R kn) + 2G R / EA)
//   p2 = -D (3 - 4 nu) / (5/3 - 2 nu + 2G/(R kn) + (2G R / 9) (R^2 / EI + 1 / EA))
// and the lining carries the hoop force (tension positive) n = -p0 R + (p2 R / 3) cos 2 theta and
// the moment (inside face in tension positive) m = (p2 R^2 / 3) cos 2 theta. (E & S drop the small
// 1/EA and 1/kn terms.) Fitted a + b cos 2 theta over all elements, the thrust at springline and
// crown and the moment's amplitude must be within 5 %.
TEST(Liner, EinsteinSchwartzFullSlip) {
    Session s;
    ASSERT_TRUE(s.run("new\n"
                      "set small\n"
                      "poly tunnel a (0,0,0) b (0,0.1,0) radius 1 box 20 ntheta 64 nrad 8 ratio 1.5\n"
                      "prop mat=1 dens=2600 ymod=5e9 prat=0.25\n"
                      "gen edge 3.0\n"
                      "gen edge 0.1 range group 'tunnel_ring1'\n"
                      "gen edge 0.15 range group 'tunnel_ring2'\n"
                      "gen edge 0.25 range group 'tunnel_ring3'\n"
                      "gen edge 0.4 range group 'tunnel_ring4'\n"
                      "gen edge 0.7 range group 'tunnel_ring5'\n"
                      "gen edge 1.2 range group 'tunnel_ring6'\n"
                      "gen edge 2.0 range group 'tunnel_ring7'\n"
                      "insitu stress -5e6 -5e6 -10e6 0 0 0\n"
                      "bound xvel 0 range x -0.001 0.001\n"
                      "bound zvel 0 range z -0.001 0.001\n"
                      "bound yvel 0 range y -0.001 0.001\n"
                      "bound yvel 0 range y 0.099 0.101\n"
                      "bound stress -5e6 0 -10e6 0 0 0 range x 19.999 20.001\n"
                      "bound stress -5e6 0 -10e6 0 0 0 range x -20.001 -19.999\n"
                      "bound stress -5e6 0 -10e6 0 0 0 range z 19.999 20.001\n"
                      "bound stress -5e6 0 -10e6 0 0 0 range z -20.001 -19.999\n"
                      "excavate range group 'tunnel'\n"
                      "prop mat=2 li_e=25e9 li_nu=0 li_thick=0.2 li_kn=1e12 li_ks=0\n"
                      "liner range cyl 0,-1,0 0,1,0 1.01 not cyl 0,-1,0 0,1,0 0.99 prop 2\n"
                      "damp auto\n"
                      "solve ratio 1e-5\n"))
        << s.error();
    const LinerSet& ls = s.model.liners;
    ASSERT_EQ(ls.size(), 1);
    // Least squares of a + b cos 2 theta.
    double n = 0, sc = 0, scc = 0, sn = 0, snc = 0, sm = 0, smc = 0;
    for (int e = 0; e < ls.n_elements(); ++e) {
        const LinerResultants r = liner_resultants(ls, e);
        const double c = std::cos(2 * std::atan2(r.centroid.z(), r.centroid.x()));
        n += 1; sc += c; scc += c * c;
        sn += r.nx; snc += r.nx * c;
        sm += r.mx; smc += r.mx * c;
    }
    const double det = n * scc - sc * sc;
    const double n0 = (sn * scc - sc * snc) / det, n2 = (n * snc - sc * sn) / det;
    const double m0 = (sm * scc - sc * smc) / det, m2 = (n * smc - sc * sm) / det;
    const double e = 5e9, nu = 0.25, g = e / (2 * (1 + nu)), r = 1.0, kn = 1e12;
    const double ea = 25e9 * 0.2, ei = 25e9 * 0.2 * 0.2 * 0.2 / 12;
    const double p = 10e6, k = 0.5, sp = p * (1 + k) / 2, d = p * (1 - k) / 2;
    const double p0 = sp / (1 + 2 * g / (r * kn) + 2 * g * r / ea);
    const double p2 = -d * (3 - 4 * nu) / (5.0 / 3.0 - 2 * nu + 2 * g / (r * kn) + (2 * g * r / 9) * (r * r / ei + 1 / ea));
    const double spring = -p0 * r + p2 * r / 3, crown = -p0 * r - p2 * r / 3, moment = p2 * r * r / 3;
    EXPECT_NEAR(n0 + n2, spring, 0.05 * std::abs(spring)) << "hoop force at the springline, N/m";
    EXPECT_NEAR(n0 - n2, crown, 0.05 * std::abs(crown)) << "hoop force at the crown, N/m";
    EXPECT_NEAR(m2, moment, 0.05 * std::abs(moment)) << "moment amplitude, N m/m";
    EXPECT_LT(std::abs(m0), 0.02 * std::abs(moment)) << "the moment has no mean part";
    std::printf("liner vs closed form: springline %.4g vs %.4g N/m (%.2f %%), crown %.4g vs %.4g N/m (%.2f %%), "
                "moment %.4g vs %.4g N m/m (%.2f %%)\n",
                n0 + n2, spring, 100 * (n0 + n2 - spring) / spring, n0 - n2, crown, 100 * (n0 - n2 - crown) / crown, m2,
                moment, 100 * (m2 - moment) / moment);
}

// A liner on the top of a held brick under gravity pulling it off the rock (gravity upwards): the
// bond holds when its tensile strength is above the liner's weight per area (rho t g = 5 kPa), and
// breaks when below, the liner then coming off.
TEST(Liner, BondBreaksInTensionPastItsStrength) {
    for (const double ncut : {2e4, 2e3}) {
        Session s;
        ASSERT_TRUE(s.run(kBrick)) << s.error();
        ASSERT_TRUE(s.run("prop mat=2 li_ncut=" + std::to_string(ncut) + " li_scoh=1e5 li_sfric=30\n"
                          "liner range z 0.99 1.01 prop 2\n"
                          "grav 0 0 10\n"
                          "step 400\n"))
            << s.error();
        const LinerSet& ls = s.model.liners;
        ASSERT_EQ(ls.size(), 1);
        int broken = 0;
        double lift = 0;
        for (int i = 0; i < ls.n_nodes(); ++i) {
            broken += (ls.state[i] & kBondBrokenTension) != 0;
            lift = std::max(lift, ls.disp[i].z());
        }
        if (ncut > 5e3) {
            EXPECT_EQ(broken, 0) << "a bond of " << ncut << " Pa holds 5 kPa";
            EXPECT_LT(lift, 1e-5) << "held: the springs' and the rock's give only";
        } else {
            EXPECT_EQ(broken, ls.n_nodes()) << "a bond of " << ncut << " Pa breaks under 5 kPa";
            EXPECT_GT(lift, 5e-5) << "the liner comes off (slowly: static masses)";
        }
    }
}

// The same liner with gravity along x: its weight shears the bond (5 kPa, no normal pressure).
// A cohesion above it holds; one below breaks in shear and the liner slides off along x, held
// back by nothing but friction on no pressure.
TEST(Liner, BondBreaksInShearPastItsCohesion) {
    for (const double scoh : {2e4, 2e3}) {
        Session s;
        ASSERT_TRUE(s.run(kBrick)) << s.error();
        ASSERT_TRUE(s.run("prop mat=2 li_ncut=1e5 li_scoh=" + std::to_string(scoh) + " li_sfric=30\n"
                          "liner range z 0.99 1.01 prop 2\n"
                          "grav 10 0 0\n"
                          "step 400\n"))
            << s.error();
        const LinerSet& ls = s.model.liners;
        ASSERT_EQ(ls.size(), 1);
        int broken = 0;
        double slide = 0;
        for (int i = 0; i < ls.n_nodes(); ++i) {
            broken += (ls.state[i] & kBondBrokenShear) != 0;
            slide = std::max(slide, ls.disp[i].x());
        }
        if (scoh > 5e3) {
            EXPECT_EQ(broken, 0) << "a cohesion of " << scoh << " Pa holds 5 kPa";
            EXPECT_LT(slide, 1e-5);
        } else {
            EXPECT_EQ(broken, ls.n_nodes()) << "a cohesion of " << scoh << " Pa breaks under 5 kPa";
            EXPECT_GT(slide, 5e-5) << "the liner slides";
        }
    }
}

TEST(Liner, PrintHistFishAndVtkReadIt) {
    Session s;
    ASSERT_TRUE(s.run(kBrick)) << s.error();
    ASSERT_TRUE(s.run("liner range z 0.99 1.01 prop 2\n"
                      "grav 0 0 -10\n"
                      "hist liner_nx 1,0.5,1\n"
                      "hist liner_mx 1,0.5,1\n"
                      "step 50\n"
                      "def f\n"
                      "  n = li_num\n"
                      "  k = li_nel(li_id(1))\n"
                      "  a = li_nx(1, 1)\n"
                      "  b = li_bond_n(1, 1)\n"
                      "end\n"
                      "@f\n"))
        << s.error();
    const LinerSet& ls = s.model.liners;
    ASSERT_EQ(ls.size(), 1);
    // The top's zone faces, covering its 2 m^2.
    double area = 0;
    for (int i = 0; i < ls.n_nodes(); ++i) area += ls.area[i];
    EXPECT_NEAR(area, 2.0, 1e-9);
    EXPECT_GT(ls.n_elements(), 30);
    s.interp.quiet = false;
    ASSERT_TRUE(s.run("print liner\nprint prop\nhist list\n")) << s.error();
    const std::string out = s.out.str();
    EXPECT_NE(out.find("liner 1 (material 2): " + std::to_string(ls.n_elements()) + " elements"), std::string::npos) << out;
    EXPECT_NE(out.find("liner materials"), std::string::npos);
    EXPECT_NE(out.find("liner_nx liner 1 element"), std::string::npos) << out;
    ASSERT_EQ(s.model.histories.items.size(), 2u);
    EXPECT_FALSE(s.model.histories.items[0].values.empty());
    // The liner weighs on the rock: the bond is in compression.
    double total = 0;
    for (int i = 0; i < ls.n_nodes(); ++i) total += ls.bond_n[i];
    EXPECT_GT(total, 0.0);
    // The picture: one triangle per element coloured by n_x; the VTK file: the triangles and
    // their forces and moments.
    odec::render::PlotOptions opt;
    odec::render::Scene scene = odec::render::begin_scene(s.model, opt);
    EXPECT_EQ(odec::render::add_liners(scene, s.model, opt), ls.n_elements());
    ASSERT_EQ(scene.polygons.size(), 1u);
    EXPECT_EQ(scene.polygons[0].cell_scalars.size(), static_cast<size_t>(ls.n_elements()));
    EXPECT_EQ(scene.polygons[0].cell_scalars[3], liner_resultants(ls, 3).nx);
    char tmpl[] = "/tmp/odec-liner-test-XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    const std::string dir = tmpl;
    ASSERT_TRUE(s.run("plot liner file '" + dir + "/lin.png' size 320 240\nexport vtk '" + dir + "/lin'")) << s.error();
    char step[32];
    std::snprintf(step, sizeof step, "%06ld", s.model.step);
    const std::string vtp = read_bytes(dir + "/lin-liners-" + step + ".vtp");
    EXPECT_NE(vtp.find("NumberOfPoints=\"" + std::to_string(ls.n_nodes()) + "\""), std::string::npos);
    EXPECT_NE(vtp.find("NumberOfPolys=\"" + std::to_string(ls.n_elements()) + "\""), std::string::npos);
    for (const char* name : {"n_x", "n_y", "n_xy", "m_x", "m_y", "m_xy", "bond_normal_force", "bond_state"}) {
        EXPECT_NE(vtp.find(std::string("Name=\"") + name + "\""), std::string::npos) << name;
    }
    EXPECT_FALSE(s.run("new\nplot liner file '" + dir + "/none.png'"));
    EXPECT_NE(s.error().find("there are no liners to plot"), std::string::npos) << s.error();
    s.all_succeeded = true;
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
}

TEST(Liner, BadInputIsRefusedWithTheModelUnchanged) {
    Session s;
    ASSERT_TRUE(s.run(kBrick)) << s.error();
    const std::string before = s.model.liners.size() == 0 ? "none" : "some";
    // No face in the range.
    EXPECT_FALSE(s.run("liner range z 5 6 prop 2\n"));
    EXPECT_NE(s.error().find("t.dat:1:1"), std::string::npos) << s.error();
    EXPECT_NE(s.error().find("no free face"), std::string::npos) << s.error();
    // The held base faces the void too, but the faces between blocks are not free: a second brick
    // on top covers the first's top.
    // A material that is not defined.
    EXPECT_FALSE(s.run("liner range z 0.99 1.01 prop 7\n"));
    EXPECT_NE(s.error().find("liner material 7 is not defined"), std::string::npos) << s.error();
    // Zero and negative properties.
    EXPECT_FALSE(s.run("prop mat=3 li_e=0 li_thick=0.1\n"));
    EXPECT_NE(s.error().find("li_e"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("prop mat=3 li_e=1e9 li_thick=-0.1\n"));
    EXPECT_NE(s.error().find("li_thick"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("prop mat=3 li_e=1e9 li_kn=-1\n"));
    EXPECT_FALSE(s.run("prop mat=3 li_nu=0.5\n"));
    // A material with no thickness.
    ASSERT_TRUE(s.run("prop mat=4 li_e=1e9\n")) << s.error();
    EXPECT_FALSE(s.run("liner range z 0.99 1.01 prop 4\n"));
    EXPECT_NE(s.error().find("li_thick"), std::string::npos) << s.error();
    // No range, no material, a zero axis, delete without id.
    EXPECT_FALSE(s.run("liner prop 2\n"));
    EXPECT_FALSE(s.run("liner range z 0.99 1.01\n"));
    EXPECT_FALSE(s.run("liner range z 0.99 1.01 prop 2 axis 0,0,0\n"));
    EXPECT_FALSE(s.run("liner delete\n"));
    EXPECT_FALSE(s.run("liner id 3 delete\n"));
    EXPECT_EQ(s.model.liners.size(), 0);
    EXPECT_EQ(s.model.liners.n_nodes(), 0);
    // On rigid blocks: refused, they have no zone faces.
    Session r;
    ASSERT_TRUE(r.run("new\npoly brick 0 1 0 1 0 1\nprop mat=2 li_e=30e9 li_thick=0.2 li_kn=1e10 li_ks=1e10\n")) << r.error();
    EXPECT_FALSE(r.run("liner range z 0.99 1.01 prop 2\n"));
    EXPECT_NE(r.error().find("deformable"), std::string::npos) << r.error();
    EXPECT_EQ(r.model.liners.size(), 0);
    // A liner made, then deleted.
    ASSERT_TRUE(s.run("liner range z 0.99 1.01 prop 2\nliner id 1 delete\n")) << s.error();
    EXPECT_EQ(s.model.liners.size(), 0);
    (void)before;
}

// A covered face is not lined: two bricks stacked, the upper one standing on the lower; the
// lower's top is covered, so a range on it finds nothing free there.
TEST(Liner, CoveredFacesAreNotLined) {
    Session s;
    ASSERT_TRUE(s.run("new\npoly brick 0 1 0 1 0 1\npoly brick 0 1 0 1 1 2\n"
                      "prop mat=1 dens=2500 ymod=10e9 prat=0.25\ngen edge 0.5\n"
                      "prop mat=2 li_e=30e9 li_thick=0.2 li_kn=1e10 li_ks=1e10\n"))
        << s.error();
    EXPECT_FALSE(s.run("liner range z 0.99 1.01 prop 2\n"));
    EXPECT_NE(s.error().find("covered by another block"), std::string::npos) << s.error();
    ASSERT_TRUE(s.run("liner range z 1.99 2.01 prop 2\n")) << s.error();
    EXPECT_EQ(s.model.liners.size(), 1);
}

// Dynamic mode: a light liner, stiffly bonded to the top of a zoned brick, whose nodes set a step
// of 8.4e-7 s.
constexpr const char* kStiffLiner = "config dyn\npoly brick 0 2 0 1 0 1\nprop mat=1 dens=2500 ymod=10e9 prat=0.25\ngen edge 0.25\n"
                          "bound xvel 0 yvel 0 zvel 0 range z -0.01 0.01\n"
                          "prop mat=2 li_e=30e9 li_nu=0.2 li_thick=0.2 li_dens=10 li_kn=1e12 li_ks=1e12\n"
                          "liner range z 0.99 1.01 prop 2\n";

// 'mscale' raises the liner nodes that hold the dynamic step down, as it raises gridpoints and
// blocks: a light, stiffly bonded liner sets a step of 8.4e-7 s; at 3e-6 s its nodes ran away
// (the report said no mass needed scaling). Raised, they run, and the report counts them.
TEST(Liner, MscaleRaisesTheNodesThatHoldTheStepDown) {
    Session s;
    s.interp.quiet = false;
    ASSERT_TRUE(s.run(std::string(kStiffLiner) + "grav 0 0 -10\nstep 1"))
        << s.error();
    const double real_dt = s.model.dt;
    ASSERT_LT(real_dt, 1e-6);
    s.out.str("");
    ASSERT_TRUE(s.run("mscale 3e-6\nstep 300")) << s.error();
    EXPECT_EQ(s.model.dt, 3e-6);
    const std::string out = s.out.str();
    EXPECT_NE(out.find("cable and liner node masses scaled"), std::string::npos) << out;
    const LinerSet& ls = s.model.liners;
    for (int i = 0; i < ls.n_nodes(); ++i) {
        ASSERT_TRUE(std::isfinite(ls.vel[i].norm())) << "node " << i + 1;
        EXPECT_LT(ls.vel[i].norm(), 1.0) << "node " << i + 1;
    }
}

// A liner node whose mass 'mscale' raises keeps its momentum (its kinetic energy never rises
// from the change), as blocks, gridpoints and cable nodes do.
TEST(Liner, ARaisedNodeKeepsItsMomentum) {
    Session s;
    ASSERT_TRUE(s.run(std::string(kStiffLiner) + "step 1"))
        << s.error();
    LinerSet& ls = s.model.liners;
    std::vector<double> momentum(ls.n_nodes());
    for (int i = 0; i < ls.n_nodes(); ++i) {
        ls.vel[i] = Vec3(1, 0, 0);
        momentum[i] = ls.inertial_mass[i];
    }
    ASSERT_EQ(choose_liner_masses(s.model, 3e-6), "");
    int raised = 0;
    for (int i = 0; i < ls.n_nodes(); ++i) {
        raised += ls.inertial_mass[i] > ls.mass[i];
        EXPECT_NEAR(ls.inertial_mass[i] * ls.vel[i].x(), momentum[i], 1e-12 * momentum[i]) << "node " << i + 1;
    }
    EXPECT_GT(raised, 0);
}
