#include "engine/TimeBudget.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "engine/ResultOnInputGrid.h"
#include "engine/StageTimer.h"
#include "kernels/BoundaryGraph.h"
#include "kernels/FeatureTransform.h"
#include "kernels/SkeletonCandidates.h"
#include "kernels/base/ParallelFor.h"

namespace skelseg {

WorkCounts countWork(const MaskVolume& mask, bool threaded, Interrupter& interrupter) {
    WorkCounts work;
    work.gridVoxels = double(mask.dims().voxelCount());
    for (std::uint8_t v : mask.values()) work.objectVoxels += v != 0;
    if (work.objectVoxels == 0) return work;
    const Volume<std::uint32_t> ft =
        featureTransform(boundaryVoxels(mask, {threaded}), {threaded}, interrupter);
    const BoundaryGraph graph = buildBoundaryGraph(mask, {threaded}, interrupter);
    work.boundaryVoxels = double(graph.nodeCount());
    CandidateOptions options;
    options.threaded = threaded;
    CandidateStats stats;
    selectSkeletonCandidates(mask, ft, graph, options, &stats, interrupter);
    work.candidates = double(stats.candidates);
    return work;
}

CostModel CostModel::fitted() {
    // bench/fit_cost_model.py --target cpu --resolutions 64,128,192 on the
    // shared shapes and PSB models (docs/performance.md, "--time-budget on
    // the current build": data, residuals). CPU seconds at 2 threads, not
    // wall: on a shared machine a wall fit measures the machine's load. The
    // margin is the 90th percentile of the leave-one-mesh-out
    // under-prediction.
    CostModel m;
    m.seconds = 0.0777;
    m.perGridVoxel = 2.72e-07;
    m.perObjectVoxel = 0.0;
    m.perCandidatePath = 3.15e-08;
    m.perMeshFace = 1.04e-05;
    m.candidateExponent = 2.9;
    m.previewSeconds = 0.6;
    m.previewPerTriangle = 2.92e-06;
    m.safetyMargin = 0.64;
    return m;
}

double CostModel::predictPreviewSeconds(double triangles) const {
    return previewSeconds + previewPerTriangle * triangles;
}

double planPreview(const CostModel& model, double triangles, double secondsLeft,
                   BudgetChoice& choice) {
    choice.previewSeconds = model.predictPreviewSeconds(triangles);
    const double withMargin = choice.previewSeconds * (1.0 + model.safetyMargin);
    choice.writePreview = withMargin <= 0.25 * secondsLeft;
    return choice.writePreview ? secondsLeft - withMargin : secondsLeft;
}

double CostModel::predictSeconds(const WorkCounts& w) const {
    return seconds + perGridVoxel * w.gridVoxels + perObjectVoxel * w.objectVoxels +
           perCandidatePath * w.candidates * std::sqrt(w.boundaryVoxels) +
           perMeshFace * w.meshFaces;
}

WorkCounts CostModel::scale(const WorkCounts& w, double factor) const {
    WorkCounts s = w;
    s.gridVoxels *= factor * factor * factor;
    s.objectVoxels *= factor * factor * factor;
    s.boundaryVoxels *= factor * factor;
    s.candidates *= std::pow(factor, candidateExponent);
    return s;
}

BudgetChoice chooseMeshResolution(const CostModel& model, const WorkCounts& probe,
                                  int probeResolution, int maximum, int minimum, double seconds) {
    BudgetChoice choice;
    choice.budgetSeconds = seconds;
    minimum = std::min(minimum, maximum);
    for (int r = maximum;; r = std::max(minimum, int(std::floor(r * 0.9)))) {
        choice.resolution = r;
        choice.predictedSeconds =
            model.predictSeconds(model.scale(probe, double(r) / double(probeResolution)));
        choice.fits = choice.predictedSeconds * (1.0 + model.safetyMargin) <= seconds;
        if (choice.fits || r == minimum) break;
    }
    choice.coarsened = choice.resolution < maximum;
    choice.safetyMargin = model.safetyMargin;
    return choice;
}

BudgetChoice chooseVolumeCoarsening(const CostModel& model, const WorkCounts& probe,
                                    int probeCoarsening, double seconds, int finestCoarsening) {
    BudgetChoice choice;
    choice.budgetSeconds = seconds;
    for (int factor : {1, 2, 4}) {
        if (factor < finestCoarsening && factor < 4) continue;
        choice.coarsening = factor;
        choice.predictedSeconds =
            model.predictSeconds(model.scale(probe, double(probeCoarsening) / double(factor)));
        choice.fits = choice.predictedSeconds * (1.0 + model.safetyMargin) <= seconds;
        if (choice.fits) break;
    }
    choice.coarsened = choice.coarsening > 1;
    choice.safetyMargin = model.safetyMargin;
    return choice;
}

double stageGrowthExponent(const std::string& stage, bool mesh) {
    if (stage == "time budget probe" || stage == "write segments.glb, viewer.html") return -1.0;
    if (stage.rfind("read ", 0) == 0 || stage == "check mesh" || stage == "face labels" ||
        stage == "write skeleton.ply, cuts.ply" ||
        (mesh && stage == "segment surfaces and preview"))
        return 0.0;
    if (stage.rfind("voxelise", 0) == 0) return 2.0;
    if (stage == "landmarks" || stage == "path sets, rims, areas, sigma" ||
        stage == "skeleton graph" || stage == "cut placement")
        return 2.5;
    return 3.0;
}

FirstPassTimes firstPassTimes(const std::vector<StageTiming>& stages, bool mesh, double seconds) {
    FirstPassTimes times;
    times.seconds = seconds;
    for (const StageTiming& t : stages) {
        if (t.name.rfind("read ", 0) == 0) {
            times.readSeconds += t.wallSeconds;
            continue;
        }
        const double exponent = stageGrowthExponent(t.name, mesh);
        if (exponent >= 0.0) times.stages.emplace_back(t.wallSeconds, exponent);
    }
    return times;
}

double predictFinerPass(const FirstPassTimes& first, double factor) {
    double staged = 0.0, predicted = first.readSeconds;
    for (const auto& [seconds, exponent] : first.stages) {
        staged += seconds;
        predicted += seconds * std::pow(factor, exponent);
    }
    // Time outside the stages (starting threads, the flow graph, waiting on
    // the writers) is kept as it was; overlapping writers make `staged`
    // exceed the pass, which only makes the prediction more cautious.
    return predicted + std::max(0.0, first.seconds - staged);
}

BudgetRefinement planBudgetRefinement(const BudgetChoice& first, int maximumResolution,
                                      const FirstPassTimes& times, double secondsLeft) {
    BudgetRefinement plan;
    plan.firstPassSeconds = times.seconds;
    plan.firstResolution = first.resolution;
    plan.firstCoarsening = first.coarsening;
    const bool mesh = first.resolution > 0;
    if (!first.fits) {
        plan.reason = "the first choice did not fit";
        return plan;
    }
    if (!first.coarsened) {
        plan.reason = "the first choice was not coarsened";
        return plan;
    }
    const double usable = secondsLeft - refinementReserve(first.budgetSeconds);
    double predicted = 0.0;
    const auto fits = [&](double factor) {
        predicted = predictFinerPass(times, factor);
        return predicted * (1.0 + kRefinementMargin) <= usable;
    };
    BudgetChoice finer = first;
    bool found = false;
    if (mesh) {
        const bool memoryCapped =
            first.memoryCapResolution > 0 || first.finerMemoryCapResolution > 0;
        const int least = int(std::ceil(kRefinementMinimumGain * first.resolution));
        if (maximumResolution < least) {
            plan.reason = memoryCapped ? "--max-memory allows nothing finer"
                                       : "--resolution allows nothing finer";
            return plan;
        }
        for (int r = maximumResolution; r >= least && !found; r = int(std::floor(r * 0.9))) {
            if (fits(double(r) / double(first.resolution))) {
                finer.resolution = r;
                // Below --resolution when --max-memory capped it.
                finer.coarsened = r < maximumResolution || memoryCapped;
                found = true;
            }
        }
    } else {
        const int finest = std::max(1, first.finerMemoryCapCoarsening);
        if (finest >= first.coarsening) {
            plan.reason = "--max-memory allows nothing finer";
            return plan;
        }
        for (int factor = finest; factor < first.coarsening && !found; factor *= 2) {
            if (fits(double(first.coarsening) / double(factor))) {
                finer.coarsening = factor;
                finer.coarsened = factor > 1;
                found = true;
            }
        }
    }
    if (!found) {
        plan.reason = "nothing finer fits in the time left";
        return plan;
    }
    finer.predictedSeconds = predicted;
    finer.predictedCpuSeconds = 0.0;  // not the cost model's: from the first pass
    finer.safetyMargin = kRefinementMargin;
    finer.fits = true;
    plan.tried = true;
    plan.choice = finer;
    return plan;
}

MaskVolume coarsenMask(const MaskVolume& mask, int factor, bool threaded) {
    const Dims d = mask.dims();
    const Dims cd{(d.x + factor - 1) / factor, (d.y + factor - 1) / factor,
                  (d.z + factor - 1) / factor};
    MaskVolume coarse(cd, 0);
    parallelForEach(
        cd.z,
        [&](int cz) {
            for (int z = cz * factor; z < std::min(d.z, (cz + 1) * factor); ++z)
                for (int y = 0; y < d.y; ++y)
                    for (int x = 0; x < d.x; ++x)
                        if (mask(x, y, z)) coarse(x / factor, y / factor, cz) = 1;
        },
        threaded);
    VolumeGeometry g = mask.geometry;
    const double centre = 0.5 * (factor - 1);
    g.origin = mask.geometry.indexToWorld(centre, centre, centre);
    for (auto& axis : g.directions)
        for (double& c : axis) c *= factor;
    coarse.geometry = g;
    return coarse;
}

LabelVolume refineLabels(const LabelVolume& coarse, const MaskVolume& fine, int factor,
                         bool threaded) {
    const Dims d = fine.dims();
    LabelVolume labels(d, 0);
    labels.geometry = fine.geometry;
    parallelForEach(
        d.z,
        [&](int z) {
            for (int y = 0; y < d.y; ++y)
                for (int x = 0; x < d.x; ++x)
                    if (fine(x, y, z)) labels(x, y, z) = coarse(x / factor, y / factor, z / factor);
        },
        threaded);
    return labels;
}

namespace {
double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace

double refinementReserve(double budgetSeconds) {
    return kRefinementReserve * budgetSeconds + kRefinementReserveSeconds;
}

BudgetRefinement planFinerPass(const BudgetChoice& first, bool mesh, int maximumResolution,
                               const std::vector<StageTiming>& stages,
                               std::chrono::steady_clock::time_point budgetStart) {
    const double elapsed = secondsSince(budgetStart);
    // first.secondsLeft is what the budget had left when the probe ended.
    const double firstPass = elapsed - (first.budgetSeconds - first.secondsLeft);
    for (int cap : {first.memoryCapResolution, first.finerMemoryCapResolution})
        if (cap > 0) maximumResolution = std::min(maximumResolution, cap);
    BudgetRefinement plan =
        planBudgetRefinement(first, maximumResolution, firstPassTimes(stages, mesh, firstPass),
                             first.budgetSeconds - elapsed);
    if (plan.tried)
        plan.deadlineSeconds = first.budgetSeconds - refinementReserve(first.budgetSeconds);
    return plan;
}

BudgetChoice planMeshRun(const TriangleMesh& mesh, const VoxelizeOptions& voxelize, double seconds,
                         const CostModel& cpuModel, const ProbeCostModel* probeModel,
                         Interrupter& interrupter) {
    const auto start = std::chrono::steady_clock::now();
    const double cpuStart = processCpuSeconds();
    VoxelizeOptions probeOptions = voxelize;
    probeOptions.resolution = std::min(voxelize.resolution, kProbeResolution);
    // Separating contacts and self-overlaps moves a few voxels and costs as
    // much as the rest of the probe on a large mesh: the counts do without,
    // and inside/outside alone needs the narrowest distance band.
    probeOptions.keepMeshTopology = false;
    probeOptions.bandWidth = 1.0;
    WorkCounts probe =
        countWork(voxelizeMesh(mesh, probeOptions, interrupter), voxelize.threaded, interrupter);
    probe.meshFaces = double(mesh.faceCount);
    const double spent = secondsSince(start);
    BudgetCalibration calibration;
    if (probeModel)
        calibration = calibrateFromProbe(*probeModel, probe, spent, processCpuSeconds() - cpuStart);
    const CostModel model = calibratedCostModel(cpuModel, calibration);
    BudgetChoice preview;
    const double left = planPreview(model, double(mesh.triangles.size()), seconds - spent, preview);
    BudgetChoice choice =
        chooseMeshResolution(model, probe, probeOptions.resolution, voxelize.resolution,
                             kSmallestBudgetResolution, left);
    choice.budgetSeconds = seconds;
    choice.probeSeconds = spent;
    choice.secondsLeft = seconds - spent;
    choice.calibration = calibration;
    choice.probeWork = probe;
    choice.predictedCpuSeconds = choice.predictedSeconds / calibration.wallPerCpuSecond;
    choice.previewSeconds = preview.previewSeconds;
    choice.writePreview = preview.writePreview;
    return choice;
}

BudgetChoice planVolumeRun(const MaskVolume& mask, double seconds, const CostModel& model,
                           int finestCoarsening, Interrupter& interrupter) {
    const auto start = std::chrono::steady_clock::now();
    const bool small = mask.dims().voxelCount() <= std::uint64_t(64) * 64 * 64;
    const int probeCoarsening = small ? 1 : 2;
    const WorkCounts probe = countWork(small ? mask : coarsenMask(mask, 2), true, interrupter);
    const double spent = secondsSince(start);
    // The preview draws the segment surfaces: about two triangles per
    // boundary voxel of the full grid.
    BudgetChoice preview;
    const double left =
        planPreview(model, 2.0 * model.scale(probe, double(probeCoarsening)).boundaryVoxels,
                    seconds - spent, preview);
    BudgetChoice choice =
        chooseVolumeCoarsening(model, probe, probeCoarsening, left, finestCoarsening);
    choice.budgetSeconds = seconds;
    choice.probeSeconds = spent;
    choice.secondsLeft = seconds - spent;
    choice.probeWork = probe;
    choice.predictedCpuSeconds = choice.predictedSeconds;
    choice.previewSeconds = preview.previewSeconds;
    choice.writePreview = preview.writePreview;
    return choice;
}

void refineSegmentationResult(SegmentationResult& result, const MaskVolume& fine, int factor) {
    // Every level the same way, so the levels still nest (each fine voxel
    // takes its coarse voxel's label at every level).
    moveResultToInputGrid(
        result, [&](const LabelVolume& labels) { return refineLabels(labels, fine, factor); },
        [&](const std::array<int, 3>& v) {
            return std::array<int, 3>{v[0] * factor + factor / 2, v[1] * factor + factor / 2,
                                      v[2] * factor + factor / 2};
        });
}

std::string describeBudgetChoice(const BudgetChoice& choice) {
    char buffer[160];
    if (choice.coarsening > 1)
        std::snprintf(buffer, sizeof buffer, "volume %dx coarser (%.1f s predicted, budget %.1f s)",
                      choice.coarsening, choice.predictedSeconds, choice.budgetSeconds);
    else if (choice.resolution > 0)
        std::snprintf(buffer, sizeof buffer, "resolution %d (%.1f s predicted, budget %.1f s)",
                      choice.resolution, choice.predictedSeconds, choice.budgetSeconds);
    else  // a volume kept at its own grid: it has no resolution to name
        std::snprintf(buffer, sizeof buffer,
                      "volume at its own grid (%.1f s predicted, budget %.1f s)",
                      choice.predictedSeconds, choice.budgetSeconds);
    return buffer;
}

}  // namespace skelseg
