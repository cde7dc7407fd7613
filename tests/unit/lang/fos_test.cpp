// 'solve fos': the factor of safety by strength reduction, against limit-equilibrium answers
// (a block on an inclined joint, with and without cohesion; the Hoek & Bray wedge), what it
// prints, the state it leaves the model in, and the errors of bad input.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include <Eigen/Dense>

#include <unistd.h>

#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/fos.h"
#include "engine/verdict.h"
#include "fish/runtime.h"
#include "io/save.h"
#include "test_util.h"

using odec::test::Session;

namespace {

const std::string kDir = std::string(ODEC_SOURCE_DIR) + "/examples/verification/";
constexpr double kDeg = M_PI / 180.0;

// The block of examples/verification/incline-fos.dat: a 30-degree incline falling toward +x
// (region 1, fixed) and on it a block with vertical sides, base 2 m along x and 1 m in y, 0.5 m
// high (region 2, id 2): V = 1 m^3, W = 20 kN, base area 2 / cos 30 m^2. Settled on a rough
// joint first.
const char* kBlock =
    "poly prism a (-2,-1,1.15470054) (4,-1,-2.30940108) (4,-1,-5.30940108) (-2,-1,-1.84529946) &\n"
    "           b (-2,2,1.15470054) (4,2,-2.30940108) (4,2,-5.30940108) (-2,2,-1.84529946) region 1\n"
    "poly prism a (0,0,0) (2,0,-1.15470054) (2,0,-0.65470054) (0,0,0.5) &\n"
    "           b (0,1,0) (2,1,-1.15470054) (2,1,-0.65470054) (0,1,0.5) region 2\n"
    "prop mat=1 dens=2000\nprop jmat=1 jkn=1e8 jks=1e8 jfric=80\ngrav 0 0 -10\nfix range region 1\nsolve\n";

double incline_factor(double c, double phi_deg) {
    const double psi = 30 * kDeg, W = 2000 * 10 * 1.0, A = 2.0 / std::cos(psi);
    return (c * A + W * std::cos(psi) * std::tan(phi_deg * kDeg)) / (W * std::sin(psi));
}

void report(const char* what, double computed, double analytic, const odec::FosResult& r, double seconds) {
    std::printf("[verification] %-34s F computed %.5f  analytic %.5f  (%+.3f %%)  %d trials, %ld steps (Nr %ld), %.2f s\n",
                what, computed, analytic, 100.0 * (computed - analytic) / analytic, r.trials, r.steps, r.nr, seconds);
}

// A session that prints what the commands say (Session runs quiet), without progress lines.
struct Talking : Session {
    Talking() {
        interp.quiet = false;
        interp.echo = false;
    }
    std::string said() const { return out.str(); }
};

// The model as 'save' writes it.
std::string model_bytes(const odec::Model& m) {
    const std::string dir = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    const std::string path = dir + "/fos-test-" + std::to_string(getpid()) + ".sav";
    std::string error;
    EXPECT_TRUE(odec::save_model(m, path, error)) << error;
    const std::string bytes = odec::test::read_bytes(path);
    std::remove(path.c_str());
    return bytes;
}

double fish_number(Session& s, const std::string& name) {
    const odec::fish::Symbol* sym = s.interp.fish().find(name);
    return sym ? sym->value.number() : -1;
}

// Runs 'solve fos' on the block with the joint given and checks F against the formula.
void check_incline(double c, double phi, const char* what) {
    Talking s;
    char joint[96];
    std::snprintf(joint, sizeof joint, "prop jmat=1 jfric=%g jcoh=%g\nsolve\n", phi, c);
    ASSERT_TRUE(s.run(std::string(kBlock) + joint)) << s.error();
    const odec::Vec3 before = s.model.blocks.centroid[1];
    const auto t0 = std::chrono::steady_clock::now();
    ASSERT_TRUE(s.run("solve fos\n@f = fos_f")) << s.error();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_TRUE(s.interp.last_fos);
    const odec::FosResult& r = *s.interp.last_fos;
    const double exact = incline_factor(c, phi);
    report(what, r.factor, exact, r, seconds);
    ASSERT_EQ(r.end, odec::FosBracket::End::Found);
    EXPECT_NEAR(r.factor, exact, 0.02 * exact);
    // The bracket holds the answer to within the resolution (and the ratio criterion's slack).
    EXPECT_LE(r.fails - r.stable, 0.01);
    EXPECT_LT(r.stable, exact * 1.001);
    EXPECT_GT(r.fails, exact * 0.999);
    EXPECT_DOUBLE_EQ(fish_number(s, "f"), r.factor);
    // Each trial says its factor and verdict; the first is at 1, stable.
    const std::string& said = s.said();
    EXPECT_NE(said.find("  trial 1: F = 1         equilibrium after "), std::string::npos) << said;
    EXPECT_NE(said.find("  trial 2: F = 2         fails after "), std::string::npos) << said;
    EXPECT_NE(said.find(": mechanism, 1 block (id 2) still moving at up to "), std::string::npos) << said;
    EXPECT_NE(said.find("trial " + std::to_string(r.trials) + ": F = "), std::string::npos) << said;
    EXPECT_NE(said.find("solve fos: factor of safety "), std::string::npos) << said;
    EXPECT_NE(said.find("resolution 0.01): " + std::to_string(r.trials) + " trials, " + std::to_string(r.steps) + " steps"),
              std::string::npos)
        << said;
    // The model is left as the last failing trial left it: the block has slid down the slope,
    // and its joint has its strengths back; the verdict is that trial's.
    // (beyond its elastic shear displacement, 4330 Pa / 1e8 Pa/m = 4.3e-5 m, and still moving).
    EXPECT_GT(s.model.blocks.centroid[1].x() - before.x(), 1e-4);
    EXPECT_GT(s.model.blocks.vel[1].x(), 0);
    EXPECT_DOUBLE_EQ(s.model.joint_materials[1].friction, phi);
    EXPECT_DOUBLE_EQ(s.model.joint_materials[1].cohesion, c);
    ASSERT_TRUE(s.interp.last_solve);
    EXPECT_EQ(s.interp.last_solve->outcome, odec::SolveOutcome::Mechanism);
}

} // namespace

