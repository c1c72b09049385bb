// skelseg: the curve-skeleton search spent where the skeleton is
// (docs/algorithm.md §3.5).
//
// measureSkeleton() examines every candidate, and almost all of them turn out
// not to be curve-skeleton points (figures in docs/algorithm.md §3.5).
// measureSkeletonInBand() finds the same simplified skeleton C_tau while
// examining a share of them; it is the engine's default (--exhaustive
// selects measureSkeleton()). The search:
//   1. coarse seeds: the mask at half the resolution (a coarse voxel is
//      object when any of its 2x2x2 fine voxels is) gets the same search,
//      recursively (a band search of its own while it has more than
//      exhaustiveBelow candidates, else the exhaustive one); the
//      full-resolution candidates within coarseBandRadius of its simplified
//      skeleton (tau scaled by 1/4, times coarseTauShare) are seeds;
//   2. thin-wall seeds: half the resolution does not resolve walls a few
//      voxels thick (the coarse search finds no skeleton on them, or has no
//      candidate there at all), so every candidate in a wall thinner than
//      2 * thinWallDepth voxels, and every candidate with no coarse candidate
//      near, is a seed. A wall's thickness at a candidate is read by steepest
//      ascent of the distance map: its own depth would not do, since most
//      candidates of thick parts lie near the surface, where the medial
//      surface reaches every edge and bump, yet climb deeper within a few
//      steps;
//   3. closure: around every point of C_tau found so far at full resolution,
//      every candidate within `closureRadius` (Chebyshev) is measured too,
//      repeated until no new point of C_tau appears (on the coarser levels
//      within `coarseClosureRadius`: their points only seed the level above).
// Every full-resolution measure is the exact per-candidate test of
// SkeletonMeasures.h (a function of the candidate's feature set alone), so a
// point found is the exhaustive search's point, bit for bit.
//
// What is guaranteed. The closure finds every point of a 26-connected piece
// of C_tau that holds one seed (radius >= 1), and with a radius of at least
// the skeleton graph's bridge gap also every piece the graph stage could
// bridge to it. What the band can miss is a piece of C_tau without a seed
// that is farther than the radius from every other piece: a branch in a part
// thicker than the thin-wall threshold that the coarse grid does not see and
// that the fine skeleton does not join. That is a measured, not a proven,
// property: the identical-answer tests and docs/performance.md compare the
// result with the exhaustive search. Optional extra seeds: grid planes (every
// piece that spans seedSpacing voxels along an axis crosses one) and ridge
// voxels of the distance map (where the web at a ball's centre sits).
//
// Points of C below tau are found only where the closure passes them; the
// graph stages never read them. Results depend only on the input, never on
// the thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "kernels/SkeletonCandidates.h"
#include "kernels/SkeletonMeasures.h"
#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

struct SkeletonBandOptions {
    /// Seeds from the skeleton at half the resolution: the full-resolution
    /// candidates within coarseBandRadius of its points. A seed need only
    /// fall on each piece of C_tau once: the closure then measures the
    /// closureRadius box around every point found, which holds nearly all
    /// of a wider band (docs/performance.md, "Fewer measures near the
    /// skeleton").
    bool coarseSeeds = true;
    int coarseBandRadius = 1;
    /// The coarse skeleton keeps points with rho_C >= tau / 4 * coarseTauShare
    /// (areas shrink by four at half the resolution; a share below 1 keeps
    /// branches close to tau).
    double coarseTauShare = 0.5;
    /// Thin walls, which half the resolution does not resolve: every
    /// candidate in a wall thinner than 2 * thinWallDepth voxels (steepest
    /// ascent of the distance map from it stays below thinWallDepth) is a
    /// seed (0: none), and so is every candidate with no candidate of the
    /// coarse search within unresolvedRadius coarse voxels of its coarse
    /// voxel (-1: none).
    double thinWallDepth = 5.0;
    int unresolvedRadius = 1;
    /// The search at half the resolution is itself a band search while it
    /// has more candidates than this (recursively); below, it measures all.
    std::size_t exhaustiveBelow = 30000;
    /// Seeds on the grid planes x, y or z = k * seedSpacing (0: none; 1 seeds
    /// every candidate, which is the exhaustive search).
    int seedSpacing = 0;
    /// Seeds at the ridge voxels of the distance map (no object neighbour
    /// deeper).
    bool ridgeSeeds = false;
    /// Chebyshev radius around each point of C_tau inside which every
    /// candidate is measured (>= 1; at least the skeleton graph's bridge gap).
    int closureRadius = 4;
    /// The same radius on the coarser levels (>= 1). Their points are seeds
    /// for the level above and never reach the skeleton graph, so they need
    /// no bridging: radius 1 follows each 26-connected piece, and the full
    /// resolution's own closure bridges the gaps.
    int coarseClosureRadius = 1;
};

struct SkeletonBandStats {
    std::uint64_t coarseCandidates = 0;    // candidates of the coarser levels, all of them
    std::uint64_t coarseMeasured = 0;      // of which measured
    std::uint32_t levels = 0;              // coarser levels searched
    std::uint64_t seeds = 0;               // full-resolution candidates measured as seeds
    std::uint64_t thinWallSeeds = 0;       // of which seeded for a thin wall
    std::uint64_t candidatesMeasured = 0;  // full resolution: seeds + closure
    std::uint32_t closureRounds = 0;       // full resolution
};

/// The points of C that the band search found, in candidate order, with
/// `candidate` indexing `candidates` (as measureSkeleton() returns them).
/// `mask` and `featureTransform`: the crop that candidates[].voxel indexes
/// and its feature transform (SkeletonCandidates.h). options.threaded is the
/// serial switch. Throws UsageError for a negative spacing or band radius or
/// a closure radius below 1,
/// InterruptedError when interrupted.
std::vector<SkeletonPoint> measureSkeletonInBand(
    const BoundaryGraph& graph, const std::vector<SkeletonCandidate>& candidates,
    const MaskVolume& mask, const Volume<std::uint32_t>& featureTransform,
    const SkeletonMeasureOptions& options, const SkeletonBandOptions& band = {},
    SkeletonBandStats* bandStats = nullptr, SkeletonMeasureStats* measureStats = nullptr,
    Interrupter& interrupter = nullInterrupter());

/// Sums the counters of two measure runs (the band measures in rounds).
void addMeasureStats(SkeletonMeasureStats& total, const SkeletonMeasureStats& part);

}  // namespace skelseg
