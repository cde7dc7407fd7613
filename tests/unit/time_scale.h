// The factor of every time limit of the tests: ODEC_TEST_TIME_SCALE (default 1; 3 on a loaded
// machine triples each limit), which ./run-tests also applies to CTest's limits.
#pragma once

#include <cstdlib>

namespace odec::test {

inline double time_scale() {
    const char* s = std::getenv("ODEC_TEST_TIME_SCALE");
    if (!s || !*s) return 1.0;
    char* end = nullptr;
    const double f = std::strtod(s, &end);
    return (*end == '\0' && f > 0 && f < 1e6) ? f : 1.0;
}

} // namespace odec::test
