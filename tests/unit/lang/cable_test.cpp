// Cables and rock bolts (engine/cable.h) against closed forms: a pull-out test (the elastic
// force profile of a bar on an elastic foundation, and the peak force at full slip of the
// grout), a bolt across an opening joint (the two grouted halves in series until the steel
// yields), in rigid and deformable blocks; and the commands, FISH and histories around them.
#include <gtest/gtest.h>

#include <stdlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/cable.h"
#include "fish/runtime.h"
#include "render/scene_builder.h"
#include "test_util.h"

using odec::test::Session;

namespace {

const std::string kDir = std::string(ODEC_SOURCE_DIR) + "/examples/verification/";

std::string read_text(const std::string& path) {
    std::ifstream f(path);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

void report(const char* what, double computed, double analytic, const char* unit) {
    std::printf("[verification] %-44s computed %12.6g  analytic %12.6g %s  (%+.3f %%)\n", what, computed, analytic, unit,
                100.0 * (computed - analytic) / analytic);
}

// The steel and grout of the examples.
constexpr double kEA = 98.6e9 * 1.81e-4;
const double kLambda = std::sqrt(112e6 / kEA);

} // namespace

TEST(Cable, PullOutElasticProfileAndPeak) {
    const std::string text = read_text(kDir + "cable-pullout.dat");
    const std::string marker = "; then on to full slip";
    const size_t cut = text.find(marker);
    ASSERT_NE(cut, std::string::npos);
    Session s;
    ASSERT_TRUE(s.run(text.substr(0, cut))) << s.error();
    const odec::CableSet& cs = s.model.cables;
    ASSERT_EQ(cs.size(), 1);
    ASSERT_EQ(cs.segments_of(0), 40);
    for (int i = 0; i < cs.n_nodes(); ++i) EXPECT_EQ(cs.host_block[i], 1) << "node " << i + 1 << " is grouted";
    // The pulled end is held at u0 (prescribed); the profile against the closed form.
    const double L = 2.0, u0 = -cs.disp[0].x();
    EXPECT_NEAR(u0, 5e-4, 1e-6);
    const double p_exact = kEA * kLambda * u0 * std::tanh(kLambda * L);
    double worst = 0;
    for (int k = 0; k < cs.segments_of(0); ++k) {
        const double x = 0.5 * (cs.pos[k].x() + cs.pos[k + 1].x());
        const double exact = kEA * kLambda * u0 * std::sinh(kLambda * (L - x)) / std::cosh(kLambda * L);
        worst = std::max(worst, std::abs(cs.axial[k] - exact) / p_exact);
    }
    const double x1 = 0.5 * (cs.pos[0].x() + cs.pos[1].x());
    report("8a pull-out: force in segment 1 (elastic)", cs.axial[0],
           kEA * kLambda * u0 * std::sinh(kLambda * (L - x1)) / std::cosh(kLambda * L), "N");
    std::printf("[verification] 8a pull-out: largest error of the elastic profile over its 40 segments: %.3f %% "
                "of the pull force\n", 100 * worst);
    EXPECT_LT(worst, 0.02);
    // Still elastic: the grout nowhere near its strength.
    for (int i = 0; i < cs.n_nodes(); ++i) EXPECT_FALSE(cs.state[i] & odec::kGroutSlipPast);
    // On to full slip: the pull force's peak is the bond strength times the embedded length.
    ASSERT_TRUE(s.run(text.substr(cut))) << s.error();
    const auto& pull = s.model.histories.items.at(1).values;
    ASSERT_GT(pull.size(), 100u);
    const double peak = *std::max_element(pull.begin(), pull.end());
    report("8a pull-out: peak pull force", peak, 0.175e6 * L, "N");
    EXPECT_NEAR(peak, 0.175e6 * L, 0.02 * 0.175e6 * L);
    for (int i = 0; i < cs.n_nodes(); ++i) EXPECT_TRUE(cs.state[i] & odec::kGroutSlipNow) << "node " << i + 1;
    // The far end has come out with the rest: every node slipped, out of the hole (along -x).
    EXPECT_LT(cs.slip.back(), 0);
    EXPECT_LT(cs.slip.front(), cs.slip.back());
}

namespace {

// The bolt across the joint: force at the joint against opening, elastic then at yield.
void check_joint_bolt(Session& s, const char* label) {
    const auto& dis = s.model.histories.items.at(0).values;
    const auto& force = s.model.histories.items.at(1).values;
    ASSERT_EQ(dis.size(), force.size());
    ASSERT_GT(dis.size(), 20u);
    const double k_exact = kEA * kLambda * std::tanh(kLambda * 1.0) / 2.0;
    // The elastic stretch: the secant stiffness at openings of 1 to 3 mm.
    int n = 0;
    double worst = 0, at2mm = 0, delta2mm = 0;
    for (size_t k = 0; k < dis.size(); ++k) {
        if (dis[k] < 1e-3 || dis[k] > 3e-3) continue;
        ++n;
        worst = std::max(worst, std::abs(force[k] / dis[k] - k_exact) / k_exact);
        if (std::abs(dis[k] - 2e-3) < std::abs(delta2mm - 2e-3)) {
            delta2mm = dis[k];
            at2mm = force[k];
        }
    }
    ASSERT_GT(n, 5);
    char what[96];
    std::snprintf(what, sizeof what, "8b %s: force / opening (elastic)", label);
    report(what, at2mm / delta2mm, k_exact, "N/m");
    EXPECT_LT(worst, 0.02) << "largest error of the secant stiffness between 1 and 3 mm of opening";
    // Past yield: the yield force, exactly.
    std::snprintf(what, sizeof what, "8b %s: force at 8 mm (yield)", label);
    report(what, force.back(), 0.1e6, "N");
    EXPECT_GT(dis.back(), 7e-3);
    EXPECT_NEAR(force.back(), 0.1e6, 1e-6 * 0.1e6);
    const odec::CableSet& cs = s.model.cables;
    EXPECT_TRUE(cs.seg_state[20] & odec::kCableYieldTensionNow);
    // The grout held (sbond was chosen so): no node slipped.
    for (int i = 0; i < cs.n_nodes(); ++i) EXPECT_FALSE(cs.state[i] & odec::kGroutSlipPast) << "node " << i + 1;
}

} // namespace

TEST(Cable, BoltAcrossOpeningJointRigidBlocks) {
    Session s;
    ASSERT_TRUE(s.interp.run_file(kDir + "cable-joint.dat")) << s.error();
    const odec::CableSet& cs = s.model.cables;
    // Nodes 1..21 in the fixed block, 22..42 in the moving one.
    EXPECT_EQ(cs.host_block[20], 1);
    EXPECT_EQ(cs.host_block[21], 2);
    check_joint_bolt(s, "bolt, rigid blocks");
}

TEST(Cable, BoltAcrossOpeningJointDeformableBlock) {
    // The same with the moving block divided into zones, all its gridpoints driven: the grout
    // reads the rock's motion from the zone's gridpoints and gives its force back to them.
    std::string text = read_text(kDir + "cable-joint.dat");
    const std::string from = "bound xvel 0.01 range region 2";
    const size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos);
    text.replace(at, from.size(), "prop mat=1 k=2e10 g=1e10\ngen edge 0.4 range region 2\nbound xvel 0.01 range region 2");
    const std::string hist_from = "hist xdis 0.5,0,0";
    text.replace(text.find(hist_from), hist_from.size(), "hist xdis 1,0.5,0.5");
    Session s;
    ASSERT_TRUE(s.run(text)) << s.error();
    const odec::CableSet& cs = s.model.cables;
    EXPECT_EQ(cs.host_gp[20][0], -1);
    EXPECT_GE(cs.host_gp[21][0], 0);
    check_joint_bolt(s, "bolt, deformable block");
}

