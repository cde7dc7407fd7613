#include "engine/parallel.h"

#include <cstdlib>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace odec {

namespace {

int cores() {
#ifdef _OPENMP
    return omp_get_num_procs();
#else
    return 1;
#endif
}

int& chosen() {
    static int n = default_thread_count();
    return n;
}

} // namespace

bool threads_available() {
#ifdef _OPENMP
    return true;
#else
    return false;
#endif
}

int default_thread_count(std::string* why) {
    if (why) why->clear();
    const char* env = std::getenv("ODEC_THREADS");
    if (env && *env) {
        char* end = nullptr;
        const long n = std::strtol(env, &end, 10);
        if (end && *end == 0 && n >= 1 && n <= kMaxThreads) return static_cast<int>(n);
        if (why) *why = "ODEC_THREADS='" + std::string(env) + "' is not a whole number from 1 to 1024";
    }
    const int c = cores();
    return c < 1 ? 1 : (c > kMaxThreads ? kMaxThreads : c);
}

int thread_count() { return threads_available() ? chosen() : 1; }

void set_thread_count(int n) { chosen() = n < 1 ? 1 : (n > kMaxThreads ? kMaxThreads : n); }

} // namespace odec
