#include "kernels/BoundaryGraph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include "io/shapes/SyntheticShapes.h"
#include "tests/kernels/KernelTestSupport.h"
#include "tests/support/DirtyAllocations.h"

namespace skelseg {
namespace {

/// Reference boundary test: object voxel with a face neighbour that is
/// background or outside the grid.
bool isBoundaryReference(const MaskVolume& mask, int x, int y, int z) {
    if (!mask(x, y, z)) return false;
    const int steps[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const auto& s : steps) {
        const int qx = x + s[0], qy = y + s[1], qz = z + s[2];
        if (!mask.contains(qx, qy, qz) || !mask(qx, qy, qz)) return true;
    }
    return false;
}

/// Checks nodes, coordinates, the node map, and that the edges are exactly
/// the 26-adjacent pairs of boundary voxels with Euclidean weights.
void expectGraphMatchesReference(const MaskVolume& mask, const BoundaryGraph& graph) {
    const Dims d = mask.dims();
    ASSERT_EQ(graph.dims, d);
    ASSERT_EQ(graph.nodeOfVoxel.size(), mask.size());
    ASSERT_EQ(graph.coord.size(), graph.voxel.size());
    ASSERT_EQ(graph.offset.size(), std::size_t(graph.nodeCount()) + 1);
    ASSERT_EQ(graph.neighbour.size(), graph.weight.size());
    ASSERT_EQ(graph.offset.back(), graph.neighbour.size());

    // Nodes: exactly the reference boundary voxels, brick by brick (8^3
    // bricks in z, y, x order, voxels inside a brick in z, y, x order).
    std::vector<std::uint32_t> expected;
    constexpr int kBrick = 8;
    for (int z0 = 0; z0 < d.z; z0 += kBrick)
        for (int y0 = 0; y0 < d.y; y0 += kBrick)
            for (int x0 = 0; x0 < d.x; x0 += kBrick)
                for (int z = z0; z < std::min(d.z, z0 + kBrick); ++z)
                    for (int y = y0; y < std::min(d.y, y0 + kBrick); ++y)
                        for (int x = x0; x < std::min(d.x, x0 + kBrick); ++x)
                            if (isBoundaryReference(mask, x, y, z))
                                expected.push_back(std::uint32_t(mask.index(x, y, z)));
    ASSERT_EQ(graph.voxel, expected);
    for (std::uint32_t n = 0; n < graph.nodeCount(); ++n) {
        const Coord c = graph.coord[n];
        ASSERT_EQ(mask.index(c.x, c.y, c.z), graph.voxel[n]);
        ASSERT_EQ(graph.nodeOfVoxel[graph.voxel[n]], n);
    }
    std::size_t mapped = 0;
    for (std::uint32_t node : graph.nodeOfVoxel) mapped += node != kNoNode;
    EXPECT_EQ(mapped, graph.nodeCount());

    // Edges: every 26-adjacent pair of boundary voxels, and nothing else.
    std::map<std::pair<std::uint32_t, std::uint32_t>, float> edges;
    for (std::uint32_t n = 0; n < graph.nodeCount(); ++n)
        for (std::uint32_t e = graph.offset[n]; e < graph.offset[n + 1]; ++e) {
            const std::uint32_t m = graph.neighbour[e];
            ASSERT_LT(m, graph.nodeCount());
            ASSERT_NE(m, n) << "self loop";
            ASSERT_TRUE(edges.emplace(std::make_pair(n, m), graph.weight[e]).second)
                << "duplicate edge";
        }
    std::size_t expectedEdges = 0;
    for (std::uint32_t n = 0; n < graph.nodeCount(); ++n) {
        const Coord c = graph.coord[n];
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    if (!dx && !dy && !dz) continue;
                    const int x = c.x + dx, y = c.y + dy, z = c.z + dz;
                    if (!mask.contains(x, y, z) || !isBoundaryReference(mask, x, y, z)) continue;
                    const std::uint32_t m = graph.nodeOfVoxel[mask.index(x, y, z)];
                    ++expectedEdges;
                    auto it = edges.find({n, m});
                    ASSERT_NE(it, edges.end()) << "missing edge between 26-neighbours";
                    const float length = std::sqrt(float(dx * dx + dy * dy + dz * dz));
                    EXPECT_EQ(it->second, length);
                    // Symmetric, with the same weight.
                    auto back = edges.find({m, n});
                    ASSERT_NE(back, edges.end());
                    EXPECT_EQ(back->second, it->second);
                }
    }
    EXPECT_EQ(edges.size(), expectedEdges) << "edges between voxels that are not 26-neighbours";
}

TEST(BoundaryGraph, RandomMasksMatchReference) {
    for (std::uint32_t seed : {1u, 2u, 3u}) {
        const MaskVolume mask = test::randomMask(Dims{13, 9, 11}, 0.55 + 0.15 * seed, seed);
        SCOPED_TRACE("seed " + std::to_string(seed));
        expectGraphMatchesReference(mask, buildBoundaryGraph(mask, {false}));
    }
}

TEST(BoundaryGraph, BlobMatchesReference) {
    const MaskVolume mask = test::randomBlob(22, 4, 7);
    expectGraphMatchesReference(mask, buildBoundaryGraph(mask, {false}));
}

TEST(BoundaryGraph, GridBorderCountsAsBackground) {
    // A completely full grid: its outer layer is the boundary.
    MaskVolume mask(Dims{5, 6, 7}, 1);
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    EXPECT_EQ(graph.nodeCount(), 5u * 6u * 7u - 3u * 4u * 5u);
    EXPECT_EQ(graph.nodeOfVoxel[mask.index(2, 3, 3)], kNoNode);
    EXPECT_NE(graph.nodeOfVoxel[mask.index(0, 3, 3)], kNoNode);
    expectGraphMatchesReference(mask, graph);
}

TEST(BoundaryGraph, BoundaryVoxelsMaskAgreesWithNodes) {
    const MaskVolume mask = test::randomBlob(20, 3, 11);
    const MaskVolume boundary = boundaryVoxels(mask, {false});
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    std::size_t count = 0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        EXPECT_EQ(boundary[i] != 0, graph.nodeOfVoxel[i] != kNoNode) << "voxel " << i;
        count += boundary[i] != 0;
    }
    EXPECT_EQ(count, graph.nodeCount());
    EXPECT_EQ(boundaryVoxels(mask, {true}).values(), boundary.values());
    // The count without the volume, serial and parallel alike.
    EXPECT_EQ(countBoundaryVoxels(mask, {false}), count);
    EXPECT_EQ(countBoundaryVoxels(mask, {true}), count);
}

