// skelseg: per-stage wall and CPU time.
//
// Stages are named; the same name used several times (once per object)
// accumulates. Each stage says whether its work runs in parallel loops, so
// the report can state the serial share of the run: the part that does not
// get faster with more cores. Stages are timed by a Stage object
// (engine/Stage.h). Thread-safe.
#pragma once

#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace skelseg {

struct StageTiming {
    std::string name;
    bool parallel = false;
    double wallSeconds = 0.0;
    double cpuSeconds = 0.0;
    int calls = 0;
};

/// Process CPU time (all threads), seconds.
double processCpuSeconds() noexcept;
/// Seconds since the process started (dynamic loading and static
/// initialisation included), from /proc/self/stat and /proc/uptime to 10 ms;
/// 0 when they cannot be read.
double processAgeSeconds() noexcept;
/// Peak resident set size of the process, bytes.
std::uint64_t peakResidentBytes() noexcept;

class StageTimer {
public:
    void add(const std::string& name, bool parallel, double wall, double cpu);
    std::vector<StageTiming> timings() const;

private:
    mutable std::mutex mMutex;
    std::vector<StageTiming> mTimings;
};

}  // namespace skelseg
