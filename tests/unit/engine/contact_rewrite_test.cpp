// A pass that rebuilds every contact of a large model writes the set in place, a window of
// jobs at a time, opening gaps where a rebuilt contact outgrows its place or a new one comes
// in ahead of old state still to be read (contact_detect.cpp, Rewrite). Whatever the windows
// and gaps, the set must come out as a detection from scratch finds it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "contact_test_util.h"

using namespace odec;
using namespace odec::test;

namespace {

// n^3 unit cubes, those of column i along x shifted by i * spread (0: packed).
Model cubes(int n, double spread) {
    Model m;
    set_material(m, 1, 2700);
    set_joint(m, 1, 1e9, 1e9, 35);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double x = i * (1 + spread);
                add_block(m, make_brick(x, x + 1, j, j + 1, k, k + 1), 0, -1, 1);
            }
    return m;
}

} // namespace

TEST(ContactRewrite, APassRebuildingEveryContactFindsWhatAFreshDetectionFinds) {
    const int n = 12; // 1728 blocks, some 20,000 contacts: several windows of jobs
    // Apart along x by twice the tolerance: only the blocks of one column (one x) touch.
    Model moved = cubes(n, 0.1);
    ASSERT_EQ(prepare_cycle(moved), "");
    const int before = moved.contacts.size();
    Model fresh = cubes(n, 0.0);
    ASSERT_EQ(prepare_cycle(fresh), "");
    ASSERT_GT(fresh.contacts.size(), before + 5000);
    // Every block where the packed model has it, to the bit: the next pass finds it moved (more
    // than ctol / 2: a full pass), rebuilds every old contact and adds the contacts across x,
    // which come in between the old ones.
    BlockSet& s = moved.blocks;
    for (int b = 0; b < s.size(); ++b) {
        s.centroid[b] = fresh.blocks.centroid[b];
        s.shape[b] = fresh.blocks.shape[b];
        s.orientation[b] = fresh.blocks.orientation[b];
    }
    refresh_world_vertices(moved);
    const long detections = moved.contacts.n_detections;
    detect_contacts(moved);
    ASSERT_EQ(moved.contacts.n_detections, detections + 1);

    const ContactSet& a = moved.contacts;
    const ContactSet& f = fresh.contacts;
    ASSERT_EQ(a.size(), f.size());
    ASSERT_EQ(a.n_subs(), f.n_subs());
    ASSERT_EQ(a.sub_offset, f.sub_offset);
    EXPECT_EQ(a.block_a, f.block_a);
    EXPECT_EQ(a.block_b, f.block_b);
    EXPECT_EQ(a.sub_key, f.sub_key);
    EXPECT_EQ(a.sub_side, f.sub_side);
    EXPECT_EQ(a.jmat, f.jmat);
    // The old contacts kept their ids, the new ones took the next ones: all different.
    std::vector<int> ids = a.id;
    std::sort(ids.begin(), ids.end());
    EXPECT_TRUE(std::adjacent_find(ids.begin(), ids.end()) == ids.end());
    EXPECT_EQ(ids.back(), a.next_id - 1);
    int mismatched = 0;
    for (int c = 0; c < a.size(); ++c) {
        if ((a.normal[c] - f.normal[c]).norm() > 1e-12 || std::abs(a.gap[c] - f.gap[c]) > 1e-12) ++mismatched;
    }
    for (int k = 0; k < a.n_subs(); ++k) {
        // The same points and areas; the closures of the old ones carried over (the same to a
        // hair: each column kept its shape).
        if (std::abs(a.sub_area[k] - f.sub_area[k]) > 1e-12 || (a.sub_local[k] - f.sub_local[k]).norm() > 1e-12 ||
            std::abs(a.sub_un[k] - f.sub_un[k]) > 1e-12) {
            ++mismatched;
        }
    }
    EXPECT_EQ(mismatched, 0);
    // The arrays hold no more than an eighth over what they need.
    EXPECT_LE(a.sub_local.capacity(), a.sub_local.size() + a.sub_local.size() / 8 + 1024);
    EXPECT_LE(a.normal.capacity(), a.normal.size() + a.normal.size() / 8 + 1024);
}
