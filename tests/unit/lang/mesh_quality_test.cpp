// Zone quality of 'gen edge': no sliver zones in blocks of ordinary shape at any edge length
// (a sliver sets the timestep of the whole model), the same zones every run, and a warning
// that names a block whose shape forces a poor zone and what that zone costs.
//
// Quality is the radius ratio 3 r_in / r_out (1 for a regular tetrahedron). Edge lengths are
// swept from half of a block's typical size down to 1/200 of it where that makes no more than
// some hundreds of thousands of zones (a minute of meshing): a cube of side L is swept down to
// L/50 (L/200 would be 50 million zones; finer zones only repeat the same local shapes), the
// thin slab down to 1/200 of its longest side, the jointed slope (blocks 2 to 3 m across)
// from 2.5 m down to 0.3 m. Blocks of an edge longer than half their size are meshed with few
// nodes besides their corners, and a thin or sharp one may then get a poor zone (a
// wedge 0.86 m thick of the slope, zoned at 4 m): 'gen' warns of it (last test below). The quick test
// takes a few sizes of each model, those that gave slivers among them; the full sweep is
// MeshQuality.SweepOfEdgeLengths and ...AroundATunnelAndInASlope, long tests that print the worst ratio for each size.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "engine/zones.h"
#include "mesh/tet_mesh.h"
#include "test_util.h"

using odec::test::Session;
using namespace odec;

namespace {

constexpr double kGood = 0.1;  // the worst radius ratio 'gen edge' must reach in ordinary blocks

const std::string kMaterial = "prop mat=1 dens=2600 k=3.9e9 g=2.8e9\n";
// A plane-strain slice 0.2 m thick (aspect ratio 50, not an ordinary block: swept only to
// edges of 4 times its thickness; beyond, no zone spanning it can be good).
const std::string kSlab = "poly brick 0 10 0 0.2 0 5\n";
const std::string kCube = "poly brick 0 1 0 1 0 1\n";
// The rings of the Kirsch verification (examples/verification/kirsch.dat): a quarter of a
// 0.5 m slice around a hole of 1 m radius, out to 20 m.
const std::string kTunnel =
    "poly tunnel a (0,0,0) b (0,0.5,0) radius 1 box 20 ntheta 32 nrad 7 ratio 1.5\n"
    "delete range x -100 0\ndelete range z -100 0\n";
// A 20 m x 4 m x 10 m block cut by two joint sets into 22 blocks.
const std::string kSlope =
    "poly brick 0 20 0 4 0 10\n"
    "jset dip 35 dd 90 origin 10,0,5 spacing 2 number 5\n"
    "jset dip 75 dd 270 origin 10,0,5 spacing 3 number 3\n";
// The grading of the Kirsch verification, with the zones at the wall of edge e.
std::string kirsch_grading(double e) {
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "gen edge 2.0\ngen edge %g range group 'tunnel_ring1'\ngen edge %g range group 'tunnel_ring2'\n"
                  "gen edge %g range group 'tunnel_ring3'\ngen edge 0.6 range group 'tunnel_ring4'\n"
                  "gen edge 1.0 range group 'tunnel_ring5'\n",
                  e, 2 * e, 3.5 * e);
    return buf;
}

std::string text(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

std::string gen(double e) { return "gen edge " + text(e) + "\n"; }

double worst_zone(const Model& m) {
    double worst = 1;
    const auto& x = m.gridpoints.ref;
    for (const auto& q : m.zones.gp) worst = std::min(worst, radius_ratio(x[q[0]], x[q[1]], x[q[2]], x[q[3]]));
    return worst;
}

struct Zoning {
    double worst = 0;
    int zones = 0;
    double seconds = 0;
    std::string messages;  // what the commands printed on the error stream (warnings)
};

Zoning zone(const std::string& geometry, const std::string& commands) {
    Session s;
    s.check_save_at_end = false;  // not what is tested here, and slow for the large models
    Zoning z;
    if (!s.run(geometry + kMaterial)) {
        ADD_FAILURE() << s.error();
        return z;
    }
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_TRUE(s.run(commands)) << s.error();
    z.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    z.worst = worst_zone(s.model);
    z.zones = s.model.zones.size();
    z.messages = s.err.str();
    return z;
}

struct Case {
    std::string name;
    std::string geometry;
    std::string commands;
};

void check(const std::vector<Case>& cases, bool print) {
    for (const Case& c : cases) {
        const Zoning z = zone(c.geometry, c.commands);
        if (print) {
            std::printf("%-28s %9d zones %7.2f s  worst radius ratio %.3f\n", c.name.c_str(), z.zones, z.seconds, z.worst);
            std::fflush(stdout);
        }
        EXPECT_GE(z.worst, kGood) << c.name;
        EXPECT_EQ(z.messages.find("warning"), std::string::npos) << c.name << ": " << z.messages;
    }
}

} // namespace

