#include "kernels/VoxelGenus.h"

#include <gtest/gtest.h>

#include "io/shapes/SyntheticShapes.h"

namespace skelseg {
namespace {

MaskVolume rasterised(const Shape& shape, int size) {
    RasterOptions options;
    options.size = size;
    return rasterise(shape, options);
}

Shape doubleTorus() {
    Shape s;
    s.torus({-0.35, 0, 0}, {0, 0, 1}, 0.4, 0.12);
    s.torus({0.35, 0, 0}, {0, 0, 1}, 0.4, 0.12);
    return s;
}

TEST(VoxelGenus, SingleVoxelIsABall) {
    MaskVolume mask(Dims{3, 3, 3}, 0);
    mask(1, 1, 1) = 1;
    const VoxelTopology t = voxelTopology(mask);
    EXPECT_EQ(t.eulerCharacteristic, 1);
    EXPECT_EQ(t.objects, 1u);
    EXPECT_EQ(t.cavities, 0u);
    EXPECT_EQ(t.genus, 0);
}

TEST(VoxelGenus, CornerContactJoinsTwoCubes) {
    MaskVolume mask(Dims{4, 4, 4}, 0);
    mask(1, 1, 1) = 1;
    mask(2, 2, 2) = 1;
    // Two closed cubes sharing a vertex: one object, chi 1 + 1 - 1.
    const VoxelTopology t = voxelTopology(mask);
    EXPECT_EQ(t.eulerCharacteristic, 1);
    EXPECT_EQ(t.objects, 1u);
    EXPECT_EQ(t.genus, 0);
}

TEST(VoxelGenus, SquareRingHasGenusOne) {
    MaskVolume mask(Dims{5, 5, 3}, 0);
    for (int y = 1; y <= 3; ++y)
        for (int x = 1; x <= 3; ++x)
            if (x != 2 || y != 2) mask(x, y, 1) = 1;
    const VoxelTopology t = voxelTopology(mask);
    EXPECT_EQ(t.eulerCharacteristic, 0);
    EXPECT_EQ(t.genus, 1);
}

TEST(VoxelGenus, HollowCubeHasACavityAndGenusZero) {
    MaskVolume mask(Dims{7, 7, 7}, 0);
    for (int z = 1; z <= 5; ++z)
        for (int y = 1; y <= 5; ++y)
            for (int x = 1; x <= 5; ++x) mask(x, y, z) = (x == 3 && y == 3 && z == 3) ? 0 : 1;
    const VoxelTopology t = voxelTopology(mask);
    EXPECT_EQ(t.cavities, 1u);
    EXPECT_EQ(t.eulerCharacteristic, 2);
    EXPECT_EQ(t.genus, 0);
}

TEST(VoxelGenus, SphereTorusAndDoubleTorus) {
    EXPECT_EQ(voxelTopology(rasterised(makeShape("sphere"), 48)).genus, 0);
    EXPECT_EQ(voxelTopology(rasterised(makeShape("torus"), 64)).genus, 1);
    EXPECT_EQ(voxelTopology(rasterised(doubleTorus(), 96)).genus, 2);
    // Two separate balls: two objects, no tunnel.
    Shape two;
    two.sphere({-0.5, 0, 0}, 0.3).sphere({0.5, 0, 0}, 0.3);
    const VoxelTopology t = voxelTopology(rasterised(two, 48));
    EXPECT_EQ(t.objects, 2u);
    EXPECT_EQ(t.genus, 0);
}

TEST(VoxelGenus, SerialEqualsParallel) {
    const MaskVolume mask = rasterised(makeShape("torus-limb"), 80);
    VoxelTopologyOptions serial, parallel;
    serial.threaded = false;
    parallel.threaded = true;
    const VoxelTopology a = voxelTopology(mask, serial), b = voxelTopology(mask, parallel);
    EXPECT_EQ(a.eulerCharacteristic, b.eulerCharacteristic);
    EXPECT_EQ(a.objects, b.objects);
    EXPECT_EQ(a.cavities, b.cavities);
    EXPECT_EQ(a.genus, 1);
    EXPECT_EQ(b.genus, 1);
}

}  // namespace
}  // namespace skelseg
