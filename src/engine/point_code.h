// A point in fourteen bytes: three 32-bit integers sharing one binary exponent, to within half
// a unit of 2^-31 of the power of two above its largest coordinate (5e-10 of its size or
// better). The contact set keeps its sub-contacts' points so (ContactSet::sub_point): they are
// made anew from the geometry at every refresh and fixed between refreshes. A code decodes to
// the same bits every time, by integer products with a power of two, and a decoded point codes
// to the same code again.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <Eigen/Dense>

namespace odec {

struct __attribute__((packed)) PointCode {
    std::int32_t m[3] = {0, 0, 0};
    std::int16_t e = 0; // the point is m * 2^(e - 31)
    bool operator==(const PointCode& o) const { return m[0] == o.m[0] && m[1] == o.m[1] && m[2] == o.m[2] && e == o.e; }
};
static_assert(sizeof(PointCode) == 14, "a point code is fourteen bytes");

// The exponents a code may have: points nearer the origin than 2^-900 m are the origin.
constexpr int kPointCodeMinExponent = -899;
constexpr int kPointCodeMaxExponent = 1024;

namespace point_code_detail {
// 2^k, for k within the normal doubles' exponents.
inline double power_of_two(int k) {
    const std::uint64_t bits = static_cast<std::uint64_t>(k + 1023) << 52;
    double x;
    std::memcpy(&x, &bits, sizeof x);
    return x;
}
} // namespace point_code_detail

// The code of x (finite; a point that is not is coded as the origin).
inline PointCode encode_point(const Eigen::Vector3d& x) {
    using namespace point_code_detail;
    PointCode p;
    const double big = x.cwiseAbs().maxCoeff();
    if (!std::isfinite(big) || !(big >= power_of_two(kPointCodeMinExponent - 1))) return p;
    int e = 0;
    (void)std::frexp(big, &e); // big = f 2^e, 0.5 <= f < 1
    for (;;) {
        const double scale = power_of_two(31 - e);
        bool fits = true;
        long long q[3];
        for (int i = 0; i < 3; ++i) {
            q[i] = std::llround(x[i] * scale);
            if (e == kPointCodeMaxExponent) q[i] = std::clamp(q[i], -(1ll << 31) + 1, (1ll << 31) - 1); // within the doubles
            fits = fits && q[i] < (1ll << 31) && q[i] >= -(1ll << 31);
        }
        if (fits) {
            for (int i = 0; i < 3; ++i) p.m[i] = static_cast<std::int32_t>(q[i]);
            p.e = static_cast<std::int16_t>(e);
            return p;
        }
        ++e; // f rounded up to 1
    }
}

// The point of code p.
[[gnu::always_inline]] inline Eigen::Vector3d decode_point(const PointCode& p) {
    const double scale = point_code_detail::power_of_two(p.e - 31);
    return Eigen::Vector3d(p.m[0] * scale, p.m[1] * scale, p.m[2] * scale);
}

// A point code and five bits of its holder's in the same fourteen bytes: the exponent, biased
// by kPointCodeBias into 11 bits (it runs from -899 to 1024), shares its 16 bits with them (the
// contact set's sub-contacts keep their flags so: ContactSet::sub_point).
constexpr int kPointCodeBias = 1023;
struct __attribute__((packed)) TaggedPointCode {
    std::int32_t m[3] = {0, 0, 0};
    std::uint16_t et = kPointCodeBias; // exponent + kPointCodeBias in bits 0..10, the tag above
};
static_assert(sizeof(TaggedPointCode) == 14, "a tagged point code is fourteen bytes");
inline TaggedPointCode tagged_point(const PointCode& p, unsigned tag) {
    TaggedPointCode t;
    for (int i = 0; i < 3; ++i) t.m[i] = p.m[i];
    t.et = static_cast<std::uint16_t>(((p.e + kPointCodeBias) & 0x7FF) | ((tag & 31u) << 11));
    return t;
}
inline PointCode untagged_point(const TaggedPointCode& t) {
    PointCode p;
    for (int i = 0; i < 3; ++i) p.m[i] = t.m[i];
    p.e = static_cast<std::int16_t>((t.et & 0x7FF) - kPointCodeBias);
    return p;
}
inline unsigned point_tag(const TaggedPointCode& t) { return t.et >> 11; }
inline void set_point_tag(TaggedPointCode& t, unsigned tag) {
    t.et = static_cast<std::uint16_t>((t.et & 0x7FF) | ((tag & 31u) << 11));
}
// The point of tagged code t: the same bits as its untagged code's.
[[gnu::always_inline]] inline Eigen::Vector3d decode_point(const TaggedPointCode& t) {
    const double scale = point_code_detail::power_of_two((t.et & 0x7FF) - kPointCodeBias - 31);
    return Eigen::Vector3d(t.m[0] * scale, t.m[1] * scale, t.m[2] * scale);
}

// Whether p is a code encode_point can make (restore checks the codes it reads).
inline bool point_code_valid(const PointCode& p) {
    if (p.m[0] == 0 && p.m[1] == 0 && p.m[2] == 0) return p.e == 0;
    return p.e >= kPointCodeMinExponent && p.e <= kPointCodeMaxExponent;
}

} // namespace odec
