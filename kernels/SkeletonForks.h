// skelseg: forks of the skeleton graph, and junction regions grown to where
// their branches separate (docs/algorithm.md §6, "Forks" and "A region
// reaches its branches' split").
//
// Both look at the parts of a shell around a node or a region, at one and
// two part radii (loopRadius of rho_S): a branch leaves the ball through the
// shell, a bump of the 2-3 voxel thick skeleton does not.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/SkeletonGraph.h"
#include "kernels/SkeletonGraphSearch.h"

namespace skelseg {

/// Fork test at node s: the nodes within 2R of s along the graph's edges,
/// R = the radius of the part at s (loopRadius(rho_S)), at least
/// `minimumRadius`. The shell (R, 2R] falls into one connected part per
/// branch leaving the ball (forEachShellPart), and a bridge from the inner
/// ball to beyond 2R is a branch too. s is a fork with three or more
/// branches, unless a J_tau point lies within R of it (the junction test
/// already marks that branching). `bodyRhoS` gets the largest of the
/// branches' median rho_S: the loop of the body through the fork.
class ForkSearch {
public:
    explicit ForkSearch(std::size_t nodeCount) : mBall(nodeCount), mPiece(nodeCount, kNoJunction) {}

    /// The number of branches leaving node s (0 when a J_tau point lies
    /// within R), the largest branch's median rho_S in `bodyRhoS`.
    std::uint32_t countBranches(const SkeletonGraph& g, const std::vector<SkeletonPoint>& points,
                                std::uint32_t s, double minimumRadius, float& bodyRhoS);

private:
    BoundedDistances mBall;
    std::vector<std::uint32_t> mPiece, mQueue;
    std::vector<float> mRho;  // rho_S along one shell part
};

/// Grows junction regions up to where their branches separate (docs/algorithm.md
/// §6, "A region reaches its branches' split"). A fork within one part radius R
/// (loopRadius of the junction's rho_S) of a J_tau point is no junction of its
/// own, because that junction marks the branching; but its region reaches only
/// `regionRadius` steps, and two limbs whose thick skeletons touch just outside
/// it leave as one piece, which the walk of §8.1 takes as one branch. So for
/// each piece touching a region: the piece's nodes at distance (R, 2R] from the
/// region (within the piece) fall into shell parts, counted as in ForkSearch;
/// when two or more count, the region takes the piece's breadth-first levels
/// from the region one at a time, up to distance R, until what is left of the
/// piece holds the counted parts in separate pieces; the bits left with none
/// of them join the region too.
void growRegionsToBranchSplits(SkeletonGraph& g, const SkeletonGraphOptions& options);

}  // namespace skelseg
