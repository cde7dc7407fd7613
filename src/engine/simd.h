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

} // namespace simd
} // namespace odec

// Built for AVX2 too where the compiler can choose at run time (GCC on x86-64): no fused
// multiply-add (AVX2 alone does not bring it, and -ffp-contract=off), so the same bits either way.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define ODEC_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define ODEC_SIMD_CLONES
#endif
