// Numbers that are not numbers, or not sensible ones: every command either refuses them with
// a located error and leaves the model as it was, or takes them and leaves every number of
// the model finite. And a forced timestep can be given back to the automatic one.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "io/save.h"
#include "test_util.h"

using odec::test::Session;

namespace {

const char* kStack =
    "poly brick 0 1 0 1 -1 0\npoly brick 0 1 0 1 0 1\npoly brick 0 1 0 1 1 2\npoly brick 0 1 0 1 2 3\n"
    "prop mat=1 dens=2000\nprop jmat=1 jkn=1e9 jks=1e9\nfix range z -1 0\ngrav 0 0 -10\n";

// The model's state as bytes (its save file without the wall-clock profile).
std::string state(const odec::Model& m) {
    static const std::string path =
        std::string(access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp") + "/odec-numbers-" + std::to_string(getpid());
    odec::Model copy = m;
    copy.profile = odec::Profile();
    std::string error;
    // As it is, whether or not restore would take it: this compares states.
    EXPECT_TRUE(odec::save_model_unchecked(copy, path, error)) << error;
    std::ifstream f(path, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    std::remove(path.c_str());
    return bytes;
}

// The first number of the model that is not finite, or "".
std::string not_finite(const odec::Model& m) {
    using namespace odec;
    auto fin = [](double x) { return std::isfinite(x); };
    const BlockSet& s = m.blocks;
    for (int b = 0; b < s.size(); ++b) {
        const std::string w = "block " + std::to_string(s.id[b]) + " ";
        for (const Vec3& v : s.shape[b].vertices)
            if (!v.allFinite()) return w + "vertex";
        if (!s.centroid[b].allFinite()) return w + "centroid";
        if (!s.vel[b].allFinite() || !s.ang_vel[b].allFinite()) return w + "velocity";
        if (!s.accel[b].allFinite() || !s.ang_accel[b].allFinite()) return w + "acceleration";
        if (!s.orientation[b].coeffs().allFinite()) return w + "orientation";
        if (!s.force[b].allFinite() || !s.moment[b].allFinite() || !fin(s.force_scale[b])) return w + "force";
        if (!s.vel_bc_value[b].allFinite()) return w + "boundary";
        for (const BlockLoad& l : s.loads[b])
            if (!l.lever.allFinite() || !l.force.allFinite() || !l.couple.allFinite()) return w + "boundary";
        if (!s.disp[b].allFinite() || !s.ref_orientation[b].coeffs().allFinite()) return w + "displacement";
        if (!fin(s.volume[b]) || !fin(s.mass[b]) || !s.inertia_body[b].allFinite() || !s.inertia_unit[b].allFinite())
            return w + "mass";
    }
    for (const Vec3& v : s.world_vertices)
        if (!v.allFinite()) return "world vertex";
    const ContactSet& c = m.contacts;
    for (int k = 0; k < c.size(); ++k) {
        if (!c.normal(k).allFinite() || !fin(c.gap[k])) return "contact";
    }
    for (int k = 0; k < c.n_subs(); ++k) {
        if (!fin(c.sub_area[k]) || !fin(c.sub_un[k]) || !fin(c.sub_dilation(k)) ||
            !c.sub_us[k].allFinite() || !c.sub_ss[k].allFinite() || !c.sub_point_local(k).allFinite())
            return "sub-contact";
    }
    if (!fin(c.ctol)) return "ctol";
    for (const Material& x : m.materials)
        if (!fin(x.density) || !fin(x.bulk) || !fin(x.shear)) return "material";
    for (const JointMaterial& x : m.joint_materials)
        if (!fin(x.kn) || !fin(x.ks) || !fin(x.cohesion) || !fin(x.tension) || !fin(x.zdilation)) return "joint material";
    if (!fin(m.time) || !fin(m.dt) || !m.gravity.allFinite()) return "time, dt or gravity";
    if (!fin(m.settings.dt_fixed) || !fin(m.settings.dtfrac) || !fin(m.settings.ctol)) return "settings";
    if (!fin(m.damping.local) || !fin(m.damping.rayleigh_frequency) || !fin(m.damping.auto_coefficient)) return "damping";
    for (const History& h : m.histories.items) {
        if (!h.point.allFinite() || !h.body_offset.allFinite()) return "history point";
        for (double v : h.values)
            if (!fin(v)) return "history value";
    }
    for (const auto& [n, t] : m.tables.tables)
        for (const auto& p : t.points)
            if (!fin(p.first) || !fin(p.second)) return "table";
    return "";
}

} // namespace

TEST(Numbers, SetDtAutoGivesTheStepBackToTheAutomaticOne) {
    Session s;
    ASSERT_TRUE(s.run(std::string(kStack) + "set dt 1e-4")) << s.error();
    EXPECT_EQ(s.model.settings.dt_fixed, 1e-4);
    ASSERT_TRUE(s.run("set dt auto\nstep 10")) << s.error();
    EXPECT_EQ(s.model.settings.dt_fixed, 0);
    EXPECT_NEAR(s.model.dt, 0.1 * 2 * std::sqrt(2000 / 1e9), 1e-12);
    ASSERT_TRUE(s.run("set dt 1e-4\nset dt 0")) << s.error();
    EXPECT_EQ(s.model.settings.dt_fixed, 0);
    Session t;
    EXPECT_FALSE(t.run("set dt automatic"));
    EXPECT_NE(t.error().find("t.dat:1:8: error: 'automatic' is not a number: 'dt' expects dt (a number or 'auto')"),
              std::string::npos)
        << t.error();
}

TEST(Numbers, AForcedTimestepBeyondTheStableLimitIsRefusedByStep) {
    Session s;
    ASSERT_TRUE(s.run("config dyn\n" + std::string(kStack) + "set dt 2e-3")) << s.error();
    const odec::Vec3 top = s.model.blocks.centroid[3];
    EXPECT_FALSE(s.run("step 1000"));
    EXPECT_EQ(s.error(),
              "t.dat:1:1: error: the forced timestep 0.002 s ('set dt') is larger than the stable limit, about "
              "0.000943 s (set by block 2 on its contacts): the motion would run away. Use 'set dt auto' "
              "(0.000283 s now) or a timestep below 0.000943 s\n"
              "    step 1000\n"
              "    ^~~~\n"
              "  see 'help step'\n");
    EXPECT_EQ(s.model.step, 0);
    EXPECT_EQ(s.model.blocks.centroid[3], top);
    EXPECT_FALSE(s.run("solve"));
    ASSERT_TRUE(s.run("set dt 9e-4\nstep 1000\nset dt auto\nsolve")) << s.error();
}

// Every command that takes a number, given numbers that are not numbers, zero, negative,
// tiny or huge. Each line either fails with a located error and leaves the model exactly as
// it was (or, for a run that blows up, names it and leaves every number finite), or succeeds
// leaving every number of the model finite.
TEST(Numbers, EveryCommandTakesOrRefusesAbsurdNumbersCleanly) {
    const std::vector<std::vector<std::string>> cases = {
        // Blocks: zero, negative, underflowing and overflowing sizes, far coordinates.
        {"poly brick 0 0 0 1 5 6"},
        {"poly brick 0 -1 0 1 5 6"},
        {"poly brick -0 1 0 1 5 6", "step 10"},
        {"poly brick 0 1e-300 0 1e-300 5 5.000001"},
        {"poly brick 0 1e-120 0 1e-120 5 5.000001"},
        {"poly brick 0 1e-300 0 1 5 6", "step 10"},
        {"poly brick -1e300 1e300 0 1 5 6"},
        {"poly brick 0 1e200 0 1e200 5 1e200"},
        {"poly brick 0 1 0 1 5 1e308"},
        {"poly brick 0 1 0 1 5 1e309"},
        {"poly brick inf 1 0 1 5 6"},
        {"poly brick nan 1 0 1 5 6"},
        {"poly brick 0 1e8 0 1e8 5 6", "step 10"},
        {"poly tetra (0,0,5) (1e300,0,5) (0,1e300,5) (0,0,1e300)"},
        {"poly tetra (0,0,5) (1e-200,0,5) (0,1e-200,5) (0,0,5.0000000001)"},
        {"poly prism a (0,0,5) (1,0,5) (0,1,5) b (0,0,1e308) (1,0,1e308) (0,1,1e308)"},
        {"poly face (0,0,0) (1,0,0) (0,1,0) face (0,0,0) (0,1,0) (0,0,inf)"},
        {"poly tunnel a (0,0,5) b (0,1,5) radius 1e-300"},
        {"poly tunnel a (0,0,5) b (0,1,5) radius 1e-120 box 1e-119"},
        {"poly tunnel a (0,0,5) b (0,1e9,5) radius 1e8 box 1e9", "step 10"},
        {"poly tunnel a (0,0,5) b (0,1e-300,5) radius 1"},
        {"poly tunnel length -1e9 1e9 radius 1 box 5", "step 10"},
        {"poly tunnel a (0,0,5) b (0,1,5) radius 1 nrad 1000 ratio 1e-300"},
        {"poly tunnel a (0,0,5) b (0,1,5) radius 1 nrad 1000 ratio 1e300"},
        {"poly tunnel a (1e9,1e9,1e9) b (-1e9,-1e9,-1e9) radius 1e-3 box 1e9"},
        // Joint sets: zero, negative, tiny and huge spacings and counts.
        {"jset dip 30 dd 0 spacing 0 number 5"},
        {"jset dip 30 dd 0 spacing -1 number 3"},
        {"jset dip 30 dd 0 spacing 1e-300 number 100000"},
        {"jset dip 45 dd 45 spacing 1e-6 number 100000"},
        {"jset dip 30 dd 0 spacing 1e305 number 100000", "step 10"},
        {"jset dip 30 dd 0 origin 1e308,0,0 spacing 1e308 number 3", "step 10"},
        {"jset dip 30 dd 0 origin 0,0,1e308"},
        {"jset dip 1e308 dd 0"},
        {"jset dip 30 dd 0 spacing 0.3 number 1e18"},
        // Tables driving boundary velocities.
        {"table 2 0 0 0 1"},
        {"table 2 1e308 0 -1e308 1"},
        {"table 2 nan 0 1 1"},
        {"table 2 0 1e308 1 -1e308", "bound xvel 1 hist table 2 range z 0 1", "step 20"},
        {"table 1e18 0 0 1 1"},
        // Histories and their interval.
        {"hist ncyc 2000000000", "step 20"},
        {"hist ncyc 0"},
        {"hist ncyc -1"},
        {"hist ncyc 1e18"},
        {"hist zdis 1e308,0,0", "step 10"},
        {"hist zdis -1e308,1e308,0", "step 10"},
        {"set ncyc 1e300"},
        // Damping.
        {"damp local 1e308"},
        {"damp local 1"},
        {"damp local -0", "step 10"},
        {"damp 1 1e300 mass", "step 10"},
        {"damp 0.5 1e6 mass", "step 10"},
        {"damp 1e-300 1e-300 mass", "step 10"},
        {"damp 0.05 0 mass"},
        // Boundary conditions and initial velocities, then cycling.
        {"bound xload 1e308 range z 0 1", "step 20"},
        {"bound zload -1e308 range z 0 1", "step 20"},
        {"bound zvel 1e308 range z 0 1", "step 20"},
        {"bound xvel -1e308 range z -1 0", "step 20"},
        {"bound xvel inf range z 0 1"},
        {"ini xvel 1e308 range z 0 1", "step 20"},
        {"ini zvel -1e308", "step 20"},
        {"ini xvel nan"},
        {"grav 1e308 0 0", "step 20"},
        {"grav 0 0 -1e308", "step 20"},
        {"grav 0 0 inf"},
        {"grav 0 0 1e-320", "step 20"},
        // Properties.
        {"prop mat=1 dens=1e308", "step 20"},
        {"prop mat=1 dens=1e-300", "step 20"},
        {"prop mat=1 dens=0"},
        {"prop mat=1 dens=-2000"},
        {"prop mat=2 dens=1e308", "change mat=2 range z 0 1", "step 10"},
        {"prop jmat=1 jkn=1e308 jks=1e308", "step 20"},
        {"prop jmat=1 jkn=1e-300 jks=1e-300", "step 20"},
        {"prop jmat=1 jcoh=1e308 jten=1e308", "step 20"},
        {"prop jmat=1 jzdil=1e308 jdil=80", "step 20"},
        {"prop jmat=1 jfric=90"},
        {"prop jmat=1 jkn=0"},
        // Settings.
        {"set dt 1e308", "step 20"},
        {"set dt 1e-300", "step 20"},
        {"set dt -0", "step 20"},
        {"set dt -1"},
        {"set dtfrac 1e-300", "step 20"},
        {"set dtfrac 0"},
        {"set dtfrac 1.5"},
        {"set ctol 1e308", "step 20"},
        {"set ctol 1e-300", "step 20"},
        {"set gravity 0,0,1e308", "step 5"},
        // Step counts and times.
        {"step 1e18"},
        {"step 2000000001"},
        {"step -5"},
        {"step 0"},
        {"step 1.5"},
        {"step time 1e308"},
        {"step time 0"},
        {"step time -1"},
        {"step time 1e-300"},
        {"solve time 1e300"},
        {"solve cycles 1e300"},
        {"solve cycles 0"},
        {"solve ratio 1e-300 cycles 100"},
        {"solve ratio 0"},
        {"solve ratio 1"},
        // Ranges.
        {"fix range x -1e308 1e308", "step 5"},
        {"fix range sphere 0,0,0 1e308", "step 5"},
        {"fix range x 1e308 -1e308"},
        {"fix range cylinder 1e308,0,0 -1e308,0,0 1"},
        {"fix range plane dip 30 dd 0 origin 0,0,1e300 above"},
        {"print block range sphere 0,0,0 1e308"},
    };
    int refused = 0, taken = 0, stopped = 0;
    for (const auto& lines : cases) {
        std::string all;
        for (const std::string& l : lines) all += l + " / ";
        SCOPED_TRACE(all);
        Session s;
        ASSERT_TRUE(s.run(std::string(kStack) + "hist ncyc 5\nhist zdis 0.5,0.5,2.5\ntable 1 0 0 1 1\nstep 5"))
            << s.error();
        for (const std::string& line : lines) {
            const std::string before = state(s.model);
            const std::string err_before = s.error();
            if (s.run(line)) {
                EXPECT_EQ(not_finite(s.model), "") << "after '" << line << "'";
                ++taken;
                continue;
            }
            const std::string e = s.error().substr(err_before.size());
            EXPECT_EQ(e.rfind("t.dat:1:", 0), 0u) << "not located: " << e;
            EXPECT_NE(e.find(": error: "), std::string::npos) << e;
            if (line.find("nan") == std::string::npos) {
                EXPECT_EQ(e.find("nan"), std::string::npos) << e;
            }
            if (e.find("error: stopped: ") != std::string::npos) {
                // A run that blew up: named, and stopped while its numbers were still numbers.
                EXPECT_NE(e.find("has run away (step "), std::string::npos) << e;
                EXPECT_NE(e.find("likely cause: "), std::string::npos) << e;
                EXPECT_EQ(not_finite(s.model), "") << e;
                ++stopped;
            } else {
                EXPECT_EQ(state(s.model), before) << "a failed '" << line << "' changed the model: " << e;
                ++refused;
            }
            break;
        }
    }
    std::printf("absurd numbers: %d commands refused, %d taken, %d runs stopped as run-aways\n", refused, taken, stopped);
}

TEST(Numbers, ALoadThatWouldJumpABlockPastTheBaseIsRefusedBeforeStepping) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 -1 0 region 1\npoly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\n"
                      "grav 0 0 -10\nfix range region 1\ndamp off\nset dt 1e-3\nbound zload -1e12 range id 2"));
    EXPECT_FALSE(s.run("step 100"));
    EXPECT_EQ(s.error(),
              "t.dat:1:1: error: block 2 would move 250 m in one step of 0.001 s, more than half its size (0.866 m), "
              "passing the blocks in its way unseen: its load, 5e+08 m/s^2 with the applied force, is too large\n"
              "    step 100\n"
              "    ^~~~\n"
              "  see 'help step'\n");
    EXPECT_EQ(s.model.step, 0);
}

