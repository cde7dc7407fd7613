// move_bytes_up and move_bytes_down (parallel.h): the same bytes as memmove, on any number of threads, for shifts
// from one byte to as long as a piece, and ranges from empty to many pieces long.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "engine/parallel.h"

namespace {

std::vector<char> pattern(std::size_t n) {
    std::vector<char> v(n);
    unsigned x = 12345;
    for (char& c : v) {
        x = x * 1103515245u + 12345u;
        c = static_cast<char>(x >> 16);
    }
    return v;
}

struct Case {
    std::size_t size, at, end, by;
};

// The bytes [at, end) of a patterned buffer moved up (or down) by `by` on 1 to 4 threads: the
// same bytes as memmove gives.
template <std::size_t N>
void expect_as_memmove(const Case (&cases)[N], bool up) {
    for (const Case& c : cases) {
        const std::vector<char> start = pattern(c.size);
        std::vector<char> want = start;
        std::memmove(want.data() + (up ? c.at + c.by : c.at - c.by), want.data() + c.at, c.end - c.at);
        for (int threads : {1, 2, 3, 4}) {
            std::vector<char> got = start;
            if (up) odec::move_bytes_up(got.data(), c.at, c.end, c.by, threads);
            else odec::move_bytes_down(got.data(), c.at, c.end, c.by, threads);
            EXPECT_TRUE(got == want) << (up ? "up" : "down") << ": size " << c.size << " at " << c.at << " end "
                                     << c.end << " by " << c.by << " threads " << threads;
        }
    }
}

constexpr std::size_t mb = std::size_t{1} << 20;

} // namespace

TEST(MoveBytes, SameBytesAsMemmoveOnAnyNumberOfThreads) {
    const Case cases[] = {
        {100, 10, 10, 5},                      // nothing to move
        {100, 10, 60, 7},                      // small: one piece
        {20 * mb, 3, 16 * mb + 5, 1},          // a byte up, several pieces
        {20 * mb, 0, 16 * mb, 24 * 1000 + 8},  // some thousand records up
        {24 * mb, 17, 16 * mb, 4 * mb - 1},    // by close to a piece of four
        {30 * mb, 1, 20 * mb, 9 * mb},         // by longer than a piece of four: fewer pieces
    };
    expect_as_memmove(cases, true);
}

TEST(MoveBytes, DownSameBytesAsMemmoveOnAnyNumberOfThreads) {
    const Case cases[] = {
        {100, 10, 10, 5},                           // nothing to move
        {100, 10, 60, 7},                           // small: one piece
        {20 * mb, 3, 16 * mb + 5, 1},               // a byte down, several pieces
        {20 * mb, 24 * 1000 + 8, 17 * mb, 24 * 1000 + 8}, // some thousand records down, to the start
        {24 * mb, 4 * mb, 20 * mb + 17, 4 * mb - 1},  // by close to a piece of four
        {30 * mb, 9 * mb + 1, 29 * mb, 9 * mb},     // by longer than a piece of four: fewer pieces
    };
    expect_as_memmove(cases, false);
}
