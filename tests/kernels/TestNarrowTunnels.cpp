#include "kernels/NarrowTunnels.h"

#include <gtest/gtest.h>

#include "kernels/VoxelGenus.h"
#include "tests/kernels/KernelTestSupport.h"
#include "tests/support/StopAtOnce.h"

namespace skelseg {
namespace {

TEST(NarrowTunnels, AHoleOneVoxelWideIsClosedAndAWiderOneIsNot) {
    MaskVolume narrow = test::plateWithSquareHole(1);
    ASSERT_EQ(voxelTopology(narrow, {false}).genus, 1);
    const std::vector<std::size_t> closed = closeNarrowTunnels(narrow);
    // The hole's bottom voxel closes it; its top voxel then seals the
    // middle one as a cavity (which the engine fills).
    ASSERT_EQ(closed.size(), 2u);
    EXPECT_EQ(closed[0], narrow.index(7, 7, 2));
    EXPECT_EQ(closed[1], narrow.index(7, 7, 4));
    const VoxelTopology after = voxelTopology(narrow, {false});
    EXPECT_EQ(after.objects, 1u);
    EXPECT_EQ(after.genus, 0);
    EXPECT_EQ(after.cavities, 1u);

    MaskVolume wide = test::plateWithSquareHole(2);
    const MaskVolume before = wide;
    EXPECT_TRUE(closeNarrowTunnels(wide).empty());
    EXPECT_EQ(wide.values(), before.values());
}

TEST(NarrowTunnels, AnArchOverTheSurfaceIsClosedAtBothEnds) {
    // A box whose top is z = 4, and an arch of five voxels over (5, 5, 5):
    // a tunnel one voxel wide along y, the kind surface noise makes.
    MaskVolume mask(Dims{11, 11, 9}, 0);
    test::fillBox(mask, {1, 1, 1}, {9, 9, 4});
    for (const auto& v :
         std::vector<std::array<int, 3>>{{4, 5, 5}, {4, 5, 6}, {5, 5, 6}, {6, 5, 6}, {6, 5, 5}})
        mask(v[0], v[1], v[2]) = 1;
    ASSERT_EQ(voxelTopology(mask, {false}).genus, 1);
    EXPECT_TRUE(closesNarrowTunnel(mask, 5, 5, 5));
    const std::vector<std::size_t> closed = closeNarrowTunnels(mask);
    // Its entrance is met first in scan order and closes it; the exit then
    // seals the voxel under the arch.
    ASSERT_EQ(closed.size(), 2u);
    EXPECT_EQ(closed[0], mask.index(5, 4, 5));
    EXPECT_EQ(closed[1], mask.index(5, 6, 5));
    const VoxelTopology after = voxelTopology(mask, {false});
    EXPECT_EQ(after.genus, 0);
    EXPECT_EQ(after.cavities, 1u);
}

TEST(NarrowTunnels, GroovesWideHolesAndBumpsAreLeftAlone) {
    // A box with a groove one voxel wide and deep along x on its top, a pit
    // two voxels wide and three deep, a bump on a face and a bump on an edge.
    MaskVolume mask(Dims{16, 16, 12}, 0);
    test::fillBox(mask, {1, 1, 1}, {14, 14, 8});
    for (int x = 1; x <= 14; ++x) mask(x, 4, 8) = 0;
    for (int z = 6; z <= 8; ++z)
        for (int y = 10; y <= 11; ++y)
            for (int x = 10; x <= 11; ++x) mask(x, y, z) = 0;
    mask(7, 10, 9) = 1;
    mask(3, 12, 9) = 1;
    mask(4, 11, 10) = 1;  // touches the bump below it by an edge only
    const MaskVolume before = mask;
    ASSERT_EQ(voxelTopology(mask, {false}).genus, 0);
    EXPECT_TRUE(closeNarrowTunnels(mask).empty());
    EXPECT_EQ(mask.values(), before.values());
}

TEST(NarrowTunnels, APitOneVoxelWideIsSealedBelowItsMouth) {
    MaskVolume mask(Dims{12, 12, 12}, 0);
    test::fillBox(mask, {1, 1, 1}, {10, 10, 8});
    for (int z = 5; z <= 8; ++z) mask(5, 5, z) = 0;
    const std::vector<std::size_t> closed = closeNarrowTunnels(mask);
    ASSERT_FALSE(closed.empty());
    for (std::size_t i : closed) {
        EXPECT_EQ(i % 12, 5u);
        EXPECT_EQ((i / 12) % 12, 5u);
    }
    const VoxelTopology after = voxelTopology(mask, {false});
    EXPECT_EQ(after.genus, 0);
    EXPECT_GE(after.cavities, 1u);
}

TEST(NarrowTunnels, NoObjectsJoinAndTheGenusNeverGrows) {
    // Random dense masks hold every local configuration; each voxel set
    // joins nothing (T26 = 1) and closes a passage (T6 >= 2).
    for (const std::uint32_t seed : {3u, 4u, 5u}) {
        SCOPED_TRACE(seed);
        MaskVolume mask = test::randomMask(Dims{26, 22, 19}, 0.55, seed);
        test::emptyOuterLayer(mask);
        const VoxelTopology before = voxelTopology(mask, {false});
        const std::vector<std::size_t> closed = closeNarrowTunnels(mask);
        ASSERT_FALSE(closed.empty());
        const VoxelTopology after = voxelTopology(mask, {false});
        EXPECT_EQ(after.objects, before.objects);
        EXPECT_LT(after.genus, before.genus);
        for (std::size_t i : closed) EXPECT_EQ(mask[i], 1);
    }
}

TEST(NarrowTunnels, StopsWhenAskedAndLeavesTheMaskUnchanged) {
    MaskVolume mask = test::plateWithSquareHole(1);
    const MaskVolume before = mask;
    test::StopAtOnce stop;
    EXPECT_THROW(closeNarrowTunnels(mask, stop), InterruptedError);
    EXPECT_EQ(mask.values(), before.values());
}

}  // namespace
}  // namespace skelseg
