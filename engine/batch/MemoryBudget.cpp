#include "engine/batch/MemoryBudget.h"

#include <algorithm>

namespace skelseg {

MemoryBudget::MemoryBudget(std::uint64_t limitBytes, std::size_t maxInFlight)
    : mLimit(limitBytes), mMaxInFlight(std::max<std::size_t>(maxInFlight, 1)) {}

bool MemoryBudget::fitsLocked(std::uint64_t bytes) const {
    if (mShapes >= mMaxInFlight) return false;
    return mShapes == 0 || mBytes + bytes <= mLimit;
}

bool MemoryBudget::acquire(std::uint64_t bytes, const std::function<bool()>& stopRequested) {
    std::unique_lock<std::mutex> lock(mMutex);
    while (!fitsLocked(bytes)) {
        if (stopRequested && stopRequested()) return false;
        mReleased.wait_for(lock, std::chrono::milliseconds(100));
    }
    if (stopRequested && stopRequested()) return false;
    mBytes += bytes;
    ++mShapes;
    mPeakShapes = std::max(mPeakShapes, mShapes);
    return true;
}

void MemoryBudget::release(std::uint64_t bytes) {
    {
        const std::lock_guard<std::mutex> lock(mMutex);
        mBytes -= std::min(bytes, mBytes);
        if (mShapes > 0) --mShapes;
    }
    mReleased.notify_all();
}

std::uint64_t MemoryBudget::bytesInFlight() const {
    const std::lock_guard<std::mutex> lock(mMutex);
    return mBytes;
}

std::size_t MemoryBudget::shapesInFlight() const {
    const std::lock_guard<std::mutex> lock(mMutex);
    return mShapes;
}

std::size_t MemoryBudget::peakShapesInFlight() const {
    const std::lock_guard<std::mutex> lock(mMutex);
    return mPeakShapes;
}

}  // namespace skelseg
