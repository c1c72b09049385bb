// Tests for io/files/IsolatedCall.h: work in a child process, and how it ended.
#include "io/files/IsolatedCall.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
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
    SKELSEG_SKIP_WHERE_FAILED_ALLOCATIONS_ABORT();
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

// Work that runs out of memory under the limit may swallow the bad_alloc and
// fail in another way, or return what it has: either is the limit.
TEST(IsolatedCall, WorkThatReachedTheLimitIsOutOfMemoryHoweverItEnds) {
    SKELSEG_SKIP_WHERE_FAILED_ALLOCATIONS_ABORT();
    IsolatedCallOptions options;
    options.memoryLimit = 64u << 20;
    // Grows in blocks of 1 MB, as a parser reading node after node does.
    const auto growUntilRefused = [] {
        std::vector<std::unique_ptr<char[]>> blocks;
        try {
            for (int i = 0; i < 4096; ++i) {
                blocks.emplace_back(new char[1u << 20]);
                std::memset(blocks.back().get(), 1, 1u << 20);
            }
        } catch (const std::bad_alloc&) {
            return blocks.size();
        }
        return blocks.size();
    };
    const IsolatedCallOutcome swallowed = runIsolated(
        [&]() -> std::string {
            growUntilRefused();
            throw std::runtime_error("read past the end of the data");
        },
        options);
    EXPECT_EQ(swallowed.ending, Ending::OutOfMemory);
    EXPECT_TRUE(swallowed.reachedMemoryLimit);
    const IsolatedCallOutcome partial =
        runIsolated([&] { return std::to_string(growUntilRefused()); }, options);
    EXPECT_EQ(partial.ending, Ending::OutOfMemory);
    // malloc's failures reach no new-handler: a null pointer used is a crash.
    const IsolatedCallOutcome crashed = runIsolated(
        []() -> std::string {
            for (int i = 0; i < 4096; ++i) {
                void* block = std::malloc(1u << 20);
                if (!block) std::raise(SIGSEGV);
                std::memset(block, 1, 1u << 20);
            }
            return "";
        },
        options);
    EXPECT_EQ(crashed.ending, Ending::OutOfMemory);
    EXPECT_TRUE(crashed.reachedMemoryLimit);
    // The control: the same crash with little memory used is a crash.
    const IsolatedCallOutcome early = runIsolated(
        []() -> std::string {
            std::raise(SIGSEGV);
            return "";
        },
        options);
    EXPECT_EQ(early.ending, Ending::Crashed);
    EXPECT_FALSE(early.reachedMemoryLimit);
}

// A damaged file can ask for an absurd size at once: that allocation fails
// far from the limit, and the caller is told it was not the limit.
TEST(IsolatedCall, AnAbsurdAllocationIsNotTheLimit) {
    SKELSEG_SKIP_WHERE_FAILED_ALLOCATIONS_ABORT();
    IsolatedCallOptions options;
    options.memoryLimit = std::uint64_t(1) << 30;
    const IsolatedCallOutcome absurd = runIsolated(
        [] {
            std::vector<char> block(std::size_t(1) << 40);
            return std::string(1, block[0]);
        },
        options);
    EXPECT_EQ(absurd.ending, Ending::OutOfMemory);
    EXPECT_FALSE(absurd.reachedMemoryLimit);
    const IsolatedCallOutcome swallowed = runIsolated(
        []() -> std::string {
            try {
                std::vector<char> block(std::size_t(1) << 40);
            } catch (const std::bad_alloc&) {
            }
            throw std::runtime_error("read past the end of the data");
        },
        options);
    EXPECT_EQ(swallowed.ending, Ending::Threw);
    EXPECT_EQ(swallowed.message, "read past the end of the data");
}

// Libraries print where they like (c-blosc's "Error allocating memory!" goes
// to standard output); the caller's streams stay its own.
TEST(IsolatedCall, TheChildWritesNothingToTheCallersStreams) {
    int capture[2];
    ASSERT_EQ(::pipe(capture), 0);
    std::fflush(stdout);
    std::fflush(stderr);
    const int savedOut = ::dup(STDOUT_FILENO), savedErr = ::dup(STDERR_FILENO);
    ::dup2(capture[1], STDOUT_FILENO);
    ::dup2(capture[1], STDERR_FILENO);
    const IsolatedCallOutcome outcome = runIsolated([] {
        std::printf("to standard output\n");
        std::fprintf(stderr, "to standard error\n");
        std::fflush(nullptr);
        return std::string("done");
    });
    ::dup2(savedOut, STDOUT_FILENO);
    ::dup2(savedErr, STDERR_FILENO);
    ::close(savedOut);
    ::close(savedErr);
    ::close(capture[1]);
    std::string written;
    char buffer[256];
    for (ssize_t n; (n = ::read(capture[0], buffer, sizeof buffer)) > 0;)
        written.append(buffer, std::size_t(n));
    ::close(capture[0]);
    EXPECT_EQ(outcome.ending, Ending::Finished);
    EXPECT_EQ(outcome.output, "done");
    EXPECT_EQ(written, "");
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
