// skelseg tests: whether AddressSanitizer's allocator replaces glibc's.
//
// Under it, mallopt() takes no setting, a failed allocation ends the process
// with a report instead of throwing std::bad_alloc, and heap damage is
// reported by ASan instead of glibc's abort. Tests of those behaviours of
// glibc skip or are compiled out where SKELSEG_TEST_SANITIZER_ALLOCATOR is 1.
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#define SKELSEG_TEST_SANITIZER_ALLOCATOR 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SKELSEG_TEST_SANITIZER_ALLOCATOR 1
#endif
#endif
#ifndef SKELSEG_TEST_SANITIZER_ALLOCATOR
#define SKELSEG_TEST_SANITIZER_ALLOCATOR 0
#endif

/// Skips the test where a failed allocation ends the process instead of
/// throwing std::bad_alloc.
#define SKELSEG_SKIP_WHERE_FAILED_ALLOCATIONS_ABORT() \
    if (SKELSEG_TEST_SANITIZER_ALLOCATOR)             \
    GTEST_SKIP() << "AddressSanitizer's allocator ends the process on a failed allocation"
