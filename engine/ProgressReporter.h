// skelseg: the engine's Interrupter: progress display, time budget, Ctrl-C.
//
// - On a terminal: a progress bar on stderr (stage, percent, elapsed, estimate),
//   redrawn at most ten times a second; otherwise one line per stage start;
//   quiet: no progress. message() lines (warnings) are printed in every mode.
//   A start() with the name of the stage on display (a kernel's scope inside
//   the engine's Stage) is not announced again.
// - Time budget: wasInterrupted() turns true once the deadline has passed;
//   kernels poll it every few milliseconds, so a run stops within about a
//   second of the limit.
// - User interrupt: installSignalHandlers() routes SIGINT/SIGTERM to a flag
//   that wasInterrupted() reports; a second signal ends the process at once
//   (a run waiting in a system call does not poll the flag).
// All members are safe to call from any thread.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

#include "kernels/base/Interrupter.h"

namespace skelseg {

class ProgressReporter final : public Interrupter {
public:
    enum class Display { Auto, Bar, Lines, Quiet };
    /// timeLimitSeconds <= 0: no limit.
    explicit ProgressReporter(Display display = Display::Auto, double timeLimitSeconds = 0.0,
                              std::FILE* stream = stderr);
    ~ProgressReporter() override;

    void start(const char* name) override;
    void end() override;
    bool wasInterrupted(double fraction = -1.0) override;
    InterruptedError::Reason reason() const override;

    /// Prints a one-line message (warnings), keeping the bar intact; also
    /// when the display is Quiet. Control characters in `line` are escaped
    /// (escapeControlCharacters()): it stays one line.
    void message(const std::string& line);
    double elapsedSeconds() const;
    /// Sets the time limit (seconds from the start; <= 0: none) after
    /// construction: --time-budget falls back to it when nothing fits.
    void setTimeLimit(double seconds) { mTimeLimit = seconds; }
    /// Seconds from construction; <= 0: no limit.
    double timeLimit() const { return mTimeLimit.load(); }

    /// SIGINT and SIGTERM set a process-wide flag that every reporter sees;
    /// the second of them (either) ends the process by its default action.
    static void installSignalHandlers();
    /// For tests: raise the flag as a signal would.
    static void requestInterrupt() noexcept;
    static void clearInterruptRequest() noexcept;

private:
    void draw(double fraction, bool force);
    void clearLine();

    Display mDisplay;
    std::FILE* mStream;
    std::chrono::steady_clock::time_point mStart, mStageStart;
    std::atomic<double> mTimeLimit;
    std::atomic<bool> mTimedOut{false};
    std::mutex mMutex;
    std::string mStage;
    std::chrono::steady_clock::time_point mLastDraw;
    bool mBarVisible = false;
};

}  // namespace skelseg
