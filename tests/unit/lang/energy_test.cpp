// The energy account ('set energy on', engine/energy.h): each term against an analytic answer or
// the balance it must close, in dynamic mode without damping unless said, with the tolerance
// stated at each check.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "engine/energy.h"
#include "fish/intrinsics.h"
#include "fish/runtime.h"
#include "test_util.h"

using odec::test::Session;

namespace {

constexpr double kDeg = M_PI / 180.0;

const std::vector<double>& hist(const Session& s, int n) { return s.model.histories.items.at(n - 1).values; }

double term(const odec::Model& m, const char* name) {
    double v = 0;
    EXPECT_TRUE(odec::energy_term(m, name, v)) << name;
    return v;
}

double max_abs(const std::vector<double>& v) {
    double x = 0;
    for (double e : v) x = std::max(x, std::abs(e));
    return x;
}

} // namespace

// (1) A block falling freely: its kinetic energy is the work gravity did, m g h, to 1e-6.
TEST(Energy, FreeFallKineticIsGravityWork) {
    Session s;
    ASSERT_TRUE(s.run("config dyn\npoly brick 0 1 0 1 10 11\nprop mat=1 dens=2000\ngrav 0 0 -10\ndamp off\n"
                      "set dt 1e-3\nset energy on\nhist ncyc 100\nhist energy kinetic\nhist energy gravity\n"
                      "hist energy error\nstep 1000"))
        << s.error();
    const odec::Model& m = s.model;
    const double k = term(m, "kinetic"), w = term(m, "gravity");
    // The account stands at the last step's start (t = 0.999 s): m g^2 t^2 / 2.
    const double t = 0.999, exact = 0.5 * 2000 * 100 * t * t;
    std::printf("[energy] free fall: kinetic %.9g J, gravity work %.9g J, m g^2 t^2 / 2 %.9g J\n", k, w, exact);
    EXPECT_NEAR(k, w, 1e-6 * w);
    EXPECT_NEAR(w, exact, 1e-6 * exact);
    EXPECT_NEAR(term(m, "error"), 0.0, 1e-6 * w);
    // Every sample too.
    const auto& hk = hist(s, 1);
    const auto& hw = hist(s, 2);
    ASSERT_EQ(hk.size(), 10u);
    for (size_t i = 0; i < hk.size(); ++i) EXPECT_NEAR(hk[i], hw[i], 1e-6 * hw.back());
    EXPECT_EQ(term(m, "jstrain"), 0.0);
    EXPECT_EQ(term(m, "damping"), 0.0);
    EXPECT_EQ(term(m, "initial"), 0.0);
    EXPECT_EQ(term(m, "given"), 0.0);
}

// (2) A block dropped 1 mm onto a joint of high friction, straight down: kinetic + joint strain
// energy - gravity work stays at zero, to 0.1 % of m g h, through the fall, the impact and the
// rebound to the top, at each normal stiffness. The contact's only error is where it closes or
// opens within a step (at most k dx^2 / 8 for the step's displacement dx): the automatic timestep
// at dtfrac 0.02 keeps it below the tolerance at any stiffness.
TEST(Energy, BounceOnAJointConserves) {
    for (const char* kn : {"1e8", "1e10", "1e12"}) {
        SCOPED_TRACE(kn);
        Session s;
        ASSERT_TRUE(s.run(std::string("config dyn\npoly brick -1 2 -1 2 -1 0\npoly brick 0 1 0 1 0.001 1.001\n"
                                      "prop mat=1 dens=2000\nprop jmat=1 jkn=") +
                          kn + " jks=" + kn + " jfric=80\ngrav 0 0 -10\nfix range z -1 0\ndamp off\nset dtfrac 0.02\n"
                          "set energy on\nhist ncyc 1\nhist energy error\nhist energy jstrain\n"
                          "hist energy kinetic\nhist zdis 0.5 0.5 0.5\nstep 1"))
            << s.error();
        // Down 1 mm in sqrt(2 h / g), half a period of the block on its joint (k = kn x 1 m^2), and up
        // again: 2.1 times the fall and the half period.
        const double t = 2.1 * std::sqrt(2 * 1e-3 / 10) + M_PI * std::sqrt(2000 / std::stod(kn));
        const long steps = static_cast<long>(t / s.model.dt);
        ASSERT_TRUE(s.run("step " + std::to_string(steps))) << s.error();
        const double mgh = 2000 * 10 * 1e-3;
        const auto& err = hist(s, 1);
        const auto& js = hist(s, 2);
        const auto& z = hist(s, 4);
        // It did bounce: the joint took the whole energy, and the block came back up near its start.
        EXPECT_GT(max_abs(js), mgh);
        // The deepest closure x, from k x^2 / 2 = m g (h + x), 0.86 mm at kn 1e8.
        const double k = std::stod(kn), x = (2e4 + std::sqrt(4e8 + 2 * k * 2e4 * 1e-3)) / k;
        EXPECT_GT(*std::min_element(z.begin(), z.end()), -1e-3 - 1.05 * x);
        EXPECT_LT(*std::min_element(z.begin(), z.end()), -1e-3 - 0.95 * x);
        EXPECT_GT(z.back(), -0.2e-3);
        std::printf("[energy] bounce, kn %s Pa/m: %ld steps, largest |error| %.3g J = %.4f %% of m g h\n", kn, steps + 1,
                    max_abs(err), 100 * max_abs(err) / mgh);
        EXPECT_LT(max_abs(err), 1e-3 * mgh);
    }
}

