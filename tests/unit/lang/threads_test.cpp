// The cycle's threads (engine/parallel.h): the same bits with 1, 2 and 4 threads.
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <string>
#include <unistd.h>
#include <vector>

#include "engine/clump.h"
#include "engine/parallel.h"
#include "test_util.h"

namespace {

using odec::test::Session;

struct Result {
    std::vector<std::vector<double>> histories;
    std::string save;
};

// A model saved in `base` (built by `script`, which saves it there), restored and run for
// `steps` on each number of threads: every run must give the histories and save file of the
// first, bit for bit (the stage timings, the one thing that differs between runs, aside).
void same_bits(const std::string& script, int steps, const std::vector<int>& threads,
               const std::function<void(const odec::Model&)>& check_model) {
    char tmpl[] = "/tmp/odec-threads-XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    const std::string dir = tmpl, base = dir + "/base.sav", file = dir + "/run.sav";
    {
        Session s;
        s.check_save_at_end = false;
        ASSERT_TRUE(s.run(script + "\nsave '" + base + "'")) << s.error();
        check_model(s.model);
    }
    Result first;
    for (size_t k = 0; k < threads.size(); ++k) {
        SCOPED_TRACE(threads[k]);
        Session s;
        s.check_save_at_end = false;
        ASSERT_TRUE(s.run("restore '" + base + "'\nset threads " + std::to_string(threads[k]) + "\nstep " +
                          std::to_string(steps)))
            << s.error();
        s.model.profile = odec::Profile();
        ASSERT_TRUE(s.run("save '" + file + "'")) << s.error();
        Result r;
        for (const auto& h : s.model.histories.items) r.histories.push_back(h.values);
        r.save = odec::test::read_bytes(file);
        if (k == 0) {
            first = r;
            continue;
        }
        EXPECT_EQ(r.histories, first.histories);
        EXPECT_TRUE(r.save == first.save) << "the save files differ";
    }
    std::remove(file.c_str());
    std::remove(base.c_str());
    rmdir(dir.c_str());
    odec::set_thread_count(odec::default_thread_count());
}

// A Mohr-Coulomb cube of about 50,000 zones and 9,000 gridpoints (above the sizes the loops
// need to be split), pressed at a steady velocity under gravity with adaptive damping (whose power
// sums are reduced across the threads), 60 steps, with the energy account (summed by chunk).
TEST(Threads, SameBitsWithOneTwoAndFourThreads) {
    same_bits("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2500 k=6.7e9 g=4e9 coh=2e5 fric=30 ten=1e5\n"
              "change cons=2\ngen edge 0.045\ngrav 0 0 -10\ndamp auto\n"
              "bound zvel 0 range z -0.001 0.001\nbound zvel -0.02 range z 0.999 1.001\n"
              "hist zreaction range z 0.999 1.001\nhist xdis 1,0.5,0.5\nhist ncyc 5\n"
              "set energy on\nhist energy plastic\nhist energy damping\nhist energy error",
              60, {1, 2, 4}, [](const odec::Model& m) {
                  EXPECT_GT(m.zones.size(), odec::kParallelMinZones);
                  EXPECT_GT(m.gridpoints.size(), odec::kParallelMinItems);
              });
}

// A cable pulled out of a zoned block: its grout gives its forces to the gridpoints in cable order
// while the zones add theirs on the threads.
TEST(Threads, CableInZonesSameBitsWithOneTwoAndFourThreads) {
    same_bits("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2500 k=6.7e9 g=4e9\ngen edge 0.045\n"
              "bound zvel 0 range z -0.001 0.001\n"
              "prop mat=2 cb_area=1e-4 cb_e=2e11 cb_kbond=1e8 cb_sbond=1e4 cb_yield=1e5\n"
              "cable 0.5,0.5,1.2 0.5,0.5,0.1 seg 11 prop 2\ncable id 1 node 1 velocity 0,0,0.05\n"
              "hist ncyc 5\nhist cable_force 0.5,0.5,0.9\nhist cable_grout 0.5,0.5,0.5\nhist zdis 0.5,0.5,1",
              60, {1, 2, 4}, [](const odec::Model& m) {
                  EXPECT_GT(m.zones.size(), odec::kParallelMinZones);
                  EXPECT_EQ(m.cables.size(), 1);
              });
}

TEST(Threads, LinerOnZonesSameBitsWithOneTwoAndFourThreads) {
    same_bits("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2500 k=6.7e9 g=4e9\ngen edge 0.045\n"
              "bound zvel 0 range z -0.001 0.001\ngrav 0 0 -10\n"
              "prop mat=2 li_e=30e9 li_nu=0.2 li_thick=0.1 li_dens=2500 li_kn=1e10 li_ks=1e10 li_ncut=1e3 li_scoh=1e4 li_sfric=30\n"
              "liner range z 0.999 1.001 prop 2\n"
              "hist ncyc 5\nhist liner_nx 0.5,0.5,1\nhist liner_mx 0.3,0.3,1\nhist zdis 0.5,0.5,1",
              60, {1, 2, 4}, [](const odec::Model& m) {
                  EXPECT_GT(m.zones.size(), odec::kParallelMinZones);
                  EXPECT_EQ(m.liners.size(), 1);
              });
}

// Rigid blocks: a 22 m cube cut into 10,648 blocks by three joint sets (about 30,000 contacts,
// above the size the contact loop needs to be split), settling under gravity in static mode
// (whose block masses the contact update sums too), 30 steps, with the energy account.
TEST(Threads, RigidBlocksSameBitsWithOneAndTwoThreads) {
    same_bits("poly brick 0 22 0 22 0 22\njset dip 0 dd 0 spacing 1 number 21 origin 0,0,11\n"
              "jset dip 90 dd 90 spacing 1 number 21 origin 11,0,0\njset dip 90 dd 0 spacing 1 number 21 origin 0,11,0\n"
              "prop mat=1 dens=2600\nprop jmat=1 jkn=1e10 jks=5e9 jfric=30\nfix range z 0 1\ngrav 0 0 -10\n"
              "hist ncyc 5\nhist zdis 11.5,11.5,21.5\nhist unbal\nset energy on\nhist energy slip\n"
              "hist energy error\nstep 1",
              30, {1, 2}, [](const odec::Model& m) {
                  EXPECT_EQ(m.blocks.size(), 22 * 22 * 22);
                  EXPECT_GT(m.contacts.size(), odec::kParallelMinItems);
              });
}

// Contacts made and rebuilt on the threads: 256 cubes in four layers, apart at first (no
// contact), thrown down at 5 to 20 m/s layer by layer (dynamic mode) onto a fixed base, so the
// layers crash into each other and 256 new contacts form (their ids given in the same order
// whatever the threads) while every refresh rebuilds hundreds of contacts; 500 steps.
TEST(Threads, ContactsBuiltOnTheThreadsGiveTheSameBits) {
    std::string script = "config dyn\npoly brick -1 9 -1 9 -1 -0.05\n";
    for (int k = 0; k < 4; ++k) {
        for (int i = 0; i < 8; ++i) {
            for (int j = 0; j < 8; ++j) {
                char line[128];
                std::snprintf(line, sizeof line, "poly brick %g %g %g %g %g %g\n", i + 0.05, i + 0.95, j + 0.05, j + 0.95,
                              k * 1.0, k + 0.9);
                script += line;
            }
        }
    }
    script += "prop mat=1 dens=2600\nprop jmat=1 jkn=1e8 jks=5e7 jfric=30\nfix range z -1 -0.05\ngrav 0 0 -10\n"
              "ini zvel -5 range z 0 0.9\nini zvel -10 range z 1 1.9\nini zvel -15 range z 2 2.9\n"
              "ini zvel -20 range z 3 3.9\nhist ncyc 10\nhist zvel 4.5,4.5,3.45\nhist zdis 0.5,0.5,0.45";
    same_bits(script, 500, {1, 2, 4}, [](const odec::Model& m) {
        EXPECT_EQ(m.blocks.size(), 257);
        EXPECT_EQ(m.contacts.size(), 0); // apart: every contact is made while cycling
    });
}

TEST(Threads, SetThreadsIsCheckedAndShown) {
    Session s;
    s.check_save_at_end = false;
    EXPECT_FALSE(s.run("set threads 0"));
    EXPECT_NE(s.error().find("set threads 0"), std::string::npos) << s.error();
    EXPECT_FALSE(s.run("set threads 1025"));
    EXPECT_FALSE(s.run("set threads two"));
    s.interp.quiet = false;
    ASSERT_TRUE(s.run("set threads 3\nprint info")) << s.error();
    if (odec::threads_available()) {
        EXPECT_EQ(odec::thread_count(), 3);
        EXPECT_NE(s.out.str().find("threads:    3"), std::string::npos) << s.out.str();
    }
    odec::set_thread_count(odec::default_thread_count());
}

} // namespace

