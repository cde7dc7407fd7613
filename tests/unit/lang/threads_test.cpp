// The cycle's threads (engine/parallel.h): the same bits with 1, 2 and 4 threads.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <unistd.h>
#include <vector>

#include "engine/parallel.h"
#include "test_util.h"

namespace {

using odec::test::Session;

// A Mohr-Coulomb cube of about 50,000 zones and 9,000 gridpoints (above the sizes the loops
// need to be split), pressed at a steady velocity under gravity with adaptive damping (whose power
// sums are reduced across the threads), saved after 60 steps (without the stage timings).
struct Result {
    std::vector<std::vector<double>> histories;
    std::string save;
};

// The model, zoned once and saved: each run restores it.
void build(const std::string& file) {
    Session s;
    s.check_save_at_end = false;
    ASSERT_TRUE(s.run("poly brick 0 1 0 1 0 1\nprop mat=1 dens=2500 k=6.7e9 g=4e9 coh=2e5 fric=30 ten=1e5\n"
                      "change cons=2\ngen edge 0.045\ngrav 0 0 -10\ndamp auto\n"
                      "bound zvel 0 range z -0.001 0.001\nbound zvel -0.02 range z 0.999 1.001\n"
                      "hist zreaction range z 0.999 1.001\nhist xdis 1,0.5,0.5\nhist ncyc 5\nsave '" + file + "'"))
        << s.error();
    EXPECT_GT(s.model.zones.size(), odec::kParallelMinZones);
    EXPECT_GT(s.model.gridpoints.size(), odec::kParallelMinItems);
}

Result run(int threads, const std::string& base, const std::string& file) {
    Session s;
    s.check_save_at_end = false;
    EXPECT_TRUE(s.run("restore '" + base + "'\nset threads " + std::to_string(threads) + "\nstep 60")) << s.error();
    // The stage timings are the one thing that differs between runs.
    s.model.profile = odec::Profile();
    EXPECT_TRUE(s.run("save '" + file + "'")) << s.error();
    Result r;
    for (const auto& h : s.model.histories.items) r.histories.push_back(h.values);
    r.save = odec::test::read_bytes(file);
    return r;
}

TEST(Threads, SameBitsWithOneTwoAndFourThreads) {
    char tmpl[] = "/tmp/odec-threads-XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    const std::string dir = tmpl;
    build(dir + "/base.sav");
    const Result one = run(1, dir + "/base.sav", dir + "/t1.sav");
    for (int n : {2, 4}) {
        SCOPED_TRACE(n);
        const Result many = run(n, dir + "/base.sav", dir + "/t" + std::to_string(n) + ".sav");
        ASSERT_EQ(many.histories.size(), one.histories.size());
        for (size_t k = 0; k < one.histories.size(); ++k) EXPECT_EQ(many.histories[k], one.histories[k]);
        EXPECT_TRUE(many.save == one.save) << "the save files differ";
    }
    for (int n : {1, 2, 4}) std::remove((dir + "/t" + std::to_string(n) + ".sav").c_str());
    std::remove((dir + "/base.sav").c_str());
    rmdir(dir.c_str());
    odec::set_thread_count(odec::default_thread_count());
}

// Rigid blocks: a 22 m cube cut into 10,648 blocks by three joint sets (about 30,000 contacts,
// above the size the contact loop needs to be split), settling under gravity in static mode
// (whose block masses the contact update sums too).
TEST(Threads, RigidBlocksSameBitsWithOneAndTwoThreads) {
    char tmpl[] = "/tmp/odec-threads-XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    const std::string dir = tmpl, base = dir + "/blocks.sav";
    {
        Session s;
        s.check_save_at_end = false;
        ASSERT_TRUE(s.run("poly brick 0 22 0 22 0 22\njset dip 0 dd 0 spacing 1 number 21 origin 0,0,11\n"
                          "jset dip 90 dd 90 spacing 1 number 21 origin 11,0,0\njset dip 90 dd 0 spacing 1 number 21 origin 0,11,0\n"
                          "prop mat=1 dens=2600\nprop jmat=1 jkn=1e10 jks=5e9 jfric=30\nfix range z 0 1\ngrav 0 0 -10\n"
                          "hist ncyc 5\nhist zdis 11.5,11.5,21.5\nhist unbal\nstep 1\nsave '" + base + "'"))
            << s.error();
        ASSERT_EQ(s.model.blocks.size(), 22 * 22 * 22);
        EXPECT_GT(s.model.contacts.size(), odec::kParallelMinItems);
    }
    std::vector<std::vector<double>> first;
    std::string first_save;
    for (int n : {1, 2}) {
        SCOPED_TRACE(n);
        Session s;
        s.check_save_at_end = false;
        ASSERT_TRUE(s.run("restore '" + base + "'\nset threads " + std::to_string(n) + "\nstep 30")) << s.error();
        s.model.profile = odec::Profile();
        const std::string file = dir + "/b" + std::to_string(n) + ".sav";
        ASSERT_TRUE(s.run("save '" + file + "'")) << s.error();
        std::vector<std::vector<double>> h;
        for (const auto& item : s.model.histories.items) h.push_back(item.values);
        const std::string bytes = odec::test::read_bytes(file);
        std::remove(file.c_str());
        if (n == 1) {
            first = h;
            first_save = bytes;
        } else {
            EXPECT_EQ(h, first);
            EXPECT_TRUE(bytes == first_save) << "the save files differ";
        }
    }
    std::remove(base.c_str());
    rmdir(dir.c_str());
    odec::set_thread_count(odec::default_thread_count());
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
