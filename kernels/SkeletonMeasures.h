// skelseg: path sets, the curve-skeleton test and the importance measures,
// per candidate voxel (docs/algorithm.md §3 to §7).
//
// For every candidate p (in parallel, one workspace per thread):
//   Gamma(p)  union of shortest boundary paths between all pairs of Fbar(p)
//   rho_S(p)  longest of those paths; (a, b) the pair realising it
//   rims      pieces of the rim of Gamma'(p)                  (RimCount.h)
//   areas     components behind the rims, rho_C               (ComponentGrowth.h)
//   sigma     geodesicness, for points of C_tau only           (Geodesicness.h)
// A rim counts when the component it bounds has at least `noiseArea` nodes:
// bundles of nearly parallel paths enclose holes of 1 to 10 voxels that are
// not loops (docs/algorithm.md §5.3). p is in C when two or more rims count.
// A rim is robust when its component reaches tau; p is a junction (J_tau) with
// three or more robust rims. When fewer distinct components than counting
// rims exist, Gamma(p) holds a loop around a handle (genus > 0): such points
// get rho_C = infinity (isHandle) so that tunnels keep their loop skeleton.
// isHandle is exact only with exactRhoC: under the growth cap the two fronts
// of a long handle loop usually stop at the cap before they meet; the point
// then keeps a finite rho_C bound >= tau, so C_tau is the same either way.
//
// Results depend only on the input, never on the thread count: each path is a
// function of its feature pair (PathSearch.h), and results are written per
// candidate and compacted in candidate order.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "kernels/BoundaryGraph.h"
#include "kernels/PathSearch.h"
#include "kernels/SkeletonCandidates.h"
#include "kernels/base/Interrupter.h"

