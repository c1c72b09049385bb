// skelseg: extended feature sets and the search pre-filter
// (docs/algorithm.md §2 and §3.1).
//
// For every object voxel p, Fbar(p) is the set of distinct nearest boundary
// nodes of the object voxels of the 2x2x2 cell p + {0,1}^3. Only voxels whose
// features are genuinely apart can be skeletal, and only they get path
// searches. The pre-filter (docs/algorithm.md §3.1, measured to lose nothing):
//   - at least 3 distinct feature nodes (2 give one path, never a loop);
//   - the largest Euclidean gap between two of them > max(gapRatio * D(p), minimumGap).
// The absolute minimum gap (default 2 voxels) drops the cells right at the
// surface, where D(p) ~ 0 and any gap would pass; a loop whose feature points
// are all within two voxels of each other cannot enclose any area.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "kernels/BoundaryGraph.h"
#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

struct SkeletonCandidate {
    std::uint32_t voxel = 0;  // linear voxel index of p
    std::uint8_t featureCount = 0;
    std::array<std::uint32_t, 8> feature{};  // boundary node ids, ascending
};

struct CandidateOptions {
    double gapRatio = 0.5;
    double minimumGap = 2.0;
    bool threaded = true;
};

struct CandidateStats {
    std::uint64_t objectVoxels = 0;
    std::uint64_t withThreeFeatures = 0;  // passed the first test
    std::uint64_t candidates = 0;         // passed both
};

/// Extended feature set of voxel (x,y,z) of `mask` (must be an object voxel),
/// written to `out`; returns the count.
std::uint32_t extendedFeatureSet(const MaskVolume& mask,
                                 const Volume<std::uint32_t>& featureTransform,
                                 const BoundaryGraph& graph, int x, int y, int z,
                                 std::array<std::uint32_t, 8>& out);

/// All candidates in increasing voxel order (independent of thread count).
std::vector<SkeletonCandidate> selectSkeletonCandidates(
    const MaskVolume& mask, const Volume<std::uint32_t>& featureTransform,
    const BoundaryGraph& graph, const CandidateOptions& options = {},
    CandidateStats* stats = nullptr, Interrupter& interrupter = nullInterrupter());

}  // namespace skelseg
