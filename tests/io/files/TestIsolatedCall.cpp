// Tests for io/files/IsolatedCall.h: work in a child process, and how it ended.
#include "io/files/IsolatedCall.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <thread>
#include <vector>

#include "kernels/base/Error.h"
#include "tests/support/SanitizerAllocator.h"

namespace skelseg {
namespace {

using Ending = IsolatedCallOutcome::Ending;

/// Asks to stop once `after` has passed since it was made.
class StopAfter final : public Interrupter {
public:
    explicit StopAfter(std::chrono::milliseconds after)
        : mDeadline(std::chrono::steady_clock::now() + after) {}
    bool wasInterrupted(double) override { return std::chrono::steady_clock::now() > mDeadline; }

private:
    std::chrono::steady_clock::time_point mDeadline;
};

TEST(IsolatedCall, WorkThatReturnsGivesItsBytesAndChangesNothingHere) {
    int touched = 0;
    const std::string bytes = std::string("binary\0bytes", 12) + std::string(1 << 20, 'x');
    const IsolatedCallOutcome outcome = runIsolated([&] {
        touched = 1;
        return bytes;
    });
    EXPECT_EQ(outcome.ending, Ending::Finished);
    EXPECT_TRUE(outcome.message.empty());
    EXPECT_EQ(outcome.output, bytes);  // a megabyte, zero bytes included
    EXPECT_EQ(touched, 0);             // the child's memory is its own
}

TEST(IsolatedCall, WorkThatThrowsGivesItsMessage) {
    const IsolatedCallOutcome input = runIsolated([]() -> std::string {
        throw InputError("file.vdb", "cannot read OpenVDB data: bad size");
    });
    EXPECT_EQ(input.ending, Ending::Threw);
    EXPECT_EQ(input.message, "cannot read OpenVDB data: bad size");  // the problem, not the name
    const IsolatedCallOutcome other =
        runIsolated([]() -> std::string { throw std::runtime_error("boom"); });
    EXPECT_EQ(other.ending, Ending::Threw);
    EXPECT_EQ(other.message, "boom");
}

TEST(IsolatedCall, ACrashIsReportedWithItsSignal) {
    const IsolatedCallOutcome aborted = runIsolated([]() -> std::string { std::abort(); });
    EXPECT_EQ(aborted.ending, Ending::Crashed);
    EXPECT_EQ(aborted.signal, SIGABRT);
    EXPECT_EQ(signalName(aborted.signal), "SIGABRT");
    const IsolatedCallOutcome illegal = runIsolated([] {
        std::raise(SIGILL);
        return std::string();
    });
    EXPECT_EQ(illegal.ending, Ending::Crashed);
    EXPECT_EQ(illegal.signal, SIGILL);
    EXPECT_EQ(signalName(64), "signal 64");
}

TEST(IsolatedCall, AllocationBeyondTheMemoryLimitIsOutOfMemory) {
#if SKELSEG_TEST_SANITIZER_ALLOCATOR
    GTEST_SKIP() << "AddressSanitizer's allocator ends the process on a failed allocation";
#endif
    IsolatedCallOptions options;
    options.memoryLimit = 64u << 20;
    const auto allocate = [] {
        std::vector<char> block(std::size_t(1) << 30);
        std::memset(block.data(), 1, block.size());
        return std::string(1, block.back());
    };
    EXPECT_EQ(runIsolated(allocate, options).ending, Ending::OutOfMemory);
    options.memoryLimit = std::uint64_t(4) << 30;  // the control: the same work fits
    EXPECT_EQ(runIsolated(allocate, options).ending, Ending::Finished);
}

TEST(IsolatedCall, TheInterrupterStopsWorkThatRunsOn) {
    StopAfter interrupter(std::chrono::milliseconds(200));
    IsolatedCallOptions options;
    options.interrupter = &interrupter;
    const auto start = std::chrono::steady_clock::now();
    const IsolatedCallOutcome outcome = runIsolated(
        []() -> std::string {
            for (volatile unsigned long spin = 0;; spin = spin + 1) {
            }
        },
        options);
    EXPECT_EQ(outcome.ending, Ending::Interrupted);
    EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(200));
}

TEST(IsolatedCall, AChildThatUsesNoCpuIsTakenForStalledAndTheWorkRunsHere) {
    IsolatedCallOptions options;
    options.stallSeconds = 0.3;
    const IsolatedCallOutcome outcome = runIsolated(
        [] {
            ::pause();
            return std::string();
        },
        options);
    EXPECT_EQ(outcome.ending, Ending::NotIsolated);
}

TEST(IsolatedCall, ThreadsOfTheParentAreNotNeeded) {
    // A thread busy in the parent at the fork is not in the child; work that
    // does not wait on it finishes.
    std::atomic<bool> stop{false};
    std::thread busy([&] {
        while (!stop) std::this_thread::yield();
    });
    const IsolatedCallOutcome outcome = runIsolated([] { return std::string(1000, 'v'); });
    stop = true;
    busy.join();
    EXPECT_EQ(outcome.ending, Ending::Finished);
}

}  // namespace
}  // namespace skelseg