// (3) A block sliding down a 40 degree incline on a joint of friction 20 degrees: what friction
// dissipates is tan 20 m g cos 40 times the distance slid, to 1 %, and it never decreases.
TEST(Energy, FrictionOnAnIncline) {
    Session s;
    ASSERT_TRUE(s.run(
        "config dyn\n"
        "poly prism a (-10,-1,8.39099631) (20,-1,-16.78199262) (20,-1,-21.78199262) (-10,-1,3.39099631) &\n"
        "           b (-10,2,8.39099631) (20,2,-16.78199262) (20,2,-21.78199262) (-10,2,3.39099631) region 1\n"
        "poly prism a (0,0,0) (7.66044443,0,-6.42787610) (10.87438248,0,-2.59765388) (3.21393805,0,3.83022222) &\n"
        "           b (0,1,0) (7.66044443,1,-6.42787610) (10.87438248,1,-2.59765388) (3.21393805,1,3.83022222) region 2\n"
        "prop mat=1 dens=2000\nprop jmat=1 jkn=1e7 jks=1e7 jfric=80\ngrav 0 0 -10\nfix range region 1\nsolve\n"
        "prop jmat=1 jfric=20\nreset disp time hist\ndamp off\nset energy on\nhist ncyc 5\nhist energy slip\n"
        "hist energy error\nstep time 1.0"))
        << s.error();
    const odec::Model& m = s.model;
    const int b = m.block_index(2);
    // The account stands at the last step's start: the block's displacement then.
    const Eigen::Vector3d d = m.blocks.disp[b] - m.blocks.vel[b] * m.dt;
    const double mass = m.blocks.mass[b], dist = d.norm();
    const double exact = std::tan(20 * kDeg) * mass * 10 * std::cos(40 * kDeg) * dist;
    const double slip = term(m, "slip");
    std::printf("[energy] incline: slid %.4f m, friction dissipated %.6g J, tan 20 m g cos 40 x distance %.6g J "
                "(%+.3f %%)\n",
                dist, slip, exact, 100 * (slip - exact) / exact);
    EXPECT_GT(dist, 1.5);
    EXPECT_NEAR(slip, exact, 0.01 * exact);
    const auto& h = hist(s, 1);
    ASSERT_GT(h.size(), 20u);
    EXPECT_GE(h.front(), 0.0);
    for (size_t i = 1; i < h.size(); ++i) EXPECT_GE(h[i], h[i - 1]) << "sample " << i;
    // And the balance closes (no contact opens or closes here): 1e-5 of the energy handled.
    EXPECT_LT(std::abs(term(m, "error")), 1e-5 * m.energy.peak);
}

