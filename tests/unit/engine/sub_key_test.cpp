// The sub-contacts' keys in four bytes (sub_key.h): every key comes back whole, those of
// ordinary blocks from their code alone, any other through the table, which gives back the
// entries of sub-contacts that are gone.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "engine/contact.h"

using odec::ContactSet;

namespace {

std::int64_t corner(int side, std::int64_t vertex) { return (static_cast<std::int64_t>(side) << 61) | vertex; }
std::int64_t crossing(std::int64_t l1, std::int64_t l2) {
    const std::int64_t lo = std::min(l1, l2), hi = std::max(l1, l2);
    return (std::int64_t{1} << 62) | (lo << 31) | hi;
}
// Edge, band and touch-line labels as detection makes them (contact_detect.cpp).
std::int64_t edge(int side, int i, int j, int nv) { return (side ? 1 << 30 : 0) | (std::min(i, j) * nv + std::max(i, j)); }
std::int64_t band(int side, int face) { return (side ? 1 << 30 : 0) | (1 << 29) | face; }
std::int64_t touch(int fa, int fb) { return (1 << 28) | ((fa & 0x3FFF) << 14) | (fb & 0x3FFF); }

} // namespace

TEST(SubKey, OrdinaryKeysComeBackFromTheirCodesAlone) {
    ContactSet cs;
    std::vector<std::int64_t> keys;
    for (int side = 0; side < 2; ++side) {
        for (std::int64_t v : {0L, 1L, 7L, 63L, 1000L, (1L << 28) - 1}) keys.push_back(corner(side, v));
        for (int gp : {0, 5, 123456, (1 << 28) - 1}) keys.push_back(odec::gridpoint_sub_key(side, gp));
    }
    // Blocks of up to 64 vertices and 64 faces: every pair of their labels.
    for (int nv : {4, 8, 20, 64}) {
        for (int i = 0; i < nv; i += 3) {
            for (int j = i + 1; j < nv; j += 5) {
                keys.push_back(crossing(edge(0, i, j, nv), edge(1, j - 1, j, nv)));
                keys.push_back(crossing(edge(1, i, j, nv), band(0, j % 64)));
                keys.push_back(crossing(touch(i % 64, j % 64), edge(0, i, j, nv)));
                keys.push_back(crossing(band(1, i), touch(63, j % 64)));
            }
        }
    }
    for (const std::int64_t key : keys) cs.push_key(key);
    EXPECT_TRUE(cs.key_table.keys.empty());
    ASSERT_EQ(cs.sub_keys(), keys);
    for (int k = 0; k < cs.n_subs(); ++k) {
        EXPECT_EQ(cs.sub_side(k), ContactSet::key_side(keys[k])) << k;
        EXPECT_EQ(cs.sub_vertex(k), ContactSet::key_vertex(keys[k])) << k;
    }
}

TEST(SubKey, AnyOtherKeyComesBackThroughTheTable) {
    ContactSet cs;
    std::vector<std::int64_t> keys = {
        corner(1, std::int64_t{1} << 28), odec::gridpoint_sub_key(1, std::numeric_limits<int>::max()),
        crossing(edge(0, 10, 90, 100), edge(1, 0, 1, 8)), // a block of 100 vertices
        crossing(touch(64, 0), band(0, 3)), crossing(band(1, 4096), band(0, 1)),
        crossing(touch(0x3FFF, 0x3FFF), (std::int64_t{1} << 31) - 1), -1, std::numeric_limits<std::int64_t>::min(),
        std::numeric_limits<std::int64_t>::max()};
    std::mt19937_64 rng(19);
    for (int i = 0; i < 5000; ++i) keys.push_back(static_cast<std::int64_t>(rng()));
    for (const std::int64_t key : keys) cs.push_key(key);
    ASSERT_EQ(cs.sub_keys(), keys);
    EXPECT_GE(cs.key_table.keys.size(), 9u);
    for (int k = 0; k < cs.n_subs(); ++k) {
        EXPECT_EQ(cs.sub_side(k), ContactSet::key_side(keys[k])) << k;
        EXPECT_EQ(cs.sub_vertex(k), ContactSet::key_vertex(keys[k])) << k;
    }
    // Most sub-contacts gone (every tenth kept): the table keeps the live keys alone, in order.
    std::vector<std::int64_t> kept;
    int w = 0;
    for (int k = 0; k < cs.n_subs(); k += 10) {
        cs.sub_code[w++] = cs.sub_code[k];
        kept.push_back(keys[k]);
    }
    cs.sub_code.resize(w);
    cs.compact_key_table();
    EXPECT_EQ(cs.sub_keys(), kept);
    size_t in_table = 0;
    for (const std::uint32_t code : cs.sub_code) in_table += odec::key_code_in_table(code);
    EXPECT_EQ(cs.key_table.keys.size(), in_table);
    EXPECT_EQ(cs.key_table.live, in_table);
    // A key set anew takes a code of its own.
    cs.set_key(0, corner(0, 3));
    EXPECT_EQ(cs.sub_key(0), corner(0, 3));
}