namespace skelseg {

/// A point of the (unsimplified) curve skeleton C with its measures.
struct SkeletonPoint {
    std::uint32_t voxel = 0;      // linear voxel index
    std::uint32_t candidate = 0;  // index into the candidate list
    float rhoS = 0.0f;            // longest feature-pair geodesic
    double rhoC = 0.0;            // area cut off by the loop; +inf for handle loops
    bool rhoCExact = true;        // false: rhoC is a lower bound (>= tau, see ComponentGrowth.h)
    bool isHandle = false;
    std::uint8_t rims = 0;        // rims whose component >= noiseArea
    std::uint8_t robustRims = 0;  // rims whose component >= tau
    /// The third-largest component area behind a counting rim, -1 with fewer
    /// than three: p is in J_t for every t <= junctionArea up to the growth
    /// cap (max(noiseArea, tau)), so one measure serves every level of a
    /// hierarchy run (engine/SegmentationLevels.h).
    double junctionArea = -1.0;
    float sigma = -1.0f;  // geodesicness; -1 where not computed (rho_C < tau)
    std::uint32_t featureA = kNoNode, featureB = kNoNode;  // pair realising rho_S
    /// Chord length of the whole loop Gamma(p) goes round (sigma's two
    /// halves, docs/algorithm.md §7.1); 0 where sigma is not computed or
    /// finds no loop.
    float loopLength = 0.0f;
};

/// Rims a point needs to be a junction point (a point of J_tau): its loop
/// cuts the boundary into at least three components of area >= tau.
constexpr std::uint8_t kJunctionRims = 3;

/// Whether `p` is a junction point, a point of J_tau (docs/algorithm.md §6).
constexpr bool isJunctionPoint(const SkeletonPoint& p) noexcept {
    return p.robustRims >= kJunctionRims;
}

/// Half the circumference of the surface round p, the length the body test
/// compares (docs/algorithm.md §8.13): half the loop's chord length plus
/// pi times half a voxel, since the loop runs through boundary-voxel centres
/// about half a voxel inside the surface. rho_S where p has no loop length.
/// Unlike rho_S, whose feature pair is not antipodal and spans an angle that
/// depends on the radius and on the part's angle to the grid, it reads the
/// same fraction of the true length at every radius and orientation.
constexpr float surfaceHalfLoop(const SkeletonPoint& p) noexcept {
    return p.loopLength > 0.0f ? 0.5f * p.loopLength + 0.5f * 3.14159265358979323846f : p.rhoS;
}

/// Radius of a round part whose loop has rho_S = `rhoS` (rho_S, the longest
/// feature-pair geodesic, is half the loop's length: pi r). The graph stages
/// turn loop lengths into distances in voxels with it.
constexpr double loopRadius(double rhoS) noexcept {
    return rhoS / 3.14159265358979323846;
}

struct SkeletonMeasureOptions {
    /// Simplification threshold in boundary-node (voxel-area) units.
    double tau = 0.0;
    /// Components smaller than this do not make a rim count (see above).
    double noiseArea = 10.0;
    /// Hierarchy runs: sigma is evaluated for every point with rho_C >= this
    /// (the finest level's tau) instead of tau; negative: tau. rho_C, the
    /// rims and junctionArea do not depend on it.
    double sigmaTau = -1.0;
    /// Compute rho_C exactly for every point (slower); otherwise growth stops
    /// once the comparison with tau is decided.
    bool exactRhoC = false;
    /// false: sigma is not evaluated (every point's sigma is -1); for
    /// searches that use only rho_C, such as the band's coarser levels.
    bool evaluateSigma = true;
    /// The surface measured has genus 0 (every boundary surface of the object
    /// is a sphere; kernels/VoxelGenus.h): no loop on it can go round a
    /// handle, so two counting rims whose pieces meet are two parts of one
    /// side of Gamma(p), parted by a digital break of the rim, and count once.
    /// A point left with fewer than two sides is not in C. false: rims that
    /// meet mark a handle (isHandle, rho_C = infinity).
    bool surfaceHasGenusZero = false;
    /// Landmarks for A* (PathSearch.h), or null for the Euclidean bound only.
    /// They change which of several equally short paths is found, so every
    /// search of one run (measures, cut loops, exact re-measures) must use
    /// the same landmarks: pass the same pointer to pathSet().
    const Landmarks* landmarks = nullptr;
    bool threaded = true;
};

struct SkeletonMeasureStats {
    SearchCounters search;  // pair searches
    std::uint64_t pathCacheHits = 0;
    std::uint64_t pathCacheMisses = 0;
    std::uint64_t rimTests = 0;
    std::uint64_t componentGrowthSteps = 0;
    std::uint64_t sigmaEvaluations = 0;
    SearchCounters sigmaSearch;             // searches made by sigma evaluation
    std::uint64_t repeatedFeatureSets = 0;  // candidates answered from an identical feature set
    std::uint64_t skeletonPoints = 0;
};

/// Measures every candidate; returns the points of C in candidate order.
std::vector<SkeletonPoint> measureSkeleton(const BoundaryGraph& graph,
                                           const std::vector<SkeletonCandidate>& candidates,
                                           const SkeletonMeasureOptions& options,
                                           SkeletonMeasureStats* stats = nullptr,
                                           Interrupter& interrupter = nullInterrupter());

/// The per-thread workspaces of measureSkeleton(), kept between calls that
/// measure parts of one candidate list (the band search's closure rounds):
/// the per-node arrays are allocated and cleared once instead of per call,
/// and the pair-path caches and the repeated-feature-set memo carry over.
/// Both caches answer as a fresh computation would, so keeping them changes
/// cost, never results. A call with another graph, other landmarks or other
/// measure options starts from fresh workspaces.
class SkeletonMeasureWorkspaces {
public:
    SkeletonMeasureWorkspaces();
    ~SkeletonMeasureWorkspaces();
    SkeletonMeasureWorkspaces(const SkeletonMeasureWorkspaces&) = delete;
    SkeletonMeasureWorkspaces& operator=(const SkeletonMeasureWorkspaces&) = delete;

    struct Impl;
    Impl& impl() noexcept { return *mImpl; }

private:
    std::unique_ptr<Impl> mImpl;
};

/// measureSkeleton() on kept workspaces (see SkeletonMeasureWorkspaces).
std::vector<SkeletonPoint> measureSkeleton(const BoundaryGraph& graph,
                                           const std::vector<SkeletonCandidate>& candidates,
                                           const SkeletonMeasureOptions& options,
                                           SkeletonMeasureWorkspaces& workspaces,
                                           SkeletonMeasureStats* stats = nullptr,
                                           Interrupter& interrupter = nullInterrupter());

/// Gamma(p) of one candidate: the union of its pair paths (sorted, unique).
/// Also returns rho_S and the pair realising it through the pointers.
std::vector<std::uint32_t> pathSet(const BoundaryGraph& graph, const SkeletonCandidate& candidate,
                                   GeodesicSearch& search, float* rhoS = nullptr,
                                   std::uint32_t* a = nullptr, std::uint32_t* b = nullptr);

/// Full measures of one candidate with exact rho_C, whatever
/// options.exactRhoC says (used for the few cut candidates where rho_C must
/// be compared exactly). Returns false when the candidate is not a point of C.
bool measurePoint(const BoundaryGraph& graph, const SkeletonCandidate& candidate,
                  const SkeletonMeasureOptions& options, SkeletonPoint& out);

}  // namespace skelseg