// (4) Local damping on the sliding block: damping takes energy out at every sample, and the
// balance still closes, to 0.1 % of the energy handled.
TEST(Energy, LocalDampingDissipatesAndTheBalanceCloses) {
    Session s;
    ASSERT_TRUE(s.run(
        "config dyn\n"
        "poly prism a (-10,-1,8.39099631) (20,-1,-16.78199262) (20,-1,-21.78199262) (-10,-1,3.39099631) &\n"
        "           b (-10,2,8.39099631) (20,2,-16.78199262) (20,2,-21.78199262) (-10,2,3.39099631) region 1\n"
        "poly prism a (0,0,0) (7.66044443,0,-6.42787610) (10.87438248,0,-2.59765388) (3.21393805,0,3.83022222) &\n"
        "           b (0,1,0) (7.66044443,1,-6.42787610) (10.87438248,1,-2.59765388) (3.21393805,1,3.83022222) region 2\n"
        "prop mat=1 dens=2000\nprop jmat=1 jkn=1e7 jks=1e7 jfric=20\ngrav 0 0 -10\nfix range region 1\n"
        "damp local 0.8\nset energy on\nhist ncyc 5\nhist energy damping\nhist energy error\nstep time 1.0"))
        << s.error();
    const odec::Model& m = s.model;
    const auto& damping = hist(s, 1);
    const auto& err = hist(s, 2);
    ASSERT_GT(damping.size(), 20u);
    EXPECT_GT(damping.front(), 0.0);
    for (size_t i = 1; i < damping.size(); ++i) EXPECT_GT(damping[i], damping[i - 1]) << "sample " << i;
    std::printf("[energy] local damping on the incline: damping %.6g J, slip %.6g J, gravity %.6g J, largest "
                "|error| %.3g J (%.2e of %.6g J)\n",
                term(m, "damping"), term(m, "slip"), term(m, "gravity"), max_abs(err), max_abs(err) / m.energy.peak,
                m.energy.peak);
    EXPECT_GT(term(m, "damping"), 0.1 * term(m, "gravity"));
    EXPECT_LT(max_abs(err), 1e-3 * m.energy.peak);
}

// (5) An elastic zoned block on rollers, loaded suddenly on its top by 'bound stress' and left to
// oscillate undamped: zone strain energy + kinetic energy is the work of the load, to 0.5 % of the
// most work done; about half of it is kinetic at times, and it swings back.
TEST(Energy, ElasticZonesOscillateUnderALoad) {
    Session s;
    ASSERT_TRUE(s.run("config dyn\npoly brick 0 1 0 1 0 2\nprop mat=1 dens=2500 ymod=10e9 prat=0.25\ngen edge 0.25\n"
                      "bound zvel 0 range z -0.001 0.001\nbound xvel 0 range x -0.001 0.001\n"
                      "bound yvel 0 range y -0.001 0.001\ndamp off\nset energy on\n"
                      "bound stress 0 0 -1e6 0 0 0 range z 1.999 2.001\nhist ncyc 5\nhist energy zstrain\n"
                      "hist energy kinetic\nhist energy load\nhist energy error\nstep 3000"))
        << s.error();
    const auto& zs = hist(s, 1);
    const auto& ke = hist(s, 2);
    const auto& load = hist(s, 3);
    const double peak = max_abs(load);
    double worst = 0;
    for (size_t i = 0; i < load.size(); ++i) worst = std::max(worst, std::abs(zs[i] + ke[i] - load[i]));
    std::printf("[energy] zoned block: largest load work %.6g J, largest |zstrain + kinetic - load| %.3g J (%.3f %%)\n",
                peak, worst, 100 * worst / peak);
    EXPECT_LT(worst, 5e-3 * peak);
    EXPECT_LT(max_abs(hist(s, 4)), 5e-3 * peak);
    // The load did F u_max / 2 twice over at the bottom of the swing: it oscillates, it does not settle.
    EXPECT_GT(max_abs(ke), 0.2 * peak);
    EXPECT_LT(load.back(), 0.9 * peak);
    EXPECT_EQ(term(s.model, "plastic"), 0.0);
}

