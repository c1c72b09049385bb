#include "engine/StageTimer.h"

#include <sys/resource.h>
#include <time.h>

namespace skelseg {

double processCpuSeconds() noexcept {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

std::uint64_t peakResidentBytes() noexcept {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return std::uint64_t(usage.ru_maxrss) * 1024u;  // Linux reports KiB
}

void StageTimer::add(const std::string& name, bool parallel, double wall, double cpu) {
    std::lock_guard<std::mutex> lock(mMutex);
    for (auto& t : mTimings)
        if (t.name == name) {
            t.wallSeconds += wall, t.cpuSeconds += cpu, ++t.calls;
            return;
        }
    mTimings.push_back({name, parallel, wall, cpu, 1});
}

std::vector<StageTiming> StageTimer::timings() const {
    std::lock_guard<std::mutex> lock(mMutex);
    return mTimings;
}

}  // namespace skelseg
