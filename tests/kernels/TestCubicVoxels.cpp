#include "kernels/CubicVoxels.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tests/support/StopAtOnce.h"

namespace skelseg {
namespace {

VolumeGeometry steps(double x, double y, double z) {
    VolumeGeometry g;
    g.origin = {3.0, -2.0, 7.5};
    g.directions = {{{x, 0, 0}, {0, y, 0}, {0, 0, z}}};
    return g;
}

MaskVolume randomMask(Dims dims, const VolumeGeometry& geometry, unsigned seed) {
    MaskVolume mask(dims, 0);
    mask.geometry = geometry;
    std::mt19937 random(seed);
    for (auto& v : mask.values()) v = std::uint8_t(random() % 3 == 0);
    return mask;
}

TEST(CubicVoxels, StepsWithinOnePercentAreCubic) {
    EXPECT_FALSE(hasAnisotropicVoxels(steps(0.5, 0.5, 0.5)));
    EXPECT_FALSE(hasAnisotropicVoxels(steps(1.0, 1.0, 1.009)));
    EXPECT_TRUE(hasAnisotropicVoxels(steps(1.0, 1.0, 1.02)));
    EXPECT_TRUE(hasAnisotropicVoxels(steps(0.7, 0.7, 3.0)));
    // A rotated grid: the steps are the lengths of its directions.
    VolumeGeometry rotated;
    const double c = std::cos(0.3), s = std::sin(0.3);
    rotated.directions = {{{c, s, 0}, {-s, c, 0}, {0, 0, 1}}};
    EXPECT_FALSE(hasAnisotropicVoxels(rotated));
}

TEST(CubicVoxels, TheCubicGridSpansTheInputsBoxWithItsShortestStep) {
    const Dims dims{20, 16, 9};
    const VolumeGeometry input = steps(1.0, 1.5, 2.5);
    const CubicGrid grid = cubicGridFor(dims, input);
    EXPECT_EQ(grid.dims[0], 20);
    EXPECT_EQ(grid.dims[1], 24);
    EXPECT_EQ(grid.dims[2], 23);  // round(9 * 2.5) = 22.5 -> 23 (half away from zero)
    const auto cubicSteps = voxelSteps(grid.geometry);
    for (int a = 0; a < 3; ++a) {
        // Each step is the input's extent over the cubic voxels of that axis.
        const double extent = voxelSteps(input)[std::size_t(a)] *
                              double(std::array<int, 3>{dims.x, dims.y, dims.z}[std::size_t(a)]);
        EXPECT_NEAR(cubicSteps[std::size_t(a)], extent / double(grid.dims[std::size_t(a)]), 1e-12);
        EXPECT_NEAR(cubicSteps[std::size_t(a)], 1.0, 0.03);
    }
    // The first and last cubic voxels' cells end where the input's cells end.
    const auto first = grid.geometry.indexToWorld(-0.5, -0.5, -0.5);
    const auto inputFirst = input.indexToWorld(-0.5, -0.5, -0.5);
    const auto last = grid.geometry.indexToWorld(
        double(grid.dims[0]) - 0.5, double(grid.dims[1]) - 0.5, double(grid.dims[2]) - 0.5);
    const auto inputLast = input.indexToWorld(dims.x - 0.5, dims.y - 0.5, dims.z - 0.5);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(first[std::size_t(c)], inputFirst[std::size_t(c)], 1e-9);
        EXPECT_NEAR(last[std::size_t(c)], inputLast[std::size_t(c)], 1e-9);
    }
}

TEST(CubicVoxels, ACubicVoxelTakesTheInputVoxelItsCentreLiesIn) {
    const Dims dims{7, 5, 4};
    const CubicGrid grid = cubicGridFor(dims, steps(1.0, 1.7, 3.3));
    for (int z = 0; z < int(grid.dims[2]); ++z)
        for (int y = 0; y < int(grid.dims[1]); ++y)
            for (int x = 0; x < int(grid.dims[0]); ++x) {
                // The centre in the input's continuous indices, cells from -0.5.
                const std::array<double, 3> centre{(x + 0.5) / grid.scale[0] - 0.5,
                                                   (y + 0.5) / grid.scale[1] - 0.5,
                                                   (z + 0.5) / grid.scale[2] - 0.5};
                const auto input = grid.inputVoxelOf({x, y, z});
                for (int a = 0; a < 3; ++a) {
                    EXPECT_LE(std::abs(centre[std::size_t(a)] - input[std::size_t(a)]), 0.5 + 1e-9)
                        << x << " " << y << " " << z << " axis " << a;
                }
            }
}

TEST(CubicVoxels, TheInputVoxelOfTheCubicVoxelOfAnInputVoxelIsItself) {
    // Every axis length and scale up to 6: the integer maps are exact inverses.
    for (std::int64_t n = 1; n <= 40; ++n)
        for (std::int64_t cubic = n; cubic <= 6 * n; ++cubic) {
            CubicGrid grid;
            grid.inputDims = Dims{int(n), 1, 1};
            grid.dims = {cubic, 1, 1};
            for (int x = 0; x < int(n); ++x)
                ASSERT_EQ(grid.inputVoxelOf(grid.cubicVoxelOf({x, 0, 0}))[0], x)
                    << "n " << n << " cubic " << cubic;
        }
}

TEST(CubicVoxels, LabelsBackOnTheInputGridGiveTheInputMask) {
    const Dims dims{13, 9, 6};
    const MaskVolume mask = randomMask(dims, steps(1.0, 1.25, 2.6), 7);
    const CubicGrid grid = cubicGridFor(dims, mask.geometry);
    const MaskVolume cubic = resampleToCubicVoxels(mask, grid);
    ASSERT_EQ(cubic.dims().z, int(grid.dims[2]));
    LabelVolume labels(cubic.dims(), 0);
    for (std::size_t i = 0; i < cubic.size(); ++i) labels[i] = cubic[i] ? 5 : 0;
    const LabelVolume back = labelsOnInputGrid(labels, grid);
    ASSERT_EQ(back.dims(), dims);
    EXPECT_EQ(back.geometry.directions, mask.geometry.directions);
    for (std::size_t i = 0; i < mask.size(); ++i) ASSERT_EQ(back[i], mask[i] ? 5 : 0) << i;
}

TEST(CubicVoxels, SerialAndParallelAgreeBitForBit) {
    const Dims dims{31, 17, 12};
    const MaskVolume mask = randomMask(dims, steps(0.8, 0.8, 2.1), 11);
    const CubicGrid grid = cubicGridFor(dims, mask.geometry);
    const MaskVolume serial = resampleToCubicVoxels(mask, grid, {false});
    const MaskVolume parallel = resampleToCubicVoxels(mask, grid, {true});
    EXPECT_EQ(serial.values(), parallel.values());
    LabelVolume labels(serial.dims(), 0);
    for (std::size_t i = 0; i < labels.size(); ++i) labels[i] = std::uint16_t(i % 7);
    EXPECT_EQ(labelsOnInputGrid(labels, grid, {false}).values(),
              labelsOnInputGrid(labels, grid, {true}).values());
}

TEST(CubicVoxels, AStopAnsweredOnceAtAnyPollThrows) {
    const Dims dims{31, 17, 12};
    const MaskVolume mask = randomMask(dims, steps(0.8, 0.8, 2.1), 11);
    const CubicGrid grid = cubicGridFor(dims, mask.geometry);
    for (const bool threaded : {false, true}) {
        SCOPED_TRACE(threaded ? "threaded" : "serial");
        EXPECT_GT(test::expectAStopAtAnyPollThrows([&](Interrupter& interrupter) {
                      resampleToCubicVoxels(mask, grid, {threaded}, interrupter);
                  }),
                  3);
    }
}

}  // namespace
}  // namespace skelseg
