#include "engine/python/CallerPolledInterrupter.h"

namespace skelseg {

CallerPolledInterrupter::CallerPolledInterrupter(double timeLimitSeconds)
    : mHasDeadline(timeLimitSeconds > 0) {
    if (mHasDeadline)
        mDeadline = std::chrono::steady_clock::now() +
                    std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                        std::chrono::duration<double>(timeLimitSeconds));
}

void CallerPolledInterrupter::start(const char* name) {
    std::lock_guard<std::mutex> lock(mStageMutex);
    mStages.push_back(name);
    mFraction = -1.0;
}

bool CallerPolledInterrupter::wasInterrupted(double fraction) {
    if (fraction >= 0) mFraction.store(fraction, std::memory_order_relaxed);
    if (mCancelled.load(std::memory_order_relaxed)) return true;
    if (mHasDeadline && !mTimedOut.load(std::memory_order_relaxed) &&
        std::chrono::steady_clock::now() >= mDeadline)
        mTimedOut = true;
    return mTimedOut.load(std::memory_order_relaxed);
}

InterruptedError::Reason CallerPolledInterrupter::reason() const {
    return mTimedOut ? InterruptedError::Reason::TimeLimit
                     : InterruptedError::Reason::UserInterrupt;
}

CallerPolledInterrupter::Progress CallerPolledInterrupter::progress() const {
    std::lock_guard<std::mutex> lock(mStageMutex);
    if (mStages.empty()) return {};
    return {mStages.back(), mFraction.load(std::memory_order_relaxed),
            static_cast<unsigned>(mStages.size())};
}

std::vector<std::string> CallerPolledInterrupter::stagesSince(unsigned alreadySeen) const {
    std::lock_guard<std::mutex> lock(mStageMutex);
    if (alreadySeen >= mStages.size()) return {};
    return {mStages.begin() + alreadySeen, mStages.end()};
}

}  // namespace skelseg
