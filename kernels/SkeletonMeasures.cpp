#include "kernels/SkeletonMeasures.h"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>

#include "kernels/ComponentGrowth.h"
#include "kernels/Geodesicness.h"
#include "kernels/RimCount.h"
#include "kernels/base/ParallelFor.h"

namespace skelseg {

namespace {

constexpr float kSheetRatio = 20.0f;
constexpr float kSheetMinimumBound = 32.0f;

/// Everything one thread needs; built lazily, once per thread.
struct Workspace {
    Workspace(const BoundaryGraph& graph, const Landmarks* landmarks)
        : search(graph, landmarks),
          sigmaSearch(graph, landmarks),
          rims(graph),
          grower(graph),
          geodesicness(graph),
          inSet(graph.nodeCount()) {}
    GeodesicSearch search, sigmaSearch;
    PathCache cache;
    RimCounter rims;
    ComponentGrower grower;
    GeodesicnessEvaluator geodesicness;
    GenerationMarks inSet;
    std::vector<std::uint32_t> gamma;
    std::uint64_t rimTests = 0, growthSteps = 0, sigmaEvaluations = 0, repeats = 0;

    /// Measures by feature set. Everything measure() computes is a function
    /// of the candidate's feature set alone, and many candidates repeat the
    /// set of a nearby voxel (docs/performance.md has the share): those copy
    /// the answer instead of redoing path sets, rims, areas and sigma. Direct-mapped (a new set
    /// evicts the slot's old one), so memory stays fixed; the cache changes cost, never results.
    struct Remembered {
        std::uint8_t featureCount = 0;  // 0: empty slot
        bool isPoint = false;
        std::array<std::uint32_t, 8> feature{};
        SkeletonPoint point;
    };
    static constexpr std::size_t kRememberedSlots = std::size_t(1) << 14;
    std::vector<Remembered> remembered{kRememberedSlots};
};

std::size_t featureSetSlot(const SkeletonCandidate& c) {
    std::uint64_t h = c.featureCount;
    for (std::uint32_t i = 0; i < c.featureCount; ++i)
        h = (h ^ c.feature[i]) * 0x9E3779B97F4A7C15ull;
    return std::size_t(h >> 40) & (Workspace::kRememberedSlots - 1);
}

/// Gamma(p) into ws.gamma via the cache; returns rho_S and the pair.
float collectPathSet(Workspace& ws, const SkeletonCandidate& c, std::uint32_t& a,
                     std::uint32_t& b) {
    ws.gamma.clear();
    ws.inSet.nextGeneration();
    float rhoS = -1.0f;
    a = b = kNoNode;
    const BoundaryGraph& g = ws.search.graph();
    // Sheets are not limbs: a feature pair whose geodesic is more than
    // kSheetRatio times the widest feature gap (the chord across the part)
    // wraps around a thin wall (a cup, a vase, a flat plate). Such a voxel is
    // not a curve-skeleton point of a limb, and bounding the search keeps
    // thin-walled shapes from costing a search around the whole rim per voxel.
    float gap = 0.0f;
    for (std::uint32_t i = 0; i < c.featureCount; ++i)
        for (std::uint32_t j = i + 1; j < c.featureCount; ++j)
            gap = std::max(gap, g.euclidean(c.feature[i], c.feature[j]));
    const float bound = std::max(kSheetRatio * gap, kSheetMinimumBound);
    for (std::uint32_t i = 0; i < c.featureCount; ++i)
        for (std::uint32_t j = i + 1; j < c.featureCount; ++j) {
            if (g.component[c.feature[i]] != g.component[c.feature[j]])
                continue;  // cavity: no path
            const PathCache::Entry& e = ws.cache.path(ws.search, c.feature[i], c.feature[j], bound);
            if (e.length == kUnreachable) return -1.0f;  // longer than the bound: a sheet
            if (e.length > rhoS) rhoS = e.length, a = c.feature[i], b = c.feature[j];
            const std::uint32_t* nodes = ws.cache.nodes(e);
            for (std::uint32_t k = 0; k < e.count; ++k)
                if (ws.inSet.insert(nodes[k])) ws.gamma.push_back(nodes[k]);
        }
    return rhoS;
}

/// The measures of one candidate (rho_C exact when options.exactRhoC).
/// Returns true when p is in C.
bool measure(Workspace& ws, const SkeletonCandidate& c, std::uint32_t candidateIndex,
             const SkeletonMeasureOptions& options, SkeletonPoint& out) {
    std::uint32_t a, b;
    const float rhoS = collectPathSet(ws, c, a, b);
    if (rhoS <= 0.0f) return false;
    ++ws.rimTests;
    const RimPieces& pieces = ws.rims.countRims(ws.gamma);
    if (pieces.pieceCount < 2) return false;

    // A tau past 2^64 voxels (--tau 1e20) is a valid "never cut"; converting
    // it to an integer is undefined, so it caps at the largest area.
    const auto areaCap = [](double area) {
        constexpr double kBeyondAnyArea = 18446744073709551616.0;  // 2^64
        return area >= kBeyondAnyArea ? std::numeric_limits<std::uint64_t>::max()
                                      : std::uint64_t(std::ceil(area));
    };
    const std::uint64_t noise = areaCap(std::max(1.0, options.noiseArea));
    const std::uint64_t tauArea = areaCap(std::max(0.0, options.tau));
    const std::uint64_t cap =
        options.exactRhoC ? ComponentGrower::kExactArea : std::max(noise, tauArea);
    const ComponentAreas& areas = ws.grower.grow(ws.rims, cap);
    ws.growthSteps += areas.growthSteps;

    std::uint32_t rims = 0, robust = 0;
    std::vector<std::uint8_t> componentCounts(areas.componentCount, 0);
    std::uint32_t distinct = 0;
    std::uint64_t largestAreas[3] = {0, 0, 0};  // of the counting rims, decreasing
    for (std::uint32_t piece = 0; piece < pieces.pieceCount; ++piece) {
        const std::uint32_t comp = areas.componentOfPiece[piece];
        const std::uint64_t area = areas.area[comp];
        if (area < noise) continue;
        if (componentCounts[comp] && options.surfaceHasGenusZero) continue;
        ++rims;
        if (area >= tauArea) ++robust;
        std::uint64_t carried = area;
        for (std::uint64_t& kept : largestAreas)
            if (carried > kept) std::swap(carried, kept);
        if (!componentCounts[comp]) ++distinct, componentCounts[comp] = 1;
    }
    if (rims < 2) return false;

    out.voxel = c.voxel;
    out.candidate = candidateIndex;
    out.rhoS = rhoS;
    out.featureA = a;
    out.featureB = b;
    out.rims = std::uint8_t(std::min<std::uint32_t>(rims, 255));
    out.robustRims = std::uint8_t(std::min<std::uint32_t>(robust, 255));
    out.junctionArea = rims >= 3 ? double(largestAreas[2]) : -1.0;
    out.isHandle = distinct < rims;
    out.rhoC = out.isHandle ? std::numeric_limits<double>::infinity() : double(areas.rhoC);
    out.rhoCExact = out.isHandle || areas.rhoCExact;
    out.sigma = -1.0f;
    if (options.evaluateSigma &&
        out.rhoC >=
            (options.sigmaTau >= 0.0 ? std::min(options.sigmaTau, options.tau) : options.tau)) {
        ++ws.sigmaEvaluations;
        const GeodesicnessResult g = ws.geodesicness.evaluate(ws.rims, a, b, ws.sigmaSearch);
        out.sigma = g.sigma;
        out.loopLength = g.loopLength;
    }
    return true;
}

}  // namespace

std::vector<std::uint32_t> pathSet(const BoundaryGraph& graph, const SkeletonCandidate& candidate,
                                   GeodesicSearch& search, float* rhoS, std::uint32_t* a,
                                   std::uint32_t* b) {
    std::vector<std::uint32_t> nodes, path;
    float best = -1.0f;
    std::uint32_t bestA = kNoNode, bestB = kNoNode;
    (void)graph;
    for (std::uint32_t i = 0; i < candidate.featureCount; ++i)
        for (std::uint32_t j = i + 1; j < candidate.featureCount; ++j) {
            const std::uint32_t u = candidate.feature[i], v = candidate.feature[j];
            const float length = search.shortestPath(std::min(u, v), std::max(u, v), &path);
            if (length == kUnreachable) continue;
            if (length > best) best = length, bestA = u, bestB = v;
            nodes.insert(nodes.end(), path.begin(), path.end());
        }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    if (rhoS) *rhoS = best;
    if (a) *a = bestA;
    if (b) *b = bestB;
    return nodes;
}

bool measurePoint(const BoundaryGraph& graph, const SkeletonCandidate& candidate,
                  const SkeletonMeasureOptions& options, SkeletonPoint& out) {
    Workspace ws(graph, options.landmarks);
    SkeletonMeasureOptions exact = options;
    exact.exactRhoC = true;
    return measure(ws, candidate, 0, exact, out);
}

struct SkeletonMeasureWorkspaces::Impl {
    tbb::enumerable_thread_specific<std::unique_ptr<Workspace>> local;
    /// What the workspaces were built for: their caches hold answers for
    /// this graph, landmarks and options only.
    const BoundaryGraph* graph = nullptr;
    SkeletonMeasureOptions options;

