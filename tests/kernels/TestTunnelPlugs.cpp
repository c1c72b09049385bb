#include "kernels/TunnelPlugs.h"

#include <gtest/gtest.h>

#include "kernels/NarrowTunnels.h"
#include "kernels/NeighbourhoodTopology.h"
#include "kernels/VoxelGenus.h"
#include "tests/kernels/KernelTestSupport.h"

namespace skelseg {
namespace {

TEST(TunnelPlugs, AHoleTwoVoxelsWideIsPluggedAndAWiderOneIsNot) {
    MaskVolume narrow = test::plateWithSquareHole(2);
    ASSERT_EQ(voxelTopology(narrow, {false}).genus, 1);
    // One voxel does not close it: the rule of NarrowTunnels.h finds nothing.
    MaskVolume copy = narrow;
    ASSERT_TRUE(closeNarrowTunnels(copy).empty());
    const std::vector<std::size_t> plugs = plugTunnelsTwoVoxelsWide(narrow);
    ASSERT_FALSE(plugs.empty());
    for (std::size_t i : plugs) {
        EXPECT_EQ(narrow[i], 1);
        const int x = int(i % 15), y = int(i / 15 % 15);
        EXPECT_TRUE(x >= 7 && x <= 8 && y >= 7 && y <= 8) << "plug voxel outside the hole";
    }
    const VoxelTopology after = voxelTopology(narrow, {false});
    EXPECT_EQ(after.objects, 1u);
    EXPECT_EQ(after.genus, 0);

    MaskVolume wide = test::plateWithSquareHole(3);
    const MaskVolume before = wide;
    EXPECT_TRUE(plugTunnelsTwoVoxelsWide(wide).empty());
    EXPECT_EQ(wide.values(), before.values());
}

TEST(TunnelPlugs, PartsTwoVoxelsApartAreNotBridged) {
    // A hook: a bar along x, a riser at its start and a bar back over it
    // with its end turned down to two voxels above the first bar. The hook
    // is nearly a ring (genus 0); filling the gap at its tip would make it
    // one. Beside it, a plate with a hole two voxels wide (genus 1), so that
    // the same mask has a tunnel to plug.
    MaskVolume mask(Dims{40, 20, 15}, 0);
    test::fillBox(mask, {2, 2, 2}, {16, 4, 4});    // the bar
    test::fillBox(mask, {2, 2, 5}, {4, 4, 9});     // the riser
    test::fillBox(mask, {2, 2, 10}, {16, 4, 12});  // the bar back over it
    test::fillBox(mask, {14, 2, 7}, {16, 4, 9});   // its end turned down: z 5, 6 open
    test::fillBox(mask, {20, 2, 2}, {36, 17, 4});  // the plate
    for (int y = 8; y <= 9; ++y)
        for (int x = 27; x <= 28; ++x)
            for (int z = 2; z <= 4; ++z) mask(x, y, z) = 0;
    const VoxelTopology before = voxelTopology(mask, {false});
    ASSERT_EQ(before.genus, 1);
    const MaskVolume original = mask;
    const std::vector<std::size_t> plugs = plugTunnelsTwoVoxelsWide(mask);
    ASSERT_FALSE(plugs.empty());
    for (std::size_t i : plugs) EXPECT_GE(int(i % 40), 20) << "a plug on the hook";
    for (std::size_t i = 0; i < mask.size(); ++i)
        if (int(i % 40) < 19) ASSERT_EQ(mask[i], original[i]) << "the hook changed";
    const VoxelTopology after = voxelTopology(mask, {false});
    EXPECT_EQ(after.objects, before.objects);
    EXPECT_EQ(after.genus, 0);
}

TEST(TunnelPlugs, GroovesAndPitsTwoVoxelsWideAreLeftAlone) {
    // A box with a groove two voxels wide and deep along x on its top and a
    // pit two voxels wide and four deep: no tunnel, nothing to plug.
    MaskVolume mask(Dims{18, 18, 12}, 0);
    test::fillBox(mask, {1, 1, 1}, {16, 16, 8});
    for (int x = 1; x <= 16; ++x)
        for (int y = 4; y <= 5; ++y)
            for (int z = 7; z <= 8; ++z) mask(x, y, z) = 0;
    for (int z = 5; z <= 8; ++z)
        for (int y = 10; y <= 11; ++y)
            for (int x = 10; x <= 11; ++x) mask(x, y, z) = 0;
    const MaskVolume before = mask;
    EXPECT_TRUE(plugTunnelsTwoVoxelsWide(mask).empty());
    EXPECT_EQ(mask.values(), before.values());
}

TEST(TunnelPlugs, NoObjectsJoinTheGenusNeverGrowsAndEveryPlugClosesAPassage) {
    // Random dense masks hold every local configuration.
    for (const std::uint32_t seed : {3u, 4u, 5u, 6u}) {
        SCOPED_TRACE(seed);
        MaskVolume mask = test::randomMask(Dims{26, 22, 19}, 0.55, seed);
        test::emptyOuterLayer(mask);
        closeNarrowTunnels(mask);
        const VoxelTopology before = voxelTopology(mask, {false});
        ASSERT_GT(before.genus, 0);
        const std::vector<std::size_t> plugs = plugTunnelsTwoVoxelsWide(mask);
        ASSERT_FALSE(plugs.empty());
        const VoxelTopology after = voxelTopology(mask, {false});
        EXPECT_EQ(after.objects, before.objects);
        EXPECT_LT(after.genus, before.genus);
        const Dims d = mask.dims();
        for (std::size_t i : plugs) {
            ASSERT_EQ(mask[i], 1);
            const int x = int(i % std::size_t(d.x)),
                      y = int(i / std::size_t(d.x) % std::size_t(d.y)),
                      z = int(i / (std::size_t(d.x) * std::size_t(d.y)));
            const std::uint32_t bits = neighbourhoodBits(mask, x, y, z);
            EXPECT_EQ(objectPieces26(bits), 1);
            EXPECT_NE(backgroundPieces6(bits), 1);
        }
    }
}

/// Asks to stop at its poll number `stopAt` (0 = the first).
class StopAtPoll final : public Interrupter {
public:
    explicit StopAtPoll(int stopAt) : mLeft(stopAt) {}
    bool wasInterrupted(double) override { return mLeft-- <= 0; }

private:
    int mLeft;
};

TEST(TunnelPlugs, StopsWhenAskedAndLeavesTheMaskUnchanged) {
    // The scan polls once per plane (5 here); the sixth poll comes after
    // the added voxels were set and thinned.
    for (const int stopAt : {0, 4, 5}) {
        SCOPED_TRACE(stopAt);
        MaskVolume mask = test::plateWithSquareHole(2);
        const MaskVolume before = mask;
        StopAtPoll stop(stopAt);
        EXPECT_THROW(plugTunnelsTwoVoxelsWide(mask, stop), InterruptedError);
        EXPECT_EQ(mask.values(), before.values());
    }
}

}  // namespace
}  // namespace skelseg
