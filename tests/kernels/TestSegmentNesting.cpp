#include "kernels/SegmentNesting.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "io/shapes/SyntheticShapes.h"
#include "tests/kernels/KernelTestSupport.h"

namespace skelseg {
namespace {

/// A capsule along x; segmentations by x slabs (cut rings as labelSurface
/// would make them), where the finer level's cuts are off by a few slices so
/// that they do not nest.
class NestingOnCapsule : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        mask = new MaskVolume(rasterise(makeShape("capsule"), {56, 2}));
        graph = new BoundaryGraph(buildBoundaryGraph(*mask, {false}));
        xMin = xMax = graph->coord[0].x;
        for (const Coord& c : graph->coord) xMin = std::min(xMin, c.x), xMax = std::max(xMax, c.x);
    }
    static void TearDownTestSuite() {
        delete graph;
        delete mask;
        graph = nullptr, mask = nullptr;
    }
    static int at(double fraction) { return xMin + int(std::lround(fraction * (xMax - xMin))); }
    static std::vector<std::uint32_t> ring(int x) {
        std::vector<std::uint32_t> nodes;
        for (std::uint32_t n = 0; n < graph->nodeCount(); ++n)
            if (graph->coord[n].x == x) nodes.push_back(n);
        return nodes;
    }
    static SurfaceSegments cutAt(const std::vector<double>& fractions, double minArea = 1.0) {
        std::vector<std::vector<std::uint32_t>> loops;
        for (double f : fractions) loops.push_back(ring(at(f)));
        return labelSurface(*graph, loops, minArea);
    }
    /// Every fine segment inside its parent, node by node.
    static void expectNested(const NestedSegments& nested, const SurfaceSegments& coarse) {
        const SurfaceSegments& fine = nested.segments;
        ASSERT_EQ(fine.nodeLabel.size(), graph->nodeCount());
        ASSERT_EQ(nested.parent.size(), fine.segmentCount);
        std::vector<std::uint64_t> area(fine.segmentCount, 0);
        for (std::uint32_t n = 0; n < graph->nodeCount(); ++n) {
            ASSERT_LT(fine.nodeLabel[n], fine.segmentCount);
            EXPECT_EQ(nested.parent[fine.nodeLabel[n]], coarse.nodeLabel[n]) << "node " << n;
            ++area[fine.nodeLabel[n]];
        }
        EXPECT_EQ(area, fine.area);
        EXPECT_TRUE(std::is_sorted(fine.area.begin(), fine.area.end(), std::greater<>()));
    }
    static MaskVolume* mask;
    static BoundaryGraph* graph;
    static int xMin, xMax;
};
MaskVolume* NestingOnCapsule::mask = nullptr;
BoundaryGraph* NestingOnCapsule::graph = nullptr;
int NestingOnCapsule::xMin = 0, NestingOnCapsule::xMax = 0;

TEST_F(NestingOnCapsule, ARefinementStaysAsItIs) {
    const SurfaceSegments coarse = cutAt({0.5});
    const SurfaceSegments fine = cutAt({0.25, 0.5, 0.75});
    const NestedSegments nested = nestSegments(*graph, coarse, fine);
    expectNested(nested, coarse);
    EXPECT_EQ(nested.movedNodes, 0u);
    EXPECT_EQ(nested.segments.nodeLabel, fine.nodeLabel);
    EXPECT_EQ(nested.segments.segmentCount, 4u);
}

TEST_F(NestingOnCapsule, ACutBesideTheCoarseCutIsRepaired) {
    // The fine level cuts 3 slices right of the coarse cut: the slab between
    // the two cuts lies in the fine segment of the left end but in the right
    // coarse segment. It must move to the right's child.
    const SurfaceSegments coarse = cutAt({0.5});
    const int shift = 6;
    const double shifted = 0.5 + double(shift) / double(xMax - xMin);
    const SurfaceSegments fine = cutAt({0.2, shifted});
    const NestedSegments nested = nestSegments(*graph, coarse, fine);
    expectNested(nested, coarse);
    EXPECT_GT(nested.movedNodes, 0u);
    EXPECT_EQ(nested.segments.segmentCount, 3u);
    // The slab between the cuts (outside their one-step dilations) joined the
    // right end's segment; the nodes left of the coarse cut did not move.
    const std::uint32_t right = nested.segments.nodeLabel[ring(at(0.8)).front()];
    for (int x = at(0.5) + 2; x <= at(0.5) + shift - 2; ++x)
        for (std::uint32_t n : ring(x)) EXPECT_EQ(nested.segments.nodeLabel[n], right) << "x " << x;
    const std::uint32_t middle = nested.segments.nodeLabel[ring(at(0.35)).front()];
    for (int x = at(0.25); x <= at(0.45); ++x)
        for (std::uint32_t n : ring(x))
            EXPECT_EQ(nested.segments.nodeLabel[n], middle) << "x " << x;
    EXPECT_NE(middle, right);
}

TEST_F(NestingOnCapsule, ACoarseSegmentWithoutChildGetsOne) {
    // Fine: no cut at all; coarse: two pieces. The fine segment's parent is
    // the larger coarse piece; the other becomes a new fine segment.
    const SurfaceSegments coarse = cutAt({0.3});
    const SurfaceSegments fine = cutAt({});
    ASSERT_EQ(fine.segmentCount, 1u);
    const NestedSegments nested = nestSegments(*graph, coarse, fine);
    expectNested(nested, coarse);
    EXPECT_EQ(nested.segments.segmentCount, 2u);
    EXPECT_EQ(nested.segments.nodeLabel, coarse.nodeLabel);
}

TEST_F(NestingOnCapsule, MismatchedSizesAreRefused) {
    SurfaceSegments coarse = cutAt({0.5});
    const SurfaceSegments fine = cutAt({0.5});
    coarse.nodeLabel.pop_back();
    EXPECT_THROW(nestSegments(*graph, coarse, fine), UsageError);
}

}  // namespace
}  // namespace skelseg
