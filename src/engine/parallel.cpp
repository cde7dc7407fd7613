#include "engine/parallel.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

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

// How many pieces a move of len bytes by `by` takes on `threads` threads. Below a few megabytes
// one thread moves it faster than a team starts; pieces must be longer than the shift, so that
// only the neighbouring piece writes over a piece's end.
static std::size_t move_pieces(std::size_t len, std::size_t by, int threads) {
    constexpr std::size_t kMinPiece = std::size_t{2} << 20;
    std::size_t pieces = threads > 1 ? std::min<std::size_t>(static_cast<std::size_t>(threads), len / kMinPiece) : 1;
    while (pieces > 1 && len / pieces <= by) --pieces;
    return pieces;
}

void move_bytes_up(char* data, std::size_t at, std::size_t end, std::size_t by, int threads) {
    if (end <= at || by == 0) return;
    const std::size_t len = end - at;
    const std::size_t pieces = move_pieces(len, by, threads);
    if (pieces <= 1) {
        std::memmove(data + at + by, data + at, len);
        return;
    }
    const std::size_t step = len / pieces;
    // The starts of the pieces above the first, before the piece below moves over them.
    thread_local std::vector<char> heads;
    heads.resize((pieces - 1) * by);
    for (std::size_t i = 1; i < pieces; ++i) std::memcpy(heads.data() + (i - 1) * by, data + at + i * step, by);
    const char* saved = heads.data();
    parallel_for(static_cast<int>(pieces), threads, true, [&](int i) {
        const std::size_t lo = at + static_cast<std::size_t>(i) * step;
        const std::size_t hi = static_cast<std::size_t>(i) + 1 == pieces ? end : lo + step;
        if (i == 0) {
            std::memmove(data + lo + by, data + lo, hi - lo);
        } else {
            std::memmove(data + lo + 2 * by, data + lo + by, hi - lo - by);
            std::memcpy(data + lo + by, saved + (static_cast<std::size_t>(i) - 1) * by, by);
        }
    });
}

void move_bytes_down(char* data, std::size_t at, std::size_t end, std::size_t by, int threads) {
    if (end <= at || by == 0) return;
    const std::size_t len = end - at;
    const std::size_t pieces = move_pieces(len, by, threads);
    if (pieces <= 1) {
        std::memmove(data + at - by, data + at, len);
        return;
    }
    const std::size_t step = len / pieces;
    // The ends of the pieces below the last, before the piece above moves over them.
    thread_local std::vector<char> tails;
    tails.resize((pieces - 1) * by);
    for (std::size_t i = 0; i + 1 < pieces; ++i) std::memcpy(tails.data() + i * by, data + at + (i + 1) * step - by, by);
    const char* saved = tails.data();
    parallel_for(static_cast<int>(pieces), threads, true, [&](int i) {
        const std::size_t lo = at + static_cast<std::size_t>(i) * step;
        const std::size_t hi = static_cast<std::size_t>(i) + 1 == pieces ? end : lo + step;
        if (static_cast<std::size_t>(i) + 1 == pieces) {
            std::memmove(data + lo - by, data + lo, hi - lo);
        } else {
            std::memmove(data + lo - by, data + lo, hi - lo - by);
            std::memcpy(data + hi - 2 * by, saved + static_cast<std::size_t>(i) * by, by);
        }
    });
}

} // namespace odec
