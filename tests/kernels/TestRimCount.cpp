#include "kernels/RimCount.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

#include "tests/kernels/KernelTestSupport.h"

namespace skelseg {
namespace {

class RimsOnSphere : public test::BallBoundaryFixture {
protected:
    /// Closed loop along the equator through four points.
    std::vector<std::uint32_t> equatorLoop(GeodesicSearch& search) const {
        return test::pathThrough(search, {at(0, 0), at(0, 90), at(0, 180), at(0, 270)}, true);
    }
};

/// Structural checks of a RimPieces result against its definition.
void expectConsistent(const BoundaryGraph& graph, const std::vector<std::uint32_t>& pathSet,
                      const RimCounter& counter) {
    const RimPieces& r = counter.result();
    // Gamma' = Gamma plus its graph neighbours, each once.
    std::set<std::uint32_t> expectedDilated(pathSet.begin(), pathSet.end());
    for (std::uint32_t n : pathSet)
        for (std::uint32_t e = graph.offset[n]; e < graph.offset[n + 1]; ++e)
            expectedDilated.insert(graph.neighbour[e]);
    const std::set<std::uint32_t> dilated(r.dilated.begin(), r.dilated.end());
    EXPECT_EQ(dilated.size(), r.dilated.size()) << "duplicates in Gamma'";
    EXPECT_EQ(dilated, expectedDilated);
    for (std::uint32_t n : pathSet) {
        EXPECT_TRUE(counter.isInPathSet(n));
        EXPECT_TRUE(counter.isInDilated(n));
    }
    // Rim = neighbours of Gamma' outside it.
    std::set<std::uint32_t> expectedRim;
    for (std::uint32_t n : expectedDilated)
        for (std::uint32_t e = graph.offset[n]; e < graph.offset[n + 1]; ++e)
            if (!expectedDilated.count(graph.neighbour[e])) expectedRim.insert(graph.neighbour[e]);
    EXPECT_EQ(std::set<std::uint32_t>(r.rimNodes.begin(), r.rimNodes.end()), expectedRim);
    EXPECT_EQ(r.rimNodes.size(), expectedRim.size());
    ASSERT_EQ(r.pieceOfRimNode.size(), r.rimNodes.size());
    for (std::uint32_t p : r.pieceOfRimNode) EXPECT_LT(p, r.pieceCount);
    // Pieces: 26-connected (graph edges) within a piece, no edge across pieces.
    std::map<std::uint32_t, std::uint32_t> pieceOf;
    for (std::size_t i = 0; i < r.rimNodes.size(); ++i)
        pieceOf[r.rimNodes[i]] = r.pieceOfRimNode[i];
    for (const auto& [n, p] : pieceOf)
        for (std::uint32_t e = graph.offset[n]; e < graph.offset[n + 1]; ++e) {
            auto it = pieceOf.find(graph.neighbour[e]);
            if (it != pieceOf.end()) {
                EXPECT_EQ(it->second, p) << "adjacent rim nodes in different pieces";
            }
        }
    std::vector<std::uint32_t> label;
    const auto sizes = test::floodFill(
        graph, [&](std::uint32_t n) { return pieceOf.count(n) > 0; }, label);
    EXPECT_EQ(sizes.size(), r.pieceCount);
}

TEST_F(RimsOnSphere, OpenPathHasOneRim) {
    GeodesicSearch search(*graph);
    const std::vector<std::uint32_t> path = test::pathThrough(search, {at(0, 0), at(0, 90)}, false);
    ASSERT_GT(path.size(), 10u);
    EXPECT_EQ(rimCount(*graph, path), 1u);
    RimCounter counter(*graph);
    counter.countRims(path);
    expectConsistent(*graph, path, counter);
    // A longer open path (a "U" over two quarters) is still one band.
    const auto u = test::pathThrough(search, {at(0, 0), at(60, 90), at(0, 180)}, false);
    EXPECT_EQ(rimCount(*graph, u), 1u);
}

TEST_F(RimsOnSphere, ClosedLoopHasTwoRims) {
    GeodesicSearch search(*graph);
    const std::vector<std::uint32_t> loop = equatorLoop(search);
    ASSERT_GT(loop.size(), 60u);
    RimCounter counter(*graph);
    EXPECT_EQ(counter.countRims(loop).pieceCount, 2u);
    expectConsistent(*graph, loop, counter);
    // The two rims lie on either side of the equator.
    const RimPieces& r = counter.result();
    const auto northIt = std::find_if(r.rimNodes.begin(), r.rimNodes.end(),
                                      [&](std::uint32_t n) { return graph->coord[n].z > 16; });
    ASSERT_NE(northIt, r.rimNodes.end());
    const std::uint32_t north = r.pieceOfRimNode[std::size_t(northIt - r.rimNodes.begin())];
    for (std::size_t i = 0; i < r.rimNodes.size(); ++i) {
        const int z = graph->coord[r.rimNodes[i]].z;
        if (z > 16) {
            EXPECT_EQ(r.pieceOfRimNode[i], north);
        }
        if (z < 14) {
            EXPECT_NE(r.pieceOfRimNode[i], north);
        }
    }
    // A tilted loop through three points, and one with duplicates in the set.
    const auto tilted = test::pathThrough(search, {at(30, 0), at(-30, 120), at(10, 240)}, true);
    EXPECT_EQ(rimCount(*graph, tilted), 2u);
    std::vector<std::uint32_t> doubled = loop;
    doubled.insert(doubled.end(), loop.begin(), loop.end());
    EXPECT_EQ(rimCount(*graph, doubled), 2u);
}

TEST_F(RimsOnSphere, ThetaHasThreeRims) {
    GeodesicSearch search(*graph);
    std::vector<std::uint32_t> theta = equatorLoop(search);
    // Across the northern hemisphere, from one loop point over the pole to
    // the opposite loop point.
    for (std::uint32_t n : test::pathThrough(search, {at(0, 0), at(90, 0), at(0, 180)}, false))
        theta.push_back(n);
    RimCounter counter(*graph);
    EXPECT_EQ(counter.countRims(theta).pieceCount, 3u);
    expectConsistent(*graph, theta, counter);
    // Add a path across the southern hemisphere too: four rims.
    for (std::uint32_t n : test::pathThrough(search, {at(0, 90), at(-90, 0), at(0, 270)}, false))
        theta.push_back(n);
    EXPECT_EQ(counter.countRims(theta).pieceCount, 4u);
}

TEST_F(RimsOnSphere, RandomLoopsHaveTwoRimsAndPathsOne) {
    // Loops through three points spread around the sphere at random
    // latitudes: the rims of such geodesic loops are often connected only
    // through corner (sqrt 3) steps, which 26-adjacency must follow.
    GeodesicSearch search(*graph);
    RimCounter counter(*graph);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> latitude(-50.0, 50.0), longitude(0.0, 120.0);
    for (int trial = 0; trial < 60; ++trial) {
        const double start = longitude(rng);
        const std::vector<std::uint32_t> points = {at(latitude(rng), start),
                                                   at(latitude(rng), start + 120.0),
                                                   at(latitude(rng), start + 240.0)};
        const auto loop = test::pathThrough(search, points, true);
        EXPECT_EQ(counter.countRims(loop).pieceCount, 2u) << "loop " << trial;
        if (trial % 10 == 0) expectConsistent(*graph, loop, counter);
        EXPECT_EQ(counter.countRims(test::pathThrough(search, points, false)).pieceCount, 1u)
            << "path " << trial;
    }
}

TEST_F(RimsOnSphere, TrivialSets) {
    RimCounter counter(*graph);
    EXPECT_EQ(counter.countRims({}).pieceCount, 0u);
    EXPECT_TRUE(counter.result().dilated.empty());
    EXPECT_EQ(counter.countRims({at(0, 0)}).pieceCount, 1u);
    expectConsistent(*graph, {at(0, 0)}, counter);
    // The workspace forgets the previous call entirely.
    GeodesicSearch search(*graph);
    counter.countRims(equatorLoop(search));
    EXPECT_EQ(counter.countRims({at(45, 45)}).pieceCount, 1u);
    EXPECT_FALSE(counter.isInPathSet(at(0, 0)));
    EXPECT_FALSE(counter.isInDilated(at(0, 0)));
}

TEST_F(RimsOnSphere, WholeSurfaceHasNoRim) {
    std::vector<std::uint32_t> all(graph->nodeCount());
    for (std::uint32_t n = 0; n < graph->nodeCount(); ++n) all[n] = n;
    EXPECT_EQ(rimCount(*graph, all), 0u);
}

}  // namespace
}  // namespace skelseg
