// skelseg: per-stage wall and CPU time.
//
// Stages are named; the same name used several times (once per object)
// accumulates. Each stage says whether its work runs in parallel loops, so
// the report can state the serial share of the run (issue 4: it must stay
// small for the engine to scale on many cores). Thread-safe.
#pragma once

#include <chrono>
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
/// Peak resident set size of the process, bytes.
std::uint64_t peakResidentBytes() noexcept;

class StageTimer {
public:
    class Scope {
    public:
        Scope(StageTimer& timer, std::string name, bool parallel);
        ~Scope();
        Scope(const Scope&) = delete;
        Scope& operator=(const Scope&) = delete;

    private:
        StageTimer& mTimer;
        std::string mName;
        bool mParallel;
        std::chrono::steady_clock::time_point mStart;
        double mCpuStart;
    };

    Scope stage(std::string name, bool parallel) { return Scope(*this, std::move(name), parallel); }
    void add(const std::string& name, bool parallel, double wall, double cpu);
    std::vector<StageTiming> timings() const;

private:
    mutable std::mutex mMutex;
    std::vector<StageTiming> mTimings;
};

}  // namespace skelseg
