// Memory figures for the benchmarks: heap in use, and resident memory read from
// /proc/self/status, with the peak reset between the phases of a run so that each phase's
// own peak shows (Linux; elsewhere the figures are 0).
#pragma once

#include <cstdio>
#include <cstring>

#include <malloc.h>

namespace odec::bench {

// Bytes of heap in use now.
inline double heap_bytes() {
    const struct mallinfo2 mi = mallinfo2();
    return static_cast<double>(mi.uordblks + mi.hblkhd);
}

// A field of /proc/self/status given in kB ("VmRSS:", "VmHWM:"), in bytes; 0 when unreadable.
inline double status_bytes(const char* field) {
    std::FILE* f = std::fopen("/proc/self/status", "r");
    if (!f) return 0;
    char line[256];
    double kb = 0;
    const size_t n = std::strlen(field);
    while (std::fgets(line, sizeof line, f)) {
        if (std::strncmp(line, field, n) == 0) {
            kb = std::atof(line + n);
            break;
        }
    }
    std::fclose(f);
    return 1024.0 * kb;
}

// Resident memory now, and its peak since the start or the last reset_peak_rss, bytes.
inline double rss_bytes() { return status_bytes("VmRSS:"); }
inline double peak_rss_bytes() { return status_bytes("VmHWM:"); }

// Start a new peak from the resident memory of now. Returns false where that cannot be done.
inline bool reset_peak_rss() {
    std::FILE* f = std::fopen("/proc/self/clear_refs", "w");
    if (!f) return false;
    const bool ok = std::fputs("5", f) >= 0;
    return std::fclose(f) == 0 && ok;
}

} // namespace odec::bench
