// skelseg: the admission rule of the batch: shapes in flight whose memory
// estimates fit in a budget, and at most a number of them.
//
// acquire() blocks the calling thread (the batch's feeder thread, never a
// TBB worker) until the shape fits: the estimates in flight plus this one
// stay within the limit, and fewer than maxInFlight shapes are in flight. A
// shape over the whole limit on its own is admitted when nothing else is in
// flight, so that `segment` reports it with its own, finer check (exit code 4
// in its summary entry) instead of the batch waiting forever.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>

namespace skelseg {

class MemoryBudget {
public:
    MemoryBudget(std::uint64_t limitBytes, std::size_t maxInFlight);

    /// Waits until `bytes` fit; returns false (without acquiring) if
    /// `stopRequested` turns true while waiting (polled every 100 ms).
    bool acquire(std::uint64_t bytes, const std::function<bool()>& stopRequested = {});
    void release(std::uint64_t bytes);

    std::uint64_t bytesInFlight() const;
    std::size_t shapesInFlight() const;
    /// The most shapes that were in flight at once.
    std::size_t peakShapesInFlight() const;

private:
    bool fitsLocked(std::uint64_t bytes) const;

    const std::uint64_t mLimit;
    const std::size_t mMaxInFlight;
    mutable std::mutex mMutex;
    std::condition_variable mReleased;
    std::uint64_t mBytes = 0;
    std::size_t mShapes = 0, mPeakShapes = 0;
};

}  // namespace skelseg