TEST(BoundaryGraph, BoundaryVoxelsEqualsReferenceUpToTheGridFaces) {
    // Dense random masks touch every face, edge and corner of the grid, where
    // the mask takes the bounds-checked test, and fill its inside, where it
    // reads the six neighbours by offsets; both must give the reference.
    for (const Dims dims : {Dims{9, 7, 6}, Dims{3, 3, 3}, Dims{2, 5, 4}, Dims{1, 1, 1}}) {
        for (unsigned seed = 1; seed <= 3; ++seed) {
            MaskVolume mask(dims, 0);
            std::uint32_t state = seed * 2654435761u;
            for (std::size_t i = 0; i < mask.size(); ++i) {
                state = state * 1664525u + 1013904223u;
                mask[i] = (state >> 24) < 200 ? 1 : 0;  // about 78% object
            }
            for (const bool threaded : {false, true}) {
                const MaskVolume boundary = boundaryVoxels(mask, {threaded});
                for (int z = 0; z < dims.z; ++z)
                    for (int y = 0; y < dims.y; ++y)
                        for (int x = 0; x < dims.x; ++x)
                            ASSERT_EQ(boundary(x, y, z) != 0, isBoundaryReference(mask, x, y, z))
                                << "voxel " << x << "," << y << "," << z << " seed " << seed;
                const auto flagged = std::uint64_t(
                    std::count(boundary.values().begin(), boundary.values().end(), 1));
                EXPECT_EQ(countBoundaryVoxels(mask, {threaded}), flagged);
            }
        }
    }
}

TEST(BoundaryGraph, DiagonalOnlyBackgroundIsNotBoundary) {
    // An interior voxel whose only background neighbour is diagonal (26 but
    // not 6) is not a boundary voxel: the 6-background rule.
    MaskVolume mask(Dims{7, 7, 7}, 0);
    test::fillBox(mask, {1, 1, 1}, {5, 5, 5});
    mask(2, 2, 2) = 0;  // hole: (3,3,3) touches it only diagonally
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    EXPECT_EQ(graph.nodeOfVoxel[mask.index(3, 3, 3)], kNoNode);
    EXPECT_NE(graph.nodeOfVoxel[mask.index(3, 2, 2)], kNoNode);  // face neighbour of the hole
    expectGraphMatchesReference(mask, graph);
}

