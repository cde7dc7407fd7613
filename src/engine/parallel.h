// Threads of the cycle (OpenMP from the compiler). Every parallel loop of the cycle gives the
// same bits with any number of threads: work is split so that no two threads add into the same
// number (zones by colour: no two zones of one colour share a gridpoint), and sums over many
// items are taken in fixed chunks whose partial sums are added in order.
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

namespace odec {

// The most threads 'set threads' accepts.
constexpr int kMaxThreads = 1024;

// Threads the cycle uses: 'set threads n', else the environment variable ODEC_THREADS, else
// every core.
int thread_count();
// n in 1..kMaxThreads.
void set_thread_count(int n);
// What ODEC_THREADS asks for, or every core; "" or the reason it was ignored in *why.
int default_thread_count(std::string* why = nullptr);
// Whether the program was built with OpenMP (otherwise the cycle runs on one thread).
bool threads_available();

// Loops shorter than this run on one thread (a parallel region costs a few microseconds).
constexpr int kParallelMinItems = 8192;
// Rigid blocks fewer than this integrate on one thread.
constexpr int kParallelMinBlocks = 4096;
// Contact builds (a common plane and its sub-contacts, some microseconds each) fewer than this
// in one detection pass run on one thread.
constexpr int kParallelMinBuilds = 64;
// The zone stage runs colour by colour, a barrier after each: below this many zones the
// colours hold too few chunks to share out, and one thread is as fast.
constexpr int kParallelMinZones = 32768;

// fn(i) for every i in [0, n): on `threads` threads in a static schedule when `parallel` and
// threads > 1, else in a plain loop. The plain loop enters no OpenMP region at all: an idle
// region (its `if` clause false) still costs the runtime a team and a wake-up, some
// microseconds each, several times a step.
template <class F>
inline void parallel_for(int n, int threads, bool parallel, F&& fn) {
    if (parallel && threads > 1) {
#pragma omp parallel for num_threads(threads) schedule(static)
        for (int i = 0; i < n; ++i) fn(i);
    } else {
        for (int i = 0; i < n; ++i) fn(i);
    }
}

// The same, for an fn that returns bits: their OR over every i.
template <class F>
inline int parallel_or(int n, int threads, bool parallel, F&& fn) {
    int bits = 0;
    if (parallel && threads > 1) {
#pragma omp parallel for num_threads(threads) schedule(static) reduction(| : bits)
        for (int i = 0; i < n; ++i) bits |= fn(i);
    } else {
        for (int i = 0; i < n; ++i) bits |= fn(i);
    }
    return bits;
}

// The lowest i in [0, n) for which pred(i) holds, or -1: in fixed chunks of `chunk`, on
// `threads` threads when `parallel`, each chunk its first; the lowest chunk's is the answer, the
// same whatever the threads.
template <class P>
inline int parallel_first(int n, int chunk, int threads, bool parallel, P&& pred) {
    const int nch = (n + chunk - 1) / chunk;
    thread_local std::vector<int> buffer;
    buffer.assign(nch, -1);
    int* first = buffer.data(); // this thread's buffer, written by the others too
    parallel_for(nch, threads, parallel, [&](int ch) {
        const int hi = std::min(n, (ch + 1) * chunk);
        for (int i = ch * chunk; i < hi; ++i) {
            if (pred(i)) {
                first[ch] = i;
                return;
            }
        }
    });
    for (int ch = 0; ch < nch; ++ch) {
        if (first[ch] >= 0) return first[ch];
    }
    return -1;
}

// The bytes [at, end) of `data` moved up by `by` (as memmove would), on `threads` threads when
// they are many (a pure copy: the same bytes whatever the threads). Each thread moves a piece
// of its own; the first `by` bytes of each piece but the first, which the piece below
// overwrites, are read from a copy taken before.
void move_bytes_up(char* data, std::size_t at, std::size_t end, std::size_t by, int threads);
// The bytes [at, end) of `data` moved down by `by` (to at - by, as memmove would), on `threads`
// threads when they are many, the mirror of move_bytes_up: the last `by` bytes of each piece
// but the last, which the piece above overwrites, are read from a copy taken before.
void move_bytes_down(char* data, std::size_t at, std::size_t end, std::size_t by, int threads);

} // namespace odec
