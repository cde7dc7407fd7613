// The broad phase (the cell grid that proposes candidate pairs) copes with any spread of
// finite coordinates: blocks far apart must not make the grid's cell count overflow.
#include <gtest/gtest.h>

#include <limits>

#include "contact_test_util.h"

using namespace odec;
using namespace odec::test;

namespace {

Polyhedron cube(double x, double y, double z) { return make_brick(x, x + 1, y, y + 1, z, z + 1); }

// A unit cube resting on a fixed one at the origin, plus unit cubes whose centroids are moved to
// `far` (the cube there is only an outline: far out, 1 m is below the resolution of a double).
Model pair_and_far_blocks(const std::vector<Vec3>& far) {
    Model m;
    set_material(m, 1, 1000);
    set_joint(m, 1, 1e7, 1e7, 30);
    add_fixed(m, cube(0, 0, 0));
    add_block(m, cube(0, 0, 1), 0, -1, 1);
    for (const Vec3& x : far) {
        const int b = add_block(m, cube(0, 0, 0), 0, -1, 1);
        m.blocks.centroid[b] = x;
    }
    m.geometry_changed = true;
    refresh_world_vertices(m);
    return m;
}

} // namespace

TEST(BroadPhase, BlocksTenThousandKilometresApart) {
    // 'poly brick 0 1 0 1 0 1' and 'poly brick 1e7 10000001 ...': the grid at the blocks' own
    // size would need ~1e20 cells; it used to overflow a long and throw std::length_error.
    Model m;
    set_material(m, 1, 1000);
    add_block(m, cube(0, 0, 0), 0, -1, 1);
    add_block(m, cube(1e7, 1e7, 1e7), 0, -1, 1);
    m.settings.dt_fixed = 1e-3;
    const CycleResult r = run_steps(m, 1);
    EXPECT_EQ(r.steps, 1);
    EXPECT_EQ(m.contacts.size(), 0);
}

TEST(BroadPhase, NearbyPairStillFoundAmongFarBlocks) {
    Model m = pair_and_far_blocks({Vec3(1e7, -1e7, 3e7), Vec3(-4e12, 0, 0), Vec3(0, 0, 1e15)});
    detect_contacts(m);
    ASSERT_EQ(m.contacts.size(), 1);
    EXPECT_GE(contact_between(m, 0, 1), 0);
}

TEST(BroadPhase, SpreadBeyondTheLargestDouble) {
    // ghi - glo overflows to infinity here; every coordinate is still finite.
    const double big = 0.9 * std::numeric_limits<double>::max();
    Model m = pair_and_far_blocks({Vec3(big, 0, 0), Vec3(-big, 0, 0), Vec3(0, -big, big), Vec3(big, big, -big)});
    detect_contacts(m);
    ASSERT_EQ(m.contacts.size(), 1);
    EXPECT_GE(contact_between(m, 0, 1), 0);
}