TEST(BoundaryGraph, TwoDisjointBlobsGiveTwoComponents) {
    MaskVolume mask(Dims{24, 12, 10}, 0);
    test::fillBox(mask, {1, 1, 1}, {6, 8, 7});    // 6x8x7: 336 - 4*6*5 = 216 boundary voxels
    test::fillBox(mask, {10, 2, 2}, {21, 6, 6});  // 12x5x5: 300 - 10*3*3 = 210 boundary voxels
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    ASSERT_EQ(graph.componentSize.size(), 2u);
    // Numbered by smallest node id: node 0 lies in the first box (lowest z, y).
    EXPECT_EQ(graph.component[0], 0u);
    const std::uint32_t a = graph.nodeOfVoxel[mask.index(1, 1, 1)];
    const std::uint32_t b = graph.nodeOfVoxel[mask.index(21, 6, 6)];
    EXPECT_EQ(graph.componentSize[graph.component[a]], 216u);
    EXPECT_EQ(graph.componentSize[graph.component[b]], 210u);
    EXPECT_NE(graph.component[a], graph.component[b]);
    std::vector<std::uint32_t> count(2, 0);
    for (std::uint32_t c : graph.component) ++count[c];
    EXPECT_EQ(count[0], graph.componentSize[0]);
    EXPECT_EQ(count[1], graph.componentSize[1]);
    // Components are closed under edges.
    for (std::uint32_t n = 0; n < graph.nodeCount(); ++n)
        for (std::uint32_t e = graph.offset[n]; e < graph.offset[n + 1]; ++e)
            ASSERT_EQ(graph.component[n], graph.component[graph.neighbour[e]]);
}

TEST(BoundaryGraph, HollowBallHasInnerAndOuterSurface) {
    MaskVolume mask = test::ballMask(Dims{21, 21, 21}, {10, 10, 10}, 9.0);
    const MaskVolume inner = test::ballMask(Dims{21, 21, 21}, {10, 10, 10}, 4.0);
    for (std::size_t i = 0; i < mask.size(); ++i)
        if (inner[i]) mask[i] = 0;
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    ASSERT_EQ(graph.componentSize.size(), 2u);
    EXPECT_GT(graph.componentSize[0], graph.componentSize[1]);  // the outer surface holds node 0
    EXPECT_EQ(graph.componentSize[0] + graph.componentSize[1], graph.nodeCount());
}

TEST(BoundaryGraph, EmptyMaskGivesEmptyGraph) {
    const MaskVolume mask(Dims{4, 5, 6}, 0);
    const BoundaryGraph graph = buildBoundaryGraph(mask);
    EXPECT_EQ(graph.nodeCount(), 0u);
    EXPECT_EQ(graph.edgeCount(), 0u);
    EXPECT_TRUE(graph.componentSize.empty());
}

TEST(BoundaryGraph, TheNodeMapIsWrittenEverywhereWhenMemoryComesDirty) {
    // The voxel -> node map is allocated unwritten and each slab writes its
    // own part; a slab left out would keep the allocator's bytes (0xA5...),
    // which no real node id or kNoNode equals.
    const test::DirtyAllocations dirty;
    const MaskVolume figure = rasterise(makeShape("figure"), {44, 2});
    const MaskVolume blob = test::randomBlob(30, 5, 3);
    for (const MaskVolume* mask : {&figure, &blob})
        for (bool threaded : {false, true}) {
            SCOPED_TRACE(std::string(threaded ? "parallel" : "serial") + ", dirty " +
                         (dirty.active() ? "yes" : "no"));
            expectGraphMatchesReference(*mask, buildBoundaryGraph(*mask, {threaded}));
        }
}

TEST(BoundaryGraph, SerialEqualsParallel) {
    const MaskVolume mask = rasterise(makeShape("figure"), {48, 2});
    const BoundaryGraph serial = buildBoundaryGraph(mask, {false});
    const BoundaryGraph parallel = buildBoundaryGraph(mask, {true});
    EXPECT_EQ(serial.voxel, parallel.voxel);
    EXPECT_EQ(serial.offset, parallel.offset);
    EXPECT_EQ(serial.neighbour, parallel.neighbour);
    EXPECT_EQ(serial.weight, parallel.weight);
    EXPECT_EQ(serial.nodeOfVoxel, parallel.nodeOfVoxel);
    EXPECT_EQ(serial.component, parallel.component);
    EXPECT_EQ(serial.componentSize, parallel.componentSize);
    EXPECT_GT(serial.nodeCount(), 500u);
}

}  // namespace
}  // namespace skelseg
