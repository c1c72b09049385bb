// skelseg: the cost model's CPU seconds in this machine's wall seconds, now
// (`skelseg segment --time-budget`, engine/TimeBudget.h).
//
// CostModel predicts the CPU seconds of a run at 2 threads; a budget counts
// wall seconds. How many wall seconds one CPU second takes depends on the
// machine and its load at the time of the run: on a quiet machine the run's
// threads share the work and its wall time is below its CPU time, on a
// shared one it is above. Comparing CPU seconds with the budget is
// therefore too cautious on a quiet machine and not cautious enough under
// load.
//
// The probe that precedes the choice is a short run of the same kernels
// (voxelising, feature transform, boundary graph, candidates) on this
// machine, just before the run: its wall seconds against the CPU seconds
// that ProbeCostModel predicts for its work say how fast the machine is now.
// The run's prediction is scaled by that ratio times the fitted ratio of a
// run's wall seconds to its probe's on the same machine (the probe
// parallelises less well than a full run), and the safety margin is the
// fit's margin for these calibrated predictions
// (bench/fit_budget_calibration.py, docs/performance.md "budget17").
// The probe's wall time is compared with a prediction, not with its own
// measured CPU time, because a batch runs inputs side by side: the process
// CPU during one input's probe includes the other inputs' work, and the
// probe's wall time is what those inputs slow down.
// The factor is clamped: a probe of a few milliseconds can be lucky or
// unlucky by more than the machine's load, and no calibration may promise
// more than two cores allow.
#pragma once

namespace skelseg {

// engine/TimeBudget.h, which includes this header for BudgetChoice.
struct WorkCounts;
struct CostModel;

/// CPU seconds of the mesh probe of planMeshRun (voxelising at the probe
/// resolution with a band of 1, countWork): a linear model in the mesh
/// faces, the probe's grid voxels and its object voxels, with the constants
/// that turn the probe's speed into the run's. Volumes are not calibrated:
/// their probe does no voxelising, and no benchmark set of volumes measured it.
struct ProbeCostModel {
    double seconds = 0.0;         // fixed per probe
    double perMeshFace = 0.0;     // voxelising: per-triangle work
    double perGridVoxel = 0.0;    // voxelising, feature transform
    double perObjectVoxel = 0.0;  // boundary graph, candidates
    /// A run's wall seconds per CPU second of CostModel when the probe took
    /// as many wall seconds as this model predicts (fitted).
    double runWallPerProbeWall = 1.0;
    /// Bounds of the factor applied to CostModel's predictions.
    double minimumFactor = 0.0;
    double maximumFactor = 0.0;
    /// Safety margin of the calibrated predictions (replaces
    /// CostModel::safetyMargin when calibrating).
    double safetyMargin = 0.0;
    /// The model fitted on the benchmark shapes (docs/performance.md).
    static ProbeCostModel fitted();
    double predictSeconds(const WorkCounts& probe) const;
};

/// What the probe measured and the factor derived from it; report.json
/// `time_budget.calibration`.
struct BudgetCalibration {
    bool enabled = false;                   // false: CPU seconds compared with wall
    double probeWallSeconds = 0.0;          // measured
    double probeCpuSeconds = 0.0;           // measured (process CPU; reported only)
    double probePredictedCpuSeconds = 0.0;  // ProbeCostModel
    double wallPerCpuSecond = 1.0;          // applied to CostModel's predictions
    bool clamped = false;                   // the factor hit a bound
    double safetyMargin = 0.0;              // used with the calibrated predictions
};

/// The calibration from a probe of `probe` work that took `probeWallSeconds`
/// (and `probeCpuSeconds` of process CPU, recorded only).
BudgetCalibration calibrateFromProbe(const ProbeCostModel& probeModel, const WorkCounts& probe,
                                     double probeWallSeconds, double probeCpuSeconds);

/// `model` in wall seconds: every cost term times
/// calibration.wallPerCpuSecond, and calibration.safetyMargin as its margin;
/// `model` itself when the calibration is not enabled.
CostModel calibratedCostModel(const CostModel& model, const BudgetCalibration& calibration);

}  // namespace skelseg
