// skelseg: one named stage of a run, timed and announced.
//
// A Stage is the RAII scope of one step of the pipeline: while it lives, the
// interrupter knows the stage by its name (progress display, InterrupterScope)
// and, when it ends, its wall and CPU time are added to the StageTimer under
// the same name (report.json "stages"). One object for both keeps the two
// names from drifting apart. Kernels may open their own InterrupterScope with
// the same name inside; the ProgressReporter announces a stage once.
//
//     {
//         Stage stage(timer, interrupter, "feature transform", true);
//         ft = featureTransform(sites, {threaded}, interrupter);
//     }
#pragma once

#include <chrono>

#include "engine/StageTimer.h"
#include "kernels/base/Interrupter.h"

namespace skelseg {

class Stage {
public:
    /// name: a string literal (the interrupter keeps the pointer); parallel:
    /// whether the stage's work runs in parallel loops (the report's serial
    /// share counts the others).
    Stage(StageTimer& timer, Interrupter& interrupter, const char* name, bool parallel);
    /// Adds the stage's time to the timer, also when it ends by an exception.
    ~Stage();
    Stage(const Stage&) = delete;
    Stage& operator=(const Stage&) = delete;

private:
    StageTimer& mTimer;
    const char* mName;
    bool mParallel;
    std::chrono::steady_clock::time_point mStart;
    double mCpuStart;
    InterrupterScope mScope;  // last: the interrupter hears of the stage inside the timing
};

}  // namespace skelseg
