#include "kernels/base/ParallelFor.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstddef>
#include <mutex>
#include <utility>
#include <vector>

namespace skelseg {
namespace {

/// Every index once, and (threaded) no range longer than the grain, however
/// cheap the body: the adaptive split of parallelFor hands out longer ranges.
TEST(ParallelFor, SmallRangesCoverEveryIndexOnceInRangesOfAtMostTheGrain) {
    for (const std::size_t grain : {std::size_t(1), std::size_t(8), std::size_t(64)}) {
        const int count = 20000;
        std::vector<std::atomic<int>> seen(count);
        for (auto& s : seen) s = 0;
        std::mutex mutex;
        std::vector<std::pair<int, int>> ranges;
        parallelForSmallRanges(
            count,
            [&](int begin, int end) {
                for (int i = begin; i < end; ++i) ++seen[std::size_t(i)];
                std::lock_guard<std::mutex> lock(mutex);
                ranges.emplace_back(begin, end);
            },
            true, grain);
        for (int i = 0; i < count; ++i) ASSERT_EQ(seen[std::size_t(i)], 1) << "index " << i;
        for (const auto& [begin, end] : ranges)
            ASSERT_LE(std::size_t(end - begin), grain) << "range " << begin << ".." << end;
    }
}

TEST(ParallelFor, SmallRangesSerialIsOneCall) {
    int calls = 0, first = -1, last = -1;
    parallelForSmallRanges(
        100,
        [&](int begin, int end) {
            ++calls;
            first = begin, last = end;
        },
        false, 8);
    EXPECT_EQ(calls, 1);
    EXPECT_EQ(first, 0);
    EXPECT_EQ(last, 100);
    parallelForSmallRanges(
        0, [&](int, int) { ++calls; }, true, 8);
    EXPECT_EQ(calls, 1);
}

}  // namespace
}  // namespace skelseg