TEST(SolveFos, BlockOnAnInclinedJointWithFrictionAlone) { check_incline(0, 40, "5a incline, phi 40, c 0"); }

TEST(SolveFos, BlockOnAnInclinedJointWithCohesion) { check_incline(2000, 30, "5b incline, phi 30, c 2000 Pa"); }

TEST(SolveFos, HoekAndBrayWedge) {
    // Limit equilibrium of the wedge of examples/verification/wedge-model.dat: the part of its
    // weight across the line of intersection l is carried by the normal forces on the two
    // planes, N_A n_A + N_B n_B; the part along it drives. F = (N_A + N_B) tan(phi) / |W . l|.
    auto normal = [](double dip, double dd) {
        return Eigen::Vector3d(std::sin(dip * kDeg) * std::sin(dd * kDeg), std::sin(dip * kDeg) * std::cos(dd * kDeg),
                               std::cos(dip * kDeg));
    };
    const Eigen::Vector3d na = normal(40, 130), nb = normal(60, 220);
    const Eigen::Vector3d l = na.cross(nb).normalized();
    const Eigen::Vector3d w(0, 0, -1);
    const Eigen::Vector3d across = w - w.dot(l) * l;
    Eigen::Matrix<double, 3, 2> M;
    M << na, nb;
    const Eigen::Vector2d n = M.colPivHouseholderQr().solve(-across);
    ASSERT_GT(n.minCoeff(), 0); // it rests on both planes
    const double phi = 35;
    const double exact = n.sum() * std::tan(phi * kDeg) / std::abs(w.dot(l));
    EXPECT_NEAR(std::atan(std::abs(w.dot(l)) / n.sum()) / kDeg, 33.36, 0.01); // the critical angle quoted

    Talking s;
    ASSERT_TRUE(s.interp.run_file(kDir + "wedge-model.dat")) << s.error();
    ASSERT_TRUE(s.run("prop jmat=1 jfric=35\nsolve\n")) << s.error();
    const auto t0 = std::chrono::steady_clock::now();
    ASSERT_TRUE(s.run("solve fos")) << s.error();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const odec::FosResult& r = *s.interp.last_fos;
    report("4 wedge, phi 35", r.factor, exact, r, seconds);
    ASSERT_EQ(r.end, odec::FosBracket::End::Found);
    EXPECT_NEAR(r.factor, exact, 0.02 * exact);
    // The wedge (the one free block) is what slides in the failing trials.
    const int wedge = s.model.group_index("wedge", false);
    ASSERT_GE(wedge, 0);
    int id = 0;
    for (int b = 0; b < s.model.blocks.size(); ++b) {
        if (s.model.blocks.group[b] == wedge) id = s.model.blocks.id[b];
    }
    EXPECT_NE(s.said().find("mechanism, 1 block (id " + std::to_string(id) + ")"), std::string::npos) << s.said();
}

