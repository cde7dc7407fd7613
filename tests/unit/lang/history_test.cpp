// Histories: a point history follows its material point through any rotation exactly (against
// the analytic turn of a spinning block, its acceleration the centripetal one), through 'reset
// disp', a history made during a run and a joint set cutting the turned block; a history made
// during a run has its own samples from the next one on, and save and restore carry them (and
// older files' NaN-padded ones) exactly; a FISH history whose function fails stops the run with
// the reason.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "engine/blocks.h"
#include "engine/history.h"
#include "io/save.h"
#include "test_util.h"

using odec::Vec3;
using odec::test::read_bytes;
using odec::test::Session;

namespace {

const double kPi = 3.14159265358979323846;
const double kSpin = 100 * kPi / 180; // rad/s: 40 degrees in 400 steps of 1 ms, 180 in 1800
const double kDt = 1e-3;

std::string text(double x) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
}
std::string text(const Vec3& v) { return text(v.x()) + "," + text(v.y()) + "," + text(v.z()); }

// A 2 m cube of 8000 kg centred at the origin, in dynamic mode, undamped, without gravity or
// contacts, spun at kSpin about `axis` (a unit vector) through its centroid. Histories of the
// displacement and velocity of the material point at p are sampled every 100 steps.
std::string spinning_cube(const Vec3& axis, const Vec3& p) {
    const Vec3 w = kSpin * axis;
    return "config dyn\npoly brick -1 1 -1 1 -1 1\nprop mat=1 dens=1000\ndamp off\nset dt " + text(kDt) +
           "\nhist ncyc 100\nhist xdis " + text(p) + "\nhist ydis " + text(p) + "\nhist zdis " + text(p) +
           "\nhist xvel " + text(p) + "\nhist yvel " + text(p) + "\nhist zvel " + text(p) +
           "\nini xrvel " + text(w.x()) + " yrvel " + text(w.y()) + " zrvel " + text(w.z()) + "\n";
}

// Histories `first` .. `first + 2` (1-based) as the vector sampled at sample k.
Vec3 sampled(const odec::HistorySet& hs, int first, size_t k) {
    Vec3 v;
    for (int i = 0; i < 3; ++i) {
        const double* x = hs.items[first - 1 + i].at(k);
        v[i] = x ? *x : std::nan("");
    }
    return v;
}

// Every displacement sample of histories 1-3 is where the material point is less where it was,
// to 1e-9 of the displacement; the velocity (histories 4-6) is the spin times the lever.
// Returns the largest error of the small-rotation form (the accumulated turn times the lever),
// for the record.
double check_spin(const Session& s, const Vec3& axis, const Vec3& p) {
    const odec::HistorySet& hs = s.model.histories;
    EXPECT_FALSE(hs.sample_steps.empty());
    double small_rotation_error = 0;
    for (size_t k = 0; k < hs.sample_steps.size(); ++k) {
        const double angle = kSpin * kDt * static_cast<double>(hs.sample_steps[k]);
        const Eigen::AngleAxisd turn(angle, axis);
        const Vec3 now = turn * p;
        const Vec3 exact = now - p;
        const Vec3 d = sampled(hs, 1, k), v = sampled(hs, 4, k);
        EXPECT_LE((d - exact).norm(), 1e-9 * exact.norm()) << "step " << hs.sample_steps[k] << ": " << d.transpose()
                                                           << " against " << exact.transpose();
        const Vec3 vel = kSpin * axis.cross(now);
        EXPECT_LE((v - vel).norm(), 1e-9 * vel.norm()) << "step " << hs.sample_steps[k];
        small_rotation_error = std::max(small_rotation_error, ((angle * axis).cross(now) - exact).norm());
    }
    return small_rotation_error;
}

} // namespace

