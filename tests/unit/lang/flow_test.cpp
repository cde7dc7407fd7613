// Fluid flow in the joints (flow.h): the verification problems of examples/verification/flow-*.dat
// against their analytic answers, conservation in transient flow, what reads the flow (print, hist,
// FISH, plot, VTK) and the refusals of bad input.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "engine/blocks.h"
#include "engine/flow.h"
#include "engine/zones.h"
#include "fish/runtime.h"
#include "test_util.h"

using odec::test::Session;

namespace {

const std::string kDir = std::string(ODEC_SOURCE_DIR) + "/examples/verification/";

std::string script_text(const std::string& name) {
    std::ifstream in(kDir + name);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

// The script with one piece of text replaced (which must be there).
std::string with(std::string script, const std::string& from, const std::string& to) {
    const size_t at = script.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) script.replace(at, from.size(), to);
    return script;
}

void report(const char* what, double computed, double analytic, const char* unit) {
    std::printf("[verification] %-44s computed %12.6g  analytic %12.6g %s  (%+.3f %%)\n", what, computed, analytic, unit,
                100.0 * (computed - analytic) / analytic);
}

// flow-opening.dat with the pressure held at p + 250 Pa along x = 0 and p - 250 Pa along x = 4;
// `zoned`: the upper block zoned, the lower one held.
std::string opening_script(double p, bool zoned) {
    char in[48], out[48];
    std::snprintf(in, sizeof in, "bound pp %.6g range x -0.01", p + 250);
    std::snprintf(out, sizeof out, "bound pp %.6g range x 3.99", p - 250);
    std::string script = with(script_text("flow-opening.dat"), "bound pp 20250 range x -0.01", in);
    script = with(script, "bound pp 19750 range x 3.99", out);
    if (zoned) {
        script = with(script, "fix range z -1 0\n", "prop mat=1 k=2e10 g=1.5e10\ngen edge 0.5 range z 0 1\nfix range z -1 -0.01\n");
    }
    return script;
}

// The flow the fixed nodes at x < x_max feed in (the inlet side), m^3/s.
double inflow_left(const odec::Model& m, double x_max) {
    const odec::FlowSet& f = m.flow;
    double q = 0;
    for (int i = 0; i < f.n_nodes(); ++i) {
        if (f.fixed[i] && f.pos[i].x() < x_max) q -= f.inflow[i];
    }
    return q;
}

} // namespace

TEST(Flow, ParallelPlateCubicLaw) {
    Session s;
    ASSERT_TRUE(s.interp.run_file(kDir + "flow-parallel-plate.dat")) << s.error();
    const double a = 2e-4, w = 2, l = 4, dp = 1e5, mu = 1e-3;
    const double q_exact = a * a * a * w * dp / (12 * mu * l);
    const double q = inflow_left(s.model, 0.01);
    report("flow: parallel plate, Q", q, q_exact, "m^3/s");
    EXPECT_NEAR(q, q_exact, 1e-3 * q_exact);
    // What flows in flows out, and the pressure inside falls linearly.
    EXPECT_NEAR(odec::fixed_inflow(s.model), q_exact, 1e-3 * q_exact);
    const odec::FlowSet& f = s.model.flow;
    int inside = 0;
    for (int i = 0; i < f.n_nodes(); ++i) {
        if (std::abs(f.pos[i].z()) > 1e-6 || f.fixed[i]) continue;
        const double p_exact = dp * (1 - f.pos[i].x() / l);
        EXPECT_NEAR(f.pp[i], p_exact, 1e-3 * dp) << "node at x = " << f.pos[i].x();
        ++inside;
    }
    EXPECT_EQ(inside, 6); // x = 1, 2, 3 on both sides
    EXPECT_NE(s.out.str().find("inflow at the fixed nodes 3.33e-05 m^3/s"), std::string::npos) << s.out.str();
}

// Whether the block on the incline slides when its base joint holds pressure p, Pa.
bool incline_slides(double p, double* moved = nullptr) {
    Session s;
    char text[32];
    std::snprintf(text, sizeof text, "bound pp %.6g", p);
    EXPECT_TRUE(s.run(with(script_text("flow-incline.dat"), "bound pp 6800", text))) << s.error();
    const int b = s.model.block_index(2);
    const double d = s.model.blocks.disp[b].norm();
    if (moved) *moved = d;
    return d > 1e-3;
}

TEST(Flow, InclineSlidesAtTheAnalyticPressure) {
    const double deg = M_PI / 180;
    const double p_c = 20000 * (std::cos(20 * deg) - std::sin(20 * deg) / std::tan(30 * deg));
    double d_lo = 0, d_hi = 0;
    EXPECT_FALSE(incline_slides(0.98 * p_c, &d_lo)) << "moved " << d_lo;
    EXPECT_TRUE(incline_slides(1.02 * p_c, &d_hi)) << "moved " << d_hi;
    // Between them, by halves: the pressure at which it starts to slide.
    double lo = 0.98 * p_c, hi = 1.02 * p_c;
    for (int k = 0; k < 5; ++k) {
        const double mid = 0.5 * (lo + hi);
        (incline_slides(mid) ? hi : lo) = mid;
    }
    const double found = 0.5 * (lo + hi);
    report("flow: incline, pressure that slides the block", found, p_c, "Pa");
    EXPECT_NEAR(found, p_c, 0.01 * p_c);
}

