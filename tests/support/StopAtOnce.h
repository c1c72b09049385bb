// Interrupters for the tests that check a kernel stops when asked and leaves
// no partial result.
#pragma once

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>

#include "kernels/base/Interrupter.h"

namespace skelseg::test {

/// Asks to stop at every poll.
class StopAtOnce final : public Interrupter {
public:
    bool wasInterrupted(double) override { return true; }
};

/// Asks to stop at poll number `stopAt` (0 = the first) and at no other: an
/// interrupter that does not repeat its answer, as a caller's flag cleared on
/// reading would. A kernel that saw the stop on one thread must throw, not
/// ask again and go on with half its work. stopAt < 0: never stops, counts.
class StopAtOnePoll final : public Interrupter {
public:
    explicit StopAtOnePoll(std::int64_t stopAt = -1) : mStopAt(stopAt) {}
    bool wasInterrupted(double) override { return mPolls.fetch_add(1) == mStopAt; }
    std::int64_t polls() const { return mPolls.load(); }

private:
    const std::int64_t mStopAt;
    std::atomic<std::int64_t> mPolls{0};
};

/// Runs `run(interrupter)` once without a stop to count its polls, then once
/// with a stop at each poll (at most `maxRuns` polls, spread evenly), and
/// expects InterruptedError every time. Returns the polls counted.
template <typename Run>
std::int64_t expectAStopAtAnyPollThrows(const Run& run, std::int64_t maxRuns = 64) {
    StopAtOnePoll counter;
    run(counter);
    const std::int64_t polls = counter.polls();
    const std::int64_t step = polls > maxRuns ? (polls + maxRuns - 1) / maxRuns : 1;
    for (std::int64_t stopAt = 0; stopAt < polls; stopAt += step) {
        SCOPED_TRACE(::testing::Message() << "stop at poll " << stopAt << " of " << polls);
        StopAtOnePoll stop(stopAt);
        EXPECT_THROW(run(stop), InterruptedError);
    }
    return polls;
}

}  // namespace skelseg::test
