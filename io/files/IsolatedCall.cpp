#include "io/files/IsolatedCall.h"

#include <fcntl.h>
#include <malloc.h>
#include <poll.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <new>
#include <optional>
#include <sstream>

#include "kernels/base/Error.h"

namespace skelseg {

namespace {

constexpr int kExitFinished = 0;
constexpr int kExitThrew = 1;
constexpr int kExitOutOfMemory = 3;
constexpr std::size_t kMaxMessageBytes = 4096;

/// VmData of this process in bytes (the figure RLIMIT_DATA bounds); 0 if unknown.
std::uint64_t dataSegmentBytes() {
    std::ifstream status("/proc/self/status");
    for (std::string line; std::getline(status, line);)
        if (line.rfind("VmData:", 0) == 0) {
            std::istringstream fields(line.substr(7));
            std::uint64_t kilobytes = 0;
            fields >> kilobytes;
            return kilobytes * 1024;
        }
    return 0;
}

/// What the child tells the parent about its memory through a page mapped
/// shared (a forked child's writes to it reach the parent), so that a parse
/// that failed for want of memory is told apart from a damaged file however
/// it failed: a caught std::bad_alloc may become another error (OpenVDB's
/// reader turns it into a stream error) and a null from malloc a crash.
struct ChildMemoryRecord {
    /// Set by the new-handler when an allocation fails while the heap has
    /// grown by at least half the limit: the limit, not an absurd size read
    /// from a damaged file, refused it.
    std::atomic<int> allocationFailedNearLimit{0};
    /// The heap in use (mallinfo2) and the peak resident kilobytes as the
    /// child started: what it inherited.
    std::atomic<std::uint64_t> heapAtStart{0};
    std::atomic<long> peakResidentKbAtStart{0};
    std::uint64_t memoryLimit = 0;
};

/// A ChildMemoryRecord in an anonymous shared mapping.
class SharedMemoryRecord {
public:
    SharedMemoryRecord() {
        void* page = ::mmap(nullptr, sizeof(ChildMemoryRecord), PROT_READ | PROT_WRITE,
                            MAP_SHARED | MAP_ANONYMOUS, -1, 0);
        if (page != MAP_FAILED) mRecord = new (page) ChildMemoryRecord();
    }
    ~SharedMemoryRecord() {
        if (mRecord) ::munmap(mRecord, sizeof(ChildMemoryRecord));
    }
    SharedMemoryRecord(const SharedMemoryRecord&) = delete;
    SharedMemoryRecord& operator=(const SharedMemoryRecord&) = delete;
    /// nullptr when the page could not be mapped.
    ChildMemoryRecord* get() const noexcept { return mRecord; }

private:
    ChildMemoryRecord* mRecord = nullptr;
};

ChildMemoryRecord* gChildMemory = nullptr;  // the child's view of the shared record

std::uint64_t heapInUse() {
    const struct mallinfo2 info = ::mallinfo2();
    return info.uordblks + info.hblkhd;
}

long peakResidentKb() {
    rusage usage{};
    ::getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss;
}

void recordFailedAllocation() {
    ChildMemoryRecord* record = gChildMemory;
    if (record && record->memoryLimit > 0) {
        const std::uint64_t heap = heapInUse(), start = record->heapAtStart.load();
        if (heap > start && heap - start >= record->memoryLimit / 2)
            record->allocationFailedNearLimit.store(1);
    }
    throw std::bad_alloc();
}

/// User plus system CPU ticks of process `pid` so far; -1 if unknown.
long long cpuTicks(pid_t pid) {
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
    const std::size_t close = text.rfind(')');  // the command name may hold spaces
    if (close == std::string::npos) return -1;
    std::istringstream fields(text.substr(close + 2));
    std::string field;
    long long utime = 0, stime = 0;
    for (int index = 3; index <= 15 && fields >> field; ++index) {
        if (index == 14) utime = std::atoll(field.c_str());
        if (index == 15) stime = std::atoll(field.c_str());
    }
    return utime + stime;
}

/// Writes all of `bytes` to `fd`; false on an error.
bool writeAll(int fd, const std::string& bytes) {
    for (std::size_t written = 0; written < bytes.size();) {
        const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        written += std::size_t(n);
    }
    return true;
}

/// The whole content of the memory file `fd`; nullopt on an error.
std::optional<std::string> readAll(int fd) {
    struct stat status {};
    if (::fstat(fd, &status) != 0 || ::lseek(fd, 0, SEEK_SET) != 0) return std::nullopt;
    std::string bytes(std::size_t(status.st_size), '\0');
    for (std::size_t done = 0; done < bytes.size();) {
        const ssize_t n = ::read(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return std::nullopt;
        done += std::size_t(n);
    }
    return bytes;
}

[[noreturn]] void runChild(const std::function<std::string()>& work, int messageFd, int outputFd,
                           std::uint64_t memoryLimit, std::uint64_t inheritedData) {
    // Libraries report to both streams (c-blosc prints "Error allocating
    // memory!" to standard output); the caller's streams are its own.
    const int devNull = ::open("/dev/null", O_WRONLY);
    if (devNull >= 0) {
        ::dup2(devNull, STDOUT_FILENO);
        ::dup2(devNull, STDERR_FILENO);
    }
    if (gChildMemory) {
        gChildMemory->heapAtStart.store(heapInUse());
        gChildMemory->peakResidentKbAtStart.store(peakResidentKb());
        gChildMemory->memoryLimit = memoryLimit;
    }
    std::set_new_handler(recordFailedAllocation);
    if (memoryLimit > 0 && inheritedData > 0) {
        const rlimit limit{inheritedData + memoryLimit, inheritedData + memoryLimit};
        ::setrlimit(RLIMIT_DATA, &limit);
    }
    const auto report = [&](const std::string& message) {
        writeAll(messageFd, message.substr(0, kMaxMessageBytes));
    };
    try {
        if (!writeAll(outputFd, work())) {
            report("cannot pass the result back: " + std::string(std::strerror(errno)));
            ::_exit(kExitThrew);
        }
    } catch (const std::bad_alloc&) {
        ::_exit(kExitOutOfMemory);
    } catch (const InputError& error) {
        report(error.problem());
        ::_exit(kExitThrew);
    } catch (const std::exception& error) {
        report(error.what());
        ::_exit(kExitThrew);
    } catch (...) {
        report("unknown error");
        ::_exit(kExitThrew);
    }
    ::_exit(kExitFinished);
}

}  // namespace

std::string signalName(int signal) {
    switch (signal) {
        case SIGSEGV:
            return "SIGSEGV";
        case SIGABRT:
            return "SIGABRT";
        case SIGBUS:
            return "SIGBUS";
        case SIGFPE:
            return "SIGFPE";
        case SIGILL:
            return "SIGILL";
        case SIGKILL:
            return "SIGKILL";
        case SIGTERM:
            return "SIGTERM";
        default:
            return "signal " + std::to_string(signal);
    }
}

IsolatedCallOutcome runIsolated(const std::function<std::string()>& work,
                                const IsolatedCallOptions& options) {
    IsolatedCallOutcome outcome;
    // Read before the fork: the child must not open files it may not need.
    const std::uint64_t inheritedData = options.memoryLimit > 0 ? dataSegmentBytes() : 0;
    SharedMemoryRecord childMemory;
    if (!childMemory.get()) return outcome;
    const int outputFd = ::memfd_create("skelseg-isolated-call", MFD_CLOEXEC);
    if (outputFd < 0) return outcome;
    int pipeFds[2];
    if (::pipe2(pipeFds, O_CLOEXEC) != 0) {
        ::close(outputFd);
        return outcome;
    }
    const pid_t child = ::fork();
    if (child < 0) {
        ::close(pipeFds[0]);
        ::close(pipeFds[1]);
        ::close(outputFd);
        return outcome;
    }
    if (child == 0) {
        ::close(pipeFds[0]);
        gChildMemory = childMemory.get();
        runChild(work, pipeFds[1], outputFd, options.memoryLimit, inheritedData);
    }
    ::close(pipeFds[1]);
    const int messageFd = pipeFds[0];

    using Clock = std::chrono::steady_clock;
    long long lastTicks = cpuTicks(child);
    Clock::time_point lastProgress = Clock::now();
    int status = 0;
    rusage usage{};
    bool ended = false, killed = false, stalled = false;
    while (!ended) {
        // The child writes its message only as it ends, so the pipe's
        // end-of-file is the moment to look at its status.
        pollfd waitFor{messageFd, POLLIN, 0};
        const int ready = ::poll(&waitFor, 1, 50);
        if (ready > 0) {
            char buffer[512];
            const ssize_t n = ::read(messageFd, buffer, sizeof buffer);
            if (n > 0 && outcome.message.size() < kMaxMessageBytes)
                outcome.message.append(buffer, std::size_t(n));
        }
        const pid_t done = ::wait4(child, &status, WNOHANG, &usage);
        if (done == child) {
            ended = true;
            break;
        }
        if (done < 0 && errno != EINTR) break;
        if (options.interrupter && options.interrupter->wasInterrupted()) {
            killed = true;
        } else {
            const long long ticks = cpuTicks(child);
            if (ticks != lastTicks) {
                lastTicks = ticks;
                lastProgress = Clock::now();
            } else if (std::chrono::duration<double>(Clock::now() - lastProgress).count() >
                       options.stallSeconds) {
                stalled = true;
            }
        }
        if (killed || stalled) {
            ::kill(child, SIGKILL);
            while (::wait4(child, &status, 0, &usage) < 0 && errno == EINTR) {
            }
            ended = true;
        }
    }
    for (char buffer[512]; outcome.message.size() < kMaxMessageBytes;) {
        const ssize_t n = ::read(messageFd, buffer, sizeof buffer);
        if (n <= 0) break;
        outcome.message.append(buffer, std::size_t(n));
    }
    ::close(messageFd);
    if (!ended) {
        ::close(outputFd);
        return outcome;
    }
    // Work that fails for want of memory may end in any way (ChildMemoryRecord).
    // It reached the limit if an allocation failed near it, or if its
    // resident memory grew by half the limit (malloc's failures reach no
    // handler); a damaged file's crash, or an absurd size read from it, comes
    // long before that.
    const ChildMemoryRecord& record = *childMemory.get();
    const long residentGrowthKb = usage.ru_maxrss - record.peakResidentKbAtStart.load();
    const bool allocationFailedNearLimit = record.allocationFailedNearLimit.load() != 0;
    outcome.reachedMemoryLimit = options.memoryLimit > 0 &&
                                 (allocationFailedNearLimit ||
                                  (residentGrowthKb > 0 && std::uint64_t(residentGrowthKb) * 1024 >=
                                                               options.memoryLimit / 2));
    const bool finished = WIFEXITED(status) && WEXITSTATUS(status) == kExitFinished;
    if (killed) {
        outcome.ending = IsolatedCallOutcome::Ending::Interrupted;
    } else if (stalled) {
        outcome.ending = IsolatedCallOutcome::Ending::NotIsolated;
    } else if (finished ? allocationFailedNearLimit : outcome.reachedMemoryLimit) {
        // Finished too: code that swallows a bad_alloc (a stream's buffer)
        // returns what it has, not what the work meant to return.
        outcome.ending = IsolatedCallOutcome::Ending::OutOfMemory;
    } else if (WIFSIGNALED(status)) {
        outcome.ending = IsolatedCallOutcome::Ending::Crashed;
        outcome.signal = WTERMSIG(status);
    } else if (WIFEXITED(status) && WEXITSTATUS(status) == kExitFinished) {
        std::optional<std::string> output = readAll(outputFd);
        if (output) {
            outcome.ending = IsolatedCallOutcome::Ending::Finished;
            outcome.output = std::move(*output);
        }  // else NotIsolated: the work runs here
    } else if (WIFEXITED(status) && WEXITSTATUS(status) == kExitOutOfMemory) {
        outcome.ending = IsolatedCallOutcome::Ending::OutOfMemory;
    } else {
        outcome.ending = IsolatedCallOutcome::Ending::Threw;
    }
    ::close(outputFd);
    return outcome;
}

}  // namespace skelseg