TEST(Flow, DamUpliftIsLinearFromHeelToToe) {
    Session s;
    ASSERT_TRUE(s.interp.run_file(kDir + "flow-dam-uplift.dat")) << s.error();
    const double p1 = 196200, p2 = 19620, b = 10, w = 2;
    const odec::FlowSet& f = s.model.flow;
    double worst = 0;
    int base = 0;
    for (int i = 0; i < f.n_nodes(); ++i) {
        if (std::abs(f.pos[i].z()) > 1e-6 || f.pos[i].x() < -1e-6 || f.pos[i].x() > b + 1e-6) continue;
        const double p_exact = p1 + (p2 - p1) * f.pos[i].x() / b;
        worst = std::max(worst, std::abs(f.pp[i] - p_exact) / p_exact);
        ++base;
    }
    EXPECT_EQ(base, 22);
    std::printf("[verification] flow: dam uplift, largest error of the base pressures %.4f %%\n", 100 * worst);
    EXPECT_LT(worst, 0.02);
    // The uplift on the dam (block 13, the last made), and where it acts.
    const int dam = s.model.block_index(13);
    const double up = f.block_force[dam].z(), up_exact = b * w * (p1 + p2) / 2;
    report("flow: dam uplift force", up, up_exact, "N");
    EXPECT_NEAR(up, up_exact, 0.02 * up_exact);
    // Its moment about the dam's centroid (x = 5) gives its line of action.
    const double x_c = s.model.blocks.centroid[dam].x() + f.block_moment[dam].y() / -up;
    const double x_exact = b * (p1 + 2 * p2) / (3 * (p1 + p2));
    report("flow: dam uplift, distance from the heel", x_c, x_exact, "m");
    EXPECT_NEAR(x_c, x_exact, 0.02 * x_exact);
}

// 'solve' waits for the flow to settle: the dam's base pressures reached by solve alone.
TEST(Flow, SolveWaitsForTheFlow) {
    Session s;
    ASSERT_TRUE(s.run(with(with(script_text("flow-dam-uplift.dat"), "step 1000", "solve ratio 1e-6"), "set substeps 20\n", "")))
        << s.error();
    const odec::FlowSet& f = s.model.flow;
    EXPECT_LT(odec::flow_unbalance(s.model), 1e-6);
    for (int i = 0; i < f.n_nodes(); ++i) {
        if (std::abs(f.pos[i].z()) > 1e-6 || f.pos[i].x() < -1e-6 || f.pos[i].x() > 10 + 1e-6) continue;
        const double p_exact = 196200 + (19620 - 196200) * f.pos[i].x() / 10;
        EXPECT_NEAR(f.pp[i], p_exact, 1e-4 * p_exact) << "node at x = " << f.pos[i].x();
    }
}

TEST(Flow, JointOpensUnderPressureAndFlowFollowsTheCubicLaw) {
    const double sigma = 25000, kn = 1e8, azero = 3e-4, w = 2, l = 4, mu = 1e-3, dp = 500;
    double q_first = 0, q_last = 0;
    for (double p : {1000.0, 10000.0, 20000.0}) {
        Session s;
        ASSERT_TRUE(s.run(opening_script(p, false))) << s.error();
        const double a_exact = azero - (sigma - p) / kn;
        const odec::ContactFlow cf = odec::contact_flow(s.model, 0);
        char what[64];
        std::snprintf(what, sizeof what, "flow: opening joint, aperture at p = %g", p);
        report(what, cf.aperture, a_exact, "m");
        EXPECT_NEAR(cf.aperture, a_exact, 0.01 * a_exact);
        const double q_exact = a_exact * a_exact * a_exact * w * dp / (12 * mu * l);
        const double q = inflow_left(s.model, 0.01);
        std::snprintf(what, sizeof what, "flow: opening joint, Q at p = %g", p);
        report(what, q, q_exact, "m^3/s");
        EXPECT_NEAR(q, q_exact, 0.01 * q_exact);
        // The joint's springs carry the effective stress.
        EXPECT_NEAR(odec::contact_info(s.model, 0).normal_stress, sigma - p, 0.01 * sigma);
        if (p == 1000.0) q_first = q;
        q_last = q;
    }
    EXPECT_GT(q_last, 50 * q_first);
}

