#include "io/files/IsolatedCall.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <new>
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

[[noreturn]] void runChild(const std::function<void()>& work, int messageFd,
                           std::uint64_t memoryLimit, std::uint64_t inheritedData) {
    const int devNull = ::open("/dev/null", O_WRONLY);
    if (devNull >= 0) ::dup2(devNull, STDERR_FILENO);
    if (memoryLimit > 0 && inheritedData > 0) {
        const rlimit limit{inheritedData + memoryLimit, inheritedData + memoryLimit};
        ::setrlimit(RLIMIT_DATA, &limit);
    }
    const auto report = [&](const std::string& message) {
        const std::size_t size = std::min(message.size(), kMaxMessageBytes);
        for (std::size_t written = 0; written < size;) {
            const ssize_t n = ::write(messageFd, message.data() + written, size - written);
            if (n <= 0) break;
            written += std::size_t(n);
        }
    };
    try {
        work();
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

IsolatedCallOutcome runIsolated(const std::function<void()>& work,
                                const IsolatedCallOptions& options) {
    IsolatedCallOutcome outcome;
    // Read before the fork: the child must not open files it may not need.
    const std::uint64_t inheritedData = options.memoryLimit > 0 ? dataSegmentBytes() : 0;
    int pipeFds[2];
    if (::pipe2(pipeFds, O_CLOEXEC) != 0) return outcome;
    const pid_t child = ::fork();
    if (child < 0) {
        ::close(pipeFds[0]);
        ::close(pipeFds[1]);
        return outcome;
    }
    if (child == 0) {
        ::close(pipeFds[0]);
        runChild(work, pipeFds[1], options.memoryLimit, inheritedData);
    }
    ::close(pipeFds[1]);
    const int messageFd = pipeFds[0];

    using Clock = std::chrono::steady_clock;
    long long lastTicks = cpuTicks(child);
    Clock::time_point lastProgress = Clock::now();
    int status = 0;
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
        const pid_t done = ::waitpid(child, &status, WNOHANG);
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
            while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
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
    if (!ended) return outcome;
    if (killed) {
        outcome.ending = IsolatedCallOutcome::Ending::Interrupted;
    } else if (stalled) {
        outcome.ending = IsolatedCallOutcome::Ending::NotIsolated;
    } else if (WIFSIGNALED(status)) {
        outcome.ending = IsolatedCallOutcome::Ending::Crashed;
        outcome.signal = WTERMSIG(status);
    } else if (WIFEXITED(status) && WEXITSTATUS(status) == kExitFinished) {
        outcome.ending = IsolatedCallOutcome::Ending::Finished;
    } else if (WIFEXITED(status) && WEXITSTATUS(status) == kExitOutOfMemory) {
        outcome.ending = IsolatedCallOutcome::Ending::OutOfMemory;
    } else {
        outcome.ending = IsolatedCallOutcome::Ending::Threw;
    }
    return outcome;
}

}  // namespace skelseg
