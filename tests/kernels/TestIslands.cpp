#include "kernels/Islands.h"

#include <gtest/gtest.h>

#include "kernels/BoundaryGraph.h"
#include "tests/kernels/KernelTestSupport.h"

namespace skelseg {
namespace {

/// A ball of radius 9 (the shape), a ball of radius 4 beside it (a small but
/// real object), a 3x3x3 cube and three single voxels, all apart.
MaskVolume scene() {
    MaskVolume mask = test::ballMask(Dims{48, 24, 24}, {11.0, 11.0, 11.0}, 9.0);
    const MaskVolume small = test::ballMask(Dims{48, 24, 24}, {30.0, 11.0, 11.0}, 4.0);
    for (std::size_t i = 0; i < mask.size(); ++i) mask[i] |= small[i];
    test::fillBox(mask, {40, 3, 3}, {42, 5, 5});
    mask(45, 20, 20) = 1;
    mask(40, 20, 2) = 1;
    mask(47, 0, 0) = 1;  // on the grid's corner: every outside face counts as background
    return mask;
}

TEST(Islands, BoundaryAreasCountSixBoundaryVoxels) {
    const MaskVolume mask = scene();
    const ConnectedObjects objects = findConnectedObjects(mask, {false});
    ASSERT_EQ(objects.objects.size(), 6u);
    const std::vector<std::uint64_t> areas = objectBoundaryAreas(mask, objects, {false});
    ASSERT_EQ(areas.size(), 6u);
    // Each object's area equals the node count of its own boundary graph.
    for (std::uint32_t o = 0; o < objects.objects.size(); ++o) {
        MaskVolume alone(mask.dims(), 0);
        const Dims d = mask.dims();
        for (int z = 0; z < d.z; ++z)
            for (int y = 0; y < d.y; ++y)
                for (int x = 0; x < d.x; ++x)
                    alone(x, y, z) = objects.componentAt(x, y, z) == o + 1;
        EXPECT_EQ(areas[o], buildBoundaryGraph(alone, {false}).nodeCount()) << "object " << o;
    }
    // A 3x3x3 cube has 26 boundary voxels, a single voxel 1.
    std::uint64_t cubes = 0, singles = 0;
    for (std::uint32_t o = 0; o < objects.objects.size(); ++o) {
        cubes += objects.objects[o].voxels == 27 && areas[o] == 26;
        singles += objects.objects[o].voxels == 1 && areas[o] == 1;
    }
    EXPECT_EQ(cubes, 1u);
    EXPECT_EQ(singles, 3u);
}

TEST(Islands, SerialAndParallelAgree) {
    const MaskVolume mask = test::randomMask(Dims{40, 33, 37}, 0.3, 7);
    const ConnectedObjects objects = findConnectedObjects(mask, {false});
    ASSERT_GT(objects.objects.size(), 10u);
    EXPECT_EQ(objectBoundaryAreas(mask, objects, {false}),
              objectBoundaryAreas(mask, objects, {true}));
}

TEST(Islands, ObjectsBelowTheNoiseAreaAreIslands) {
    const MaskVolume mask = scene();
    const ConnectedObjects objects = findConnectedObjects(mask, {false});
    const std::vector<std::uint64_t> areas = objectBoundaryAreas(mask, objects, {false});
    const std::uint32_t largest = largestObject(areas);
    EXPECT_GT(objects.objects[largest].voxels, 2000u);  // the big ball
    // A noise area between the cube (26) and the small ball (~150).
    const Islands islands = findIslands(objects.objects, areas, 60.0);
    EXPECT_EQ(islands.count, 4u);
    EXPECT_EQ(islands.voxels, 27u + 3u);
    for (std::uint32_t o = 0; o < objects.objects.size(); ++o)
        EXPECT_EQ(islands.isIsland[o] != 0, areas[o] < 60) << "object " << o;
    EXPECT_EQ(islands.isIsland[largest], 0);
}

TEST(Islands, TheLargestObjectIsNeverAnIsland) {
    MaskVolume mask(Dims{8, 8, 8}, 0);
    mask(3, 3, 3) = 1;
    mask(6, 6, 6) = 1;
    const ConnectedObjects objects = findConnectedObjects(mask, {false});
    const std::vector<std::uint64_t> areas = objectBoundaryAreas(mask, objects, {false});
    const Islands islands = findIslands(objects.objects, areas, 10.0);
    // Two single voxels: the first (lower id) is kept as the shape.
    EXPECT_EQ(islands.count, 1u);
    EXPECT_EQ(islands.isIsland[0], 0);
    EXPECT_EQ(islands.isIsland[1], 1);
    EXPECT_EQ(findIslands({}, {}, 10.0).count, 0u);
}

// Objects broken off a mesh piece: only the voxeliser knows their piece
// (ObjectSource); an object that is not its piece's largest and is smaller
// than a part of it is a fragment.
TEST(Islands, ObjectsBrokenOffAPieceAndSmallerThanAPartAreFragments) {
    const MaskVolume mask = scene();
    const ConnectedObjects found = findConnectedObjects(mask, {false});
    ASSERT_EQ(found.objects.size(), 6u);
    const std::vector<std::uint64_t> areas = objectBoundaryAreas(mask, found, {false});
    // The two balls come from piece 5, the 3x3x3 cube alone from piece 7;
    // the single voxels have no source. Each object named by a voxel of it.
    const auto voxelOf = [&](std::uint32_t object) {
        const Dims d = mask.dims();
        for (int z = 0; z < d.z; ++z)
            for (int y = 0; y < d.y; ++y)
                for (int x = 0; x < d.x; ++x)
                    if (found.componentAt(x, y, z) == object + 1)
                        return std::array<int, 3>{x, y, z};
        return std::array<int, 3>{-1, -1, -1};
    };
    std::uint32_t bigBall = 0, smallBall = 0, cube = 0;
    for (std::uint32_t o = 0; o < 6; ++o) {
        if (found.objects[o].voxels > 1000)
            bigBall = o;
        else if (found.objects[o].voxels > 100)
            smallBall = o;
        else if (found.objects[o].voxels == 27)
            cube = o;
    }
    const std::vector<ObjectSource> sources = {
        {voxelOf(smallBall), 5}, {voxelOf(bigBall), 5}, {voxelOf(cube), 7}};
    const double ratio = double(areas[smallBall]) / double(areas[bigBall]);
    ASSERT_LT(ratio, 0.5);

    // A part of piece 5 needs more area than the small ball has: a fragment.
    const auto share = [](double fraction) {
        return [fraction](double area) { return fraction * area; };
    };
    Fragments fragments = findFragments(found, areas, sources, {}, share(ratio + 0.01));
    EXPECT_EQ(fragments.count, 1u);
    EXPECT_EQ(fragments.voxels, found.objects[smallBall].voxels);
    for (std::uint32_t o = 0; o < 6; ++o)
        EXPECT_EQ(fragments.isFragment[o], o == smallBall ? 1 : 0) << "object " << o;
    // Large enough to be a part: an object of its own, as a limb beyond a
    // neck thinner than a voxel is.
    EXPECT_EQ(findFragments(found, areas, sources, {}, share(ratio - 0.01)).count, 0u);
    // The only object of its piece is never a fragment, however small.
    EXPECT_EQ(findFragments(found, areas, sources, {}, share(1e9)).isFragment[cube], 0);
    // An island is neither a fragment nor its piece's largest: with the big
    // ball an island, the small one is piece 5's largest.
    std::vector<std::uint8_t> skip(6, 0);
    skip[bigBall] = 1;
    EXPECT_EQ(findFragments(found, areas, sources, skip, share(ratio + 0.01)).count, 0u);
    // Without sources nothing is a fragment.
    EXPECT_EQ(findFragments(found, areas, {}, {}, share(1e9)).count, 0u);
}

}  // namespace
}  // namespace skelseg