// Transient flow with closed boundaries: no water is made or lost, and the pressure evens out.
TEST(Flow, TransientKeepsTheWater) {
    Session s;
    std::string script = with(script_text("flow-parallel-plate.dat"), "bound pp 1e5 range x -0.01 0.01\nbound pp 0 range x 3.99 4.01\n",
                              "set flow transient\ninsitu pp 1e5 range x -0.01 1.01\n");
    script = with(script, "set substeps 20\nstep 100\n", "step 1\n");
    ASSERT_TRUE(s.run(script)) << s.error();
    const odec::FlowSet& f = s.model.flow;
    auto stored = [&] {
        double v = 0;
        for (int i = 0; i < f.n_nodes(); ++i) v += f.volume[i] * f.pp[i];
        return v;
    };
    const double before = stored();
    ASSERT_GT(before, 0);
    ASSERT_TRUE(s.run("step 3000")) << s.error();
    EXPECT_NEAR(stored(), before, 1e-9 * before);
    double lo = 1e300, hi = 0, vol = 0;
    for (int i = 0; i < f.n_nodes(); ++i) {
        lo = std::min(lo, f.pp[i]);
        hi = std::max(hi, f.pp[i]);
        vol += f.volume[i];
    }
    EXPECT_NEAR(lo, before / vol, 1e-3 * before / vol);
    EXPECT_NEAR(hi, before / vol, 1e-3 * before / vol);
    EXPECT_GT(f.time, 0);
}

// A water table: the nodes below it start hydrostatic, and hydrostatic pressure moves no water.
TEST(Flow, WaterTableIsHydrostaticAndAtRest) {
    Session s;
    ASSERT_TRUE(s.run("config flow\ngrav 0 0 -10\npoly brick 0 1 0 1 0 10\npoly brick 1 2 0 1 0 10\n"
                      "prop mat=1 dens=2500\nprop jmat=1 jkn=1e10 jks=1e10 azero=1e-4\nfix\n"
                      "insitu wtable 8\nstep 200"))
        << s.error();
    const odec::FlowSet& f = s.model.flow;
    ASSERT_GT(f.n_nodes(), 0);
    for (int i = 0; i < f.n_nodes(); ++i) {
        const double p_exact = std::max(0.0, 1000 * 10 * (8 - f.pos[i].z()));
        EXPECT_NEAR(f.pp[i], p_exact, 1e-6 * 8e4) << "node at z = " << f.pos[i].z();
    }
}

TEST(Flow, HistoriesFishPrintPlotAndExportReadIt) {
    Session s;
    std::string script = script_text("flow-parallel-plate.dat");
    script = with(script, "set substeps 20\n", "set substeps 20\nhist ncyc 10\nhist pp 2,0,0\nhist aperture 2,0,0\nhist flowrate\n");
    ASSERT_TRUE(s.run(script)) << s.error();
    const auto& h = s.model.histories.items;
    ASSERT_EQ(h.size(), 3u);
    EXPECT_NEAR(h[0].values.back(), 5e4, 50);
    EXPECT_NEAR(h[1].values.back(), 2e-4, 1e-9);
    EXPECT_NEAR(h[2].values.back(), 3.3333e-5, 1e-8);
    ASSERT_TRUE(s.run("def f\n  p = fl_pp(1,0,0)\n  a = fl_aperture(vector(1,0,0))\n  q = fl_flow\n  n = fl_nnode\nend\n@f"))
        << s.error();
    auto g = [&](const char* n) { return s.interp.fish().find(n)->value.number(); };
    EXPECT_NEAR(g("p"), 7.5e4, 75);
    EXPECT_NEAR(g("a"), 2e-4, 1e-9);
    EXPECT_NEAR(g("q"), 3.3333e-5, 1e-8);
    EXPECT_EQ(g("n"), 16);
    s.out.str("");
    ASSERT_TRUE(s.run("print contact")) << s.error();
    EXPECT_NE(s.out.str().find("aperture"), std::string::npos) << s.out.str();
    const std::string stem = "/tmp/odec-flow-test-" + std::to_string(::getpid());
    ASSERT_TRUE(s.run("export vtk '" + stem + "'")) << s.error();
    const std::string vtp = odec::test::read_bytes(stem + "-subcontacts-000100.vtp");
    EXPECT_NE(vtp.find("pore_pressure"), std::string::npos);
    EXPECT_NE(vtp.find("aperture"), std::string::npos);
    std::system(("rm -f '" + stem + "'-* '" + stem + ".pvd'").c_str());
}

