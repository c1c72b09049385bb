// skelseg: progress over a batch of shapes.
//
// On a terminal, one bar on stderr redrawn as shapes finish: shapes finished
// of the total, shapes per minute, estimated time left; failures and warnings
// print as lines above it. Otherwise (a log file, a cluster job's output) one
// line per finished shape, with the same figures. Quiet: nothing per shape.
// The rate counts shapes this run segmented (not skipped ones), over the
// run's wall time so far. All members are safe to call from any thread.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdio>
#include <mutex>
#include <string>

#include "engine/batch/BatchSummary.h"

namespace skelseg {

class BatchProgress {
public:
    enum class Display { Auto, Bar, Lines, Quiet };
    /// `total`: inputs of this shard; `skipped`: how many of them were done earlier.
    BatchProgress(std::size_t total, std::size_t skipped, Display display = Display::Auto,
                  std::FILE* stream = stderr);
    ~BatchProgress();
    BatchProgress(const BatchProgress&) = delete;
    BatchProgress& operator=(const BatchProgress&) = delete;

    /// Counts a finished (done or failed) input and shows it.
    void shapeFinished(const BatchEntry& entry);
    /// A line above the bar (printed in every mode), control characters
    /// escaped as in errors.
    void message(const std::string& line);
    /// "12/45 shapes, 3.4 shapes/min, ETA 9m41s".
    std::string statusText() const;
    double elapsedSeconds() const;
    Display display() const { return mDisplay; }

private:
    std::string statusTextLocked() const;
    void drawBarLocked();
    void clearBarLocked();

    Display mDisplay;
    std::FILE* mStream;
    std::chrono::steady_clock::time_point mStart;
    std::size_t mTotal, mFinished, mSegmented = 0;  // skipped inputs count as finished
    mutable std::mutex mMutex;
    bool mBarVisible = false;
};

/// "2h05m", "9m41s", "12s".
std::string formatDuration(double seconds);

}  // namespace skelseg