TEST(SolveFos, MohrCoulombColumnUnderItsWeightIsAboveItsLowerBound) {
    // A 1 x 1 x 2 m column of purely cohesive Mohr-Coulomb zones (c = 30 kPa, phi = 0) on a
    // smooth base, held in x on its face x = 0 and in y on y = 0 (planes of symmetry: a quarter
    // of a 2 x 2 column), free on the others, under its weight (20 kPa/m). Lower bound: the
    // uniaxial stress field rho g (H - z) is in equilibrium, free of traction on the sides, and
    // reaches the strength 2 c / F at the base at F = 2 c / (rho g H) = 1.5, so the factor of
    // the collapse is at least that. (No upper bound is checked: the mechanisms of the
    // symmetric column are not the single sliding wedge's, and 4 tetrahedral zones across are
    // too few to be held to one.)
    const double c = 30000, rho_g = 20000, H = 2;
    const double lower = 2 * c / (rho_g * H);
    Talking s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 2\nprop mat=1 dens=2000 k=1e8 g=6e7 coh=30000 fric=0 ten=1e6 dil=0\n"
                      "change cons=2\ngen edge 0.25\nbound zvel 0 range z -0.001 0.001\n"
                      "bound xvel 0 range x -0.001 0.001\nbound yvel 0 range y -0.001 0.001\ngrav 0 0 -10\nsolve"))
        << s.error();
    const auto t0 = std::chrono::steady_clock::now();
    ASSERT_TRUE(s.run("solve fos")) << s.error();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const odec::FosResult& r = *s.interp.last_fos;
    std::printf("[verification] MC column: F computed %.5f, lower bound %.4f; %d trials, %ld steps (Nr %ld), %.2f s\n",
                r.factor, lower, r.trials, r.steps, r.nr, seconds);
    ASSERT_EQ(r.end, odec::FosBracket::End::Found);
    EXPECT_GE(r.stable, lower);
    EXPECT_NE(s.said().find("reducing friction (its tangent), cohesion and tension of the Mohr-Coulomb zones of material 1"),
              std::string::npos)
        << s.said();
    // Left as the last failing trial left it, with the strengths given back.
    EXPECT_DOUBLE_EQ(s.model.materials[1].cohesion, 30000);
    EXPECT_DOUBLE_EQ(s.model.materials[1].tension, 1e6);
}

// In large strain a failing slope of zones can move far enough to find a new equilibrium (the
// Mohr-Coulomb slope of examples/verification/slope-fos.dat, its ground then reaching x = 32 m,
// stood at F = 1.4076, 2 % above its factor, after 15,645 steps): 'solve fos' says so when it reduces zones in large strain, and
// not in small strain nor when it reduces joints alone.
TEST(SolveFos, ReducingZonesInLargeStrainIsWarned) {
    const char* column = "poly brick 0 1 0 1 0 2\nprop mat=1 dens=2000 k=1e8 g=6e7 coh=30000 fric=0 ten=1e6 dil=0\n"
                         "change cons=2\ngen edge 0.5\nbound zvel 0 range z -0.001 0.001\n"
                         "bound xvel 0 range x -0.001 0.001\nbound yvel 0 range y -0.001 0.001\ngrav 0 0 -10\n";
    const std::string warning = "warning: large strain ('set large', the default): zones whose strength is reduced";
    {
        Talking s;
        ASSERT_TRUE(s.run(std::string(column) + "solve\nsolve fos bracket 1 1")) << s.error();
        EXPECT_NE(s.error().find(warning), std::string::npos) << s.error();
    }
    {
        Talking s;
        ASSERT_TRUE(s.run(std::string("set small\n") + column + "solve\nsolve fos bracket 1 1")) << s.error();
        EXPECT_EQ(s.error().find("warning"), std::string::npos) << s.error();
        ASSERT_TRUE(s.interp.last_fos);
        EXPECT_EQ(s.interp.last_fos->trials, 1);
    }
    {
        Talking s;
        ASSERT_TRUE(s.run(std::string(kBlock) + "prop jmat=1 jfric=40\nsolve\nsolve fos bracket 1 1")) << s.error();
        EXPECT_EQ(s.error().find("warning"), std::string::npos) << s.error();
    }
}

