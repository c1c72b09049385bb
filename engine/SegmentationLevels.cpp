#include "engine/SegmentationLevels.h"

#include <algorithm>
#include <unordered_set>

#include "engine/Stage.h"
#include "kernels/SegmentNesting.h"

namespace skelseg {

LevelClock::LevelClock(LevelSeconds& seconds)
    : mSeconds(seconds), mStart(std::chrono::steady_clock::now()), mCpuStart(processCpuSeconds()) {}

LevelClock::~LevelClock() {
    mSeconds.wall +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - mStart).count();
    mSeconds.cpu += processCpuSeconds() - mCpuStart;
}

namespace {

/// The shared points with the junction test of a level at `tauArea`: only
/// isJunctionPoint reads robustRims downstream, so kJunctionRims stands for
/// "three or more".
std::vector<SkeletonPoint> pointsAtLevel(const std::vector<SkeletonPoint>& shared, double tauArea) {
    std::vector<SkeletonPoint> points = shared;
    for (SkeletonPoint& p : points)
        p.robustRims = p.junctionArea >= tauArea
                           ? std::max(p.robustRims, kJunctionRims)
                           : std::min<std::uint8_t>(p.robustRims, kJunctionRims - 1);
    return points;
}

}  // namespace

void placeFinerLevelCuts(ObjectState& state) {
    ObjectSegmentation& out = state.out;
    // The coarsest level's results, restored at the end.
    const double coarseTau = out.tauArea, coarseNoise = out.noiseArea;
    std::vector<SkeletonPoint> shared = std::move(state.points);
    SkeletonGraph coarseSkeleton = std::move(state.skeleton);
    CutPlan coarsePlan = std::move(state.plan);
    std::vector<std::vector<std::uint32_t>> coarseLoops = std::move(state.cutLoops);
    std::vector<std::vector<std::array<int, 3>>> coarsePolylines = std::move(out.cutLoops);
    // report.json lists the coarsest level's cuts only (the finer levels' are
    // in their own cuts.ply).
    std::vector<CutInfo> coarseCuts = std::move(out.cuts);
    // Crop voxels of every coarser level's cut points: the joint level keeps
    // its distance from them as from the finest level's own.
    std::vector<std::uint32_t> cutVoxels;
    for (std::uint32_t node : coarsePlan.cutNodes)
        cutVoxels.push_back(shared[coarseSkeleton.point[node]].voxel);

    const std::size_t first = state.firstJunctionLevel(), end = state.endJunctionLevels();
    for (std::size_t k = end; k-- > first;) {
        ObjectLevelWork& level = state.finerLevels[k];
        LevelClock clock(level.seconds);
        out.tauArea = level.tauArea;
        out.noiseArea = level.noiseArea;
        if (level.noiseArea != coarseNoise) {
            // Another noise area changes which rims count: measure again.
            Stage stage(state.timer, state.interrupter, "path sets, rims, areas, sigma", true);
            SkeletonMeasureOptions options = state.measureOptions();
            options.sigmaTau = -1.0;
            state.points =
                measureSkeleton(state.graph, state.candidates, options, nullptr, state.interrupter);
        } else {
            state.points = pointsAtLevel(shared, level.tauArea);
        }
        state.cutLoops.clear();
        out.cutLoops.clear();
        out.cuts.clear();
        buildObjectSkeletonGraph(state);
        placeObjectCuts(state);
        // Every coarser cut stays: the next coarser level's set holds them all.
        const auto& coarserLoops = k + 1 < end ? state.finerLevels[k + 1].cutLoops : coarseLoops;
        const auto& coarserPolylines =
            k + 1 < end ? out.finerLevels[k + 1].cutLoops : coarsePolylines;
        const std::size_t own = state.cutLoops.size();
        for (std::size_t i = 0; i < coarserLoops.size(); ++i)
            if (std::find(state.cutLoops.begin(), state.cutLoops.begin() + std::ptrdiff_t(own),
                          coarserLoops[i]) == state.cutLoops.begin() + std::ptrdiff_t(own)) {
                state.cutLoops.push_back(coarserLoops[i]);
                out.cutLoops.push_back(coarserPolylines[i]);
            }
        if (k == first && state.parameters.joints) placeJointLevelCuts(state, cutVoxels);
        for (std::uint32_t node : state.plan.cutNodes)
            cutVoxels.push_back(state.points[state.skeleton.point[node]].voxel);
        level.cutLoops = std::move(state.cutLoops);
        out.finerLevels[k].cutLoops = std::move(out.cutLoops);
        state.cutLoops.clear();
        out.cutLoops.clear();
    }

    out.tauArea = coarseTau;
    out.noiseArea = coarseNoise;
    state.points = std::move(shared);
    state.skeleton = std::move(coarseSkeleton);
    state.plan = std::move(coarsePlan);
    state.cutLoops = std::move(coarseLoops);
    out.cutLoops = std::move(coarsePolylines);
    out.cuts = std::move(coarseCuts);
}