TEST(History, PointDisplacementIsExactThrough40And180Degrees) {
    for (const Vec3& axis : {Vec3(0, 0, 1), Vec3(1, 1, 1).normalized()}) {
        SCOPED_TRACE(axis.transpose());
        const Vec3 p(0.9, 0.5, 0.3);
        Session s;
        ASSERT_TRUE(s.run(spinning_cube(axis, p) + "hist xacc " + text(p) + "\nhist yacc " + text(p) + "\nhist zacc " +
                          text(p) + "\nstep 400"))
            << s.error();
        ASSERT_EQ(s.model.histories.sample_steps.back(), 400);
        const double at40 = check_spin(s, axis, p);
        // Its acceleration is the centripetal one, w x (w x r), towards the axis.
        for (size_t k = 0; k < 4; ++k) {
            const Vec3 r = Eigen::AngleAxisd(kSpin * kDt * s.model.histories.sample_steps[k], axis) * p;
            const Vec3 a = kSpin * kSpin * axis.cross(axis.cross(r));
            EXPECT_LE((sampled(s.model.histories, 7, k) - a).norm(), 1e-9 * a.norm()) << k;
        }
        ASSERT_TRUE(s.run("step 1400")) << s.error();
        ASSERT_EQ(s.model.histories.sample_steps.back(), 1800);
        const double at180 = check_spin(s, axis, p);
        // At 180 degrees the point is across the axis: its displacement is twice its distance from it.
        const Vec3 radial = p - p.dot(axis) * axis;
        EXPECT_NEAR((sampled(s.model.histories, 1, 17) + 2 * radial).norm(), 0, 1e-12);
        // The small-rotation form was far off: by over a quarter of the displacement at 40 degrees.
        EXPECT_GT(at40, 0.25 * 2 * radial.norm() * std::sin(kPi / 9));
        EXPECT_GT(at180, radial.norm());
        std::printf("lever %.4f m: small-rotation form off by %.4f m at 40 deg, %.4f m at 180 deg\n",
                    radial.norm(), at40, at180);
        // The block's own records agree: its centroid has not moved, and it has turned by the angle.
        EXPECT_EQ(s.model.blocks.disp[0], Vec3::Zero());
        EXPECT_NEAR(odec::rotation_since_reset(s.model, 0).norm(), kPi, 1e-12);
    }
}

TEST(History, ResetDispAndHistoriesMadeDuringTheRunCountFromTheReset) {
    const Vec3 axis(0, 0, 1), p(0.9, 0.5, 0.3);
    Session s;
    ASSERT_TRUE(s.run(spinning_cube(axis, p) + "step 400")) << s.error();
    // At 40 degrees, a history of the point now at q: that material point was at turn(-40) q
    // when the displacements were last reset (when the cube was made).
    const Vec3 q(-0.2, 0.8, -0.6);
    ASSERT_TRUE(s.run("hist xdis " + text(q) + "\nhist ydis " + text(q) + "\nhist zdis " + text(q) + "\nstep 500"))
        << s.error();
    const odec::HistorySet& hs = s.model.histories;
    ASSERT_EQ(hs.items[6].first, 4); // its own samples start after the four before it was made
    const Vec3 q0 = Eigen::AngleAxisd(-0.4 * kSpin, axis) * q;
    for (size_t k = 4; k < hs.sample_steps.size(); ++k) {
        const Vec3 exact = Eigen::AngleAxisd(kSpin * kDt * hs.sample_steps[k], axis) * q0 - q0;
        EXPECT_LE((sampled(hs, 7, k) - exact).norm(), 1e-9 * exact.norm()) << hs.sample_steps[k];
    }
    // 'reset disp' at 90 degrees: from then on each point's displacement counts from where it
    // was at the reset.
    ASSERT_TRUE(s.run("reset disp")) << s.error();
    for (int i = 0; i < 3; ++i) EXPECT_EQ(odec::history_value(s.model, hs.items[i]), 0.0);
    ASSERT_TRUE(s.run("step 900")) << s.error();
    ASSERT_EQ(hs.sample_steps[9], 1000);
    const Vec3 p90 = Eigen::AngleAxisd(0.9 * kSpin, axis) * p;
    for (size_t k = 9; k < hs.sample_steps.size(); ++k) {
        const double angle = kSpin * kDt * (hs.sample_steps[k] - 900);
        const Vec3 exact = Eigen::AngleAxisd(angle, axis) * p90 - p90;
        EXPECT_LE((sampled(hs, 1, k) - exact).norm(), 1e-9 * exact.norm()) << hs.sample_steps[k];
    }
}

