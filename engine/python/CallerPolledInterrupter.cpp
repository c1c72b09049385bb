#include "engine/python/CallerPolledInterrupter.h"

namespace skelseg {

CallerPolledInterrupter::CallerPolledInterrupter(double timeLimitSeconds) {
    setTimeLimit(timeLimitSeconds);
}

void CallerPolledInterrupter::setTimeLimit(double seconds) {
    mTimeLimit.store(seconds > 0 ? seconds : 0.0);
}

void CallerPolledInterrupter::start(const char* name) {
    std::lock_guard<std::mutex> lock(mStageMutex);
    mStages.push_back(name);
    mFraction = -1.0;
}

bool CallerPolledInterrupter::wasInterrupted(double fraction) {
    if (fraction >= 0) mFraction.store(fraction, std::memory_order_relaxed);
    if (mCancelled.load(std::memory_order_relaxed)) return true;
    const double limit = mTimeLimit.load(std::memory_order_relaxed);
    if (limit > 0 && !mTimedOut.load(std::memory_order_relaxed) &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - mStart).count() >= limit)
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