TEST(SolveFos, AGivenBracketIsTestedAndTheFactorOutsideItSaid) {
    const double exact = incline_factor(0, 40); // 1.4534
    {
        Talking s;
        ASSERT_TRUE(s.run(std::string(kBlock) + "prop jmat=1 jfric=40\nsolve\nsolve fos bracket 1.2 1.3")) << s.error();
        EXPECT_EQ(s.interp.last_fos->end, odec::FosBracket::End::Above);
        EXPECT_EQ(s.interp.last_fos->trials, 2);
        EXPECT_EQ(s.interp.last_fos->factor, 0);
        EXPECT_NE(s.said().find("solve fos: the model is stable at F = 1.3, the highest factor tried"), std::string::npos)
            << s.said();
        EXPECT_NE(s.said().find("no trial failed; the model is as it was before 'solve fos'"), std::string::npos);
    }
    {
        Talking s;
        ASSERT_TRUE(s.run(std::string(kBlock) + "prop jmat=1 jfric=40\nsolve\nsolve fos bracket 1.4 1.5 res 0.02"))
            << s.error();
        const odec::FosResult& r = *s.interp.last_fos;
        ASSERT_EQ(r.end, odec::FosBracket::End::Found);
        EXPECT_LE(r.fails - r.stable, 0.02);
        EXPECT_NEAR(r.factor, exact, 0.02 * exact);
        EXPECT_NE(s.said().find("  trial 1: F = 1.4       equilibrium"), std::string::npos) << s.said();
        EXPECT_NE(s.said().find("  trial 2: F = 1.5       fails"), std::string::npos) << s.said();
    }
    {
        Talking s;
        ASSERT_TRUE(s.run(std::string(kBlock) + "prop jmat=1 jfric=40\nsolve\nsolve fos bracket 1.6 1.6")) << s.error();
        EXPECT_EQ(s.interp.last_fos->end, odec::FosBracket::End::OneFails);
        EXPECT_EQ(s.interp.last_fos->trials, 1);
        EXPECT_NE(s.said().find("solve fos: fails at F = 1.6: the factor of safety is below that"), std::string::npos);
    }
}

TEST(SolveFos, IncludeAndExcludeChooseWhatIsReduced) {
    // Excluding friction leaves a joint of friction 40 and no cohesion unreduced: nothing to do.
    Session s;
    ASSERT_TRUE(s.run(std::string(kBlock) + "prop jmat=1 jfric=40\nsolve")) << s.error();
    EXPECT_FALSE(s.run("solve fos exclude friction"));
    EXPECT_NE(s.error().find("'solve fos' finds nothing to reduce"), std::string::npos) << s.error();
    // Reducing the cohesion alone of a joint whose friction alone cannot hold the block.
    Talking t;
    ASSERT_TRUE(t.run(std::string(kBlock) + "prop jmat=1 jfric=25 jcoh=3000\nsolve\nsolve fos include cohesion"))
        << t.error();
    // tan 25 < tan 30: friction alone cannot hold; c A / F + W cos30 tan25 = W sin30 gives F.
    const double psi = 30 * kDeg, W = 20000, A = 2 / std::cos(psi);
    const double exact = 3000 * A / (W * std::sin(psi) - W * std::cos(psi) * std::tan(25 * kDeg));
    const odec::FosResult& r = *t.interp.last_fos;
    ASSERT_EQ(r.end, odec::FosBracket::End::Found);
    EXPECT_NEAR(r.factor, exact, 0.02 * exact);
    EXPECT_NE(t.said().find("solve fos: reducing cohesion of joint material 1 by trial factors F"), std::string::npos)
        << t.said();
}