TEST(Flow, BadInputIsRefusedWithTheModelUnchanged) {
    {
        Session s;
        EXPECT_FALSE(s.run("fluid density 1000"));
        EXPECT_NE(s.error().find("t.dat:1:1: error: fluid flow is not configured"), std::string::npos) << s.error();
        EXPECT_NE(s.error().find("config flow"), std::string::npos) << s.error();
        EXPECT_EQ(s.model.flow.density, 1000);
        EXPECT_FALSE(s.run("set flow on"));
        EXPECT_NE(s.error().find("fluid flow is not configured"), std::string::npos) << s.error();
        EXPECT_FALSE(s.model.flow.on);
        EXPECT_FALSE(s.run("poly brick 0 1 0 1 0 1\nbound pp 1e5"));
        EXPECT_NE(s.error().find("t.dat:2:7: error: fluid flow is not configured"), std::string::npos) << s.error();
    }
    {
        Session s;
        ASSERT_TRUE(s.run("config flow\npoly brick 0 1 0 1 0 1\nprop mat=1 dens=2000"));
        EXPECT_FALSE(s.run("bound pp 1e5"));
        EXPECT_NE(s.error().find("t.dat:1:1: error: there is no joint between rigid blocks"), std::string::npos) << s.error();
        ASSERT_TRUE(s.run("poly brick 0 1 0 1 1 2\nprop jmat=1 jkn=1e9 jks=1e9 azero=1e-4"));
        EXPECT_FALSE(s.run("bound pp 1e5 range x 5 6"));
        EXPECT_NE(s.error().find("the range selects no flow node (no joint there)"), std::string::npos) << s.error();
        for (int i = 0; i < s.model.flow.n_nodes(); ++i) EXPECT_FALSE(s.model.flow.fixed[i]);
        EXPECT_FALSE(s.run("bound pp 1e5 pfree"));
        EXPECT_FALSE(s.run("bound pgrad 0,0,1"));
        EXPECT_NE(s.error().find("'pgrad' goes with 'pp'"), std::string::npos) << s.error();
        EXPECT_FALSE(s.run("bound pp 1e5 xvel 1"));
        EXPECT_NE(s.error().find("'xvelocity' does not go with the pore pressure"), std::string::npos) << s.error();
        EXPECT_FALSE(s.run("bound wtable 3"));
        EXPECT_NE(s.error().find("a water table needs gravity"), std::string::npos) << s.error();
        EXPECT_FALSE(s.model.flow.has_wtable);
        EXPECT_FALSE(s.run("prop jmat=1 ares=1e-4 amax=1e-5"));
        EXPECT_NE(s.error().find("amax 1e-05 m) is below the residual one"), std::string::npos) << s.error();
        EXPECT_EQ(s.model.joint_materials[1].ares, 0);
        EXPECT_FALSE(s.run("insitu pp 1e5 stress 0 0 0 0 0 0"));
        EXPECT_NE(s.error().find("'stress' does not go with the pore pressure"), std::string::npos) << s.error();
    }
    {
        // Flow on without any hydraulic aperture: said before the first step (deformable blocks carry flow).
        Session s;
        ASSERT_TRUE(s.run("config flow\npoly brick 0 1 0 1 0 1\npoly brick 0 1 0 1 1 2\nprop mat=1 dens=2000 k=1e9 g=1e9\n"
                          "prop jmat=1 jkn=1e9 jks=1e9\nfix range z 0 1\ngrav 0 0 -10"));
        EXPECT_FALSE(s.run("step 1"));
        EXPECT_NE(s.error().find("no joint material has a hydraulic aperture"), std::string::npos) << s.error();
        EXPECT_EQ(s.model.step, 0);
        ASSERT_TRUE(s.run("prop jmat=1 azero=1e-4\ngen edge 0.5 range z 1 2\nstep 1")) << s.error();
        EXPECT_EQ(s.model.step, 1);
    }
}

// ---- Deformable blocks: the flow nodes are the gridpoints on the joints (flow.h) ----

namespace {

// The pressure force the joints' water puts on the gridpoints of block `blk` (its sub-contacts'
// p x area along the normal, away from the joint), N, and its moment about the origin, N m.
void gridpoint_uplift(const odec::Model& m, int blk, Eigen::Vector3d& force, Eigen::Vector3d& moment) {
    const odec::ContactSet& cs = m.contacts;
    const odec::FlowSet& f = m.flow;
    force.setZero();
    moment.setZero();
    for (int c = 0; c < cs.size(); ++c) {
        for (int k = cs.sub_offset[c]; k < cs.sub_offset[c + 1]; ++k) {
            const int side = cs.sub_side(k);
            if (side < 3 || f.sub_node[k] < 0) continue;
            const int owner = side == 3 ? cs.block_a[c] : cs.block_b[c];
            if (owner != blk) continue;
            const Eigen::Vector3d fg = (side == 3 ? -1.0 : 1.0) * f.pp[f.sub_node[k]] * cs.sub_area[k] * f.sub_wet[k] * cs.normal(c);
            force += fg;
            moment += m.gridpoints.pos[cs.sub_vertex(k)].cross(fg);
        }
    }
}

} // namespace

