#include "kernels/VoxelGenus.h"

#include <gtest/gtest.h>

#include "io/shapes/SyntheticShapes.h"
#include "tests/kernels/KernelTestSupport.h"
#include "tests/support/StopAtOnce.h"

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

/// Reference chi: V - E + F - C of the union of closed object cubes, counted
/// cell by cell (each lattice vertex, edge, face present when a voxel
/// around it is an object voxel).
std::int64_t bruteForceEuler(const MaskVolume& mask) {
    const Dims d = mask.dims();
    auto at = [&](int x, int y, int z) { return mask.contains(x, y, z) && mask(x, y, z) != 0; };
    std::int64_t vertices = 0, edges = 0, faces = 0, cubes = 0;
    for (int z = 0; z <= d.z; ++z)
        for (int y = 0; y <= d.y; ++y)
            for (int x = 0; x <= d.x; ++x) {
                bool vertex = false;
                for (int c = 0; c < 8; ++c)
                    vertex |= at(x - (c & 1), y - (c >> 1 & 1), z - (c >> 2));
                vertices += vertex;
                // Edges from (x, y, z) along +x, +y, +z: the four voxels around each.
                edges += at(x, y - 1, z - 1) || at(x, y, z - 1) || at(x, y - 1, z) || at(x, y, z);
                edges += at(x - 1, y, z - 1) || at(x, y, z - 1) || at(x - 1, y, z) || at(x, y, z);
                edges += at(x - 1, y - 1, z) || at(x, y - 1, z) || at(x - 1, y, z) || at(x, y, z);
                // Faces at (x, y, z) normal to x, y, z: the two voxels beside each.
                faces += at(x - 1, y, z) || at(x, y, z);
                faces += at(x, y - 1, z) || at(x, y, z);
                faces += at(x, y, z - 1) || at(x, y, z);
                cubes += at(x, y, z);
            }
    return vertices - edges + faces - cubes;
}

/// Reference cavities: 6-connected background floods that never reach a side.
std::size_t bruteForceCavities(const MaskVolume& mask) {
    const Dims d = mask.dims();
    std::vector<std::uint8_t> seen(mask.size(), 0);
    std::size_t cavities = 0;
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) {
                if (mask(x, y, z) || seen[mask.index(x, y, z)]) continue;
                bool side = false;
                std::vector<std::array<int, 3>> stack{{x, y, z}};
                seen[mask.index(x, y, z)] = 1;
                while (!stack.empty()) {
                    const auto [vx, vy, vz] = stack.back();
                    stack.pop_back();
                    side |= vx == 0 || vy == 0 || vz == 0 || vx + 1 == d.x || vy + 1 == d.y ||
                            vz + 1 == d.z;
                    const int steps[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                             {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
                    for (const auto& s : steps) {
                        const int qx = vx + s[0], qy = vy + s[1], qz = vz + s[2];
                        if (!mask.contains(qx, qy, qz) || mask(qx, qy, qz)) continue;
                        if (seen[mask.index(qx, qy, qz)]) continue;
                        seen[mask.index(qx, qy, qz)] = 1;
                        stack.push_back({qx, qy, qz});
                    }
                }
                cavities += !side;
            }
    return cavities;
}

TEST(VoxelGenus, RandomMasksMatchACellCountSerialAndParallel) {
    // Random masks have every local configuration and many enclosed pockets;
    // the sizes cross the 8-plane slab seams.
    const Dims sizes[] = {{1, 1, 1}, {6, 9, 4}, {17, 13, 19}};
    for (const Dims& d : sizes)
        for (double density : {0.2, 0.5, 0.7, 0.85})
            for (std::uint32_t seed = 1; seed <= 2; ++seed) {
                const MaskVolume mask = test::randomMask(d, density, seed);
                SCOPED_TRACE(::testing::Message()
                             << d.x << "x" << d.y << "x" << d.z << " density " << density);
                VoxelTopologyOptions serial;
                serial.threaded = false;
                const VoxelTopology a = voxelTopology(mask, serial), b = voxelTopology(mask);
                EXPECT_EQ(a.eulerCharacteristic, bruteForceEuler(mask));
                EXPECT_EQ(a.cavities, bruteForceCavities(mask));
                EXPECT_EQ(a.eulerCharacteristic, b.eulerCharacteristic);
                EXPECT_EQ(a.objects, b.objects);
                EXPECT_EQ(a.cavities, b.cavities);
                EXPECT_EQ(voxelEulerCharacteristic(mask, false), a.eulerCharacteristic);
            }
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

TEST(VoxelGenus, AStopAnsweredOnceAtAnyPollThrows) {
    // The runs, their components and the Euler sum each poll per slab.
    const MaskVolume mask = test::randomMask(Dims{24, 20, 40}, 0.4, 5);
    for (const bool threaded : {false, true}) {
        SCOPED_TRACE(threaded ? "threaded" : "serial");
        EXPECT_GT(test::expectAStopAtAnyPollThrows([&](Interrupter& interrupter) {
                      voxelTopology(mask, {threaded}, interrupter);
                  }),
                  3);
    }
}

}  // namespace
}  // namespace skelseg
