#include "kernels/SkeletonBand.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "kernels/BoundaryGraph.h"
#include "kernels/FeatureTransform.h"
#include "kernels/PathSearch.h"
#include "kernels/base/Error.h"
#include "kernels/base/ParallelFor.h"

namespace skelseg {

void addMeasureStats(SkeletonMeasureStats& total, const SkeletonMeasureStats& part) {
    total.search += part.search;
    total.pathCacheHits += part.pathCacheHits;
    total.pathCacheMisses += part.pathCacheMisses;
    total.rimTests += part.rimTests;
    total.componentGrowthSteps += part.componentGrowthSteps;
    total.sigmaEvaluations += part.sigmaEvaluations;
    total.sigmaSearch += part.sigmaSearch;
    total.repeatedFeatureSets += part.repeatedFeatureSets;
    total.skeletonPoints += part.skeletonPoints;
}

namespace {

/// Measures candidates[batch[i]] and appends the points found to `found`
/// with their candidate index rewritten to the full list.
void measureBatch(const BoundaryGraph& graph, const std::vector<SkeletonCandidate>& candidates,
                  const std::vector<std::uint32_t>& batch, const SkeletonMeasureOptions& options,
                  SkeletonMeasureWorkspaces& workspaces, SkeletonMeasureStats& stats,
                  Interrupter& interrupter, std::vector<SkeletonPoint>& found,
                  std::vector<SkeletonPoint>& newInTau) {
    std::vector<SkeletonCandidate> subset;
    subset.reserve(batch.size());
    for (std::uint32_t i : batch) subset.push_back(candidates[i]);
    SkeletonMeasureStats part;
    std::vector<SkeletonPoint> points =
        measureSkeleton(graph, subset, options, workspaces, &part, interrupter);
    addMeasureStats(stats, part);
    newInTau.clear();
    for (SkeletonPoint& p : points) {
        p.candidate = batch[p.candidate];
        if (p.rhoC >= options.tau) newInTau.push_back(p);
        found.push_back(p);
    }
}

/// Marks, in `measured`, every candidate within `radius` (Chebyshev) of the
/// fine voxels [lo, hi] (inclusive box); appends the newly marked ones.
void markBox(const std::vector<SkeletonCandidate>& candidates, const Dims& dims,
             std::array<int, 3> lo, std::array<int, 3> hi, int radius,
             std::vector<std::uint8_t>& measured, std::vector<std::uint32_t>& batch) {
    const std::uint32_t nx = std::uint32_t(dims.x), ny = std::uint32_t(dims.y);
    const int x0 = std::max(lo[0] - radius, 0), x1 = std::min(hi[0] + radius, dims.x - 1);
    // Candidates are sorted by voxel index, so each row of the box is one
    // contiguous run found by one binary search.
    for (int z = std::max(lo[2] - radius, 0); z <= std::min(hi[2] + radius, dims.z - 1); ++z)
        for (int y = std::max(lo[1] - radius, 0); y <= std::min(hi[1] + radius, dims.y - 1); ++y) {
            const std::uint32_t row = nx * (std::uint32_t(y) + ny * std::uint32_t(z));
            const std::uint32_t first = row + std::uint32_t(x0), last = row + std::uint32_t(x1);
            auto it = std::lower_bound(
                candidates.begin(), candidates.end(), first,
                [](const SkeletonCandidate& c, std::uint32_t v) { return c.voxel < v; });
            for (; it != candidates.end() && it->voxel <= last; ++it) {
                const std::uint32_t i = std::uint32_t(it - candidates.begin());
                if (!measured[i]) measured[i] = 1, batch.push_back(i);
            }
        }
}

/// The mask at half the resolution: coarse voxel c covers the fine voxels
/// 2c - 1 and 2c on each axis (any object voxel makes it object, which keeps
/// thin limbs; coarse voxel 0 covers the fine padding, so the coarse grid is
/// padded too).
MaskVolume halveMask(const MaskVolume& mask, bool threaded) {
    const Dims d = mask.dims();
    MaskVolume coarse(Dims{d.x / 2 + 2, d.y / 2 + 2, d.z / 2 + 2}, 0);
    // One task per coarse slice: coarse slice cz covers the fine slices
    // 2cz - 1 and 2cz, so no two tasks write the same coarse voxel.
    parallelFor(
        d.z / 2 + 2,
        [&](int cz0, int cz1) {
            for (int cz = cz0; cz < cz1; ++cz)
                for (int z = std::max(2 * cz - 1, 0); z <= std::min(2 * cz, d.z - 1); ++z)
                    for (int y = 0; y < d.y; ++y)
                        for (int x = 0; x < d.x; ++x)
                            if (mask(x, y, z)) coarse((x + 1) / 2, (y + 1) / 2, cz) = 1;
        },
        threaded, 4);
    return coarse;
}

/// What the search at half the resolution saw: its simplified skeleton, and
/// which coarse voxels it examined at all (candidates).
struct CoarseView {
    std::vector<std::array<int, 3>> skeleton;  // coarse voxels with rho_C >= the scaled tau
    MaskVolume candidate;                      // 1 at every coarse candidate
};

}  // namespace

namespace {

std::vector<SkeletonPoint> bandSearch(
    const BoundaryGraph& graph, const std::vector<SkeletonCandidate>& candidates,
    const MaskVolume& mask, const Volume<std::uint32_t>& featureTransform,
    const SkeletonMeasureOptions& options, const SkeletonBandOptions& band, int level,
    SkeletonBandStats& bandStats, SkeletonMeasureStats& stats, Interrupter& interrupter);

/// The search on the mask at half the resolution, itself a band search while
/// it has more than band.exhaustiveBelow candidates (each level then costs
/// about an eighth of the one above).
CoarseView coarseSearch(const MaskVolume& mask, const SkeletonMeasureOptions& options,
                        const SkeletonBandOptions& band, int level, SkeletonBandStats& bandStats,
                        SkeletonMeasureStats& stats, Interrupter& interrupter) {
    const MaskVolume coarse = halveMask(mask, options.threaded);
    const Dims cd = coarse.dims();
    const BoundaryGraphOptions graphOptions{options.threaded};
    const Volume<std::uint32_t> ft =
        featureTransform(boundaryVoxels(coarse, graphOptions), {options.threaded}, interrupter);
    const BoundaryGraph graph = buildBoundaryGraph(coarse, graphOptions, interrupter);
    CandidateOptions candidateOptions;
    candidateOptions.threaded = options.threaded;
    const std::vector<SkeletonCandidate> candidates =
        selectSkeletonCandidates(coarse, ft, graph, candidateOptions, nullptr, interrupter);
    const Landmarks landmarks = computeLandmarks(graph, options.threaded, interrupter);
    // Areas shrink by four at half the resolution; tauShare < 1 keeps
    // branches that are close to tau at full resolution.
    SkeletonMeasureOptions coarseOptions = options;
    coarseOptions.landmarks = &landmarks;
    coarseOptions.tau = options.tau / 4.0 * band.coarseTauShare;
    coarseOptions.noiseArea = std::max(1.0, std::min(options.noiseArea / 4.0, coarseOptions.tau));
    coarseOptions.exactRhoC = false;
    coarseOptions.evaluateSigma = false;  // the coarse view keeps only voxels and rho_C
    // Halving can close a gap into a handle; the coarse view stays a superset.
    coarseOptions.surfaceHasGenusZero = false;
    bandStats.coarseCandidates += candidates.size();
    bandStats.levels = std::max(bandStats.levels, std::uint32_t(level + 1));
    SkeletonMeasureStats coarseStats;
    std::vector<SkeletonPoint> points;
    // Halving stops shrinking a grid of about 4 voxels (padding), so tiny
    // grids are always measured whole.
    if (candidates.size() > band.exhaustiveBelow && std::min({cd.x, cd.y, cd.z}) > 8) {
        points = bandSearch(graph, candidates, coarse, ft, coarseOptions, band, level + 1,
                            bandStats, coarseStats, interrupter);
    } else {
        points = measureSkeleton(graph, candidates, coarseOptions, &coarseStats, interrupter);
        bandStats.coarseMeasured += candidates.size();
    }
    coarseStats.skeletonPoints = 0;  // not points of the result
    addMeasureStats(stats, coarseStats);
    CoarseView view;
    const std::uint32_t nx = std::uint32_t(cd.x), ny = std::uint32_t(cd.y);
    for (const SkeletonPoint& p : points) {
        if (!(p.rhoC >= coarseOptions.tau)) continue;
        view.skeleton.push_back(
            {int(p.voxel % nx), int((p.voxel / nx) % ny), int(p.voxel / (nx * ny))});
    }
    view.candidate = MaskVolume(cd, 0);
    for (const SkeletonCandidate& c : candidates) view.candidate[c.voxel] = 1;
    return view;
}

/// The band search on one level: `level` 0 is the full resolution, whose
/// counters go to bandStats; deeper levels count as coarse work.
std::vector<SkeletonPoint> bandSearch(
    const BoundaryGraph& graph, const std::vector<SkeletonCandidate>& candidates,
    const MaskVolume& mask, const Volume<std::uint32_t>& featureTransform,
    const SkeletonMeasureOptions& options, const SkeletonBandOptions& band, int level,
    SkeletonBandStats& bandStats, SkeletonMeasureStats& stats, Interrupter& interrupter) {
    const Dims dims = mask.dims();
    const std::uint32_t nx = std::uint32_t(dims.x), ny = std::uint32_t(dims.y);
    const std::uint32_t spacing = std::uint32_t(band.seedSpacing);
    auto depth2 = [&](std::size_t voxel) {
        const std::uint32_t f = featureTransform[voxel];
        return f == kNoFeature ? std::int64_t(0) : squaredDistance(dims, std::uint32_t(voxel), f);
    };
    // depth2 of voxel q = (qx, qy, qz): the same value, with q's coordinates
    // known and 32-bit divisions for its feature's (the ascent below asks it
    // 26 times per step, for every candidate).
    auto depth2At = [&](std::size_t q, int qx, int qy, int qz) {
        const std::uint32_t f = featureTransform[q];
        if (f == kNoFeature) return std::int64_t(0);
        const std::uint32_t fyz = f / nx;
        const std::int64_t dx = std::int64_t(f - fyz * nx) - qx, dy = std::int64_t(fyz % ny) - qy,
                           dz = std::int64_t(fyz / ny) - qz;
        return dx * dx + dy * dy + dz * dz;
    };
    CoarseView coarse;
    if (band.coarseSeeds && !candidates.empty())
        coarse = coarseSearch(mask, options, band, level, bandStats, stats, interrupter);
    const bool haveCoarse = coarse.candidate.size() > 0;
    const Dims cd = coarse.candidate.dims();
    const double thinDepth2 = band.thinWallDepth * band.thinWallDepth;
    // The local thickness at a candidate: the depth reached by steepest
    // ascent of the distance map from it. Its own depth would not do: most
    // candidates of a thick part lie near the surface (the medial surface
    // reaches it at every edge and bump), but the ascent from them soon
    // climbs deeper than the threshold, while in a thin wall it stops below.
    const int ascentSteps = 4 * int(std::ceil(band.thinWallDepth)) + 4;
    auto inThinWall = [&](int x, int y, int z) {
        std::int64_t own = depth2At(mask.index(x, y, z), x, y, z);
        for (int step = 0; step < ascentSteps; ++step) {
            if (double(own) >= thinDepth2) return false;
            std::int64_t best = own;
            int bx = x, by = y, bz = z;
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        if (!mask.contains(x + dx, y + dy, z + dz)) continue;
                        const std::size_t q = mask.index(x + dx, y + dy, z + dz);
                        if (!mask[q]) continue;
                        const std::int64_t d = depth2At(q, x + dx, y + dy, z + dz);
                        if (d > best) best = d, bx = x + dx, by = y + dy, bz = z + dz;
                    }
            if (best == own) return true;  // a local maximum below the threshold
            own = best, x = bx, y = by, z = bz;
        }
        return double(own) < thinDepth2;
    };
    const int unseen = band.unresolvedRadius;
    // Where the coarse search examined no candidate near a fine candidate it
    // could not have seen a skeleton there (thin walls and plates), so the
    // band measures such candidates itself.
    auto unresolved = [&](int x, int y, int z) {
        if (!haveCoarse || unseen < 0) return false;
        const int cx = (x + 1) / 2, cy = (y + 1) / 2, cz = (z + 1) / 2;
        for (int dz = -unseen; dz <= unseen; ++dz)
            for (int dy = -unseen; dy <= unseen; ++dy)
                for (int dx = -unseen; dx <= unseen; ++dx)
                    if (coarse.candidate.contains(cx + dx, cy + dy, cz + dz) &&
                        coarse.candidate(cx + dx, cy + dy, cz + dz))
                        return false;
        return true;
    };
    std::vector<std::uint8_t> measured(candidates.size(), 0);
    std::vector<std::uint8_t> thin(candidates.size(), 0);
    parallelFor(
        candidates.size(),
        [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) {
                const std::uint32_t v = candidates[i].voxel;
                const int x = int(v % nx), y = int((v / nx) % ny), z = int(v / (nx * ny));
                if (band.seedSpacing > 0 &&
                    (std::uint32_t(x) % spacing == 0 || std::uint32_t(y) % spacing == 0 ||
                     std::uint32_t(z) % spacing == 0)) {
                    measured[i] = 1;
                    continue;
                }
                if ((haveCoarse && inThinWall(x, y, z)) || unresolved(x, y, z)) {
                    measured[i] = thin[i] = 1;
                    continue;
                }
                if (!band.ridgeSeeds) continue;
                // A ridge voxel of the distance map: no object neighbour
                // is deeper.
                const std::int64_t own = depth2(v);
                bool ridge = true;
                for (int dz = -1; dz <= 1 && ridge; ++dz)
                    for (int dy = -1; dy <= 1 && ridge; ++dy)
                        for (int dx = -1; dx <= 1 && ridge; ++dx) {
                            if (!mask.contains(x + dx, y + dy, z + dz)) continue;
                            const std::size_t q = mask.index(x + dx, y + dy, z + dz);
                            ridge = !mask[q] || depth2(q) <= own;
                        }
                measured[i] = ridge ? 1 : 0;
            }
        },
        options.threaded, 1024);
    (void)cd;
    std::vector<std::uint32_t> batch;
    std::uint64_t thinSeeds = 0;
    for (std::uint32_t i = 0; i < candidates.size(); ++i) {
        if (measured[i]) batch.push_back(i);
        thinSeeds += thin[i];
    }
    for (const auto& c : coarse.skeleton)
        markBox(candidates, dims, {2 * c[0] - 1, 2 * c[1] - 1, 2 * c[2] - 1},
                {2 * c[0], 2 * c[1], 2 * c[2]}, band.coarseBandRadius, measured, batch);
    std::sort(batch.begin(), batch.end());
    std::uint64_t measuredHere = 0;
    if (level == 0) bandStats.seeds = batch.size(), bandStats.thinWallSeeds = thinSeeds;
    std::vector<SkeletonPoint> found, newInTau;
    const int r = level == 0 ? band.closureRadius : band.coarseClosureRadius;
    SkeletonMeasureWorkspaces workspaces;  // one graph and options for every round
    while (!batch.empty()) {
        measuredHere += batch.size();
        if (level == 0) ++bandStats.closureRounds;
        measureBatch(graph, candidates, batch, options, workspaces, stats, interrupter, found,
                     newInTau);
        batch.clear();
        for (const SkeletonPoint& p : newInTau) {
            const std::array<int, 3> v = {int(p.voxel % nx), int((p.voxel / nx) % ny),
                                          int(p.voxel / (nx * ny))};
            markBox(candidates, dims, v, v, r, measured, batch);
        }
        std::sort(batch.begin(), batch.end());
    }
    if (level == 0)
        bandStats.candidatesMeasured = measuredHere;
    else
        bandStats.coarseMeasured += measuredHere;
    std::sort(found.begin(), found.end(), [](const SkeletonPoint& a, const SkeletonPoint& b) {
        return a.candidate < b.candidate;
    });
    return found;
}

}  // namespace

std::vector<SkeletonPoint> measureSkeletonInBand(
    const BoundaryGraph& graph, const std::vector<SkeletonCandidate>& candidates,
    const MaskVolume& mask, const Volume<std::uint32_t>& featureTransform,
    const SkeletonMeasureOptions& options, const SkeletonBandOptions& band,
    SkeletonBandStats* bandStats, SkeletonMeasureStats* measureStats, Interrupter& interrupter) {
    if (band.seedSpacing < 0 || band.closureRadius < 1 || band.coarseClosureRadius < 1 ||
        band.coarseBandRadius < 0)
        throw UsageError(
            "the skeleton band needs closure radii of at least 1 and no negative spacing or "
            "band radius");
    SkeletonBandStats localBand;
    SkeletonMeasureStats stats;
    std::vector<SkeletonPoint> found = bandSearch(graph, candidates, mask, featureTransform,
                                                  options, band, 0, localBand, stats, interrupter);
    stats.skeletonPoints = found.size();  // the coarse runs' points are not counted
    if (bandStats) *bandStats = localBand;
    if (measureStats) *measureStats = stats;
    return found;
}

}  // namespace skelseg
