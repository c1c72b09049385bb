// skelseg: a result within a time budget (`skelseg segment --time-budget SEC`).
//
// Unlike --time-limit, which stops a run that takes too long, the budget
// picks a run that fits. A cheap probe measures the work counters of the
// first stages (grid, object and boundary voxels, skeleton candidates) on a
// coarse grid; a cost model fitted on the benchmark shapes
// (bench/fit_cost_model.py, docs/performance.md) predicts the seconds of a
// full run from them (CPU seconds at 2 threads); for meshes the probe's own
// wall time turns them into this machine's wall seconds now
// (engine/BudgetCalibration.h), which the wall-clock budget, counted from
// the start of the process, is compared with, with a safety margin chosen
// from the fit's residuals; the engine then takes
//   - for meshes: the largest resolution up to --resolution that fits;
//   - for volumes: the finest of 1, 2 or 4 times coarser grids that fits,
//     none finer than --max-memory allows
//     (coarsenMask: a coarse voxel is object when any of its fine voxels is;
//     refineLabels gives each fine object voxel its coarse voxel's label).
// preview.png costs about as much as a small run on a large mesh, so it is
// skipped (and report.json says so) when it would take more than a quarter of
// the budget left after the probe, or when the run reaches it too late.
// When even the coarsest choice does not fit, the budget becomes the run's
// time limit: it stops as --time-limit does (exit 3, no output), or, if it
// ends within the budget after all, gives its output with report.json's
// `fits` false. A run whose
// choice fits finishes even if it overruns the prediction (a late answer is
// worth more than none; report.json gives predicted and actual seconds).
// A first choice that leaves time over is followed by a finer pass
// (BudgetRefinement below), which the caller stops at the budget and falls
// back from.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "engine/BudgetCalibration.h"
#include "engine/Segmenter.h"
#include "engine/StageTimer.h"
#include "io/mesh/MeshIO.h"
#include "io/mesh/MeshVoxelizer.h"
#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// What a run will work on; doubles, since they are also scaled predictions.
struct WorkCounts {
    double gridVoxels = 0;
    double objectVoxels = 0;
    double boundaryVoxels = 0;
    double candidates = 0;
    double meshFaces = 0;  // 0 for volumes
};

/// The counters of `mask`: boundary graph, feature transform and candidates
/// over the whole grid (all objects at once). Costs about what these stages
/// cost in a run; meant for a coarse probe grid.
WorkCounts countWork(const MaskVolume& mask, bool threaded,
                     Interrupter& interrupter = nullInterrupter());

/// Predicted seconds of `skelseg segment` (all outputs but preview.png) from the work
/// counters: a linear model in the grid voxels, the object voxels, the
/// candidates times the typical path length (square root of the boundary
/// voxels) and the mesh faces, fitted by bench/fit_cost_model.py.
struct CostModel {
    double seconds = 0.0;             // fixed per run
    double perGridVoxel = 0.0;        // voxelising, labels, outputs
    double perObjectVoxel = 0.0;      // feature transform, candidates, interior labels
    double perCandidatePath = 0.0;    // path sets: candidates * sqrt(boundary voxels)
    double perMeshFace = 0.0;         // reading, voxelising, face labels
    double candidateExponent = 2.0;   // candidates grow as resolution^this
    double previewSeconds = 0.0;      // preview.png: fixed part
    double previewPerTriangle = 0.0;  // preview.png: per triangle drawn
    /// A choice fits when predicted * (1 + safetyMargin) is within the
    /// seconds left: the fit's relative residuals, so that a run the model
    /// under-predicts still ends within the budget.
    double safetyMargin = 0.0;
    /// The model fitted on the benchmark shapes (docs/performance.md).
    static CostModel fitted();
    double predictSeconds(const WorkCounts& work) const;
    /// Predicted seconds of preview.png for a scene of `triangles` triangles.
    double predictPreviewSeconds(double triangles) const;
    /// The counters of the same shape on a grid `factor` times finer
    /// (voxels grow with factor^3, boundary with factor^2).
    WorkCounts scale(const WorkCounts& work, double factor) const;
};