TEST(Cable, CommandsFishAndHistories) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 2 -0.5 0.5 -0.5 0.5\n"
                      "prop mat=1 dens=2700\n"
                      "prop mat=3 cb_area=1e-4 cb_e=2e11 cb_kbond=1e8 cb_sbond=1e5 cb_dens=7800\n"
                      "cable -1,0,0 1,0,0 seg 4 prop 3 pretension 1e3\n"))
        << s.error();
    const odec::CableSet& cs = s.model.cables;
    ASSERT_EQ(cs.size(), 1);
    // Nodes at -1 and -0.5 are in no block: no grout.
    EXPECT_EQ(cs.host_block[0], 0);
    EXPECT_EQ(cs.host_block[1], 0);
    EXPECT_EQ(cs.host_block[2], 1);
    EXPECT_DOUBLE_EQ(cs.axial[0], 1e3);
    s.out.str("");
    s.interp.quiet = false;
    ASSERT_TRUE(s.run("print cable")) << s.error();
    EXPECT_NE(s.out.str().find("cable 1 (material 3): 4 segments"), std::string::npos) << s.out.str();
    EXPECT_NE(s.out.str().find("free"), std::string::npos);
    ASSERT_TRUE(s.run("print prop")) << s.error();
    EXPECT_NE(s.out.str().find("cable materials"), std::string::npos);
    s.interp.quiet = true;
    ASSERT_TRUE(s.run("def f\n  a = cable_force(1,2)\n  b = cable_nseg(1)\n  c = cable_gstate(1,1)\n"
                      "  d = cable_block(1,3)\n  e = xcomp(cable_pos(1,5))\n  n = cable_num\nend\n@f"))
        << s.error();
    auto number = [&s](const char* name) {
        const odec::fish::Symbol* sym = s.interp.fish().find(name);
        EXPECT_NE(sym, nullptr) << name;
        return sym ? sym->value.number() : -1.0;
    };
    EXPECT_DOUBLE_EQ(number("a"), 1000.0);
    EXPECT_EQ(number("b"), 4);
    EXPECT_EQ(number("c"), -1);
    EXPECT_EQ(number("d"), 1);
    EXPECT_DOUBLE_EQ(number("e"), 1.0);
    EXPECT_EQ(number("n"), 1);
    // Histories of a segment's force and a node's grout force.
    ASSERT_TRUE(s.run("hist cable_force 0.75,0,0\nhist cable_grout 1,0,0")) << s.error();
    EXPECT_EQ(s.model.histories.items[0].cable_item, 4);
    EXPECT_EQ(s.model.histories.items[1].cable_item, 5);
    // Bad input: a clear error, and the model as it was.
    EXPECT_FALSE(s.run("cable 0,0,0 1,0,0 seg 4 prop 7"));
    EXPECT_NE(s.error().find("cable material 7 is not defined"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("cable 0,0,0 1,0,0 prop 3"));
    EXPECT_NE(s.error().find("'seg n'"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("cable id 2 delete"));
    EXPECT_NE(s.error().find("there is no cable 2"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("cable id 1 node 9 velocity 0,0,0"));
    EXPECT_NE(s.error().find("has 5 nodes"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("def h\n  h = cable_force(1,5)\nend\n@h"));
    EXPECT_NE(s.error().find("has 4 segments"), std::string::npos) << s.error();
    EXPECT_EQ(cs.size(), 1);
    s.all_succeeded = true;
    // Cycling (static mode, the nodes' masses from their stiffness), the cable's free end held
    // (its plate): the free part keeps the pretension, less what the grout let the cable slide
    // in; the grouted part sheds it into the rock.
    ASSERT_TRUE(s.run("fix\ncable id 1 node 1 velocity 0,0,0\nsolve ratio 1e-8")) << s.error();
    EXPECT_GT(cs.axial[0], 500);
    EXPECT_LE(cs.axial[0], 1e3);
    EXPECT_NEAR(cs.axial[1], cs.axial[0], 1e-3 * cs.axial[0]);
    EXPECT_LT(cs.axial[2], cs.axial[1]);
    EXPECT_LT(cs.axial[3], cs.axial[2]);
    EXPECT_GT(cs.axial[3], 0);
    ASSERT_TRUE(s.run("cable id 1 delete")) << s.error();
    EXPECT_EQ(cs.size(), 0);
    EXPECT_EQ(s.model.histories.items.size(), 2u);
}

TEST(Cable, BoltedBlockOnIncline) {
    const std::string text = read_text(kDir + "cable-incline.dat");
    // Without its bolt the block slides away.
    {
        std::string loose = text;
        const size_t from = loose.find("cable 1.95");
        ASSERT_NE(from, std::string::npos);
        loose.erase(from, loose.find('\n', from) - from);
        const size_t h = loose.find("hist cable_force");
        loose.erase(h, loose.find('\n', h) - h);
        const size_t solve = loose.rfind("solve ratio 1e-6");
        loose.replace(solve, loose.size() - solve, "step 3000\n");
        Session s;
        ASSERT_TRUE(s.run(loose)) << s.error();
        const double slid = s.model.histories.items.at(0).values.back();
        std::printf("[verification] 8c incline without the bolt: the block has slid %.3g m in 3000 steps\n", slid);
        EXPECT_GT(slid, 0.1);
    }
    Session s;
    ASSERT_TRUE(s.run(text)) << s.error();
    const auto& dis = s.model.histories.items.at(0).values;
    const auto& force = s.model.histories.items.at(1).values;
    ASSERT_GT(dis.size(), 5u);
    // Held: it stopped within millimetres, in equilibrium with the bolt's force.
    EXPECT_GT(dis.back(), 1e-4);
    EXPECT_LT(dis.back(), 0.02);
    EXPECT_NEAR(dis.back(), dis[dis.size() - 3], 1e-3 * dis.back());
    ASSERT_TRUE(s.run("def imbalance\n  imbalance = balance\nend\n@imbalance")) << s.error();
    const odec::fish::Symbol* b = s.interp.fish().find("imbalance");
    ASSERT_NE(b, nullptr);
    const double imbalance = b->value.number();
    std::printf("[verification] 8c bolted block: bolt force %.6g N after %.3g mm of sliding; limit equilibrium "
                "off by %.3g %% of W sin 40\n", force.back(), 1e3 * dis.back(), 100 * imbalance);
    EXPECT_LT(std::abs(imbalance), 0.02);
    // The bolt carries what the joint cannot: about W (sin 40 - cos 40 tan 20) / (cos b + sin b tan 20).
    EXPECT_GT(force.back(), 3e5);
    EXPECT_LT(force.back(), 2e6);
}

TEST(Cable, PlotAndVtkExport) {
    char tmpl[] = "/tmp/odec-cable-test-XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    const std::string dir = tmpl;
    Session s;
    ASSERT_TRUE(s.interp.run_file(kDir + "cable-joint.dat")) << s.error();
    EXPECT_FALSE(s.run("new\nplot cable file '" + dir + "/none.png'"));
    EXPECT_NE(s.error().find("there are no cables to plot"), std::string::npos) << s.error();
    s.all_succeeded = true;
    ASSERT_TRUE(s.interp.run_file(kDir + "cable-joint.dat")) << s.error();
    // The picture: a tube of 4 faces per segment, coloured by the axial force over its range.
    odec::render::PlotOptions opt;
    odec::render::Scene scene = odec::render::begin_scene(s.model, opt);
    EXPECT_EQ(odec::render::add_cables(scene, s.model, opt), 41);
    ASSERT_EQ(scene.polygons.size(), 1u);
    const auto& layer = scene.polygons[0];
    EXPECT_EQ(layer.cell_scalars.size(), 4u * 41u);
    EXPECT_DOUBLE_EQ(*std::max_element(layer.cell_scalars.begin(), layer.cell_scalars.end()), 1e5);
    EXPECT_EQ(layer.scale.units, "N");
    ASSERT_TRUE(s.run("plot block cable file '" + dir + "/bolt.png' size 320 240\nexport vtk '" + dir + "/bolt'"))
        << s.error();
#if ODEC_HAVE_PICTURES
    EXPECT_GT(odec::test::read_bytes(dir + "/bolt.png").size(), 1000u);
#else
    EXPECT_EQ(odec::test::read_bytes(dir + "/bolt.png").size(), 0u); // built without pictures: none drawn
#endif
    const std::string vtp = odec::test::read_bytes(dir + "/bolt-cables-" + [&] {
        char step[32];
        std::snprintf(step, sizeof step, "%06ld", s.model.step);
        return std::string(step);
    }() + ".vtp");
    EXPECT_NE(vtp.find("NumberOfPoints=\"42\""), std::string::npos);
    EXPECT_NE(vtp.find("NumberOfLines=\"41\""), std::string::npos);
    EXPECT_NE(vtp.find("Name=\"axial_force\""), std::string::npos);
    EXPECT_NE(vtp.find("Name=\"grout_force\""), std::string::npos);
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
}

TEST(Cable, RestoredModelCyclesOnToTheSameBits) {
    // A cable model saved mid-run and restored steps on to the same bits as one never saved.
    char tmpl[] = "/tmp/odec-cable-save-XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    const std::string dir = tmpl;
    std::string text = read_text(kDir + "cable-joint.dat");
    text.replace(text.find("step time 0.8"), std::string("step time 0.8").size(), "step 2000");
    Session straight;
    ASSERT_TRUE(straight.run(text + "\nstep 1000\nsave '" + dir + "/straight'")) << straight.error();
    Session first;
    ASSERT_TRUE(first.run(text + "\nsave '" + dir + "/half'")) << first.error();
    Session second;
    ASSERT_TRUE(second.run("restore '" + dir + "/half'\nstep 1000\nsave '" + dir + "/resumed'")) << second.error();
    EXPECT_EQ(straight.model.cables.axial, second.model.cables.axial);
    EXPECT_EQ(straight.model.cables.pos, second.model.cables.pos);
    EXPECT_EQ(straight.model.histories.items[1].values, second.model.histories.items[1].values);
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
}

TEST(Cable, RefusedPropertiesChangeNothing) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=2 cb_area=1e-4 cb_e=2e11 cb_kbond=1e8\n"
                      "cable 0.5,0.5,0.2 0.5,0.5,0.8 seg 3 prop 2"))
        << s.error();
    // A cable property with a joint material, a cable left without steel, a bad block density
    // beside a good cable property: each refused, the cable material as it was.
    EXPECT_FALSE(s.run("prop jmat=1 cb_area=1"));
    EXPECT_NE(s.error().find("'cb_area' is a cable property: give it with 'mat=n'"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("prop mat=2 cb_e=0"));
    EXPECT_FALSE(s.run("prop mat=2 cb_kbond=5e8 ymod=1e9"));
    EXPECT_NE(s.error().find("'ymod' and 'prat' go together"), std::string::npos) << s.error();
    s.all_succeeded = true;
    EXPECT_EQ(s.model.cables.materials[2].kbond, 1e8);
    EXPECT_EQ(s.model.cables.materials[2].e, 2e11);
    // Both at once when both are right.
    ASSERT_TRUE(s.run("prop mat=2 cb_kbond=5e8 cb_dens=7800 dens=2700")) << s.error();
    EXPECT_EQ(s.model.cables.materials[2].kbond, 5e8);
    EXPECT_EQ(s.model.materials[2].density, 2700);
    EXPECT_DOUBLE_EQ(s.model.cables.mass[1], 7800 * 1e-4 * 0.2);
}

// A block cut after a bolt was grouted into it ('jset' through the bolt): each node stays grouted
// to its point of rock, now in the piece that holds it, and the bolt works across the new joint
// exactly as one installed after the cut. Before, the nodes beyond the cut stayed tied to the
// first piece at levers from its old centroid: pulled 1 mm apart, the bolt carried 3.8 kN at the
// joint (and 16.8 kN three segments on) where the bolt installed after the cut carries 21.5 kN.
TEST(Cable, ABoltInABlockCutLaterWorksAcrossTheNewJoint) {
    const std::string rock = "poly brick 0 4 -0.5 0.5 -0.5 0.5\nprop mat=1 dens=2700\n"
                             "prop jmat=1 jkn=1e10 jks=1e10 jfric=30\n"
                             "prop mat=2 cb_area=1.81e-4 cb_e=98.6e9 cb_yield=1e6 cb_kbond=112e6 cb_sbond=10e6 "
                             "cb_dens=7800\n";
    const std::string bolt = "cable 0.1,0,0 3.9,0,0 seg 19 prop 2\n", cut = "jset dip 90 dd 90 origin 3,0,0\n";
    const std::string pull = "fix range x 0 3\nbound xvel 0.01 range x 3 4\nstep time 0.1\nbound xvel 0 range x 3 4\n"
                             "solve ratio 1e-8\n";
    Session before, after;
    ASSERT_TRUE(before.run(rock + bolt + cut + pull)) << before.error();
    ASSERT_TRUE(after.run(rock + cut + bolt + pull)) << after.error();
    const odec::CableSet& a = before.model.cables;
    const odec::CableSet& b = after.model.cables;
    for (int i = 0; i < a.n_nodes(); ++i) {
        EXPECT_EQ(a.host_block[i], a.pos[i].x() < 3 ? 1 : 2) << "node " << i + 1;
        EXPECT_NEAR((a.host_lever[i] - b.host_lever[i]).norm(), 0.0, 1e-12) << "node " << i + 1;
    }
    // Segment 15 (x 2.9 to 3.1) crosses the joint.
    report("bolt grouted before the cut: force at the joint", a.axial[14], b.axial[14], "N");
    EXPECT_NEAR(a.axial[14], b.axial[14], 1e-6 * b.axial[14]);
    EXPECT_GT(a.axial[14], 2e4);
}

// The grout of a node whose rock is excavated is gone: the node is free and carries no grout
// force (it used to keep 21.9 kN, printed beside "free", and brought it back into the rock on
// 'fill'); a node whose block is only zoned again keeps its grout's force.
TEST(Cable, GroutGoesWithItsRockAndStaysWhenTheRockIsZoned) {
    const std::string model = "poly brick -1 0 -0.5 0.5 -0.5 0.5 region 1\npoly brick 0 1 -0.5 0.5 -0.5 0.5 region 2\n"
                              "prop mat=1 dens=2700 k=1e10 g=1e10\nprop jmat=1 jkn=1e10 jks=1e10 jfric=30\nfix range region 1\n"
                              "prop mat=2 cb_area=1.81e-4 cb_e=98.6e9 cb_yield=1e6 cb_kbond=112e6 cb_sbond=2e6 cb_dens=7800\n"
                              "cable -1,0,0 1,0,0 seg 20 prop 2\nbound xvel 0.01 range region 2\nstep time 0.1\n"
                              "bound xvel 0 range region 2\nsolve ratio 1e-7\n";
    Session s;
    ASSERT_TRUE(s.run(model)) << s.error();
    const odec::CableSet& cs = s.model.cables;
    const std::vector<double> loaded = cs.grout_force;
    double right = 0;
    for (int i = 11; i < cs.n_nodes(); ++i) right += std::abs(loaded[i]);
    EXPECT_GT(right, 2e4);
    Session zoned;
    ASSERT_TRUE(zoned.run(model + "gen edge 0.25 range region 2\n")) << zoned.error();
    ASSERT_TRUE(zoned.run("step 1")) << zoned.error();
    for (int i = 11; i < cs.n_nodes(); ++i) {
        EXPECT_GT(zoned.model.cables.host_gp[i][0], -1) << "node " << i + 1;
        EXPECT_NEAR(zoned.model.cables.grout_force[i], loaded[i], 0.01 * std::abs(loaded[i]) + 1) << "node " << i + 1;
    }
    ASSERT_TRUE(s.run("excavate range region 2\nstep 1")) << s.error();
    for (int i = 11; i < cs.n_nodes(); ++i) {
        EXPECT_EQ(cs.host_block[i], 0) << "node " << i + 1;
        EXPECT_EQ(cs.grout_force[i], 0.0) << "node " << i + 1;
        EXPECT_EQ(cs.slip[i], 0.0) << "node " << i + 1;
    }
}

// A bolt that carries no compression (cb_ycomp 0) goes slack across a closing joint: no force,
// and no yield reported (every segment read "yield-p" and cable_yield 3 at 1 to 41 kN below the
// 100 kN yield); one with a compressive yield reports it once it is reached.
TEST(Cable, ASlackBoltDoesNotYield) {
    for (const double ycomp : {0.0, 5e4}) {
        Session s;
        ASSERT_TRUE(s.run("poly brick -1 0 -0.5 0.5 -0.5 0.5 region 1\npoly brick 0 1 -0.5 0.5 -0.5 0.5 region 2\n"
                          "prop mat=1 dens=2700\nprop jmat=1 jkn=1e10 jks=1e10 jfric=30\nfix range region 1\n"
                          "prop mat=2 cb_area=1.81e-4 cb_e=98.6e9 cb_yield=1e5 cb_ycomp=" + std::to_string(ycomp) +
                          " cb_kbond=112e6 cb_sbond=2e6 cb_dens=7800\ncable -1,0,0 1,0,0 seg 41 prop 2\n"
                          "bound xvel -0.01 range region 2\nstep time 0.5\nbound xvel 0 range region 2\nsolve ratio 1e-8"))
            << s.error();
        const odec::CableSet& cs = s.model.cables;
        // Segment 21 crosses the joint, closed by 5 mm: -2.2e7 x 5e-3 = -1.1e5 N elastic, past
        // either limit (the blocks settle back a little after the push: within 1 %).
        EXPECT_GE(cs.axial[20], -ycomp);
        EXPECT_LT(cs.axial[20], -ycomp + 0.01 * 1.1e5);
        int yielded = 0;
        for (std::uint8_t st : cs.seg_state) yielded += (st & odec::kCableYieldPast) != 0;
        if (ycomp == 0) {
            EXPECT_EQ(yielded, 0);
        } else {
            EXPECT_GT(yielded, 0);
        }
    }
}
