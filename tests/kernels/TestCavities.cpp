#include "kernels/Cavities.h"

#include <gtest/gtest.h>

#include <queue>

#include "kernels/VoxelGenus.h"
#include "tests/kernels/KernelTestSupport.h"
#include "tests/support/StopAtOnce.h"

namespace skelseg {
namespace {

/// The reference: a flood fill of the background from the grid's border
/// through shared faces; what it does not reach is a cavity. Returns the
/// mask with those voxels set and counts their 6-connected components.
MaskVolume filledByFloodFill(const MaskVolume& mask, std::size_t& components) {
    const Dims d = mask.dims();
    std::vector<std::uint8_t> reached(mask.size(), 0);
    std::queue<std::array<int, 3>> queue;
    const auto visit = [&](int x, int y, int z) {
        if (x < 0 || y < 0 || z < 0 || x >= d.x || y >= d.y || z >= d.z) return;
        const std::size_t i = mask.index(x, y, z);
        if (mask[i] || reached[i]) return;
        reached[i] = 1;
        queue.push({x, y, z});
    };
    const auto flood = [&] {
        while (!queue.empty()) {
            const auto [x, y, z] = queue.front();
            queue.pop();
            visit(x - 1, y, z), visit(x + 1, y, z), visit(x, y - 1, z);
            visit(x, y + 1, z), visit(x, y, z - 1), visit(x, y, z + 1);
        }
    };
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x)
                if (x == 0 || y == 0 || z == 0 || x + 1 == d.x || y + 1 == d.y || z + 1 == d.z)
                    visit(x, y, z);
    flood();
    MaskVolume filled = mask;
    for (std::size_t i = 0; i < mask.size(); ++i) filled[i] = mask[i] || !reached[i];
    components = 0;
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) {
                const std::size_t i = mask.index(x, y, z);
                if (mask[i] || reached[i]) continue;
                ++components;
                visit(x, y, z);  // marks the whole cavity as reached
                flood();
            }
    return filled;
}

/// The voxels of `runs` as a mask of their grid.
MaskVolume maskOfRuns(const VoxelRuns& runs) {
    MaskVolume mask(runs.dims, 0);
    for (int z = 0; z < runs.dims.z; ++z)
        for (int y = 0; y < runs.dims.y; ++y) {
            const std::size_t row = runs.rowOf(y, z);
            for (std::uint32_t k = runs.rowStart[row]; k < runs.rowStart[row + 1]; ++k)
                for (int x = runs.runs[k].x0; x <= runs.runs[k].x1; ++x) mask(x, y, z) = 1;
        }
    return mask;
}

TEST(Cavities, FillWhatAFloodFillFromTheBorderDoesNotReach) {
    // Dense random masks hold many cavities, single voxels and larger ones,
    // and background that reaches the border through faces only.
    for (const std::uint32_t seed : {1u, 2u, 3u}) {
        SCOPED_TRACE(seed);
        const MaskVolume mask = test::randomMask(Dims{23, 19, 17}, 0.62, seed);
        std::size_t expectedCount = 0;
        const MaskVolume expected = filledByFloodFill(mask, expectedCount);
        ASSERT_GT(expectedCount, 5u);
        MaskVolume filled = mask;
        const FilledCavities cavities = fillCavities(filled, {false});
        EXPECT_EQ(cavities.count, expectedCount);
        EXPECT_EQ(filled.values(), expected.values());
        // The runs are exactly the voxels filled.
        const MaskVolume runsMask = maskOfRuns(cavities.runs);
        std::uint64_t voxels = 0;
        for (std::size_t i = 0; i < mask.size(); ++i) {
            ASSERT_EQ(runsMask[i] != 0, expected[i] && !mask[i]) << "voxel " << i;
            voxels += runsMask[i];
        }
        EXPECT_EQ(cavities.voxels, voxels);
        // Nothing is left to fill, and the topology has no cavity.
        EXPECT_EQ(voxelTopology(filled, {false}).cavities, 0u);
    }
}

TEST(Cavities, ABackgroundVoxelJoinedToTheOutsideByAnEdgeOnlyIsACavity) {
    // A hollow 5^3 cube: its centre is a cavity. Opening a face voxel joins
    // the centre to the outside; removing an edge voxel of the shell instead
    // leaves the centre touching the outside through an edge only.
    MaskVolume mask(Dims{7, 7, 7}, 0);
    test::fillBox(mask, {1, 1, 1}, {5, 5, 5});
    for (int z = 2; z <= 4; ++z)
        for (int y = 2; y <= 4; ++y)
            for (int x = 2; x <= 4; ++x) mask(x, y, z) = 0;
    MaskVolume closed = mask;
    FilledCavities cavities = fillCavities(closed, {false});
    EXPECT_EQ(cavities.count, 1u);
    EXPECT_EQ(cavities.voxels, 27u);
    EXPECT_EQ(closed(3, 3, 3), 1);

    MaskVolume open = mask;
    open(3, 3, 1) = 0;  // a hole through the middle of a face
    cavities = fillCavities(open, {false});
    EXPECT_EQ(cavities.count, 0u);
    EXPECT_EQ(open.values(), [&] {
        MaskVolume m = mask;
        m(3, 3, 1) = 0;
        return m.values();
    }());
}

TEST(Cavities, SerialAndParallelAgree) {
    const MaskVolume mask = test::randomMask(Dims{61, 47, 53}, 0.6, 11);
    MaskVolume serial = mask, parallel = mask;
    const FilledCavities a = fillCavities(serial, {false});
    const FilledCavities b = fillCavities(parallel, {true});
    ASSERT_GT(a.count, 10u);
    EXPECT_EQ(a.count, b.count);
    EXPECT_EQ(a.voxels, b.voxels);
    EXPECT_EQ(a.runs.rowStart, b.runs.rowStart);
    EXPECT_EQ(a.runs.runs, b.runs.runs);
    EXPECT_EQ(serial.values(), parallel.values());
}

TEST(Cavities, ClearingTheRunsGivesBackTheInput) {
    const MaskVolume mask = test::randomMask(Dims{30, 20, 25}, 0.6, 5);
    MaskVolume filled = mask;
    const FilledCavities cavities = fillCavities(filled, {false});
    ASSERT_GT(cavities.voxels, 0u);
    Volume<std::uint16_t> labels(mask.dims(), 0);
    for (std::size_t i = 0; i < mask.size(); ++i) labels[i] = filled[i] ? 7 : 0;
    clearVoxelRuns(labels, cavities.runs);
    for (std::size_t i = 0; i < mask.size(); ++i)
        ASSERT_EQ(labels[i], mask[i] ? 7 : 0) << "voxel " << i;
}

TEST(Cavities, StopsWhenAskedAndLeavesTheMaskUnchanged) {
    const MaskVolume mask = test::randomMask(Dims{30, 20, 25}, 0.6, 5);
    MaskVolume filled = mask;
    test::StopAtOnce stop;
    EXPECT_THROW(fillCavities(filled, {false}, stop), InterruptedError);
    EXPECT_EQ(filled.values(), mask.values());
}

}  // namespace
}  // namespace skelseg