/// What the budget chose.
struct BudgetChoice {
    double budgetSeconds = 0.0;
    double probeSeconds = 0.0;         // spent on the probe
    double predictedSeconds = 0.0;     // of the chosen run, probe excluded (calibrated: wall)
    double predictedCpuSeconds = 0.0;  // the same, as CostModel predicts it (CPU at 2 threads)
    int resolution = 0;                // meshes: the chosen --resolution
    int coarsening = 1;                // volumes: 1, 2 or 4
    bool coarsened = false;            // resolution below --resolution, or coarsening > 1
    bool fits = true;                  // false: even the coarsest choice is predicted over
    double safetyMargin = 0.0;         // the margin used in the choice (calibrated or not)
    double previewSeconds = 0.0;       // predicted cost of preview.png
    bool writePreview = true;          // false: preview.png skipped to fit the budget
    double secondsLeft = 0.0;          // of the budget when the probe ended
    /// Meshes: the largest resolution --max-memory allows when below
    /// --resolution (no choice, first or finer, goes above it); 0: no cap.
    int memoryCapResolution = 0;
    /// Meshes: the same for a finer pass, which runs beside the first pass's
    /// result (SegmentInput.h heldResultBytes); 0: no cap.
    int finerMemoryCapResolution = 0;
    /// Volumes: the finest coarsening --max-memory allows when above 1, for
    /// the first pass and for a finer pass that runs beside the first
    /// pass's result (SegmentInput.h CoarseningMemoryCaps); 0: no cap, above
    /// 4: no finer pass fits.
    int memoryCapCoarsening = 0;
    int finerMemoryCapCoarsening = 0;
    WorkCounts probeWork;           // the probe's counters
    BudgetCalibration calibration;  // meshes: from the probe; volumes: not enabled
};

/// The finer pass of a budget run. The first choice is cautious (its margin
/// covers the shapes the cost model under-predicts most, and the model's
/// growth with the resolution is steeper than most runs'), so on most inputs
/// the first pass ends with most of the budget left. The first pass's own
/// stage times then predict a finer choice of the same input, each stage
/// grown by its own power of the resolution (stageGrowthExponent) and the
/// time outside the stages kept as it was. The finest
/// choice whose prediction, with kRefinementMargin, fits in what is left
/// runs as a second pass, stopped at the budget less the reserve; if it is
/// stopped, the first pass's outputs are given. report.json:
/// `time_budget.refinement`.
struct BudgetRefinement {
    bool tried = false;
    std::string reason;             // why not tried ("" when tried)
    BudgetChoice choice;            // the finer choice (when tried)
    int firstResolution = 0;        // meshes: the first choice's
    int firstCoarsening = 1;        // volumes: the first choice's
    double firstPassSeconds = 0.0;  // measured: the first pass after its probe
    double deadlineSeconds = 0.0;   // the second pass stops here (budget clock)
    bool kept = false;              // the second pass finished by its deadline
    /// Not kept because the second pass needed more than --max-memory (a
    /// volume's finer grid; a mesh's second voxelisation): the first pass's
    /// output is given, as when the deadline stops it.
    bool overMemory = false;
};

/// What the first pass of a budget run took.
struct FirstPassTimes {
    double seconds = 0.0;      // wall, from the end of the probe to the last output
    double readSeconds = 0.0;  // reading the input (before the probe), which a second pass repeats
    /// Each stage of the pass: wall seconds and stageGrowthExponent().
    std::vector<std::pair<double, double>> stages;
};

/// How a stage's time grows with the resolution r, as r^exponent, rounded
/// up from the cost growth measured from 64 to 400 (docs/performance.md,
/// "Cost growth"): 0 for work per mesh face (checking the mesh, the face
/// labels, a mesh's surfaces and preview, the small PLY files), 2 for
/// voxelising (per face and per voxel of the surface band; measured 0.4 to
/// 0.8), 2.5 for the stages on the surface and the skeleton (landmarks, path
/// sets, the skeleton graph, cut placement; measured 2.1 to 2.3), and 3 for
/// every stage over the grid (the feature transform, measured 3.0) and any
/// stage not named here. Stages a second pass does not run (the probe) or
/// that run inside another (the viewer's writer) give a negative exponent:
/// left out.
double stageGrowthExponent(const std::string& stage, bool mesh);

/// A second pass's prediction times 1 + this must fit.
constexpr double kRefinementMargin = 0.15;
/// Kept from the budget for stopping a second pass and putting the first
/// pass's outputs back: this share of the budget, plus kRefinementReserveSeconds.
constexpr double kRefinementReserve = 0.03;
constexpr double kRefinementReserveSeconds = 0.05;
/// Meshes: a second pass only for a resolution at least this many times the first's.
constexpr double kRefinementMinimumGain = 1.25;

/// The first pass's times from its stage timer: `seconds` from the end of
/// its probe to its last output, the stages that read the input apart
/// (they ran before the probe), the others with their growth exponents.
FirstPassTimes firstPassTimes(const std::vector<StageTiming>& stages, bool mesh, double seconds);

/// Predicted wall seconds of a second pass on a grid `factor` times finer
/// (per axis) than the first's: see BudgetRefinement.
double predictFinerPass(const FirstPassTimes& first, double factor);

/// What a finer pass keeps from the budget: kRefinementReserve of it plus
/// kRefinementReserveSeconds.
double refinementReserve(double budgetSeconds);

