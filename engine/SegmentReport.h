// skelseg: report.json of `skelseg segment`.
//
// The report is the last output: it holds the input and grid, the
// parameters, per-object counts and work counters, junctions and critical
// points, the segments, every stage's time (the names of engine/Stage.h
// scopes), the memory figures and the warnings (stages: docs/outputs.md).
// The process CPU time and the peak resident size are the
// process's: when several runs share a process at once, they count all of them.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "engine/SegmentCommand.h"
#include "engine/SegmentOutput.h"
#include "engine/StageTimer.h"
#include "engine/TimeBudget.h"

namespace skelseg {

/// Figures of the run as a whole, measured by the caller.
struct SegmentRunFigures {
    int threads = 1;
    std::uint64_t memoryLimit = 0;
    double wallSeconds = 0.0;              // from the start of the command
    double cpuSeconds = 0.0;               // process CPU time since the start of the command
    bool previewSkippedForBudget = false;  // --time-budget left no time for preview.png
    /// --time-budget: the finer pass, planned or not (time_budget.refinement).
    std::optional<BudgetRefinement> budgetRefinement;
};

/// The warning of a run whose preview.png --time-budget skipped (stderr and
/// report.json "warnings").
std::string previewSkippedWarning(double budgetSeconds);

/// A volume's voxel shape in report.json's "input": `voxel_steps` (the
/// length of each voxel step of the input's grid) and `cubic_voxels` (null,
/// or the cubic grid it was segmented on: `grid`, `voxel_size`, `scale`,
/// kernels/CubicVoxels.h).
void addVoxelAspect(nlohmann::json& input, const SegmentedShape& shape);

/// report.json's content; "input" describes options.input. The Python
/// module's result holds it too, with its own "input" (ResultReport.h).
nlohmann::json segmentReport(const SegmentCommandOptions& options, const SegmentedShape& shape,
                             const std::vector<StageTiming>& timings,
                             const SegmentRunFigures& figures);

/// The text of report.json (indented, ending in a newline).
std::string segmentReportJson(const SegmentCommandOptions& options, const SegmentedShape& shape,
                              const std::vector<StageTiming>& timings,
                              const SegmentRunFigures& figures);

}  // namespace skelseg
