// skelseg: the interrupter of a Python call, polled by the calling thread.
//
// The engine runs on a worker thread; its kernels call wasInterrupted() from
// any of their threads, thousands of times a second. Those calls must not
// touch Python (taking the GIL there would stall the kernels and can
// deadlock against a caller that waits for them), so this interrupter only
// keeps atomics and a short list: every stage started, in order, and the
// fraction of the current one for the caller to read, a cancel flag for the
// caller to raise, and the time limit. The calling thread, which
// waits for the worker with the GIL released, wakes every few tens of
// milliseconds, takes the GIL, checks for Ctrl-C and calls the progress
// callback (EngineCall.h); it cancels through cancel().
#pragma once

#include <atomic>
#include <chrono>
#include <mutex>
#include <string>
#include <vector>

#include "kernels/base/Interrupter.h"

namespace skelseg {

class CallerPolledInterrupter final : public Interrupter {
public:
    /// timeLimitSeconds <= 0: no limit. The clock starts now.
    explicit CallerPolledInterrupter(double timeLimitSeconds = 0.0);

    void start(const char* name) override;
    bool wasInterrupted(double fraction = -1.0) override;
    InterruptedError::Reason reason() const override;

    /// Sets the time limit, counted from the construction (a time budget that
    /// nothing fits becomes one, engine/SegmentSteps.h); <= 0: none.
    void setTimeLimit(double seconds);
    /// The time limit in seconds from the construction; 0: none.
    double timeLimit() const noexcept { return mTimeLimit.load(); }

    /// Asks the engine to stop at its next poll (from any thread).
    void cancel() noexcept { mCancelled = true; }

    struct Progress {
        std::string stage;
        double fraction = -1.0;  // < 0: unknown
        unsigned stageNumber = 0;
    };
    /// The stage started last and the fraction of it done, as last polled.
    Progress progress() const;

    /// The names of the stages started after the first `alreadySeen` ones, in
    /// order: a caller that polls less often than stages start still sees
    /// every stage once.
    std::vector<std::string> stagesSince(unsigned alreadySeen) const;

private:
    const std::chrono::steady_clock::time_point mStart = std::chrono::steady_clock::now();
    std::atomic<double> mTimeLimit{0.0};
    std::atomic<bool> mCancelled{false};
    std::atomic<bool> mTimedOut{false};
    std::atomic<double> mFraction{-1.0};
    mutable std::mutex mStageMutex;
    std::vector<std::string> mStages;
};

}  // namespace skelseg
