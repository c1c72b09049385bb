#include "engine/batch/FreedMemoryReuse.h"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cstdlib>
#include <cstring>
#include <vector>

#include "tests/support/SanitizerAllocator.h"

namespace skelseg {
namespace {

long threadMinorFaults() {
    rusage usage{};
    ::getrusage(RUSAGE_THREAD, &usage);
    return usage.ru_minflt;
}

/// Allocates `count` blocks of `bytes`, writes every page, frees them; returns
/// the minor page faults taken.
long faultsOfOneRound(std::size_t count, std::size_t bytes) {
    const long before = threadMinorFaults();
    std::vector<char*> blocks;
    for (std::size_t k = 0; k < count; ++k) {
        blocks.push_back(static_cast<char*>(std::malloc(bytes)));
        if (blocks.back()) std::memset(blocks.back(), int(k + 1), bytes);
    }
    for (auto it = blocks.rbegin(); it != blocks.rend(); ++it) std::free(*it);
    return threadMinorFaults() - before;
}

#if defined(__GLIBC__) && !SKELSEG_TEST_SANITIZER_ALLOCATOR
TEST(FreedMemoryReuse, ASecondShapeOfTheSameSizeTakesNoFreshPages) {
    // Three blocks just under the mmap threshold, as a preview's panels: freed
    // together they are more than glibc's own trim threshold ever reaches
    // (twice its largest mmap threshold, 64 MB), so without the policy the
    // second round faults on every page again, as each batch input did.
    ASSERT_TRUE(keepFreedMemoryForReuse());
    const std::size_t bytes = kBatchMmapThresholdBytes - (std::size_t(1) << 20);
    const std::size_t pages = 3 * bytes / 4096;
    faultsOfOneRound(3, bytes);  // the heap grows once
    const long second = faultsOfOneRound(3, bytes);
    EXPECT_LT(second, long(pages / 20)) << "of " << pages << " pages";
}
#endif

}  // namespace
}  // namespace skelseg
