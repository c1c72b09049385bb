#include "engine/python/EngineCall.h"

#include <tbb/task_arena.h>

#include <pthread.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "engine/UsableThreads.h"

namespace py = pybind11;

namespace skelseg {

namespace {

constexpr auto kPollInterval = std::chrono::milliseconds(50);
constexpr auto kProgressInterval = std::chrono::milliseconds(100);

py::object fractionObject(double fraction) {
    return fraction >= 0 ? py::object(py::float_(fraction)) : py::object(py::none());
}

bool interpreterFinalizing() {
#if PY_VERSION_HEX >= 0x030D0000
    return Py_IsFinalizing() != 0;
#else
    return _Py_IsFinalizing() != 0;
#endif
}

/// Parks the calling thread for good without the GIL: the process is
/// exiting, and a daemon thread may never take the GIL again (CPython before
/// 3.14 ends a thread that asks for it with pthread_exit, whose unwinding
/// would destroy a running worker's std::thread and abort the process).
/// CPython 3.14 parks its own daemon threads in the same way.
[[noreturn]] void parkForExit(py::gil_scoped_release& release) {
    release.disarm();
    for (;;) std::this_thread::sleep_for(std::chrono::hours(1));
}

/// The engine calls under way, so that the interpreter's exit can stop them
/// and wait for their workers before it tears down what they use. Without
/// that wait, exit() ran the static destructors (oneTBB's among them) while
/// a cancelled worker was still unwinding through them: "pure virtual
/// method called", SIGABRT. Never destroyed: parked threads outlive every
/// static destructor.
struct RunningCalls {
    std::mutex mutex;
    std::condition_variable workerStopped;
    std::set<CallerPolledInterrupter*> interrupters;
    bool exiting = false;
};

std::atomic<RunningCalls*> gRunningCalls{nullptr};

/// A child of fork() has none of its parent's other threads, so none of
/// their calls: it starts with an empty list (the parent's may hold calls
/// that will never end in the child, and its mutex may be locked by a
/// thread the child does not have; without this, a child ending normally
/// waited for those calls forever). The parent's list is left as it is.
void forgetCallsInForkedChild() {
    gRunningCalls.store(new RunningCalls);
}

RunningCalls& runningCalls() {
    static const bool created = [] {
        gRunningCalls.store(new RunningCalls);
        pthread_atfork(nullptr, nullptr, &forgetCallsInForkedChild);
        return true;
    }();
    (void)created;
    return *gRunningCalls.load();
}

/// Registers a call; false when the interpreter is exiting and the caller
/// is not the main thread (which is then running the exit handlers itself,
/// so its calls finish before anything is torn down).
bool registerCall(CallerPolledInterrupter& interrupter, bool mainThread) {
    RunningCalls& calls = runningCalls();
    std::lock_guard<std::mutex> lock(calls.mutex);
    if (calls.exiting && !mainThread) return false;
    calls.interrupters.insert(&interrupter);
    return true;
}

/// Called once the call's worker has been joined.
void unregisterCall(CallerPolledInterrupter& interrupter) {
    RunningCalls& calls = runningCalls();
    std::lock_guard<std::mutex> lock(calls.mutex);
    calls.interrupters.erase(&interrupter);
    calls.workerStopped.notify_all();
}

bool exiting() {
    RunningCalls& calls = runningCalls();
    std::lock_guard<std::mutex> lock(calls.mutex);
    return calls.exiting;
}

}  // namespace

void stopEngineCallsForExit() {
    RunningCalls& calls = runningCalls();
    py::gil_scoped_release release;  // the callers may need it to notice
    std::unique_lock<std::mutex> lock(calls.mutex);
    calls.exiting = true;
    for (CallerPolledInterrupter* interrupter : calls.interrupters) interrupter->cancel();
    calls.workerStopped.wait(lock, [&] { return calls.interrupters.empty(); });
}

void runEngineCall(const std::function<void()>& work, CallerPolledInterrupter& interrupter,
                   int threads, const py::object& progress) {
    std::mutex mutex;
    std::condition_variable finished;
    bool done = false;
    std::exception_ptr engineError;
    std::optional<py::error_already_set> pythonError;
    const bool reportProgress = !progress.is_none();

    unsigned reportedStages = 0;
    double reportedFraction = -2.0;
    auto lastReport = std::chrono::steady_clock::now() - kProgressInterval;
    // Calls progress once for every stage started since the last report, in
    // order (the fraction known only for the current stage), and within a
    // stage when its fraction moved and kProgressInterval has passed. So a
    // run shorter than one poll still reports each of its stages.
    const auto report = [&](bool finalFlush) {
        const std::vector<std::string> started = interrupter.stagesSince(reportedStages);
        const CallerPolledInterrupter::Progress p = interrupter.progress();
        const unsigned seen = reportedStages + static_cast<unsigned>(started.size());
        // A stage started between the two reads: its fraction belongs to none of
        // `started`; the next poll reports it.
        const bool pCurrent = p.stageNumber == seen;
        const auto now = std::chrono::steady_clock::now();
        const bool due = !started.empty() || (pCurrent && p.fraction != reportedFraction &&
                                              now - lastReport >= kProgressInterval);
        if (seen == 0 || !due) return;
        try {
            for (std::size_t i = 0; i < started.size(); ++i) {
                const bool last = i + 1 == started.size() && pCurrent && !finalFlush;
                progress(started[i], last ? fractionObject(p.fraction) : py::none());
            }
            if (started.empty()) progress(p.stage, fractionObject(p.fraction));
        } catch (py::error_already_set& error) {
            pythonError.emplace(std::move(error));
            interrupter.cancel();
        }
        reportedStages = seen;
        reportedFraction = pCurrent ? p.fraction : -1.0;
        lastReport = now;
    };
    const bool mainThread = _PyOS_IsMainThread() != 0;
    {
        py::gil_scoped_release release;
        if (!registerCall(interrupter, mainThread)) parkForExit(release);
        std::thread worker([&] {
            try {
                if (threads > 0) {
                    tbb::task_arena arena(usableThreads(threads));
                    arena.execute(work);
                } else {
                    work();
                }
            } catch (...) {
                engineError = std::current_exception();
            }
            std::lock_guard<std::mutex> lock(mutex);
            done = true;
            finished.notify_all();
        });
        // Unwinding past the worker (pthread_exit's forced unwind when the
        // interpreter ends this thread) stops it first: a joinable
        // std::thread's destructor would abort the process.
        struct StopAtUnwind {
            CallerPolledInterrupter& interrupter;
            std::thread& worker;
            py::gil_scoped_release& release;
            ~StopAtUnwind() {
                if (!worker.joinable()) return;
                interrupter.cancel();
                worker.join();
                unregisterCall(interrupter);
                if (interpreterFinalizing()) release.disarm();
            }
        } stopAtUnwind{interrupter, worker, release};

        for (;;) {
            {
                std::unique_lock<std::mutex> lock(mutex);
                if (finished.wait_for(lock, kPollInterval, [&] { return done; })) break;
            }
            if (pythonError) continue;  // cancelled: wait for the worker to stop
            // (A shutdown that starts between this check and the GIL is rare;
            // stopAtUnwind below keeps even that from aborting.)
            if (interpreterFinalizing()) {
                interrupter.cancel();
                worker.join();
                unregisterCall(interrupter);
                parkForExit(release);
            }
            py::gil_scoped_acquire acquire;
            if (PyErr_CheckSignals() != 0) {
                pythonError.emplace();
                interrupter.cancel();
                continue;
            }
            if (reportProgress) report(false);
        }
        worker.join();
        unregisterCall(interrupter);
        // The interpreter began to exit during the call (stopEngineCallsForExit
        // cancelled it): a thread other than the main one never returns.
        if (!mainThread && exiting()) parkForExit(release);
    }
    if (pythonError) throw std::move(*pythonError);
    if (engineError) std::rethrow_exception(engineError);
    if (reportProgress) {
        report(true);  // the stages a short run started between two polls
        if (pythonError) throw std::move(*pythonError);
        progress("done", 1.0);
    }
}

}  // namespace skelseg
