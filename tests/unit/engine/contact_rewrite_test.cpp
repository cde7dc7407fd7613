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
    EXPECT_EQ(a.sub_keys(), f.sub_keys());
    EXPECT_EQ(a.joint, f.joint);
    // The old contacts kept their ids, the new ones took the next ones: all different.
    std::vector<int> ids(a.id.begin(), a.id.end());
    std::sort(ids.begin(), ids.end());
    EXPECT_TRUE(std::adjacent_find(ids.begin(), ids.end()) == ids.end());
    EXPECT_EQ(ids.back(), a.next_id - 1);
    int mismatched = 0;
    for (int c = 0; c < a.size(); ++c) {
        if ((a.normal(c) - f.normal(c)).norm() > 1e-12 || std::abs(a.gap[c] - f.gap[c]) > 1e-12) ++mismatched;
    }
    for (int k = 0; k < a.n_subs(); ++k) {
        // The same points and areas; the closures of the old ones carried over (the same to a
        // hair: each column kept its shape).
        if (std::abs(a.sub_area[k] - f.sub_area[k]) > 1e-12 || (a.sub_point_local(k) - f.sub_point_local(k)).norm() > 1e-12 ||
            std::abs(a.sub_un[k] - f.sub_un[k]) > 1e-12) {
            ++mismatched;
        }
    }
    EXPECT_EQ(mismatched, 0);
    // The arrays hold no more than an eighth over what they need.
    EXPECT_LE(a.sub_point.capacity(), a.sub_point.size() + a.sub_point.size() / 8 + 1024);
    EXPECT_LE(a.normal_code.capacity(), a.normal_code.size() + a.normal_code.size() / 8 + 1024);
    // The offsets, written anew below the old ones still to be read, the same.
    EXPECT_EQ(a.sub_offset.size(), static_cast<size_t>(a.size()) + 1);
    EXPECT_LE(a.sub_offset.capacity(), a.sub_offset.size() + a.sub_offset.size() / 8 + 1024);
}

// Two square prisms crossed edge to edge, 1 mm apart: their contact exists (within ctol) with
// no sub-contact. As the upper one lands, its edge crossing the lower's must be seen at once
// (no corner of either goes into the other: watched by the corners alone, the prism sank 5 mm
// before the next refresh and was thrown off, a run-away), and the refresh that gives the
// contact its crossing without changing which pairs are in contact must take it into the
// colouring of the contacts that carry sub-contacts: otherwise its force would be left out.
TEST(ContactRewrite, AContactThatStartsToCarryIsTakenIntoTheColouring) {
    Model m;
    set_material(m, 1, 2000);
    set_joint(m, 1, 1e9, 1e9, 30);
    m.gravity = Vec3(0, 0, -10);
    const double h = 0.5 * std::sqrt(2.0); // half the diagonal of a unit square
    // Below: its top edge along y at z = 0; above: its bottom edge along x, 1 mm higher.
    Polyhedron low = rotated(make_brick(-0.5, 0.5, -0.5, 0.5, -0.5, 0.5), Vec3::Zero(), Vec3::UnitY(), M_PI / 4);
    low.translate(Vec3(0, 0, -h));
    Polyhedron high = rotated(make_brick(-0.5, 0.5, -0.5, 0.5, -0.5, 0.5), Vec3::Zero(), Vec3::UnitX(), M_PI / 4);
    high.translate(Vec3(0, 0, h + 0.001));
    const int base = add_fixed(m, low);
    const int top = add_block(m, high, 0, -1, 1);
    ASSERT_EQ(prepare_cycle(m), "");
    const int c = contact_between(m, base, top);
    ASSERT_GE(c, 0);
    ASSERT_EQ(m.contacts.sub_offset[c], m.contacts.sub_offset[c + 1]); // apart: nothing to carry
    const CycleResult r = run_steps(m, 2000);
    ASSERT_EQ(r.message, "");
    ASSERT_EQ(r.steps, 2000);
    const ContactSet& cs = m.contacts;
    const int c2 = contact_between(m, base, top);
    ASSERT_GE(c2, 0);
    ASSERT_GT(cs.sub_offset[c2 + 1], cs.sub_offset[c2]);
    ASSERT_TRUE(cs.colored);
    EXPECT_NE(std::find(cs.color_order.begin(), cs.color_order.end(), c2), cs.color_order.end());
    // Held up by the crossing, closed by 60 um (2e4 N on the crossing's spring).
    EXPECT_GT(m.blocks.centroid[top].z(), h - 1e-4);
    EXPECT_LT(m.blocks.centroid[top].z(), h - 1e-5); // it did land
}