// The refusals the table above only requires to be clean, each with its own message.
TEST(Numbers, EachAbsurdInputIsRefusedForItsReason) {
    const struct {
        const char* input;
        const char* error;
    } cases[] = {
        {"poly brick 0 1e-300 0 1e-300 5 5.000001", "t.dat:1:6: error: the block is too small: its volume underflows (0 m^3)"},
        {"poly brick 0 1e-120 0 1e-120 5 5.000001", "t.dat:1:6: error: the block is too small: its moment of inertia underflows"},
        {"poly brick -1e8 1e8 0 1e-300 0 1", "t.dat:1:6: error: the block is too small: its moment of inertia underflows"},
        {"poly brick -1e50 1e50 0 1 5 6", "error: coordinate 1e+50 is too far from the origin: poly takes coordinates within 1e+09 m"},
        {"poly brick -1e300 1e300 0 1 5 6", "t.dat:1:12: error: 'brick' x1 must be a number of magnitude at most 1e100 (got -1e300): what odec computes from larger ones overflows"},
        {"poly tetra (0,0,5) (1e50,0,5) (0,1e50,5) (0,0,1e50)", "error: coordinate 1e+50 is too far"},
        {"poly tetra (0,0,5) (1e300,0,5) (0,1e300,5) (0,0,1e300)", "t.dat:1:21: error: 'tetra' v2 components must be numbers of magnitude at most 1e100 (got 1e300)"},
        {"poly brick 0 1e9 0 1e9 0 1e9\nprop mat=1 dens=1e300", "t.dat:2:17: error: 'density' must be a number of magnitude at most 1e100 (got 1e300)"},
        {"prop mat=2 dens=1e300\npoly brick 0 1e9 0 1e9 0 1e9 mat 2", "t.dat:1:17: error: 'density' must be a number of magnitude at most 1e100 (got 1e300)"},
        {"prop mat=2 dens=1e-310\nchange mat=2 range z 0 1", "t.dat:2:12: error: block 2: its mass, density 1e-310 times volume 1 m^3, underflows"},
        {"jset dip 30 dd 0 spacing 1e-300 number 100000", "t.dat:1:26: error: planes 1e-300 m apart would cut only slivers: the spacing must be at least 1e-06 m here"},
        {"jset dip 45 dd 45 spacing 1e-5 number 100000", "t.dat:1:39: error: 100000 of these planes cross the blocks; one 'jset' may cut with at most 5000"},
        {"hist zdis 1e50,0,0", "t.dat:1:11: error: the point (1e+50,0,0) is too far from the origin"},
        {"step time 1e90", "t.dat:1:1: error: a time of 1e+90 s is more than 2e9 steps of 0.000283 s, the most one command may take (5.66e+05 s)"},
        {"solve time 1e90", "t.dat:1:1: error: a time of 1e+90 s is more than 2e9 steps"},
        {"bound zload -1e308 range z 0 1", "t.dat:1:13: error: 'zload' must be a number of magnitude at most 1e100 (got -1e308)"},
        {"prop jmat=1 jkn=1e308", "t.dat:1:17: error: 'jkn' must be > 0 and <= 1e+18 (got 1e308)"},
        {"grav 0 0 -1e308\nstep 1", "t.dat:1:10: error: 'gravity' components must be numbers of magnitude at most 1e100 (got -1e308)"},
        {"ini xvel 1e90 range z 0 1\nstep 1", "t.dat:2:1: error: block 2 would move 2.83e+86 m in one step of 0.000283 s, more than half its size (0.866 m), passing the blocks in its way unseen: its velocity, 1e+90 m/s ('ini' or 'bound ...vel'), is too large"},
        {"table 2 0 1 1 1e90\nbound zvel 1 hist table 2 range z 0 1\nstep 1", "t.dat:3:1: error: block 2 would move 2.83e+86 m in one step of 0.000283 s, more than half its size (0.866 m), passing the blocks in its way unseen: its velocity, 1e+90 m/s ('ini' or 'bound ...vel' times its table), is too large"},
        {"prop jmat=1 jkn=1e-300 jks=1e-300\nstep 1", "error: block 2 would move"},
        {"fix range cylinder 1e308,0,0 -1e308,0,0 1", "t.dat:1:20: error: 'cylinder' a components must be numbers of magnitude at most 1e100 (got 1e308)"},
        {"damp 0.5 1e6 mass\nstep 1", "t.dat:2:1: error: Rayleigh damping of fraction 0.5 at 1e+06 Hz is unstable at the timestep 0.000283 s"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.input);
        Session s;
        ASSERT_TRUE(s.run(kStack)) << s.error();
        EXPECT_FALSE(s.run(c.input));
        EXPECT_NE(s.error().find(c.error), std::string::npos) << s.error();
        EXPECT_EQ(s.model.step, 0);
    }
}
