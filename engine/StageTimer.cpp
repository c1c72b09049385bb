#include "engine/StageTimer.h"

#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

namespace skelseg {

double processCpuSeconds() noexcept {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double processAgeSeconds() noexcept {
    std::FILE* uptimeFile = std::fopen("/proc/uptime", "r");
    std::FILE* statFile = std::fopen("/proc/self/stat", "r");
    double uptime = 0.0;
    unsigned long long startTicks = 0;
    bool ok = uptimeFile && statFile && std::fscanf(uptimeFile, "%lf", &uptime) == 1;
    if (ok) {
        // Field 22 (starttime, clock ticks after boot) follows the command
        // name in parentheses, which may hold spaces: skip to its last ')'.
        char buffer[1024];
        const std::size_t length = std::fread(buffer, 1, sizeof buffer - 1, statFile);
        buffer[length] = '\0';
        const char* field = std::strrchr(buffer, ')');
        ok = field != nullptr;
        for (int f = 2; ok && f < 22; ++f) {
            field = std::strchr(field + 1, ' ');
            ok = field != nullptr;
        }
        ok = ok && std::sscanf(field, " %llu", &startTicks) == 1;
    }
    if (uptimeFile) std::fclose(uptimeFile);
    if (statFile) std::fclose(statFile);
    const long ticksPerSecond = sysconf(_SC_CLK_TCK);
    if (!ok || ticksPerSecond <= 0) return 0.0;
    return std::max(0.0, uptime - double(startTicks) / double(ticksPerSecond));
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
