#include "kernels/ConnectedObjects.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "tests/kernels/KernelTestSupport.h"

namespace skelseg {
namespace {

/// A labelling per voxel: object id + 1, 0 for background.
struct FloodLabels {
    std::vector<ObjectExtent> objects;
    std::vector<std::uint32_t> component;
};

/// Reference: scan in voxel order, flood each new component (26-adjacency).
FloodLabels floodReference(const MaskVolume& mask) {
    const Dims d = mask.dims();
    FloodLabels r;
    r.component.assign(mask.size(), 0);
    std::vector<std::size_t> stack;
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) {
                const std::size_t seed = mask.index(x, y, z);
                if (!mask[seed] || r.component[seed]) continue;
                ObjectExtent o;
                o.id = std::uint32_t(r.objects.size());
                o.lo = {x, y, z};
                o.hi = {x, y, z};
                r.component[seed] = o.id + 1;
                stack.assign(1, seed);
                while (!stack.empty()) {
                    const std::size_t v = stack.back();
                    stack.pop_back();
                    ++o.voxels;
                    const int vx = int(v % std::size_t(d.x)),
                              vy = int(v / std::size_t(d.x) % std::size_t(d.y)),
                              vz = int(v / (std::size_t(d.x) * std::size_t(d.y)));
                    o.lo = {std::min(o.lo[0], vx), std::min(o.lo[1], vy), std::min(o.lo[2], vz)};
                    o.hi = {std::max(o.hi[0], vx), std::max(o.hi[1], vy), std::max(o.hi[2], vz)};
                    for (int dz = -1; dz <= 1; ++dz)
                        for (int dy = -1; dy <= 1; ++dy)
                            for (int dx = -1; dx <= 1; ++dx) {
                                if (!mask.contains(vx + dx, vy + dy, vz + dz)) continue;
                                const std::size_t q = mask.index(vx + dx, vy + dy, vz + dz);
                                if (mask[q] && !r.component[q])
                                    r.component[q] = o.id + 1, stack.push_back(q);
                            }
                }
                r.objects.push_back(o);
            }
    return r;
}

void expectSameExtents(const std::vector<ObjectExtent>& a, const std::vector<ObjectExtent>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].id, b[i].id);
        EXPECT_EQ(a[i].voxels, b[i].voxels) << "object " << i;
        EXPECT_EQ(a[i].lo, b[i].lo) << "object " << i;
        EXPECT_EQ(a[i].hi, b[i].hi) << "object " << i;
    }
}

/// The run-length labelling says the same as the flood, voxel by voxel.
void expectSameLabels(const ConnectedObjects& found, const FloodLabels& reference,
                      const MaskVolume& mask) {
    expectSameExtents(found.objects, reference.objects);
    const Dims d = mask.dims();
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x)
                ASSERT_EQ(found.componentAt(x, y, z), reference.component[mask.index(x, y, z)])
                    << "voxel " << x << " " << y << " " << z;
}

void expectSameObjects(const ConnectedObjects& a, const ConnectedObjects& b) {
    ASSERT_EQ(a.objects.size(), b.objects.size());
    for (std::size_t i = 0; i < a.objects.size(); ++i) {
        EXPECT_EQ(a.objects[i].id, b.objects[i].id);
        EXPECT_EQ(a.objects[i].voxels, b.objects[i].voxels) << "object " << i;
        EXPECT_EQ(a.objects[i].lo, b.objects[i].lo) << "object " << i;
        EXPECT_EQ(a.objects[i].hi, b.objects[i].hi) << "object " << i;
    }
    EXPECT_TRUE(a.runs.rowStart == b.runs.rowStart);
    EXPECT_TRUE(a.runs.runs == b.runs.runs);
    EXPECT_TRUE(a.objectOfRun == b.objectOfRun);
}

MaskVolume randomMask(Dims d, double density, unsigned seed) {
    std::mt19937 random(seed);
    std::bernoulli_distribution on(density);
    MaskVolume mask(d, 0);
    for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = on(random) ? 1 : 0;
    return mask;
}

TEST(ConnectedObjects, RandomMasksMatchAFloodFillSerialAndParallel) {
    // Sparse masks give many small objects, diagonal-only contacts and
    // components that cross the 8-plane slab seams; dense ones one big object.
    const Dims sizes[] = {{1, 1, 1}, {7, 5, 3}, {23, 17, 29}, {40, 9, 33}};
    for (const Dims& d : sizes)
        for (double density : {0.05, 0.15, 0.3, 0.6})
            for (unsigned seed = 1; seed <= 2; ++seed) {
                const MaskVolume mask = randomMask(d, density, seed);
                const FloodLabels reference = floodReference(mask);
                SCOPED_TRACE(::testing::Message()
                             << d.x << "x" << d.y << "x" << d.z << " density " << density);
                const ConnectedObjects serial = findConnectedObjects(mask, {false});
                const ConnectedObjects parallel = findConnectedObjects(mask, {true});
                expectSameLabels(serial, reference, mask);
                expectSameObjects(parallel, serial);
            }
}

TEST(ConnectedObjects, DiagonalContactJoinsAcrossASlabSeam) {
    // Two voxels touching only at a corner, on either side of the z = 8 seam.
    MaskVolume mask(Dims{4, 4, 12}, 0);
    mask(1, 1, 7) = 1;
    mask(2, 2, 8) = 1;
    mask(0, 3, 11) = 1;  // a separate object
    const ConnectedObjects found = findConnectedObjects(mask);
    ASSERT_EQ(found.objects.size(), 2u);
    EXPECT_EQ(found.objects[0].voxels, 2u);
    EXPECT_EQ(found.objects[1].voxels, 1u);
    EXPECT_EQ(found.componentAt(2, 2, 8), 1u);
    EXPECT_EQ(found.componentAt(0, 3, 11), 2u);
}

TEST(ConnectedObjects, EmptyMaskHasNoObjects) {
    const MaskVolume mask(Dims{5, 6, 7}, 0);
    const ConnectedObjects found = findConnectedObjects(mask);
    EXPECT_TRUE(found.objects.empty());
    EXPECT_TRUE(found.runs.runs.empty());
    EXPECT_EQ(found.runs.rowStart.size(), std::size_t(6 * 7 + 1));
    EXPECT_EQ(found.componentAt(2, 3, 4), 0u);
}

}  // namespace
}  // namespace skelseg