// The parallel plate with every block zoned (the meshes of the two faces do not match): the flow
// and the linear pressure as with rigid blocks.
TEST(Flow, DeformableParallelPlate) {
    Session s;
    const std::string script =
        with(script_text("flow-parallel-plate.dat"), "fix\n", "gen edge 0.5\nprop mat=1 k=1e10 g=1e10\nfix range z -2 2\n");
    ASSERT_TRUE(s.run(with(script, "step 100", "step 3000"))) << s.error();
    const double a = 2e-4, w = 2, l = 4, dp = 1e5, mu = 1e-3;
    const double q_exact = a * a * a * w * dp / (12 * mu * l);
    const double q = inflow_left(s.model, 0.01);
    report("flow: deformable parallel plate, Q", q, q_exact, "m^3/s");
    EXPECT_NEAR(q, q_exact, 1e-3 * q_exact);
    const odec::FlowSet& f = s.model.flow;
    int inside = 0;
    double worst = 0;
    for (int i = 0; i < f.n_nodes(); ++i) {
        // The base joint (the vertical joints between the upper blocks carry nodes too: dead ends).
        if (f.fixed[i] || std::abs(f.pos[i].z()) > 1e-9) continue;
        worst = std::max(worst, std::abs(f.pp[i] - dp * (1 - f.pos[i].x() / l)) / dp);
        ++inside;
    }
    EXPECT_GT(inside, 50);
    std::printf("[verification] flow: deformable parallel plate, %d gridpoint nodes, largest pressure error %.3f %% of dp\n",
                inside, 100 * worst);
    EXPECT_LT(worst, 5e-3);
}

// The opening joint with the upper block zoned: its gridpoints carry the water's push, the joint's
// springs the effective stress.
TEST(Flow, DeformableJointOpensUnderPressure) {
    const double sigma = 25000, kn = 1e8, azero = 3e-4, w = 2, l = 4, mu = 1e-3, dp = 500;
    for (double p : {1000.0, 20000.0}) {
        Session s;
        ASSERT_TRUE(s.run(opening_script(p, true))) << s.error();
        const double a_exact = azero - (sigma - p) / kn;
        const odec::ContactFlow cf = odec::contact_flow(s.model, 0);
        char what[72];
        std::snprintf(what, sizeof what, "flow: deformable opening joint, aperture at p = %g", p);
        report(what, cf.aperture, a_exact, "m");
        EXPECT_NEAR(cf.aperture, a_exact, 0.01 * a_exact);
        const double q_exact = a_exact * a_exact * a_exact * w * dp / (12 * mu * l);
        const double q = inflow_left(s.model, 0.01);
        std::snprintf(what, sizeof what, "flow: deformable opening joint, Q at p = %g", p);
        report(what, q, q_exact, "m^3/s");
        EXPECT_NEAR(q, q_exact, 0.03 * q_exact);
        EXPECT_NEAR(odec::contact_info(s.model, 0).normal_stress, sigma - p, 0.01 * sigma);
        // The water's push on the gridpoints and the joint's springs carry the block's weight (the
        // pressure is not quite linear along the joint: the block tilts, the aperture varies).
        Eigen::Vector3d up, mo;
        gridpoint_uplift(s.model, s.model.block_index(2), up, mo);
        const odec::ContactInfo ci = odec::contact_info(s.model, 0);
        EXPECT_NEAR(up.z(), p * w * l, 0.02 * p * w * l);
        EXPECT_NEAR(up.z() + ci.normal_stress * ci.area, sigma * w * l, 1e-3 * sigma * w * l);
    }
}

// The dam's base uplift with the dam zoned: linear from heel to toe, its resultant and line of action.
TEST(Flow, DeformableDamUplift) {
    Session s;
    std::string script = with(script_text("flow-dam-uplift.dat"), "fix\n", "prop mat=1 k=1e10 g=1e10\ngen edge 1 range z 0 20\nfix\n");
    ASSERT_TRUE(s.run(with(script, "step 1000", "step 3000"))) << s.error();
    const double p1 = 196200, p2 = 19620, b = 10, w = 2;
    const odec::FlowSet& f = s.model.flow;
    double worst = 0;
    int base = 0;
    for (int i = 0; i < f.n_nodes(); ++i) {
        if (std::abs(f.pos[i].z()) > 1e-6 || f.pos[i].x() < -1e-6 || f.pos[i].x() > b + 1e-6) continue;
        const double p_exact = p1 + (p2 - p1) * f.pos[i].x() / b;
        worst = std::max(worst, std::abs(f.pp[i] - p_exact) / p_exact);
        ++base;
    }
    EXPECT_GT(base, 22);
    std::printf("[verification] flow: deformable dam, %d base nodes, largest error of the pressures %.4f %%\n", base, 100 * worst);
    EXPECT_LT(worst, 0.02);
    Eigen::Vector3d up, mo;
    gridpoint_uplift(s.model, s.model.block_index(13), up, mo);
    const double up_exact = b * w * (p1 + p2) / 2;
    report("flow: deformable dam uplift force", up.z(), up_exact, "N");
    EXPECT_NEAR(up.z(), up_exact, 0.02 * up_exact);
    const double x_c = mo.y() / -up.z();
    const double x_exact = b * (p1 + 2 * p2) / (3 * (p1 + p2));
    report("flow: deformable dam uplift, distance from the heel", x_c, x_exact, "m");
    EXPECT_NEAR(x_c, x_exact, 0.02 * x_exact);
}