// Zone plasticity: a Mohr-Coulomb cube crushed at a steady velocity. The driven top's work goes
// into plastic flow (never negative), strain energy and damping; the balance closes to 0.1 %.
TEST(Energy, PlasticFlowOfZones) {
    Session s;
    ASSERT_TRUE(s.run("config dyn\npoly brick 0 1 0 1 0 1\nprop mat=1 dens=2500 k=6.7e9 g=4e9 coh=2e5 fric=30 ten=1e5\n"
                      "change cons=2\ngen edge 0.25\ndamp local 0.8\nset energy on\n"
                      "bound zvel 0 range z -0.001 0.001\nbound xvel 0 range x -0.001 0.001\n"
                      "bound yvel 0 range y -0.001 0.001\nbound zvel -0.05 range z 0.999 1.001\nhist ncyc 20\n"
                      "hist energy plastic\nhist energy error\nstep 2000"))
        << s.error();
    const odec::Model& m = s.model;
    const auto& plastic = hist(s, 1);
    for (size_t i = 1; i < plastic.size(); ++i) EXPECT_GE(plastic[i], plastic[i - 1]) << "sample " << i;
    const double w = term(m, "velocity");
    std::printf("[energy] crushed cube: velocity work %.6g J, plastic %.6g J, zstrain %.6g J, damping %.6g J, "
                "error %.3g J\n",
                w, term(m, "plastic"), term(m, "zstrain"), term(m, "damping"), term(m, "error"));
    EXPECT_GT(term(m, "plastic"), 0.5 * w);
    EXPECT_LT(max_abs(hist(s, 2)), 1e-3 * m.energy.peak);
}

// The commands: 'print energy' shows every term with its unit; errors change nothing; a FISH
// intrinsic reads each term; static mode is said to be unphysical.
TEST(Energy, CommandsAndFish) {
    Session s;
    s.interp.quiet = false;
    EXPECT_FALSE(s.run("print energy"));
    EXPECT_NE(s.error().find("the energy account is off"), std::string::npos) << s.error();
    EXPECT_NE(s.error().find("t.dat:1:7"), std::string::npos) << s.error();
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\ngrav 0 0 -10"));
    const long before = s.model.step;
    EXPECT_FALSE(s.run("reset disp energy"));
    EXPECT_NE(s.error().find("the energy account is off"), std::string::npos) << s.error();
    EXPECT_EQ(s.model.step, before);
    EXPECT_FALSE(s.run("hist energy potential"));
    EXPECT_NE(s.error().find("potential"), std::string::npos) << s.error();
    EXPECT_TRUE(s.model.histories.items.empty());
    // Static mode (no 'config dyn'): a warning that the energies are not physical.
    std::string before_err = s.error();
    ASSERT_TRUE(s.run("set energy on"));
    EXPECT_NE(s.error().find("not physical"), std::string::npos) << s.error();
    ASSERT_TRUE(s.run("set energy off\nconfig dyn\ndamp off\nset dt 1e-3\nset energy on\nstep 100"));
    s.out.str("");
    ASSERT_TRUE(s.run("print energy"));
    const std::string out = s.out.str();
    for (const odec::EnergyTermInfo& t : odec::energy_terms()) {
        EXPECT_NE(out.find(std::string("  ") + t.name), std::string::npos) << t.name << "\n" << out;
    }
    EXPECT_NE(out.find("energy account, J: stored energies at the start of the last step (t = 0.099 s)"),
              std::string::npos)
        << out;
    EXPECT_NE(out.find("error (their difference)"), std::string::npos) << out;
    EXPECT_EQ(out.find("note:"), std::string::npos) << out;
    // One intrinsic per term, named energy_<term>, reading what the account reports.
    std::string def = "def read_terms\n";
    for (const odec::EnergyTermInfo& t : odec::energy_terms()) {
        const std::string name = std::string("energy_") + t.name;
        ASSERT_NE(odec::fish::find_intrinsic(name), nullptr) << name;
        def += "  v_" + std::string(t.name) + " = " + name + "\n";
    }
    ASSERT_TRUE(s.run(def + "end\n@read_terms")) << s.error();
    for (const odec::EnergyTermInfo& t : odec::energy_terms()) {
        const odec::fish::Symbol* sym = s.interp.fish().find(std::string("v_") + t.name);
        ASSERT_NE(sym, nullptr) << t.name;
        EXPECT_EQ(sym->value.number(), term(s.model, t.name)) << t.name;
    }
    EXPECT_GT(term(s.model, "kinetic"), 900.0);
    // 'set energy on' again goes on; 'reset energy' starts afresh.
    ASSERT_TRUE(s.run("set energy on"));
    EXPECT_EQ(s.model.energy.start_step, 0);
    ASSERT_TRUE(s.run("reset energy"));
    EXPECT_EQ(s.model.energy.start_step, 100);
    EXPECT_EQ(term(s.model, "gravity"), 0.0);
    EXPECT_NEAR(term(s.model, "initial"), term(s.model, "kinetic"), 1e-12);
    ASSERT_TRUE(s.run("set energy off"));
    EXPECT_FALSE(s.model.energy.on);
}