void placeJointLevelCuts(ObjectState& state, const std::vector<std::uint32_t>& coarserCutVoxels) {
    // The finest level's own cuts, and the nodes of this skeleton at the
    // coarser levels' cut points.
    std::vector<std::uint32_t> existing = state.plan.cutNodes;
    const std::unordered_set<std::uint32_t> voxels(coarserCutVoxels.begin(),
                                                   coarserCutVoxels.end());
    for (std::uint32_t n = 0; n < state.skeleton.nodeCount(); ++n)
        if (voxels.count(state.points[state.skeleton.point[n]].voxel) &&
            std::find(existing.begin(), existing.end(), n) == existing.end())
            existing.push_back(n);
    const std::size_t junctionCuts = state.cutLoops.size();
    const std::size_t reportedCuts = state.out.cuts.size();
    placeJointCuts(state, existing);
    ObjectLevelWork& joint = state.finerLevels.front();
    joint.cutLoops = state.cutLoops;
    state.out.finerLevels.front().cutLoops = state.out.cutLoops;
    state.cutLoops.resize(junctionCuts);
    state.out.cutLoops.resize(junctionCuts);
    state.out.cuts.resize(reportedCuts);
}

void splitSingleTauJointLevels(ObjectState& state) {
    // The top-level cuts are the junction rule's, then the joint cuts.
    std::size_t junctionCuts = 0;
    while (junctionCuts < state.out.cuts.size() &&
           state.out.cuts[junctionCuts].kind == CutKind::Junction)
        ++junctionCuts;
    ObjectLevelWork& joint = state.finerLevels.front();
    ObjectLevelWork& junction = state.finerLevels.back();
    joint.cutLoops = state.cutLoops;
    state.out.finerLevels.front().cutLoops = state.out.cutLoops;
    junction.cutLoops.assign(state.cutLoops.begin(),
                             state.cutLoops.begin() + std::ptrdiff_t(junctionCuts));
    state.out.finerLevels.back().cutLoops.assign(
        state.out.cutLoops.begin(), state.out.cutLoops.begin() + std::ptrdiff_t(junctionCuts));
}

void labelFinerLevels(ObjectState& state) {
    const SegmentationParameters& p = state.parameters;
    const std::size_t levels = state.finerLevels.size();
    // Without a list, the joint level's own labelling is the top-level one
    // and the coarsest level (the last) has no coarser level to nest in.
    const bool topIsJointLevel = p.joints && p.finerTaus.empty();
    for (std::size_t k = levels; k-- > 0;) {
        ObjectLevelWork& level = state.finerLevels[k];
        LevelClock clock(level.seconds);
        const bool isJointLevel = p.joints && k == 0;
        SurfaceSegments own;
        if (isJointLevel && topIsJointLevel) {
            own = state.segments;
        } else {
            Stage stage(state.timer, state.interrupter, "labelling", false);
            const double smallest =
                isJointLevel ? p.jointOptions.minSegmentTauFraction * level.tauArea : level.tauArea;
            own = labelSurface(state.graph, level.cutLoops, std::max(smallest, level.noiseArea));
        }
        if (topIsJointLevel && k + 1 == levels) {
            level.segments = std::move(own);
        } else {
            Stage stage(state.timer, state.interrupter, "level nesting", false);
            const SurfaceSegments& coarser =
                k + 1 < levels ? state.finerLevels[k + 1].segments : state.segments;
            NestedSegments nested = nestSegments(state.graph, coarser, own);
            level.segments = std::move(nested.segments);
            level.parent = std::move(nested.parent);
            level.movedNodes = nested.movedNodes;
        }
        {
            Stage stage(state.timer, state.interrupter, "interior labels", true);
            level.localLabels = objectInteriorLabels(state, level.segments);
        }
        throwIfInterrupted(state.interrupter);
    }
}

}  // namespace skelseg