TEST(History, PointsFollowTheirMaterialIntoThePiecesOfACut) {
    // The cube turned 40 degrees about z is cut by the plane x = 0; both halves go on spinning,
    // and each, no longer held by the other, moves off along its centroid's velocity.
    const Vec3 axis(0, 0, 1), p(0.9, 0.5, 0.3), q(-0.7, 0.1, -0.4);
    Session s;
    ASSERT_TRUE(s.run(spinning_cube(axis, p) + "hist xdis " + text(q) + "\nhist ydis " + text(q) + "\nhist zdis " +
                      text(q) + "\nhist xvel " + text(q) + "\nhist yvel " + text(q) + "\nhist zvel " + text(q) +
                      "\nprop jmat=1 jkn=1e6 jks=1e6 jfric=30\nstep 400"))
        << s.error();
    ASSERT_TRUE(s.run("jset dip 90 dd 90 origin 0,0,0")) << s.error();
    const odec::Model& m = s.model;
    ASSERT_EQ(m.blocks.size(), 2);
    const Eigen::AngleAxisd at_cut(0.4 * kSpin, axis);
    Vec3 c_cut[2];
    for (int piece = 0; piece < 2; ++piece) {
        // Each piece's centroid is displaced as that material point of the cube was.
        c_cut[piece] = m.blocks.centroid[piece];
        EXPECT_LE((m.blocks.disp[piece] - (c_cut[piece] - at_cut.inverse() * c_cut[piece])).norm(), 1e-12);
    }
    ASSERT_TRUE(s.run("step 500")) << s.error();
    const odec::HistorySet& hs = m.histories;
    ASSERT_EQ(hs.sample_steps.size(), 9u);
    for (int h : {1, 7}) {
        const Vec3 x0 = h == 1 ? p : q;
        const Vec3 x = at_cut * x0; // where the point was at the cut
        const int piece = c_cut[0].x() * x.x() > 0 ? 0 : 1; // the half on its side of x = 0
        ASSERT_GT(c_cut[piece].x() * x.x(), 0);
        EXPECT_EQ(hs.items[h - 1].block_id, m.blocks.id[piece]); // it follows the half that holds it
        const Vec3 v = kSpin * axis.cross(c_cut[piece]);
        for (size_t k = 4; k < hs.sample_steps.size(); ++k) {
            const double t = kDt * (hs.sample_steps[k] - 400);
            const Vec3 centre = c_cut[piece] + v * t;
            const Vec3 now = centre + Eigen::AngleAxisd(kSpin * t, axis) * (x - c_cut[piece]);
            const Vec3 exact = now - x0;
            EXPECT_LE((sampled(hs, h, k) - exact).norm(), 1e-9 * exact.norm()) << "history " << h << " step " << hs.sample_steps[k];
            const Vec3 vel = v + kSpin * axis.cross(now - centre);
            EXPECT_LE((sampled(hs, h + 3, k) - vel).norm(), 1e-9 * vel.norm()) << "history " << h + 3;
        }
    }
}

TEST(History, SpinIsGivenToRigidBlocksOnly) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\npoly brick 2 3 0 1 0 1\nprop mat=1 dens=1000 ymod 1e9 prat 0.25\n"
                      "gen edge 0.5 range id 2"))
        << s.error();
    EXPECT_FALSE(s.run("ini zrvel 1"));
    EXPECT_NE(s.error().find("t.dat:1:5: error: 'zrvel' spins rigid blocks: the range holds gridpoints of deformable blocks"),
              std::string::npos)
        << s.error();
    EXPECT_EQ(s.model.blocks.ang_vel[0], Vec3::Zero()); // nothing was changed
    ASSERT_TRUE(s.run("ini zrvel 1 xvel 2 range id 1")) << s.error();
    EXPECT_EQ(s.model.blocks.ang_vel[0], Vec3(0, 0, 1));
    EXPECT_EQ(s.model.blocks.vel[0], Vec3(2, 0, 0));
    // Components not given keep their value at the present time.
    ASSERT_TRUE(s.run("ini xrvel 0.5 range id 1")) << s.error();
    EXPECT_EQ(odec::spin_at_t(s.model, 0), Vec3(0.5, 0, 1));
    EXPECT_EQ(odec::velocity_at_t(s.model, 0), Vec3(2, 0, 0));
}

