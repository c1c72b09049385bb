#include "engine/python/EngineCall.h"

#include <tbb/task_arena.h>

#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>

namespace py = pybind11;

namespace skelseg {

namespace {

constexpr auto kPollInterval = std::chrono::milliseconds(50);
constexpr auto kProgressInterval = std::chrono::milliseconds(100);

py::object fractionObject(double fraction) {
    return fraction >= 0 ? py::object(py::float_(fraction)) : py::object(py::none());
}

}  // namespace

void runEngineCall(const std::function<void()>& work, CallerPolledInterrupter& interrupter,
                   int threads, const py::object& progress) {
    std::mutex mutex;
    std::condition_variable finished;
    bool done = false;
    std::exception_ptr engineError;
    std::optional<py::error_already_set> pythonError;
    const bool reportProgress = !progress.is_none();

    {
        py::gil_scoped_release release;
        std::thread worker([&] {
            try {
                if (threads > 0) {
                    tbb::task_arena arena(threads);
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

        unsigned reportedStage = 0;
        double reportedFraction = -2.0;
        auto lastReport = std::chrono::steady_clock::now() - kProgressInterval;
        for (;;) {
            {
                std::unique_lock<std::mutex> lock(mutex);
                if (finished.wait_for(lock, kPollInterval, [&] { return done; })) break;
            }
            if (pythonError) continue;  // cancelled: wait for the worker to stop
            py::gil_scoped_acquire acquire;
            if (PyErr_CheckSignals() != 0) {
                pythonError.emplace();
                interrupter.cancel();
                continue;
            }
            if (!reportProgress) continue;
            const auto now = std::chrono::steady_clock::now();
            const CallerPolledInterrupter::Progress p = interrupter.progress();
            const bool newStage = p.stageNumber != reportedStage;
            if (p.stageNumber == 0 || (!newStage && p.fraction == reportedFraction) ||
                (!newStage && now - lastReport < kProgressInterval))
                continue;
            try {
                progress(p.stage, fractionObject(p.fraction));
            } catch (py::error_already_set& error) {
                pythonError.emplace(std::move(error));
                interrupter.cancel();
            }
            reportedStage = p.stageNumber;
            reportedFraction = p.fraction;
            lastReport = now;
        }
        worker.join();
    }
    if (pythonError) throw std::move(*pythonError);
    if (engineError) std::rethrow_exception(engineError);
    if (reportProgress) progress("done", 1.0);
}

}  // namespace skelseg