// Clumps (engine/clump.h): 128 L-shaped blocks, each two convex pieces moving as one rigid body,
// in two layers, thrown down spinning onto a fixed base (dynamic mode, energy account on): their
// forces summed about each clump's centroid and their pieces placed give the same bits whatever
// the threads; 400 steps.
TEST(Threads, ClumpsSameBitsWithOneTwoAndFourThreads) {
    std::string script = "config dyn\npoly brick -1 17 -1 9 -1 -0.05\n";
    for (int k = 0; k < 2; ++k) {
        for (int i = 0; i < 8; ++i) {
            for (int j = 0; j < 8; ++j) {
                const double x = 2 * i + 0.05, y = j + 0.05, z = 3.5 * k;
                char line[1024];
                std::snprintf(line, sizeof line,
                              "poly prism a (%g,%g,%g) (%g,%g,%g) (%g,%g,%g) (%g,%g,%g) (%g,%g,%g) (%g,%g,%g) "
                              "b (%g,%g,%g) (%g,%g,%g) (%g,%g,%g) (%g,%g,%g) (%g,%g,%g) (%g,%g,%g)\n",
                              x, y, z, x + 1.8, y, z, x + 1.8, y, z + 0.9, x + 0.9, y, z + 0.9, x + 0.9, y, z + 2.7, x, y,
                              z + 2.7, x, y + 0.9, z, x + 1.8, y + 0.9, z, x + 1.8, y + 0.9, z + 0.9, x + 0.9, y + 0.9,
                              z + 0.9, x + 0.9, y + 0.9, z + 2.7, x, y + 0.9, z + 2.7);
                script += line;
            }
        }
    }
    script += "prop mat=1 dens=2600\nprop jmat=1 jkn=1e8 jks=5e7 jfric=30\nfix range z -1 -0.05\ngrav 0 0 -10\n"
              "ini zvel -5 yrvel 0.5 range z 0 3\nini zvel -8 xrvel -0.3 range z 3.5 7\nset energy on\n"
              "hist ncyc 10\nhist zvel 1,0.5,0.5\nhist zdis 15,7.5,4\nhist energy error";
    same_bits(script, 400, {1, 2, 4}, [](const odec::Model& m) {
        EXPECT_EQ(m.blocks.size(), 1 + 2 * 128);
        EXPECT_EQ(odec::list_clumps(m.blocks).size(), 128);
    });
}