TEST(History, MadeDuringARunItHasItsOwnSamplesAndRestoresExactly) {
    char tmpl[] = "/tmp/odec-history-test-XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    const std::string dir = tmpl;
    const auto at = [&](const std::string& name) { return dir + "/" + name; };
    Session a;
    a.interp.quiet = false;
    a.interp.echo = false;
    ASSERT_TRUE(a.run("config dyn\npoly brick -2 2 -2 2 -1 0\npoly brick -0.25 0.25 -0.5 0.5 0 2\nprop mat=1 dens=2000\n"
                      "prop jmat=1 jkn=1e9 jks=1e9 jfric=40\ngrav 0 0 -10\nfix range z -1 0\ndamp off\nset dt 1e-4\n"
                      "hist ncyc 50\nhist unbal\nhist xdis 0.25,0.5,2\nini xvel 1.5 range z 0 2\nstep 200\n"
                      "hist zdis 0.25,0,2\nhist time\nstep 200"))
        << a.error();
    const odec::HistorySet& hs = a.model.histories;
    ASSERT_EQ(hs.sample_steps.size(), 8u);
    EXPECT_EQ(hs.items[0].first, 0);
    EXPECT_EQ(hs.items[2].first, 4);
    EXPECT_EQ(hs.items[2].values.size(), 4u);
    EXPECT_EQ(hs.items[2].at(3), nullptr);
    ASSERT_NE(hs.items[3].at(4), nullptr);
    EXPECT_NEAR(*hs.items[3].at(4), 0.025, 1e-15); // the time of step 250
    const std::string report = "hist list\nprint hist 1 2 3 4\nhist write 1 3 4 file '" + at("h.csv") +
                               "'\nhist write 2 vs 4 file '" + at("vs.csv") + "'\n";
    std::string out_a;
    {
        const size_t from = a.out.str().size();
        ASSERT_TRUE(a.run(report)) << a.error();
        out_a = a.out.str().substr(from);
    }
    // Blank where a history had not been made: no 'nan', in the table or the file.
    EXPECT_EQ(out_a.find("nan"), std::string::npos) << out_a;
    EXPECT_NE(out_a.find("   3         4          250  zdis (0.25,0,2) block 2\n"), std::string::npos) << out_a;
    const std::string csv = read_bytes(at("h.csv")), vs = read_bytes(at("vs.csv"));
    EXPECT_NE(csv.find("\n200,"), std::string::npos) << csv;
    EXPECT_NE(csv.find(",,\n"), std::string::npos) << csv; // step 200: histories 3 and 4 empty
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 9);
    EXPECT_EQ(std::count(vs.begin(), vs.end(), '\n'), 5); // only the rows where history 4 has a value
    EXPECT_EQ(vs.find("nan"), std::string::npos) << vs;
    EXPECT_NE(out_a.find("wrote 4 samples of 1 histories"), std::string::npos) << out_a;

    ASSERT_TRUE(a.run("save '" + at("mid") + "'")) << a.error();
    Session b;
    b.interp.quiet = false;
    b.interp.echo = false;
    ASSERT_TRUE(b.run("restore '" + at("mid") + "'")) << b.error();
    const std::string csv_a = csv, vs_a = vs;
    const size_t from = b.out.str().size();
    ASSERT_TRUE(b.run(report)) << b.error();
    EXPECT_EQ(b.out.str().substr(from), out_a);
    EXPECT_EQ(read_bytes(at("h.csv")), csv_a);
    EXPECT_EQ(read_bytes(at("vs.csv")), vs_a);
    for (size_t k = 0; k < hs.items.size(); ++k) {
        EXPECT_EQ(b.model.histories.items[k].first, hs.items[k].first);
        EXPECT_EQ(std::memcmp(b.model.histories.items[k].values.data(), hs.items[k].values.data(),
                              hs.items[k].values.size() * sizeof(double)),
                  0);
    }
    // Both go on the same, and a history made after the restore starts with the next sample.
    ASSERT_TRUE(a.run("step 100\nhist ydis 0,0,1\nstep 100")) << a.error();
    ASSERT_TRUE(b.run("step 100\nhist ydis 0,0,1\nstep 100")) << b.error();
    EXPECT_EQ(b.model.histories.items[4].first, 10);
    for (size_t k = 0; k < hs.items.size(); ++k) {
        EXPECT_EQ(b.model.histories.items[k].values, hs.items[k].values) << k;
    }
    // 'reset hist' starts every history afresh, together.
    ASSERT_TRUE(b.run("reset hist\nstep 50")) << b.error();
    for (const odec::History& h : b.model.histories.items) {
        EXPECT_EQ(h.first, 0);
        EXPECT_EQ(h.values.size(), 1u);
    }
    for (const char* f : {"mid.sav", "h.csv", "vs.csv"}) std::remove(at(f).c_str());
    rmdir(dir.c_str());
}

