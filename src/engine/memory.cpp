#include "engine/memory.h"

#include <cstdlib> // defines __GLIBC__ where the C library is glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace odec {

void tune_allocator() {
#if defined(__GLIBC__)
    // glibc's own starting values, kept: left to itself it raises both each time a mapped block
    // is freed (up to 32 MB and twice that), after which arrays below that size come from the
    // heap and the holes they leave when they grow stay resident (the 27,000-block cube settling:
    // 16 MB more at the peak of its first 30 steps, 24 MB at their end). Setting either one stops
    // that.
    mallopt(M_MMAP_THRESHOLD, 128 * 1024);
    mallopt(M_TRIM_THRESHOLD, 128 * 1024);
#endif
}

} // namespace odec