// A zoned block on the incline slides when its base joint's pressure passes the analytic one.
TEST(Flow, DeformableInclineSlidesAtTheAnalyticPressure) {
    const double deg = M_PI / 180;
    const double p_c = 20000 * (std::cos(20 * deg) - std::sin(20 * deg) / std::tan(30 * deg));
    auto slides = [&](double p) {
        Session s;
        char text[32];
        std::snprintf(text, sizeof text, "bound pp %.6g", p);
        std::string script = with(script_text("flow-incline.dat"), "bound pp 6800", text);
        script = with(script, "fix range z -1 0\n", "prop mat=1 k=5e9 g=5e9\ngen edge 0.5 range z 0 1\nfix range z -1 -0.01\n");
        script = with(script, "step 4000", "step 20000");
        EXPECT_TRUE(s.run(script)) << s.error();
        double d = 0;
        for (const Eigen::Vector3d& u : s.model.gridpoints.disp) d = std::max(d, u.norm());
        return d;
    };
    const double d_lo = slides(0.98 * p_c), d_hi = slides(1.02 * p_c);
    std::printf("[verification] flow: deformable incline, moved %.3g m at 0.98 p_c, %.3g m at 1.02 p_c\n", d_lo, d_hi);
    EXPECT_LT(d_lo, 1e-4);
    EXPECT_GT(d_hi, 1e-3);
}

// A zoned block on a larger zoned block, meshes that do not match, water fed along the upper
// block's edges only: the lower face's network takes its water from the upper face's gridpoints,
// which follow it, so the joint carries the whole cubic-law flow (half of it with the two faces'
// networks apart).
TEST(Flow, DeformableFacesHoldOneFilm) {
    Session s;
    ASSERT_TRUE(s.run("config flow\nfluid density 1000 viscosity 1e-3 bulk 2e9\n"
                      "poly brick 0 4 0 2 -1 0\npoly brick 0.3 3.7 0 2 0 1\n"
                      "prop mat=1 dens=2500 k=1e10 g=1e10\n"
                      "prop jmat=1 jkn=1e10 jks=1e10 jfric=30 azero=2e-4 ares=1e-5\n"
                      "gen edge 0.45 range z -1 0\ngen edge 0.3 range z 0 1\nfix range z -2 2\n"
                      "bound pp 1e5 range x 0.29 0.31\nbound pp 0 range x 3.69 3.71\nset substeps 20\nstep 3000"))
        << s.error();
    const double a = 2e-4, w = 2, l = 3.4, dp = 1e5, mu = 1e-3;
    const double q_exact = a * a * a * w * dp / (12 * mu * l);
    const double q = inflow_left(s.model, 0.31);
    report("flow: zoned faces that do not match, Q", q, q_exact, "m^3/s");
    EXPECT_NEAR(q, q_exact, 0.01 * q_exact);
    const odec::FlowSet& f = s.model.flow;
    int followers = 0;
    double worst = 0;
    for (int i = 0; i < f.n_nodes(); ++i) {
        followers += f.follow_offset[i + 1] > f.follow_offset[i];
        if (f.fixed[i] || std::abs(f.pos[i].z()) > 1e-9 || f.pos[i].x() < 0.3 || f.pos[i].x() > 3.7) continue;
        worst = std::max(worst, std::abs(f.pp[i] - dp * (3.7 - f.pos[i].x()) / l) / dp);
    }
    EXPECT_GT(followers, 20);
    std::printf("[verification] flow: zoned faces that do not match, %d following nodes, largest pressure error %.3f %% of dp\n",
                followers, 100 * worst);
    EXPECT_LT(worst, 0.01);
}