TEST(SolveFos, BadInputIsRefusedWithTheModelLeftAsItWas) {
    Session s;
    ASSERT_TRUE(s.run(std::string(kBlock) + "prop jmat=1 jfric=40\nsolve")) << s.error();
    const std::string before = model_bytes(s.model);
    struct Case {
        const char* command;
        const char* says;
    };
    const Case cases[] = {
        {"solve fos resolution -0.01", "t.dat:1:"},
        {"solve fos resolution 0", "t.dat:1:"},
        {"solve fos bracket 2 1", "the bracket's second factor (1) is below its first (2)"},
        {"solve fos bracket 0 1", "t.dat:1:"},
        {"solve resolution 0.01", "'resolution' belongs to 'solve fos'"},
        {"solve fos time 1", "'solve fos' takes no 'time'"},
        {"solve fos elastic", "'solve fos' takes no 'elastic'"},
        {"solve fos exclude joints zones", "excluding 'zones' leaves nothing to reduce"},
        {"solve fos exclude joints", "'solve fos' finds nothing to reduce"},
        {"solve fos include zones", "'solve fos' finds nothing to reduce"},
        {"solve fos include sideways", "t.dat:1:"},
        {"solve fos range x 100 200", "the range selects no contact and no zoned block with a strength to reduce"},
        {"solve range x -10 10", "a range belongs to 'solve fos'"},
    };
    for (const Case& c : cases) {
        s.err.str("");
        EXPECT_FALSE(s.run(c.command)) << c.command;
        EXPECT_NE(s.error().find(c.says), std::string::npos) << c.command << "\n" << s.error();
        EXPECT_NE(s.error().find("t.dat:1:"), std::string::npos) << c.command << "\n" << s.error();
        EXPECT_EQ(model_bytes(s.model), before) << c.command;
        EXPECT_FALSE(s.interp.last_fos) << c.command;
    }
    // An elastic joint (no strength at all) has nothing to reduce.
    Session e;
    ASSERT_TRUE(e.run("poly brick 0 1 0 1 -1 0 region 1\npoly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\n"
                      "prop jmat=1 jkn=1e8 jks=1e8\ngrav 0 0 -10\nfix range region 1\nsolve"))
        << e.error();
    const std::string elastic = model_bytes(e.model);
    EXPECT_FALSE(e.run("solve fos"));
    EXPECT_NE(e.error().find("t.dat:1:7: error: 'solve fos' finds nothing to reduce"), std::string::npos) << e.error();
    EXPECT_EQ(model_bytes(e.model), elastic);
    // Without gravity, loads or stresses nothing can fail.
    Session g;
    ASSERT_TRUE(g.run("poly brick 0 1 0 1 -1 0 region 1\npoly brick 0 1 0 1 0 1\nprop mat=1 dens=2000\n"
                      "prop jmat=1 jkn=1e8 jks=1e8 jfric=30\nfix range region 1\n"))
        << g.error();
    const std::string unloaded = model_bytes(g.model);
    EXPECT_FALSE(g.run("solve fos"));
    EXPECT_NE(g.error().find("t.dat:1:7: error: nothing loads the model"), std::string::npos) << g.error();
    EXPECT_EQ(model_bytes(g.model), unloaded);
}

TEST(SolveFos, ARangeNarrowsTheSearchToWhatItSelects) {
    // Two 1 m cubes on one flat base, gravity tilted 30 degrees: cube A (x 0-1) on a joint of
    // friction 40, F = tan 40 / tan 30 = 1.4534; cube B (x 10-11) on one of 50, F = 2.0642.
    // The whole model fails with A; a range that selects B's contact finds B's factor, one that
    // leaves it out ('not') A's. Afterwards every contact has its own joint material again and
    // the copies are gone.
    Session s;
    ASSERT_TRUE(s.run("poly brick -5 25 -2 2 -1 0\npoly brick 0 1 0 1 0 1\npoly brick 10 11 0 1 0 1\n"
                      "prop mat=1 dens=2000\nprop jmat=1 jkn=1e9 jks=1e9 jfric=40\nprop jmat=2 jkn=1e9 jks=1e9 jfric=50\n"
                      "grav 5 0 -8.660254\nfix range z -1 0\nsolve\nchange jmat=2 range x 5 15\nsolve"))
        << s.error();
    const double fa = std::tan(40 * M_PI / 180) / std::tan(M_PI / 6), fb = std::tan(50 * M_PI / 180) / std::tan(M_PI / 6);
    auto jmats = [&] {
        std::vector<int> v;
        for (int c = 0; c < s.model.contacts.size(); ++c) v.push_back(s.model.contacts.jmat(c));
        return v;
    };
    const std::vector<int> own = jmats();
    ASSERT_EQ(own.size(), 2u);
    struct Case {
        const char* command;
        double expected;
    };
    for (const Case& c : {Case{"solve fos range x 5 15", fb}, Case{"solve fos", fa}, Case{"solve fos range not x 5 15", fa}}) {
        ASSERT_TRUE(s.run(c.command)) << c.command << "\n" << s.error();
        ASSERT_TRUE(s.interp.last_fos) << c.command;
        const double f = s.interp.last_fos->factor;
        std::printf("[fos] %s: F %.5f, analytic %.5f (%+.2f %%)\n", c.command, f, c.expected, 100 * (f / c.expected - 1));
        EXPECT_NEAR(f, c.expected, 0.02 * c.expected) << c.command;
        EXPECT_EQ(jmats(), own) << c.command;
        EXPECT_EQ(s.model.joint_materials.size(), 3u) << c.command;
    }
}