TEST(History, OlderFilesGiveUpTheirNaNs) {
    // A format 6 file: a brick toppling off a base, histories 3 and 4 made at step 2000 of 4000
    // (a NaN for each of the 40 samples before them), and the brick's turn kept as the sum of
    // its spin over the steps (about y alone: exact for this planar motion).
    const std::string file = std::string(ODEC_SOURCE_DIR) + "/tests/fuzz/regressions/restore/toppling-v6.sav";
    const std::string bytes = read_bytes(file);
    std::uint32_t format = 0;
    ASSERT_GT(bytes.size(), 16u);
    std::memcpy(&format, &bytes[12], 4);
    ASSERT_EQ(format, 6u);
    Session s;
    ASSERT_TRUE(s.run("restore '" + file + "'")) << s.error();
    const odec::Model& m = s.model;
    const odec::HistorySet& hs = m.histories;
    ASSERT_EQ(hs.sample_steps.size(), 80u);
    ASSERT_EQ(hs.items.size(), 4u);
    EXPECT_EQ(hs.items[1].first, 0);
    EXPECT_EQ(hs.items[2].first, 40);
    EXPECT_EQ(hs.items[3].first, 40);
    EXPECT_EQ(hs.items[3].values.size(), 40u);
    EXPECT_NEAR(hs.items[3].values.front(), 0.205, 1e-13); // the time of step 2050
    for (const odec::History& h : hs.items) {
        for (double v : h.values) EXPECT_TRUE(std::isfinite(v));
    }
    // The brick was never reset: its reference orientation is the one it was made with.
    const int b = m.block_index(2);
    ASSERT_GE(b, 0);
    EXPECT_LT((m.blocks.ref_orientation[b].coeffs() - odec::Quat::Identity().coeffs()).norm(), 1e-12);
    const Vec3 turn = odec::rotation_since_reset(m, b);
    EXPECT_GT(turn.norm(), 0.01);
    EXPECT_LT(std::abs(turn.x()) + std::abs(turn.z()), 1e-9 * turn.norm());
    // It goes on, and saves as the present format.
    ASSERT_TRUE(s.run("step 100")) << s.error();
    EXPECT_EQ(hs.sample_steps.size(), 82u);
    EXPECT_EQ(hs.items[3].values.size(), 42u);
}

TEST(History, AFailingFishHistoryStopsTheRunAndSaysWhy) {
    Session s;
    ASSERT_TRUE(s.run("config dyn\npoly brick -1 1 -1 1 -1 1\nprop mat=1 dens=1000\nset dt 1e-3\nhist ncyc 10\n"
                      "hist unbal\nhist xdis 1,0,0\n"
                      "def load_ratio\n  if step > 25 then\n    load_ratio = 1 / (step - step)\n  else\n    load_ratio = step\n  endif\nend\n"
                      "hist @load_ratio"))
        << s.error();
    EXPECT_FALSE(s.run("step 50"));
    EXPECT_EQ(s.error(), "t.dat:1:1: error: history 3 (@load_ratio) failed at step 30, which stands without its "
                         "sample: t.dat:10:20: error: division by zero (integer)\n"
                         "        load_ratio = 1 / (step - step)\n"
                         "                       ^\n"
                         "  in 'load_ratio', sampled by history 3\n"
                         "  see 'help fish'\n"
                         "\n"
                         "    step 50\n"
                         "    ^~~~\n"
                         "  see 'help step'\n");
    // The step that ran stands; no history has its sample, each has the two before.
    const odec::HistorySet& hs = s.model.histories;
    EXPECT_EQ(s.model.step, 30);
    EXPECT_EQ(hs.sample_steps, (std::vector<long>{10, 20}));
    for (const odec::History& h : hs.items) EXPECT_EQ(h.values.size(), 2u);
    EXPECT_EQ(hs.items[2].values, (std::vector<double>{10, 20}));
    // The session goes on: with the function mended the run continues from there.
    s.err.str("");
    ASSERT_TRUE(s.run("def load_ratio\n  load_ratio = 0.5\nend\nstep 20")) << s.error();
    EXPECT_EQ(hs.sample_steps, (std::vector<long>{10, 20, 40, 50}));
    EXPECT_EQ(hs.items[2].values, (std::vector<double>{10, 20, 0.5, 0.5}));
    // What is not a number is refused too, named.
    EXPECT_FALSE(s.run("def load_ratio\n  load_ratio = 'high'\nend\nstep 10"));
    EXPECT_NE(s.error().find("error: history 3 (@load_ratio) failed at step 60, which stands without its sample: "
                             "'@load_ratio' is a string, not a number"),
              std::string::npos)
        << s.error();
    EXPECT_EQ(hs.sample_steps.size(), 4u);
    // True and false record 1 and 0.
    s.err.str("");
    ASSERT_TRUE(s.run("def load_ratio\n  load_ratio = step > 65\nend\nstep 10")) << s.error();
    EXPECT_EQ(hs.items[2].values.back(), 1.0);
}

