#include "engine/SegmentationLevels.h"

#include <algorithm>

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
/// robustRims >= 3 is read downstream, so 3 stands for "three or more".
std::vector<SkeletonPoint> pointsAtLevel(const std::vector<SkeletonPoint>& shared, double tauArea) {
    std::vector<SkeletonPoint> points = shared;
    for (SkeletonPoint& p : points)
        p.robustRims = p.junctionArea >= tauArea ? std::max<std::uint8_t>(p.robustRims, 3)
                                                 : std::min<std::uint8_t>(p.robustRims, 2);
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

    const std::size_t levels = state.finerLevels.size();
    for (std::size_t k = levels; k-- > 0;) {
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
        const auto& coarserLoops = k + 1 < levels ? state.finerLevels[k + 1].cutLoops : coarseLoops;
        const auto& coarserPolylines =
            k + 1 < levels ? out.finerLevels[k + 1].cutLoops : coarsePolylines;
        const std::size_t own = state.cutLoops.size();
        for (std::size_t i = 0; i < coarserLoops.size(); ++i)
            if (std::find(state.cutLoops.begin(), state.cutLoops.begin() + std::ptrdiff_t(own),
                          coarserLoops[i]) == state.cutLoops.begin() + std::ptrdiff_t(own)) {
                state.cutLoops.push_back(coarserLoops[i]);
                out.cutLoops.push_back(coarserPolylines[i]);
            }
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

void labelFinerLevels(ObjectState& state) {
    const std::size_t levels = state.finerLevels.size();
    for (std::size_t k = levels; k-- > 0;) {
        ObjectLevelWork& level = state.finerLevels[k];
        LevelClock clock(level.seconds);
        SurfaceSegments own;
        {
            Stage stage(state.timer, state.interrupter, "labelling", false);
            own =
                labelSurface(state.graph, level.cutLoops, std::max(level.tauArea, level.noiseArea));
        }
        {
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
