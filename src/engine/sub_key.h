// A sub-contact's key in four bytes. The key (ContactSet::sub_key) is a 63-bit number: a block
// vertex or a gridpoint with its side, or the crossing of two 31-bit edge labels
// (contact_detect.cpp). The keys of ordinary blocks (up to 64 vertices and 64 faces, 2^28
// vertices or gridpoints) fit a 32-bit code exactly; any other key is kept whole in a table
// beside the codes (KeyTable), the code its index there. Either way a code gives back the key
// it was made from, bit for bit.
//
// Code, by its two top bits:
//   00  a vertex or gridpoint: bit 29 of block b, bit 28 gridpoint, bits 0..27 its index
//   01  a crossing: two labels of 15 bits (the lower one above): bits 12..14 the label's three
//       flag bits (of block b, band, touch line), bits 0..11 its payload (an edge's number, a
//       face, or for a touch line its two faces, 6 bits each)
//   11  a key of the table: bits 0..29 its index
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace odec {

namespace sub_key_detail {
constexpr std::uint32_t kKindShift = 30;
constexpr std::uint32_t kPoint = 0, kCrossing = 1, kTable = 3;
constexpr std::int64_t kCrossingBit = std::int64_t{1} << 62;
constexpr std::int64_t kPointIndexLimit = std::int64_t{1} << 28;
constexpr std::uint32_t kTouchFlag = 1; // the lowest of a label's three flag bits

// A 31-bit label in 15 bits, when it fits.
inline bool short_label(std::int64_t label, std::uint32_t& out) {
    const std::uint32_t flags = static_cast<std::uint32_t>(label >> 28) & 7;
    const std::int64_t p = label & ((std::int64_t{1} << 28) - 1);
    std::int64_t q = p;
    if (flags & kTouchFlag) {
        const std::int64_t fa = p >> 14, fb = p & 0x3FFF;
        if (fa >= 64 || fb >= 64) return false;
        q = (fa << 6) | fb;
    } else if (p >= 4096) {
        return false;
    }
    out = (flags << 12) | static_cast<std::uint32_t>(q);
    return true;
}
inline std::int64_t long_label(std::uint32_t c) {
    const std::uint32_t flags = (c >> 12) & 7, q = c & 0xFFF;
    const std::int64_t p = (flags & kTouchFlag) ? (static_cast<std::int64_t>(q >> 6) << 14) | (q & 63) : q;
    return (static_cast<std::int64_t>(flags) << 28) | p;
}
} // namespace sub_key_detail

// The 32-bit code of a key that fits one (not a table's), or false.
inline bool short_key_code(std::int64_t key, std::uint32_t& code) {
    using namespace sub_key_detail;
    if (key < 0) return false;
    if (key & kCrossingBit) {
        if (key >> 63) return false;
        const std::int64_t lo = (key >> 31) & 0x7FFFFFFF, hi = key & 0x7FFFFFFF;
        std::uint32_t cl, ch;
        if (!short_label(lo, cl) || !short_label(hi, ch)) return false;
        code = (kCrossing << kKindShift) | (cl << 15) | ch;
        return true;
    }
    const std::int64_t index = key & ((std::int64_t{1} << 60) - 1);
    if (index >= kPointIndexLimit) return false;
    const std::uint32_t gp = static_cast<std::uint32_t>((key >> 60) & 1), of_b = static_cast<std::uint32_t>((key >> 61) & 1);
    code = (of_b << 29) | (gp << 28) | static_cast<std::uint32_t>(index);
    return true;
}

// Whether code is an index into a table of whole keys.
inline bool key_code_in_table(std::uint32_t code) { return (code >> sub_key_detail::kKindShift) == sub_key_detail::kTable; }
inline std::uint32_t table_key_code(std::size_t index) {
    return (sub_key_detail::kTable << sub_key_detail::kKindShift) | static_cast<std::uint32_t>(index);
}
inline std::size_t key_code_index(std::uint32_t code) { return code & ((1u << sub_key_detail::kKindShift) - 1); }
// The largest index a table code can hold, plus one.
constexpr std::size_t kKeyTableLimit = std::size_t{1} << sub_key_detail::kKindShift;

// The side (ContactSet::key_side) of the key of a code short_key_code made: a crossing, or a
// vertex (0, 1) or gridpoint (3, 4) of block a or b.
inline int short_code_side(std::uint32_t code) {
    using namespace sub_key_detail;
    if ((code >> kKindShift) == kCrossing) return 2;
    const int of_b = static_cast<int>((code >> 29) & 1);
    return (code >> 28) & 1 ? 3 + of_b : of_b;
}

// The key of a code short_key_code made.
inline std::int64_t key_of_short_code(std::uint32_t code) {
    using namespace sub_key_detail;
    if ((code >> kKindShift) == kCrossing) {
        const std::int64_t lo = long_label((code >> 15) & 0x7FFF), hi = long_label(code & 0x7FFF);
        return kCrossingBit | (lo << 31) | hi;
    }
    return (static_cast<std::int64_t>((code >> 28) & 3) << 60) | (code & (kPointIndexLimit - 1));
}

// The keys that no short code holds, by index (their codes: table_key_code). Entries of
// sub-contacts that are gone stay until there are more of them than live ones
// (ContactSet::compact_key_table).
struct KeyTable {
    std::vector<std::int64_t> keys;
    std::size_t live = 0; // entries in use at the last compaction
};

} // namespace odec
