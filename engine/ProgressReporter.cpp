#include "engine/ProgressReporter.h"

#include <unistd.h>

#include <csignal>

#include "kernels/base/Error.h"

namespace skelseg {

namespace {
std::atomic<bool> gInterruptRequested{false};
// Signals received: requestInterrupt() raises the flag without counting, so
// that a signal after it is still the first.
std::atomic<int> gSignalsReceived{0};
static_assert(std::atomic<int>::is_always_lock_free, "used in a signal handler");

// The first signal asks the stages to stop at their next poll, which ends the
// run within a second or so and leaves no output. The stages cannot poll
// while the process waits in a system call (a pipe nobody reads, a stalled
// network file), so a second SIGINT or SIGTERM ends the process at once by
// the signal's default action, as if the handler were not there: outputs are
// staged, so nothing half-written is left under a final name, and the next
// run on the folder removes the staging directory.
extern "C" void onSignal(int signalNumber) {
    gInterruptRequested.store(true);
    if (gSignalsReceived.fetch_add(1) > 0) {
        std::signal(signalNumber, SIG_DFL);
        std::raise(signalNumber);
    }
}
}  // namespace

ProgressReporter::ProgressReporter(Display display, double timeLimitSeconds, std::FILE* stream)
    : mDisplay(display),
      mStream(stream),
      mStart(std::chrono::steady_clock::now()),
      mStageStart(mStart),
      mTimeLimit(timeLimitSeconds),
      mLastDraw(mStart) {
    if (mDisplay == Display::Auto)
        mDisplay = ::isatty(::fileno(stream)) ? Display::Bar : Display::Lines;
}

ProgressReporter::~ProgressReporter() {
    std::lock_guard<std::mutex> lock(mMutex);
    clearLine();
}

void ProgressReporter::installSignalHandlers() {
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
}
void ProgressReporter::requestInterrupt() noexcept {
    gInterruptRequested.store(true);
}
void ProgressReporter::clearInterruptRequest() noexcept {
    gInterruptRequested.store(false);
}

double ProgressReporter::elapsedSeconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - mStart).count();
}

void ProgressReporter::start(const char* name) {
    std::lock_guard<std::mutex> lock(mMutex);
    // A kernel's own scope inside the engine's Stage of the same name: the
    // stage is already on display.
    if (mStage == name) return;
    mStage = name;
    mStageStart = std::chrono::steady_clock::now();
    if (mDisplay == Display::Lines) {
        std::fprintf(mStream, "skelseg: %s (%.1f s)\n", name, elapsedSeconds());
        std::fflush(mStream);
    } else if (mDisplay == Display::Bar) {
        draw(0.0, true);
    }
}

void ProgressReporter::end() {}

bool ProgressReporter::wasInterrupted(double fraction) {
    if (gInterruptRequested.load(std::memory_order_relaxed)) return true;
    if (mTimedOut.load(std::memory_order_relaxed)) return true;
    const double limit = mTimeLimit.load(std::memory_order_relaxed);
    if (limit > 0.0 && elapsedSeconds() > limit) {
        mTimedOut.store(true);
        return true;
    }
    if (mDisplay == Display::Bar && fraction >= 0.0) {
        std::unique_lock<std::mutex> lock(mMutex, std::try_to_lock);
        if (lock.owns_lock()) draw(fraction, false);
    }
    return false;
}

InterruptedError::Reason ProgressReporter::reason() const {
    return mTimedOut.load() ? InterruptedError::Reason::TimeLimit
                            : InterruptedError::Reason::UserInterrupt;
}

void ProgressReporter::message(const std::string& line) {
    // Also when quiet: --quiet silences progress, not warnings. Lines name
    // files, and a file name may hold a newline or an escape sequence.
    const std::string shown = escapeControlCharacters(line);
    std::lock_guard<std::mutex> lock(mMutex);
    clearLine();
    std::fprintf(mStream, "%s\n", shown.c_str());
    std::fflush(mStream);
}

void ProgressReporter::clearLine() {
    if (!mBarVisible) return;
    std::fprintf(mStream, "\r\033[K");
    std::fflush(mStream);
    mBarVisible = false;
}

void ProgressReporter::draw(double fraction, bool force) {
    const auto now = std::chrono::steady_clock::now();
    if (!force && now - mLastDraw < std::chrono::milliseconds(100)) return;
    mLastDraw = now;
    const double stageElapsed = std::chrono::duration<double>(now - mStageStart).count();
    char eta[32] = "";
    if (fraction > 0.02 && fraction < 1.0)
        std::snprintf(eta, sizeof eta, ", ~%.0f s left",
                      stageElapsed / fraction * (1.0 - fraction));
    const int width = 30, filled = int(fraction * width + 0.5);
    std::string bar(std::size_t(std::max(0, std::min(width, filled))), '#');
    bar.resize(std::size_t(width), '.');
    std::fprintf(mStream, "\r\033[K%-30s [%s] %3.0f%%  %.1f s%s", mStage.c_str(), bar.c_str(),
                 fraction * 100.0, elapsedSeconds(), eta);
    std::fflush(mStream);
    mBarVisible = true;
}

}  // namespace skelseg