TEST(FosBracket, BracketsByDoublingAndHalvingThenBisects) {
    // A model that fails above 1.3: stable at 1, fails at 2, then the middle until 0.01 wide.
    odec::FosBracket b(0.01, 0, 0);
    int trials = 0;
    while (b.next() > 0 && trials < 100) {
        b.report(b.next() <= 1.3);
        ++trials;
    }
    EXPECT_EQ(b.end(), odec::FosBracket::End::Found);
    EXPECT_LE(b.fails() - b.stable(), 0.01);
    EXPECT_LE(b.stable(), 1.3);
    EXPECT_GT(b.fails(), 1.3);
    EXPECT_EQ(trials, 9); // 1, 2, then 7 halvings of 1 down to 1/128
    // Failing at 1: halves down until stable.
    odec::FosBracket h(0.01, 0, 0);
    trials = 0;
    while (h.next() > 0 && trials < 100) {
        h.report(h.next() <= 0.3);
        ++trials;
    }
    EXPECT_EQ(h.end(), odec::FosBracket::End::Found);
    EXPECT_LE(h.stable(), 0.3);
    EXPECT_GT(h.fails(), 0.3);
    // Never failing: ends above kFosFar.
    odec::FosBracket never(0.01, 0, 0);
    trials = 0;
    while (never.next() > 0 && trials < 100) {
        never.report(true);
        ++trials;
    }
    EXPECT_EQ(never.end(), odec::FosBracket::End::Above);
    EXPECT_EQ(never.stable(), odec::kFosFar);
}

// A resolution finer than a double can hold ends the search where the bracket can narrow no
// more (its ends neighbours, whose midpoint is one of them), instead of repeating that trial for ever.
TEST(FosBracket, AResolutionBelowWhatADoubleHoldsStillEnds) {
    odec::FosBracket b(1e-300, 0, 0);
    int trials = 0;
    while (b.next() > 0 && trials < 1000) {
        b.report(b.next() <= 1.3);
        ++trials;
    }
    EXPECT_EQ(b.end(), odec::FosBracket::End::Found);
    EXPECT_LT(trials, 100);
    EXPECT_EQ(std::nextafter(b.stable(), 2.0), b.fails());
}

TEST(SolveFos, ARangeGivesTheZonesOfTheBlocksItSelectsCopiesOfTheirMaterial) {
    // Two zoned Mohr-Coulomb blocks of one material: a range selecting one gives it a copy of
    // the material that alone is reduced; the other keeps the material as it is; undoing gives
    // the block its number back and drops the copy.
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\npoly brick 3 4 0 1 0 1\n"
                      "prop mat=1 dens=2000 k=1e8 g=6e7 coh=30000 fric=30 ten=1e5 dil=0\nchange cons=2\ngen edge 0.5"))
        << s.error();
    odec::Model& m = s.model;
    odec::FosTargets t;
    odec::FosReducible r = odec::fos_reducible(m, t);
    ASSERT_EQ(r.zone_materials, std::vector<int>{1});
    odec::Range range;
    odec::Filter f;
    f.kind = odec::FilterKind::X;
    f.lo = 2;
    f.hi = 5;
    range.filters.push_back(f);
    const int n_materials = static_cast<int>(m.materials.size());
    const odec::FosIsolation iso = odec::fos_isolate(m, range, r);
    ASSERT_EQ(r.zone_materials, std::vector<int>{n_materials});
    EXPECT_EQ(m.blocks.material[0], 1);
    EXPECT_EQ(m.blocks.material[1], n_materials);
    const odec::FosBase base = odec::fos_base(m);
    odec::reduce_strengths(m, base, r, t, 2.0);
    EXPECT_DOUBLE_EQ(m.materials[n_materials].cohesion, 15000);
    EXPECT_NEAR(std::tan(m.materials[n_materials].friction * M_PI / 180), std::tan(M_PI / 6) / 2, 1e-12);
    EXPECT_DOUBLE_EQ(m.materials[1].cohesion, 30000);
    odec::fos_unisolate(m, iso);
    EXPECT_EQ(m.blocks.material[1], 1);
    EXPECT_EQ(static_cast<int>(m.materials.size()), n_materials);
}

