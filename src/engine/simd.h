// Four doubles in one vector, for the engine's kernels that run several items per instruction
// (GCC's vector extensions: one AVX instruction per operation where a function is built for
// AVX2, two SSE2 instructions elsewhere). Each operation is IEEE's, lane by lane, as the scalar
// one: with -ffp-contract=off a kernel gives every lane the bits of the scalar code it mirrors.
#pragma once

#include <cstring>

namespace odec {
namespace simd {

// (Passed only between inline functions and lambdas of a file that includes this: no call
// between files sees their ABI, so GCC's note on it is off: CMakeLists.txt, -Wno-psabi.)
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

// Four packed 3-vectors (x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3 from p) as their x, y and z
// lanes, and back.
[[gnu::always_inline]] inline void load_xyz4(const double* p, V4& x, V4& y, V4& z) {
    const V4 p0 = load4(p), p1 = load4(p + 4), p2 = load4(p + 8);
    x = __builtin_shuffle(__builtin_shuffle(p0, p1, I4{0, 3, 6, 6}), p2, I4{0, 1, 2, 5});
    y = __builtin_shuffle(__builtin_shuffle(p0, p1, I4{1, 4, 7, 7}), p2, I4{0, 1, 2, 6});
    z = __builtin_shuffle(__builtin_shuffle(p0, p1, I4{2, 5, 5, 5}), p2, I4{0, 1, 4, 7});
}
[[gnu::always_inline]] inline void store_xyz4(double* p, V4 x, V4 y, V4 z) {
    store4(p, __builtin_shuffle(__builtin_shuffle(x, y, I4{0, 4, 0, 1}), z, I4{0, 1, 4, 3}));
    store4(p + 4, __builtin_shuffle(__builtin_shuffle(y, z, I4{1, 5, 2, 2}), x, I4{0, 1, 6, 2}));
    store4(p + 8, __builtin_shuffle(__builtin_shuffle(z, x, I4{2, 7, 3, 3}), y, I4{0, 1, 7, 2}));
}
// The 4 x 4 transpose of rows a, b, c, d (in place).
[[gnu::always_inline]] inline void transpose4(V4& a, V4& b, V4& c, V4& d) {
    const V4 t0 = __builtin_shuffle(a, b, I4{0, 4, 1, 5}), t1 = __builtin_shuffle(c, d, I4{0, 4, 1, 5});
    const V4 t2 = __builtin_shuffle(a, b, I4{2, 6, 3, 7}), t3 = __builtin_shuffle(c, d, I4{2, 6, 3, 7});
    a = __builtin_shuffle(t0, t1, I4{0, 1, 4, 5});
    b = __builtin_shuffle(t0, t1, I4{2, 3, 6, 7});
    c = __builtin_shuffle(t2, t3, I4{0, 1, 4, 5});
    d = __builtin_shuffle(t2, t3, I4{2, 3, 6, 7});
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
