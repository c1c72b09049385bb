#include "kernels/CutLoopOrder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "tests/kernels/KernelTestSupport.h"

namespace skelseg {
namespace {

using test::hasEdge;
using test::nearestNode;

/// A round tube along z: radius 6 around (10, 10), z from 2 to 29.
struct Tube {
    static constexpr double kCentre = 10.0, kRadius = 6.0;
    static constexpr int kMiddle = 15;
    MaskVolume mask;
    BoundaryGraph graph;
    std::vector<std::uint32_t> ring;  // boundary nodes of the cross-section z = kMiddle
    std::uint32_t a = kNoNode, b = kNoNode;

    Tube() : mask(Dims{21, 21, 32}, 0) {
        for (int z = 2; z < 30; ++z)
            for (int y = 0; y < 21; ++y)
                for (int x = 0; x < 21; ++x) {
                    const double dx = x - kCentre, dy = y - kCentre;
                    mask(x, y, z) = dx * dx + dy * dy <= kRadius * kRadius ? 1 : 0;
                }
        graph = buildBoundaryGraph(mask, {false});
        for (std::uint32_t n = 0; n < graph.nodeCount(); ++n)
            if (graph.coord[n].z == kMiddle) ring.push_back(n);
        a = nearestNode(graph, {kCentre + kRadius, kCentre, double(kMiddle)});
        b = nearestNode(graph, {kCentre - kRadius, kCentre, double(kMiddle)});
    }
};

void expectWalk(const BoundaryGraph& graph, const std::vector<std::uint32_t>& loop) {
    for (std::size_t i = 1; i < loop.size(); ++i)
        EXPECT_TRUE(hasEdge(graph, loop[i - 1], loop[i])) << "step " << i << " is not an edge";
    const std::set<std::uint32_t> distinct(loop.begin(), loop.end());
    EXPECT_EQ(distinct.size(), loop.size()) << "a node is visited twice";
}

TEST(CutLoopOrder, CrossSectionOfATubeIsAClosedWalk) {
    const Tube tube;
    ASSERT_GT(tube.ring.size(), 20u);
    ASSERT_EQ(tube.graph.coord[tube.a].z, Tube::kMiddle);
    ASSERT_EQ(tube.graph.coord[tube.b].z, Tube::kMiddle);
    const std::vector<std::uint32_t> loop = orderCutLoop(tube.graph, tube.ring, tube.a, tube.b);
    ASSERT_GE(loop.size(), 3u);
    EXPECT_EQ(loop.front(), tube.a);
    EXPECT_NE(std::find(loop.begin(), loop.end(), tube.b), loop.end());
    expectWalk(tube.graph, loop);
    EXPECT_TRUE(hasEdge(tube.graph, loop.back(), loop.front())) << "the loop is not closed";
    for (std::uint32_t n : loop) EXPECT_EQ(tube.graph.coord[n].z, Tube::kMiddle);
    // Both halves of the ring are walked: the loop goes round the tube.
    bool above = false, below = false;
    for (std::uint32_t n : loop) {
        above |= tube.graph.coord[n].y > Tube::kCentre + 3;
        below |= tube.graph.coord[n].y < Tube::kCentre - 3;
    }
    EXPECT_TRUE(above && below);
}

TEST(CutLoopOrder, HalfRingStaysAnOpenArc) {
    // With one half of the ring only, no way back exists inside the set, nor
    // in its dilation once the first arc is blocked: the open arc a -> b.
    const Tube tube;
    std::vector<std::uint32_t> half;
    for (std::uint32_t n : tube.ring)
        if (tube.graph.coord[n].y >= int(Tube::kCentre)) half.push_back(n);
    const std::vector<std::uint32_t> arc = orderCutLoop(tube.graph, half, tube.a, tube.b);
    ASSERT_GE(arc.size(), 3u);
    EXPECT_EQ(arc.front(), tube.a);
    EXPECT_EQ(arc.back(), tube.b);
    expectWalk(tube.graph, arc);
    for (std::uint32_t n : arc) EXPECT_GE(tube.graph.coord[n].y, int(Tube::kCentre));
}

TEST(CutLoopOrder, UnreachableEndLeavesTheSetAsGiven) {
    const Tube tube;
    std::vector<std::uint32_t> twoSpots = {tube.a, tube.b};
    std::sort(twoSpots.begin(), twoSpots.end());
    EXPECT_EQ(orderCutLoop(tube.graph, twoSpots, tube.a, tube.b), twoSpots);
}

TEST(CutLoopOrder, CallerWorkspacesGiveTheSameLoop) {
    const Tube tube;
    const Landmarks landmarks = computeLandmarks(tube.graph, false);
    GeodesicSearch search(tube.graph, &landmarks);
    RimCounter rims(tube.graph);
    const auto first = orderCutLoop(tube.graph, tube.ring, tube.a, tube.b, search, rims);
    // A used workspace (marks left from the first call) answers the same.
    const auto again = orderCutLoop(tube.graph, tube.ring, tube.a, tube.b, search, rims);
    EXPECT_EQ(first, again);
    EXPECT_EQ(first, orderCutLoop(tube.graph, tube.ring, tube.a, tube.b, &landmarks));
}

}  // namespace
}  // namespace skelseg