TEST(History, ListAndWriteTakeNoSettings) {
    Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nhist unbal")) << s.error();
    EXPECT_FALSE(s.run("hist list ncyc 5"));
    EXPECT_NE(s.error().find("error: 'ncyc' does not go with 'list': give it in a 'history' of its own"),
              std::string::npos)
        << s.error();
    EXPECT_FALSE(s.run("hist write 1 file 'x.csv' ncyc 5"));
    EXPECT_NE(s.error().find("error: 'ncyc' does not go with 'write'"), std::string::npos) << s.error();
    EXPECT_EQ(s.model.histories.ncyc, 10);
}

namespace {

// A history of a point or a zone of a block that is zoned, or zoned again, follows the point to
// the block's new gridpoint and zone nearest where the point is now. A rigid block's point read
// the frozen rigid motion after 'gen' (velocity and acceleration of the last rigid step, for
// ever), and a finer 'gen' of a deformable block left its histories reading 0.
TEST(History, PointAndZoneHistoriesFollowTheirBlockWhenItIsZoned) {
    odec::test::Session s;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 -1 0\npoly brick 0 1 0 1 0 1\nprop mat=1 dens=2000 ymod=1e9 prat=0.25\n"
                      "prop jmat=1 jkn=1e9 jks=1e9 jfric=40\nfix range z -1 0\ngrav 0 0 -10\n"
                      "hist zvel 0.5,0.5,1\nstep 20\ngen edge 0.5 range z 0 1\nhist szz 0.5,0.5,0.5"))
        << s.error();
    const auto& items = s.model.histories.items;
    ASSERT_EQ(items.size(), 2u);
    const int top = s.model.block_index(2);
    auto on_top = [&](int gp) {
        for (int z = 0; z < s.model.zones.size(); ++z) {
            if (s.model.zones.block[z] != top) continue;
            for (int q : s.model.zones.gp[z]) {
                if (q == gp) return true;
            }
        }
        return false;
    };
    ASSERT_GE(items[0].gridpoint, 0);
    EXPECT_TRUE(on_top(items[0].gridpoint));
    EXPECT_LT((s.model.gridpoints.pos[items[0].gridpoint] - Vec3(0.5, 0.5, 1)).norm(), 0.25);
    // Sampled every step from here: the velocity of a settling continuum, not one frozen number.
    ASSERT_TRUE(s.run("hist ncyc 1\nstep 5")) << s.error();
    const std::vector<double>& v = items[0].values;
    ASSERT_GE(v.size(), 5u);
    EXPECT_NE(v[v.size() - 1], v[v.size() - 2]);
    EXPECT_NE(v[v.size() - 2], v[v.size() - 3]);
    // Zoned again, finer: both histories go on reading their block, not 0.
    ASSERT_TRUE(s.run("gen edge 0.25 range z 0 1\nstep 10")) << s.error();
    ASSERT_GE(items[0].gridpoint, 0);
    EXPECT_TRUE(on_top(items[0].gridpoint));
    ASSERT_GE(items[1].zone, 0);
    EXPECT_EQ(s.model.zones.block[items[1].zone], top);
    EXPECT_NE(items[1].values.back(), 0.0);
}

} // namespace