/// The whole plan after a first pass under `first` whose stages took
/// `stages`, on the budget's clock that started at `budgetStart` (the
/// budget is first.budgetSeconds): planBudgetRefinement() on the first
/// pass's times and what is left now, with the deadline (the budget less
/// refinementReserve()) when a finer pass is tried. A caller with an earlier
/// limit of its own lowers the deadline to it. `maximumResolution` is
/// lowered to first.memoryCapResolution and first.finerMemoryCapResolution
/// when they are set.
BudgetRefinement planFinerPass(const BudgetChoice& first, bool mesh, int maximumResolution,
                               const std::vector<StageTiming>& stages,
                               std::chrono::steady_clock::time_point budgetStart);

/// Plans the second pass after a first pass under `first` that took `times`,
/// with `secondsLeft` of the budget left; `maximumResolution` is the mesh's
/// --resolution. The finer choice is the largest resolution (meshes, from
/// the maximum down in steps of about 10%, at least kRefinementMinimumGain
/// times the first) or the smallest coarsening (volumes, none below
/// first.finerMemoryCapCoarsening) whose prediction fits; none when the first choice was not
/// coarsened, did not fit, or nothing finer fits (refinement.reason says which).
BudgetRefinement planBudgetRefinement(const BudgetChoice& first, int maximumResolution,
                                      const FirstPassTimes& times, double secondsLeft);

/// Whether preview.png fits: its predicted cost, with the safety margin, is
/// at most a quarter of `secondsLeft`. Sets choice.previewSeconds and
/// choice.writePreview; returns the seconds left for the run itself.
double planPreview(const CostModel& model, double triangles, double secondsLeft,
                   BudgetChoice& choice);

/// Meshes: the largest resolution in [minimum, maximum] whose predicted time
/// fits in `seconds`, from counters measured at `probeResolution` (the mesh
/// faces counted once). Resolutions are tried in steps of about 10%.
BudgetChoice chooseMeshResolution(const CostModel& model, const WorkCounts& probe,
                                  int probeResolution, int maximum, int minimum, double seconds);

/// Volumes: the smallest coarsening of {1, 2, 4}, none below
/// `finestCoarsening`, that fits, from counters of the volume coarsened
/// `probeCoarsening` times.
BudgetChoice chooseVolumeCoarsening(const CostModel& model, const WorkCounts& probe,
                                    int probeCoarsening, double seconds, int finestCoarsening = 1);

/// `factor` times coarser mask: a coarse voxel is object when any of its
/// factor^3 fine voxels is. Geometry: voxels `factor` times larger.
/// `threaded`: slabs of coarse z in parallel (the same result either way).
MaskVolume coarsenMask(const MaskVolume& mask, int factor, bool threaded = true);

/// Labels on the fine grid: each object voxel of `fine` takes the label of
/// its coarse voxel; background stays 0. Geometry of `fine`.
LabelVolume refineLabels(const LabelVolume& coarse, const MaskVolume& fine, int factor,
                         bool threaded = true);

/// A result segmented on a `factor` times coarser volume, brought back to
/// the input grid `fine`: labels per fine voxel (refineLabels), voxel
/// positions scaled (to within half a coarse voxel), segment voxel counts
/// recounted.
void refineSegmentationResult(SegmentationResult& result, const MaskVolume& fine, int factor);

/// "resolution 128 (3.2 s predicted, budget 5.0 s)" or "volume 2x coarser
/// (...)": the choice in words, for the preview title and report.json.
std::string describeBudgetChoice(const BudgetChoice& choice);

/// Resolution of the mesh probe: the counts scale well from it
/// (docs/performance.md), and it costs little beyond the per-face work.
constexpr int kProbeResolution = 64;

/// The coarsest resolution a budget chooses for a mesh.
constexpr int kSmallestBudgetResolution = 16;

/// The whole plan for a mesh: voxelises at a probe resolution
/// (kProbeResolution, or --resolution when lower; without the topology
/// separations), counts the work, calibrates `model` to wall seconds with
/// the probe's time when `probeModel` is given (calibrateFromProbe;
/// otherwise CPU seconds are compared with the budget), decides the preview
/// (planPreview) and chooses a resolution from `voxelize.resolution` down to
/// kSmallestBudgetResolution that fits in `seconds` minus the probe's own time and the preview's.
BudgetChoice planMeshRun(const TriangleMesh& mesh, const VoxelizeOptions& voxelize, double seconds,
                         const CostModel& model, const ProbeCostModel* probeModel,
                         Interrupter& interrupter = nullInterrupter());

/// The whole plan for a volume: counts the work on the volume coarsened 2
/// times (or on the volume itself when it is small) and chooses a
/// coarsening, none finer than `finestCoarsening` (what --max-memory allows).
BudgetChoice planVolumeRun(const MaskVolume& mask, double seconds, const CostModel& model,
                           int finestCoarsening = 1, Interrupter& interrupter = nullInterrupter());

}  // namespace skelseg
