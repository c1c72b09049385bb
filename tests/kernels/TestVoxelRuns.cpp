#include "kernels/VoxelRuns.h"

#include <gtest/gtest.h>

#include <vector>

#include "tests/kernels/KernelTestSupport.h"

namespace skelseg {
namespace {

/// The mask the runs describe: 1 on every run's voxels.
MaskVolume paint(const VoxelRuns& runs) {
    MaskVolume mask(runs.dims, 0);
    for (int z = 0; z < runs.dims.z; ++z)
        for (int y = 0; y < runs.dims.y; ++y) {
            const std::size_t row = runs.rowOf(y, z);
            for (std::uint32_t k = runs.rowStart[row]; k < runs.rowStart[row + 1]; ++k) {
                const VoxelRun& run = runs.runs[k];
                EXPECT_LE(run.x0, run.x1);
                if (k > runs.rowStart[row]) EXPECT_GT(run.x0, runs.runs[k - 1].x1 + 1);
                for (int x = run.x0; x <= run.x1; ++x) mask(x, y, z) = 1;
            }
        }
    return mask;
}

/// Reference: per voxel of value `value`, the first voxel (in voxel order) of
/// its component under `adjacency`, by flood fill; ~0 elsewhere.
std::vector<std::size_t> floodFirstVoxel(const MaskVolume& mask, bool value,
                                         VoxelAdjacency adjacency) {
    const Dims d = mask.dims();
    std::vector<std::size_t> first(mask.size(), ~std::size_t(0));
    std::vector<std::array<int, 3>> stack;
    auto has = [&](int x, int y, int z) { return (mask(x, y, z) != 0) == value; };
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) {
                const std::size_t seed = mask.index(x, y, z);
                if (!has(x, y, z) || first[seed] != ~std::size_t(0)) continue;
                first[seed] = seed;
                stack.assign(1, {x, y, z});
                while (!stack.empty()) {
                    const auto [vx, vy, vz] = stack.back();
                    stack.pop_back();
                    for (int dz = -1; dz <= 1; ++dz)
                        for (int dy = -1; dy <= 1; ++dy)
                            for (int dx = -1; dx <= 1; ++dx) {
                                const int steps = (dx != 0) + (dy != 0) + (dz != 0);
                                if (steps == 0) continue;
                                if (adjacency == VoxelAdjacency::Face6 && steps > 1) continue;
                                const int qx = vx + dx, qy = vy + dy, qz = vz + dz;
                                if (!mask.contains(qx, qy, qz) || !has(qx, qy, qz)) continue;
                                const std::size_t q = mask.index(qx, qy, qz);
                                if (first[q] != ~std::size_t(0)) continue;
                                first[q] = seed;
                                stack.push_back({qx, qy, qz});
                            }
                }
            }
    return first;
}

/// Every run's component root is the run holding its component's first voxel.
void expectComponentsMatchFlood(const MaskVolume& mask, const VoxelRuns& runs, bool value,
                                VoxelAdjacency adjacency, const std::vector<std::uint32_t>& root) {
    const std::vector<std::size_t> first = floodFirstVoxel(mask, value, adjacency);
    ASSERT_EQ(root.size(), runs.runs.size());
    for (int z = 0; z < runs.dims.z; ++z)
        for (int y = 0; y < runs.dims.y; ++y) {
            const std::size_t row = runs.rowOf(y, z);
            for (std::uint32_t k = runs.rowStart[row]; k < runs.rowStart[row + 1]; ++k) {
                const VoxelRun& run = runs.runs[k];
                const std::size_t firstVoxel = first[mask.index(run.x0, y, z)];
                // The root run starts at the first voxel of the component.
                const std::uint32_t r = root[k];
                ASSERT_LE(r, k);
                EXPECT_EQ(root[r], r);
                bool found = false;
                for (std::size_t rr = 0; rr < runs.rowCount() && !found; ++rr)
                    if (r >= runs.rowStart[rr] && r < runs.rowStart[rr + 1]) {
                        const int ry = int(rr % std::size_t(runs.dims.y)),
                                  rz = int(rr / std::size_t(runs.dims.y));
                        EXPECT_EQ(mask.index(runs.runs[r].x0, ry, rz), firstVoxel)
                            << "run " << k << " of row " << y << " " << z;
                        found = true;
                    }
                EXPECT_TRUE(found);
            }
        }
}

TEST(VoxelRuns, RunsDescribeTheMaskAndItsBackground) {
    for (double density : {0.0, 0.1, 0.5, 0.9, 1.0}) {
        const MaskVolume mask = test::randomMask(Dims{19, 7, 21}, density, 3);
        SCOPED_TRACE(::testing::Message() << "density " << density);
        const VoxelRuns serial = objectRuns(mask, false);
        const VoxelRuns parallel = objectRuns(mask, true);
        EXPECT_TRUE(serial.rowStart == parallel.rowStart);
        EXPECT_TRUE(serial.runs == parallel.runs);
        EXPECT_TRUE(paint(serial).values() == mask.values());
        const VoxelRuns background = backgroundRuns(serial, true);
        EXPECT_TRUE(backgroundRuns(serial, false).runs == background.runs);
        const MaskVolume free = paint(background);
        for (std::size_t i = 0; i < mask.size(); ++i)
            ASSERT_EQ(free[i], mask[i] ? 0 : 1) << "voxel " << i;
    }
}

TEST(VoxelRuns, ComponentsMatchAFloodFillSerialAndParallel) {
    // Sizes over the 8-plane slab seams; sparse masks give many components
    // joined only at edges and corners.
    const Dims sizes[] = {{1, 1, 1}, {9, 6, 17}, {23, 11, 30}};
    for (const Dims& d : sizes)
        for (double density : {0.1, 0.3, 0.6})
            for (VoxelAdjacency adjacency : {VoxelAdjacency::Face6, VoxelAdjacency::Full26}) {
                const MaskVolume mask = test::randomMask(d, density, 11);
                SCOPED_TRACE(::testing::Message()
                             << d.x << "x" << d.y << "x" << d.z << " density " << density
                             << (adjacency == VoxelAdjacency::Face6 ? " 6" : " 26"));
                const VoxelRuns objects = objectRuns(mask, true);
                const VoxelRuns background = backgroundRuns(objects, true);
                for (const bool value : {true, false}) {
                    const VoxelRuns& runs = value ? objects : background;
                    const std::vector<std::uint32_t> serial = runComponents(runs, adjacency, false);
                    const std::vector<std::uint32_t> parallel =
                        runComponents(runs, adjacency, true);
                    EXPECT_TRUE(serial == parallel);
                    expectComponentsMatchFlood(mask, runs, value, adjacency, serial);
                }
            }
}

}  // namespace
}  // namespace skelseg