// What commands change between steps is given, not an error: a velocity given by 'ini' and a
// block deleted. (The error left is the start of each block's motion from a velocity given at t,
// its first step half a kick: m g^2 dt^2 / 8 each, 0.0125 J here.)
TEST(Energy, CommandsBetweenStepsAreGiven) {
    Session s;
    ASSERT_TRUE(s.run("config dyn\npoly brick 0 1 0 1 0 1\npoly brick 3 4 0 1 0 1\nprop mat=1 dens=1000\n"
                      "grav 0 0 -10\ndamp off\nset dt 1e-3\nset energy on\nstep 100\n"))
        << s.error();
    // 'ini' gives the velocity at t: the fall it leaves as it is, taken from half a step back to t.
    const double vz_half = s.model.blocks.vel[0].z();
    ASSERT_TRUE(s.run("ini xvel 2 range id 1")) << s.error();
    const double vz_t = s.model.blocks.vel[0].z();
    EXPECT_NEAR(vz_t, vz_half - 10 * 0.5e-3, 1e-12);
    const double given = 0.5 * 1000 * (4 + vz_t * vz_t - vz_half * vz_half);
    EXPECT_NEAR(term(s.model, "given"), given, 1e-9);
    EXPECT_NEAR(term(s.model, "error"), -2 * 0.0125, 1e-9);
    ASSERT_TRUE(s.run("step 100")) << s.error();
    // Block 2 falls on: what it carries leaves with it.
    const double vz = s.model.blocks.vel[s.model.block_index(2)].z();
    ASSERT_TRUE(s.run("delete range id 2")) << s.error();
    EXPECT_NEAR(term(s.model, "given"), given - 0.5 * 1000 * vz * vz, 1e-9);
    ASSERT_TRUE(s.run("step 100")) << s.error();
    EXPECT_NEAR(term(s.model, "error"), -3 * 0.0125, 1e-6);
}

// Saved and restored: the account goes on to the same bits as one never saved; a file of the
// format before the account restores with it off.
TEST(Energy, SavedAndRestored) {
    char tmpl[] = "/tmp/odec-energy-XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    const std::string dir = tmpl;
    const std::string setup = "config dyn\npoly brick -1 2 -1 2 -1 0\npoly brick 0 1 0 1 0.001 1.001\n"
                              "prop mat=1 dens=2000\nprop jmat=1 jkn=1e9 jks=1e9 jfric=30\ngrav 0 0 -10\n"
                              "fix range z -1 0\ndamp off\nset energy on\nhist energy error\nhist ncyc 5\n";
    Session whole;
    ASSERT_TRUE(whole.run(setup + "step 400")) << whole.error();
    Session first;
    ASSERT_TRUE(first.run(setup + "step 150\nsave '" + dir + "/half'")) << first.error();
    Session second;
    ASSERT_TRUE(second.run("restore '" + dir + "/half'\nstep 250")) << second.error();
    EXPECT_TRUE(second.model.energy.on);
    for (const odec::EnergyTermInfo& t : odec::energy_terms()) {
        EXPECT_EQ(term(second.model, t.name), term(whole.model, t.name)) << t.name;
    }
    EXPECT_EQ(hist(second, 1), hist(whole, 1));
    // A file older than the account (format 6, a toppling brick) restores with it off.
    Session old;
    const std::string v6 = std::string(ODEC_SOURCE_DIR) + "/tests/fuzz/regressions/restore/toppling-v6.sav";
    ASSERT_TRUE(old.run("restore '" + v6 + "'")) << old.error();
    EXPECT_FALSE(old.model.energy.on);
    EXPECT_GT(old.model.step, 0);
    for (const char* f : {"/half.sav"}) std::remove((dir + f).c_str());
    rmdir(dir.c_str());
}