// A model with water in its joints starts at rest: 'insitu stress' with water loads the joint
// springs with the effective stress, and 'insitu wtable' after 'insitu stress' hands the change of
// pressure to the springs (the total stress stays), zoned or rigid.
TEST(Flow, InsituWithWaterStartsAtRest) {
    const std::string zoned =
        "config flow\npoly brick 0 2 0 2 -2 0\npoly brick 0 2 0 2 0 2\n"
        "prop mat=1 dens=2500 k=5e9 g=3e9\nprop jmat=1 jkn=1e10 jks=1e10 jfric=30 azero=1e-4 ares=1e-5\n"
        "gen edge 0.5\ngrav 0 0 -10\n";
    const std::string field = "insitu stress 0 0 -1e6 0 0 0 zgrad 0 0 25000 0 0 0\n";
    const std::string water = "insitu wtable 5\n";
    const std::string bounds = "bound stress 0 0 -1e6 0 0 0 zgrad 0 0 25000 0 0 0 range z 1.99 2.01\nfix range z -2.01 -1.99\n";
    for (int order = 0; order < 2; ++order) {
        Session s;
        ASSERT_TRUE(s.run(zoned + (order == 0 ? field + water : water + field) + bounds + "step 100")) << s.error();
        double v = 0, f = 0;
        for (const Eigen::Vector3d& x : s.model.gridpoints.vel) v = std::max(v, x.norm());
        const odec::GridpointSet& g = s.model.gridpoints;
        for (int i = 0; i < g.size(); ++i) {
            if (!g.vel_bc[i]) f = std::max(f, g.force[i].norm()); // the held base carries its reactions
        }
        EXPECT_LT(v, 1e-9) << "order " << order;
        EXPECT_LT(f, 1e-3) << "order " << order;
        // The joint's springs carry 1 MPa less the 50 kPa of the water 5 m above.
        EXPECT_NEAR(odec::contact_info(s.model, 0).normal_stress, 1e6 - 5e4, 1e-6 * 1e6);
        EXPECT_NEAR(odec::contact_flow(s.model, 0).pp, 5e4, 1e-9 * 5e4);
    }
    {
        // Before any step, 'print contact' shows the joint's aperture as it stands: closed by the
        // effective stress to below azero - sn'/jkn, so at its residual 1e-5 m.
        Session s;
        ASSERT_TRUE(s.run(zoned + field + water + "print contact")) << s.error();
        const std::string out = s.out.str();
        EXPECT_NE(out.find("5e+04     1e-05 elastic"), std::string::npos) << out;
    }
    {
        // A rigid block on a rigid base: 50 kPa of weight on its joint, 30 kPa of it water.
        Session s;
        ASSERT_TRUE(s.run("config flow\npoly brick 0 2 0 2 -2 0\npoly brick 0 2 0 2 0 2\nprop mat=1 dens=2500\n"
                          "prop jmat=1 jkn=1e10 jks=1e10 jfric=30 azero=1e-4 ares=1e-5\ngrav 0 0 -10\nfix range z -2 0\n"
                          "insitu stress 0 0 -5e4 0 0 0\ninsitu wtable 3\nstep 100"))
            << s.error();
        const int b = s.model.block_index(2);
        EXPECT_LT(s.model.blocks.vel[b].norm(), 1e-12);
        EXPECT_NEAR(odec::contact_info(s.model, 0).normal_stress, 2e4, 1e-6 * 5e4);
    }
}

namespace {

// Two models hold the same flow state: every saved setting and every node's position, pressure,
// fixity and last volume, bit for bit (a save file would also hold the run's timings), with the
// same steps taken and the blocks where they are.
void expect_same_flow(const odec::Model& a, const odec::Model& b, const std::string& what) {
    const odec::FlowSet& f = a.flow;
    const odec::FlowSet& g = b.flow;
    EXPECT_EQ(f.configured, g.configured) << what;
    EXPECT_EQ(f.on, g.on) << what;
    EXPECT_EQ(f.mode, g.mode) << what;
    EXPECT_EQ(f.substeps, g.substeps) << what;
    EXPECT_EQ(f.density, g.density) << what;
    EXPECT_EQ(f.viscosity, g.viscosity) << what;
    EXPECT_EQ(f.bulk, g.bulk) << what;
    EXPECT_EQ(f.has_wtable, g.has_wtable) << what;
    EXPECT_EQ(f.wtable, g.wtable) << what;
    EXPECT_EQ(f.time, g.time) << what;
    EXPECT_EQ(f.steps, g.steps) << what;
    EXPECT_EQ(f.pos, g.pos) << what;
    EXPECT_EQ(f.pp, g.pp) << what;
    EXPECT_EQ(f.fixed, g.fixed) << what;
    EXPECT_EQ(f.last_volume, g.last_volume) << what;
    EXPECT_EQ(a.step, b.step) << what;
    EXPECT_EQ(a.blocks.disp, b.blocks.disp) << what;
}

} // namespace

// 3DEC's 'config fluid' is odec's 'config flow': the parallel-plate problem set up with either
// ends in the same state (pressures, fixities, volumes, settings), bit for bit.
TEST(FlowNames, ConfigFluidIsConfigFlow) {
    Session a, b;
    ASSERT_TRUE(a.run(script_text("flow-parallel-plate.dat"))) << a.error();
    ASSERT_TRUE(b.run(with(script_text("flow-parallel-plate.dat"), "config flow", "config fluid"))) << b.error();
    EXPECT_TRUE(b.model.flow.configured);
    EXPECT_TRUE(b.model.flow.on);
    ASSERT_GT(b.model.flow.n_nodes(), 0);
    expect_same_flow(a.model, b.model, "config fluid");
    // Abbreviated as 3DEC allows, and beside 'dyn' on one line.
    Session c;
    ASSERT_TRUE(c.run("config dyn flu")) << c.error();
    EXPECT_TRUE(c.model.flow.configured);
    EXPECT_TRUE(c.model.settings.dyn_configured);
}