    bool builtFor(const BoundaryGraph& g, const SkeletonMeasureOptions& o) const {
        return graph == &g && options.landmarks == o.landmarks && options.tau == o.tau &&
               options.noiseArea == o.noiseArea && options.sigmaTau == o.sigmaTau &&
               options.exactRhoC == o.exactRhoC && options.evaluateSigma == o.evaluateSigma &&
               options.surfaceHasGenusZero == o.surfaceHasGenusZero;
    }
};

SkeletonMeasureWorkspaces::SkeletonMeasureWorkspaces() : mImpl(std::make_unique<Impl>()) {}
SkeletonMeasureWorkspaces::~SkeletonMeasureWorkspaces() = default;

std::vector<SkeletonPoint> measureSkeleton(const BoundaryGraph& graph,
                                           const std::vector<SkeletonCandidate>& candidates,
                                           const SkeletonMeasureOptions& options,
                                           SkeletonMeasureStats* stats, Interrupter& interrupter) {
    SkeletonMeasureWorkspaces fresh;
    return measureSkeleton(graph, candidates, options, fresh, stats, interrupter);
}

std::vector<SkeletonPoint> measureSkeleton(const BoundaryGraph& graph,
                                           const std::vector<SkeletonCandidate>& candidates,
                                           const SkeletonMeasureOptions& options,
                                           SkeletonMeasureWorkspaces& kept,
                                           SkeletonMeasureStats* stats, Interrupter& interrupter) {
    InterrupterScope scope(interrupter, "path sets, rims, areas, sigma");
    const std::size_t n = candidates.size();
    std::vector<SkeletonPoint> slots(n);
    std::vector<std::uint8_t> isPoint(n, 0);
    SkeletonMeasureWorkspaces::Impl& impl = kept.impl();
    if (!impl.builtFor(graph, options)) {
        impl.local.clear();
        impl.graph = &graph;
        impl.options = options;
    }
    auto& workspaces = impl.local;
    // Counters are per call: a kept workspace starts each call at zero.
    for (auto& slot : workspaces) {
        if (!slot) continue;
        Workspace& ws = *slot;
        ws.search.counters = SearchCounters{};
        ws.sigmaSearch.counters = SearchCounters{};
        ws.cache.hits = ws.cache.misses = 0;
        ws.rimTests = ws.growthSteps = ws.sigmaEvaluations = ws.repeats = 0;
    }
    std::atomic<bool> stop{false};
    std::atomic<std::size_t> done{0};

    auto range = [&](std::size_t begin, std::size_t end) {
        auto& slot = workspaces.local();
        if (!slot) slot = std::make_unique<Workspace>(graph, options.landmarks);
        Workspace& ws = *slot;
        for (std::size_t i = begin; i < end; ++i) {
            if ((i & 63) == 0) {
                if (stop.load(std::memory_order_relaxed)) return;
                if (interrupter.wasInterrupted(double(done.load(std::memory_order_relaxed)) /
                                               double(std::max<std::size_t>(n, 1)))) {
                    stop = true;
                    return;
                }
            }
            const SkeletonCandidate& c = candidates[i];
            Workspace::Remembered& memo = ws.remembered[featureSetSlot(c)];
            if (memo.featureCount == c.featureCount &&
                std::equal(c.feature.begin(), c.feature.begin() + c.featureCount,
                           memo.feature.begin())) {
                ++ws.repeats;
                isPoint[i] = memo.isPoint ? 1 : 0;
                if (memo.isPoint) {
                    slots[i] = memo.point;
                    slots[i].voxel = c.voxel;
                    slots[i].candidate = std::uint32_t(i);
                }
                continue;
            }
            isPoint[i] = measure(ws, c, std::uint32_t(i), options, slots[i]) ? 1 : 0;
            memo.featureCount = c.featureCount;
            std::copy(c.feature.begin(), c.feature.begin() + c.featureCount, memo.feature.begin());
            memo.isPoint = isPoint[i] != 0;
            if (memo.isPoint) memo.point = slots[i];
        }
        done += end - begin;
    };
    // Small ranges: a measure near the skeleton costs a hundred times one
    // far from it, so the adaptive split's long ranges left one thread
    // measuring the last of them alone (docs/performance.md, "speed8").
    parallelForSmallRanges(n, range, options.threaded, 8);
    if (stop) throwInterrupted(interrupter);

    std::vector<SkeletonPoint> points;
    for (std::size_t i = 0; i < n; ++i)
        if (isPoint[i]) points.push_back(slots[i]);
    if (stats) {
        SkeletonMeasureStats s;
        for (const auto& slot : workspaces) {
            if (!slot) continue;
            s.search += slot->search.counters;
            s.sigmaSearch += slot->sigmaSearch.counters;
            s.pathCacheHits += slot->cache.hits;
            s.pathCacheMisses += slot->cache.misses;
            s.rimTests += slot->rimTests;
            s.componentGrowthSteps += slot->growthSteps;
            s.sigmaEvaluations += slot->sigmaEvaluations;
            s.repeatedFeatureSets += slot->repeats;
        }
        s.skeletonPoints = points.size();
        *stats = s;
    }
    return points;
}

}  // namespace skelseg