// A free dam on a foundation cut every metre, its reservoir pushing it and lifting its base. In the
// trials that fail it slides, its base loses its water and it stops metres downstream: stable by the
// unbalanced force alone (said, trial by trial). 'dmax 0.1' counts those trials as failing, and the
// factor is then the friction the base mobilises at the start: tan(35) N' / T over its joints.
TEST(SolveFos, AMechanismThatFindsANewFootingIsSaidAndDmaxFailsIt) {
    std::string script = "config flow\nfluid density 1000 viscosity 1e-3 bulk 2e9\ngrav 0 0 -9.81\npoly brick -10 0 0 2 -10 0\n";
    for (int x = 0; x < 10; ++x) script += "poly brick " + std::to_string(x) + " " + std::to_string(x + 1) + " 0 2 -10 0\n";
    script += "poly brick 10 30 0 2 -10 0\npoly brick 0 10 0 2 0 20\nprop mat=1 dens=2400\n"
              "prop jmat=1 jkn=1e10 jks=1e10 jfric=35 azero=1e-4 ares=1e-5\nfix range z -10 0\n"
              "bound pp 196200 range x -0.01 0.01 z -0.01 0.01\nbound pp 19620 range x 9.99 10.01 z -0.01 0.01\n"
              "bound stress -196200 0 0 0 0 0 zgrad 9810 0 0 0 0 0 range x -0.01 0.01 z 0 20\nsolve\n";
    double mobilised = 0;
    {
        Talking s;
        ASSERT_TRUE(s.run(script)) << s.error();
        // The base's effective normal and shear forces on the dam (block 13).
        const int dam = s.model.block_index(13);
        double n = 0, t = 0;
        for (int c = 0; c < s.model.contacts.size(); ++c) {
            if (s.model.contacts.block_b[c] != dam) continue;
            const odec::ContactInfo ci = odec::contact_info(s.model, c);
            if (!(ci.normal.z() > 0.99)) continue;
            n += ci.normal_stress * ci.area;
            t += ci.shear_stress_vec.x() * ci.area;
        }
        ASSERT_GT(n, 0);
        mobilised = std::tan(35 * M_PI / 180) * n / std::abs(t);
        ASSERT_TRUE(s.run("solve fos")) << s.error();
        ASSERT_TRUE(s.interp.last_fos);
        const std::string out = s.said();
        EXPECT_NE(out.find("but block 13 moved"), std::string::npos) << out;
        EXPECT_NE(s.error().find("moved more than 1 % of the model's size before coming to rest"), std::string::npos) << s.error();
        EXPECT_GT(s.interp.last_fos->factor, 1.3); // the footing the dam found downstream
    }
    {
        Talking s;
        ASSERT_TRUE(s.run(script + "solve fos dmax 0.1")) << s.error();
        ASSERT_TRUE(s.interp.last_fos);
        const odec::FosResult& r = *s.interp.last_fos;
        std::printf("[verification] fos: dam with uplift, dmax 0.1 m: F %.4f, the base's mobilised friction %.4f (%+.2f %%)\n",
                    r.factor, mobilised, 100 * (r.factor - mobilised) / mobilised);
        EXPECT_NEAR(r.factor, mobilised, 0.02 * mobilised);
        EXPECT_NE(s.said().find("more than dmax 0.1 m: a mechanism that found a new footing"), std::string::npos);
    }
    {
        // dmax without fos, and a dmax of 0: refused, the model unchanged.
        Session s;
        EXPECT_FALSE(s.run("solve dmax 0.1"));
        EXPECT_NE(s.error().find("'dmax' belongs to 'solve fos'"), std::string::npos) << s.error();
        EXPECT_FALSE(s.run("solve fos dmax 0"));
        EXPECT_NE(s.error().find("dmax"), std::string::npos) << s.error();
    }
}