// UDEC writes the flow's settings as one 'set flow' with several words ('set flow steady off'):
// the same state as one word at a time; 'clear' and a word that contradicts another are refused
// where they stand, the model unchanged.
TEST(FlowNames, SetFlowTakesSeveralWordsAsUdecWritesThem) {
    const std::string setup = "config flow\npoly brick 0 1 0 1 0 1\npoly brick 0 1 0 1 1 2\n"
                              "prop mat=1 dens=2000\nprop jmat=1 jkn=1e9 jks=1e9 azero=1e-4\n";
    for (const auto& [together, apart] :
         {std::pair<std::string, std::string>{"set flow transient off", "set flow transient\nset flow off"},
          {"set flow off steady", "set flow off\nset flow steady"},
          {"set flow on transient", "set flow transient\nset flow on"}}) {
        Session a, b;
        ASSERT_TRUE(a.run(setup + apart)) << a.error();
        ASSERT_TRUE(b.run(setup + together)) << b.error();
        EXPECT_EQ(a.model.flow.on, b.model.flow.on) << together;
        EXPECT_EQ(a.model.flow.mode, b.model.flow.mode) << together;
        expect_same_flow(a.model, b.model, together);
    }
    Session s;
    ASSERT_TRUE(s.run(setup + "set flow transient")) << s.error();
    EXPECT_FALSE(s.run("set flow clear steady off"));
    EXPECT_NE(s.error().find("t.dat:1:10: error: 'set flow clear' (UDEC) has no counterpart in odec"), std::string::npos)
        << s.error();
    EXPECT_NE(s.error().find("insitu pp"), std::string::npos) << s.error();
    EXPECT_EQ(s.model.flow.mode, odec::FlowMode::Transient);
    EXPECT_TRUE(s.model.flow.on);
    EXPECT_FALSE(s.run("set flow steady off on"));
    EXPECT_NE(s.error().find("t.dat:1:21: error: 'on' after 'off'"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("set flow steady transient"));
    EXPECT_NE(s.error().find("'transient' after 'steady'"), std::string::npos) << s.error();
    EXPECT_EQ(s.model.flow.mode, odec::FlowMode::Transient);
    EXPECT_TRUE(s.model.flow.on);
    // The words stop at the next keyword of 'set'.
    ASSERT_TRUE(s.run("set flow steady substeps 7")) << s.error();
    EXPECT_EQ(s.model.flow.mode, odec::FlowMode::Steady);
    EXPECT_EQ(s.model.flow.substeps, 7);
}

// What odec cannot do as 3DEC and UDEC do is refused where it stands, with what to write instead:
// 3DEC's WATER (a water table without flow) and UDEC's contact offsets $KCQ and $KCAP.
TEST(FlowNames, WaterAndFlowOffsetsAreRefusedWithWhatToWrite) {
    Session s;
    ASSERT_TRUE(s.run("config flow\npoly brick 0 1 0 1 0 1"));
    EXPECT_FALSE(s.run("grav 0 0 -9.81\nwater density 1200"));
    EXPECT_NE(s.error().find("t.dat:2:1: error: the 'water' command is not available"), std::string::npos) << s.error();
    EXPECT_NE(s.error().find("insitu wtable z"), std::string::npos) << s.error();
    EXPECT_FALSE(s.model.flow.has_wtable);
    EXPECT_EQ(s.model.flow.density, 1000); // the default, not set by the refused line
    EXPECT_FALSE(s.run("def f\n  c = contact_head\n  x = fmem(c + $KCAP)\nend\n@f"));
    EXPECT_NE(s.error().find("'$KCAP' is a memory offset"), std::string::npos) << s.error();
    EXPECT_NE(s.error().find("fl_aperture(c_x(c), c_y(c), c_z(c))"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("def g\n  c = contact_head\n  x = fmem(c + $KCQ)\nend\n@g"));
    EXPECT_NE(s.error().find("no flow rate per contact: fl_flow"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("pfix 1e5 range x -0.01 0.01"));
    EXPECT_NE(s.error().find("t.dat:1:1: error: odec has no 'pfix' command"), std::string::npos) << s.error();
    EXPECT_NE(s.error().find("'bound pp p"), std::string::npos) << s.error();
}

// Flow nodes that lie far out (a restored file may put them anywhere finite) are carried into
// the new network by a hash grid of cells 1e-12 m wide at least: a coordinate of 1e200 m is
// 1e212 cells, beyond any integer. Found by fuzzing `restore` (undefined behaviour, the cast of
// the cell index overflowed); the sanitizer build of this test catches it again.
TEST(Flow, FarNodesDoNotOverflowTheCellIndex) {
    Session s;
    ASSERT_TRUE(s.interp.run_file(kDir + "flow-parallel-plate.dat")) << s.error();
    odec::FlowSet& f = s.model.flow;
    ASSERT_GT(f.n_nodes(), 2);
    f.pos[0] = odec::Vec3(1e200, -1e200, 1e200);
    f.pos[1] = odec::Vec3(-1e300, 1e300, 0);
    f.invalidate();
    ASSERT_TRUE(s.run("step 1")) << s.error();
    // The far nodes carried nothing to the new ones; the network is rebuilt where the joints are.
    for (int i = 0; i < f.n_nodes(); ++i) {
        EXPECT_TRUE(f.pos[i].allFinite());
        EXPECT_LT(f.pos[i].norm(), 10.0);
        EXPECT_TRUE(std::isfinite(f.pp[i]));
    }
}
