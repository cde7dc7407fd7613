// The cell of a spatial hash grid that holds coordinate q (in cells): floor(q) as an integer,
// clamped to +-2^52 so that no coordinate, however far out or not a number, overflows the cast
// (NaN counts as the lowest cell). Points beyond the clamp share the end cells: a search there
// compares more points, and still finds the right ones.
#pragma once

#include <cmath>
#include <cstdint>

namespace odec {

inline std::int64_t grid_cell(double q) {
    constexpr double kMax = 4503599627370496.0; // 2^52
    if (!(q > -kMax)) return -static_cast<std::int64_t>(kMax);
    if (!(q < kMax)) return static_cast<std::int64_t>(kMax);
    return static_cast<std::int64_t>(std::floor(q));
}

// A hash of three cell indices (unsigned arithmetic: wraps, never overflows).
inline std::uint64_t grid_cell_hash(std::int64_t x, std::int64_t y, std::int64_t z) {
    return static_cast<std::uint64_t>(x) * 73856093ULL ^ static_cast<std::uint64_t>(y) * 19349663ULL ^
           static_cast<std::uint64_t>(z) * 83492791ULL;
}

} // namespace odec
