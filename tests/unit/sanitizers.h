// Which sanitizers the tests are built with, for the few tests that measure what a sanitizer
// changes (memory, address space): ODEC_TEST_ASAN is defined under AddressSanitizer (gcc says
// __SANITIZE_ADDRESS__, clang __has_feature(address_sanitizer)).
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#define ODEC_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ODEC_TEST_ASAN 1
#endif
#endif