// Sizes that gave slivers before (the slab at 0.125 m: a zone of radius ratio 0.0003 set a
// timestep 8 times smaller than at 0.1 m; the tunnel slice at 2 m: 0.03; the Kirsch grading:
// 0.045) and a few others.
TEST(MeshQuality, NoSliversInOrdinaryBlocks) {
    std::vector<Case> cases;
    for (double e : {0.8, 0.3, 0.15, 0.125}) cases.push_back({"slab, edge " + text(e), kSlab, gen(e)});
    for (double e : {0.5, 0.3, 0.1}) cases.push_back({"cube, edge " + text(e), kCube, gen(e)});
    for (double e : {2.0, 1.0}) cases.push_back({"tunnel, edge " + text(e), kTunnel, gen(e)});
    cases.push_back({"tunnel, Kirsch grading", kTunnel, kirsch_grading(0.1)});
    for (double e : {2.0, 0.7}) cases.push_back({"slope, edge " + text(e), kSlope, gen(e)});
    check(cases, false);
}

// Edges from `from` down to `to`, each 0.8 of the one before.
void sweep(std::vector<Case>& cases, const std::string& name, const std::string& geometry, double from, double to) {
    for (double e = from; e >= to * 0.999; e *= 0.8) cases.push_back({name + ", edge " + text(e), geometry, gen(e)});
}

// In two halves, each well under a minute.
TEST(MeshQuality, SweepOfEdgeLengths) {
    std::vector<Case> cases;
    sweep(cases, "slab", kSlab, 0.8, 0.05); // 4 x its thickness down to 1/200 of its length
    sweep(cases, "cube", kCube, 0.5, 0.02); // 1/2 down to 1/50 of its side
    check(cases, true);
}

TEST(MeshQuality, SweepOfEdgeLengthsAroundATunnelAndInASlope) {
    std::vector<Case> cases;
    sweep(cases, "tunnel", kTunnel, 2.0, 0.16); // 4 x the slice thickness down to 1/125 of the model
    sweep(cases, "slope", kSlope, 2.5, 0.3);    // 1/2 of its larger blocks down to 1/67 of its length
    for (double e : {0.4, 0.2, 0.1, 0.05}) cases.push_back({"tunnel, Kirsch grading, " + text(e), kTunnel, kirsch_grading(e)});
    check(cases, true);
}

// The same zones every run, bit for bit, whatever the session did before, where the
// improvement of the mesher's zones works (the slab at 0.125 m, the tunnel slice).
TEST(MeshQuality, TheSameZonesEveryRun) {
    for (const std::string& model : {kSlab + kMaterial + "gen edge 0.125", kTunnel + kMaterial + "gen edge 2.0"}) {
        Session a, b;
        a.check_save_at_end = b.check_save_at_end = false;
        ASSERT_TRUE(a.run(model)) << a.error();
        ASSERT_TRUE(b.run("poly brick 0 9 0 9 0 9\njset dip 30 dd 20 origin 1,1,1 spacing 0.7\n" + kMaterial +
                          "gen edge 1\nnew\n" + model))
            << b.error();
        ASSERT_EQ(a.model.zones.size(), b.model.zones.size());
        EXPECT_TRUE(a.model.zones.gp == b.model.zones.gp);
        EXPECT_TRUE(a.model.gridpoints.ref == b.model.gridpoints.ref);
    }
}

// A block too thin for any good zone of the edge asked: the warning names it, the quality of
// its worst zone and the timestep that zone sets against the model's median zone timestep;
// the ordinary block beside it is not named.
TEST(MeshQuality, ABlockTooThinForTheEdgeIsNamedInAWarning) {
    Session s;
    s.check_save_at_end = false;
    ASSERT_TRUE(s.run("poly brick 0 10 0 0.02 0 5\npoly brick 0 10 1 3 0 5\n" + kMaterial + "gen edge 1")) << s.error();
    const std::string w = s.err.str();
    EXPECT_NE(w.find("warning: block 1 is too thin or too sharp for zones of 1 m: its worst zone has a radius ratio of "),
              std::string::npos)
        << w;
    EXPECT_NE(w.find("times smaller than the model's median zone timestep"), std::string::npos) << w;
    EXPECT_NE(w.find("zones of 0.02 m or less (the block's thickness) would be better"), std::string::npos) << w;
    EXPECT_EQ(w.find("block 2"), std::string::npos) << w;
    EXPECT_LT(worst_zone(s.model), kGood);
    // The ratio it reports is that of the engine's own estimate of the gridpoint timesteps.
    const size_t at = w.find("timestep is ");
    ASSERT_NE(at, std::string::npos);
    EXPECT_GT(std::stod(w.substr(at + 12)), 2.0) << w;

    // Before the block has a material its zones have no mass: the warning says so.
    Session t;
    t.check_save_at_end = false;
    ASSERT_TRUE(t.run("poly brick 0 10 0 0.02 0 5\ngen edge 1")) << t.error();
    EXPECT_NE(t.err.str().find("warning: block 1 is too thin"), std::string::npos) << t.err.str();
    EXPECT_NE(t.err.str().find("once the block has a material"), std::string::npos) << t.err.str();
}

TEST(MeshQuality, PrintInfoReportsTheWorstZone) {
    Session s;
    s.check_save_at_end = false;
    ASSERT_TRUE(s.run(kCube + kMaterial + "gen edge 0.3\nprint info")) << s.error();
    const std::string out = s.out.str();
    const size_t at = out.find("zone quality: worst radius ratio ");
    ASSERT_NE(at, std::string::npos) << out;
    EXPECT_NEAR(std::stod(out.substr(at + 33)), worst_zone(s.model), 1e-5) << out;
}
