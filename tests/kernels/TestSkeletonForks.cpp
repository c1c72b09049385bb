#include "kernels/SkeletonForks.h"

#include <gtest/gtest.h>

#include "tests/kernels/SkeletonTestPoints.h"

namespace skelseg {
namespace {

using test::nodeOf;
using test::SkeletonPointSet;

/// A Y of chains in the z = 1 plane, `scale` times a 12-voxel arm: a stem
/// of rho_S 20 * scale and two limbs of 10 * scale; the centre is a J_tau
/// point when `centreRims` is 3.
struct Y {
    SkeletonPointSet set;
    std::uint32_t centre;
    std::vector<std::uint32_t> stem, limb;
    Y(int scale, std::uint8_t centreRims) : set(Dims{40 * scale + 1, 40 * scale + 1, 3}) {
        const int c = 20 * scale, length = 12 * scale;
        const float rho = 10.0f * float(scale);
        centre = set.add({c, c, 1}, rho, 1000.0, centreRims);
        stem = set.chain({c + 1, c, 1}, {1, 0, 0}, length, 2.0f * rho);
        limb = set.chain({c - 1, c + 1, 1}, {-1, 1, 0}, length, rho);
        set.chain({c - 1, c - 1, 1}, {-1, -1, 0}, length, rho);
    }
};

/// The graph without forks or grown regions: what ForkSearch is given.
SkeletonGraph plainGraph(const std::vector<SkeletonPoint>& points, const Dims& dims) {
    SkeletonGraphOptions options;
    options.forkJunctions = false;
    options.growRegionsToSplits = false;
    return buildSkeletonGraph(points, dims, options);
}

TEST(SkeletonForks, CentreOfAYHasThreeBranchesAndTheStemsLoop) {
    for (int scale : {1, 2}) {
        Y y(scale, 2);
        const std::vector<SkeletonPoint> points = y.set.points();
        const SkeletonGraph g = plainGraph(points, y.set.dims());
        ForkSearch search(g.nodeCount());
        float bodyRhoS = 0.0f;
        EXPECT_EQ(search.countBranches(g, points, nodeOf(g, points, y.centre), 3.0, bodyRhoS), 3u)
            << "scale " << scale;
        EXPECT_EQ(bodyRhoS, 20.0f * float(scale)) << "scale " << scale;
        // Half-way along a limb the skeleton passes through: two branches.
        const std::uint32_t middle = nodeOf(g, points, y.limb[y.limb.size() / 2]);
        EXPECT_EQ(search.countBranches(g, points, middle, 3.0, bodyRhoS), 2u) << "scale " << scale;
    }
}

TEST(SkeletonForks, JunctionPointWithinOneRadiusLeavesNoFork) {
    Y y(2, 3);
    const std::vector<SkeletonPoint> points = y.set.points();
    const SkeletonGraph g = plainGraph(points, y.set.dims());
    ForkSearch search(g.nodeCount());
    float bodyRhoS = 0.0f;
    EXPECT_EQ(search.countBranches(g, points, nodeOf(g, points, y.limb[0]), 3.0, bodyRhoS), 0u);
}

TEST(SkeletonForks, ReusedSearchCountsAsAFreshOne) {
    // ForkSearch keeps its buffers between nodes; what one node left behind
    // must not change the next node's count.
    Y y(2, 2);
    const std::vector<SkeletonPoint> points = y.set.points();
    const SkeletonGraph g = plainGraph(points, y.set.dims());
    ForkSearch reused(g.nodeCount());
    std::uint32_t forks = 0;
    for (std::uint32_t n = 0; n < g.nodeCount(); ++n) {
        ForkSearch fresh(g.nodeCount());
        float rhoReused = -1.0f, rhoFresh = -2.0f;
        const std::uint32_t countReused = reused.countBranches(g, points, n, 3.0, rhoReused);
        ASSERT_EQ(countReused, fresh.countBranches(g, points, n, 3.0, rhoFresh)) << "node " << n;
        ASSERT_EQ(rhoReused, rhoFresh) << "node " << n;
        forks += countReused >= 3;
    }
    EXPECT_GT(forks, 0u);
}

}  // namespace
}  // namespace skelseg
