// Four doubles in one vector, for the engine's kernels that run several items per instruction
// (GCC's vector extensions: one AVX instruction per operation where a function is built for
// AVX2, two SSE2 instructions elsewhere). Each operation is IEEE's, lane by lane, as the scalar
// one: with -ffp-contract=off a kernel gives every lane the bits of the scalar code it mirrors.
#pragma once

#include <cstring>

namespace odec {
namespace simd {

// (Passed only between always-inline functions and lambdas of one file: no call at all sees their
// ABI, so the compilers' note on it is off: CMakeLists.txt, -Wno-psabi. A helper that takes or
// gives one must be inlined whatever the optimization: one built apart for the default target,
// called from a function's AVX2 version, would take and give it differently. Lambdas say so with
// ODEC_INLINE.)
#define ODEC_INLINE __attribute__((always_inline))
typedef double V4 __attribute__((vector_size(32)));
typedef long long M4 __attribute__((vector_size(32))); // what comparisons give: all ones or zero
typedef long long I4 __attribute__((vector_size(32))); // shuffle indices

[[gnu::always_inline]] inline V4 load4(const double* p) {
    V4 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
[[gnu::always_inline]] inline void store4(double* p, V4 v) { std::memcpy(p, &v, sizeof v); }
[[gnu::always_inline]] inline V4 splat(double x) { return V4{x, x, x, x}; }
// |x| lane by lane (std::abs: the sign bit cleared).
[[gnu::always_inline]] inline V4 abs4(V4 x) {
    const long long m = 0x7fffffffffffffffLL;
    return (V4)((M4)x & M4{m, m, m, m}); // (vector casts: the same bits)
}
// Lanes that are numbers and not infinite (|x| < inf, which NaN is not).
[[gnu::always_inline]] inline M4 finite4(V4 x) { return abs4(x) < splat(__builtin_inf()); }
// A three-term sum as Eigen's fixed-size products and dot products add it.
[[gnu::always_inline]] inline V4 sum3(V4 a0, V4 a1, V4 a2) { return a0 + (a1 + a2); }

// The lanes i0 .. i3 of a and b side by side (0 .. 3: a's, 4 .. 7: b's), in GCC's and clang's
// spellings.
template <int i0, int i1, int i2, int i3>
[[gnu::always_inline]] inline V4 shuffle(V4 a, V4 b) {
#if defined(__clang__)
    return __builtin_shufflevector(a, b, i0, i1, i2, i3);
#else
    return __builtin_shuffle(a, b, I4{i0, i1, i2, i3});
#endif
}

// Four packed 3-vectors (x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3 from p) as their x, y and z
// lanes, and back.
[[gnu::always_inline]] inline void load_xyz4(const double* p, V4& x, V4& y, V4& z) {
    const V4 p0 = load4(p), p1 = load4(p + 4), p2 = load4(p + 8);
    x = shuffle<0, 1, 2, 5>(shuffle<0, 3, 6, 6>(p0, p1), p2);
    y = shuffle<0, 1, 2, 6>(shuffle<1, 4, 7, 7>(p0, p1), p2);
    z = shuffle<0, 1, 4, 7>(shuffle<2, 5, 5, 5>(p0, p1), p2);
}
[[gnu::always_inline]] inline void store_xyz4(double* p, V4 x, V4 y, V4 z) {
    store4(p, shuffle<0, 1, 4, 3>(shuffle<0, 4, 0, 1>(x, y), z));
    store4(p + 4, shuffle<0, 1, 6, 2>(shuffle<1, 5, 2, 2>(y, z), x));
    store4(p + 8, shuffle<0, 1, 7, 2>(shuffle<2, 7, 3, 3>(z, x), y));
}
// The 4 x 4 transpose of rows a, b, c, d (in place).
[[gnu::always_inline]] inline void transpose4(V4& a, V4& b, V4& c, V4& d) {
    const V4 t0 = shuffle<0, 4, 1, 5>(a, b), t1 = shuffle<0, 4, 1, 5>(c, d);
    const V4 t2 = shuffle<2, 6, 3, 7>(a, b), t3 = shuffle<2, 6, 3, 7>(c, d);
    a = shuffle<0, 1, 4, 5>(t0, t1);
    b = shuffle<2, 3, 6, 7>(t0, t1);
    c = shuffle<0, 1, 4, 5>(t2, t3);
    d = shuffle<2, 3, 6, 7>(t2, t3);
}

// Four quaternions side by side, a vector per coefficient.
struct Quat4 {
    V4 x, y, z, w;
};
// The four quaternions kept one after another from p (as Eigen keeps one: x, y, z, w).
[[gnu::always_inline]] inline Quat4 load_quats4(const double* p) {
    Quat4 q{load4(p), load4(p + 4), load4(p + 8), load4(p + 12)};
    transpose4(q.x, q.y, q.z, q.w);
    return q;
}
// The product a b, lane by lane, with the operations of Eigen's quaternion product.
[[gnu::always_inline]] inline Quat4 quat_product4(const Quat4& a, const Quat4& b) {
    return Quat4{a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y, a.w * b.y + a.y * b.w + a.z * b.x - a.x * b.z,
                 a.w * b.z + a.z * b.w + a.x * b.y - a.y * b.x, a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z};
}

} // namespace simd
} // namespace odec

// Built for AVX2 too where the compiler can choose at run time (GCC on x86-64): no fused
// multiply-add (AVX2 alone does not bring it, and -ffp-contract=off), so the same bits either way.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define ODEC_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define ODEC_SIMD_CLONES
#endif
