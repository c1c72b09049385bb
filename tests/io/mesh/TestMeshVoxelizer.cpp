#include "io/mesh/MeshVoxelizer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>

#include "io/mesh/MeshCheck.h"
#include "kernels/base/Error.h"
#include "tests/io/mesh/SphereTestMeshes.h"
#include "tests/support/Pi.h"
#include "tests/support/ShapeMeshes.h"
#include "tests/support/StopAtOnce.h"

namespace skelseg {
namespace {

using test::icosphere;
using test::kPi;
using test::solidCount;
using test::solidShareOfClosed;
using test::withoutCap;

TEST(MeshVoxelizer, SphereVolumeAndGrid) {
    const double radius = 1.5;
    const std::array<double, 3> centre{0.3, -0.2, 10.5};
    const TriangleMesh sphere = icosphere(4, radius, centre);
    ASSERT_TRUE(checkMesh(sphere).closed);
    VoxelizeOptions options;
    options.resolution = 64;
    options.margin = 3;
    const MaskVolume mask = voxelizeMesh(sphere, options);

    // The longest side spans `resolution` voxels, plus the margins.
    const int longestAxis = std::max({mask.dims().x, mask.dims().y, mask.dims().z});
    EXPECT_EQ(longestAxis, 64 + 2 * 3);
    double low = HUGE_VAL, high = -HUGE_VAL;
    for (const auto& p : sphere.vertices) low = std::min(low, p[0]), high = std::max(high, p[0]);
    double longest = 0;
    for (int c = 0; c < 3; ++c) {
        double lo = HUGE_VAL, hi = -HUGE_VAL;
        for (const auto& p : sphere.vertices) lo = std::min(lo, p[c]), hi = std::max(hi, p[c]);
        longest = std::max(longest, hi - lo);
    }
    const double h = mask.geometry.voxelSize();
    EXPECT_NEAR(h, longest / 64, 1e-12);

    // Volume within 3% of the ball's.
    const double volume = double(solidCount(mask)) * h * h * h;
    const double ball = 4.0 / 3.0 * kPi * radius * radius * radius;
    EXPECT_NEAR(volume / ball, 1.0, 0.03) << "voxel volume " << volume << " vs " << ball;

    // Every solid voxel centre lies (nearly) inside the sphere, and the margin is empty.
    for (int z = 0; z < mask.dims().z; ++z)
        for (int y = 0; y < mask.dims().y; ++y)
            for (int x = 0; x < mask.dims().x; ++x) {
                if (!mask(x, y, z)) continue;
                const auto w = mask.geometry.indexToWorld(x, y, z);
                const double r = std::sqrt((w[0] - centre[0]) * (w[0] - centre[0]) +
                                           (w[1] - centre[1]) * (w[1] - centre[1]) +
                                           (w[2] - centre[2]) * (w[2] - centre[2]));
                ASSERT_LT(r, radius + h) << x << " " << y << " " << z;
                ASSERT_TRUE(x >= 3 && y >= 3 && z >= 3 && x < mask.dims().x - 3 &&
                            y < mask.dims().y - 3 && z < mask.dims().z - 3);
            }

    // Voxel <-> world both ways.
    const WorldToIndex toIndex(mask.geometry);
    for (const Coord c : {Coord{0, 0, 0}, Coord{5, 17, 33}, Coord{69, 69, 69}}) {
        const auto index = toIndex(mask.geometry.indexToWorld(c.x, c.y, c.z));
        EXPECT_NEAR(index[0], c.x, 1e-9);
        EXPECT_NEAR(index[1], c.y, 1e-9);
        EXPECT_NEAR(index[2], c.z, 1e-9);
    }
    const Coord middle = voxelContaining(mask.geometry, centre);
    EXPECT_NEAR(middle.x, (mask.dims().x - 1) / 2.0, 0.6);
    EXPECT_EQ(mask(middle.x, middle.y, middle.z), 1);
    const Coord inside =
        voxelContaining(mask.geometry, {centre[0] + 0.9 * radius, centre[1], centre[2]});
    const Coord outside =
        voxelContaining(mask.geometry, {centre[0] + 1.1 * radius, centre[1], centre[2]});
    EXPECT_EQ(mask(inside.x, inside.y, inside.z), 1);
    EXPECT_EQ(mask(outside.x, outside.y, outside.z), 0);
}

TEST(MeshVoxelizer, SerialAndThreadedAgree) {
    const TriangleMesh sphere = icosphere(3, 1.0, {0, 0, 0});
    VoxelizeOptions options;
    options.resolution = 40;
    const MaskVolume threaded = voxelizeMesh(sphere, options);
    options.threaded = false;
    const MaskVolume serial = voxelizeMesh(sphere, options);
    EXPECT_EQ(threaded.dims(), serial.dims());
    EXPECT_TRUE(threaded.values() == serial.values());
    EXPECT_GT(solidCount(serial), 0u);
}

TEST(MeshVoxelizer, TheFaceOrderChangesNoVoxelAndNoNearestTriangle) {
    // OpenVDB answers ties (a voxel as near to two triangles) by the lower
    // index, and rounds a triangle's distances by the corner it starts at:
    // the same sphere with its triangles shuffled and their corners rotated
    // must still give the same voxels, and each voxel the same nearest
    // triangle, named by the mesh's own index.
    const TriangleMesh mesh = icosphere(3, 1.0, {0.1, -0.2, 0.3});
    VoxelizeOptions options;
    options.resolution = 24;
    options.keepMeshTopology = true;
    SignedVoxelization original;
    const MeshVoxelization first =
        voxelizeMeshWithContacts(mesh, options, nullInterrupter(), &original);
    ASSERT_EQ(original.nearestTriangle.size(), first.mask.size());
    auto cornersOf = [](const TriangleMesh& m, std::int32_t t) {
        std::array<std::array<double, 3>, 3> c{m.vertices[m.triangles[std::size_t(t)][0]],
                                               m.vertices[m.triangles[std::size_t(t)][1]],
                                               m.vertices[m.triangles[std::size_t(t)][2]]};
        std::sort(c.begin(), c.end());
        return c;
    };
    for (unsigned seed : {1u, 2u}) {
        const TriangleMesh shuffled = test::reorderedTriangles(mesh, seed);
        SignedVoxelization again;
        const MeshVoxelization second =
            voxelizeMeshWithContacts(shuffled, options, nullInterrupter(), &again);
        EXPECT_TRUE(second.mask.values() == first.mask.values()) << "seed " << seed;
        ASSERT_EQ(again.nearestTriangle.size(), original.nearestTriangle.size());
        std::size_t known = 0, differing = 0;
        for (std::size_t i = 0; i < original.nearestTriangle.size(); ++i) {
            const std::int32_t a = original.nearestTriangle[i], b = again.nearestTriangle[i];
            ASSERT_EQ(a < 0, b < 0) << "voxel " << i;
            if (a < 0) continue;
            ++known;
            differing += cornersOf(mesh, a) != cornersOf(shuffled, b);
        }
        EXPECT_GT(known, 1000u);
        EXPECT_EQ(differing, 0u) << "seed " << seed;
    }
}

TEST(MeshVoxelizer, TinyAndHugeUnitsGiveTheVoxelsOfOrdinaryOnes) {
    // OpenVDB refuses voxels whose volume is below 3e-15 and float distances
    // overflow on huge ones; the voxeliser measures those in voxels. Sizes
    // outside 1e-100..1e100 are refused.
    const TriangleMesh unit = icosphere(3, 1.0, {0, 0, 0});
    TriangleMesh open = unit;
    open.triangles.pop_back();
    open.triangleFace.pop_back();
    --open.faceCount;
    VoxelizeOptions options;
    options.resolution = 24;
    for (const TriangleMesh* mesh : {&unit, static_cast<const TriangleMesh*>(&open)}) {
        const MaskVolume reference = voxelizeMesh(*mesh, options);
        for (double scale : {1e-5, 1e-60, 1e35, 1e90}) {
            SCOPED_TRACE(scale);
            TriangleMesh scaled = *mesh;
            for (auto& v : scaled.vertices)
                for (double& c : v) c *= scale;
            const MaskVolume mask = voxelizeMesh(scaled, options);
            EXPECT_EQ(mask.dims(), reference.dims());
            EXPECT_EQ(solidCount(mask), solidCount(reference));
        }
        TriangleMesh huge = *mesh;
        for (auto& v : huge.vertices)
            for (double& c : v) c *= 1e200;
        EXPECT_THROW(voxelizeMesh(huge, options), UsageError);
    }
}

// A face with a repeated corner ("f 1 1 2") bounds nothing, but OpenVDB
// rasterised it as the segment between its two corners: 2,000 of them
// across the horse gave 101 handles and one part instead of six.
TEST(MeshVoxelizer, ZeroAreaFacesAddNoVoxels) {
    // Two balls apart, and zero-area faces from one to the other: as
    // segments they would bridge the gap.
    TriangleMesh sphere = icosphere(3, 1.0, {-2, 0, 0});
    const TriangleMesh other = icosphere(3, 1.0, {2, 0, 0});
    const std::uint32_t n = std::uint32_t(sphere.vertices.size());
    sphere.vertices.insert(sphere.vertices.end(), other.vertices.begin(), other.vertices.end());
    for (const auto& t : other.triangles) {
        sphere.triangles.push_back({t[0] + n, t[1] + n, t[2] + n});
        sphere.triangleFace.push_back(std::uint32_t(sphere.faceCount++));
    }
    TriangleMesh withLines = sphere;
    for (std::uint32_t k = 0; k < 40; ++k) {
        const std::uint32_t a = (k * 7919u) % n, b = n + (k * 104729u) % n;
        withLines.triangles.push_back({a, a, b});
        withLines.triangleFace.push_back(std::uint32_t(withLines.faceCount++));
    }
    VoxelizeOptions options;
    options.resolution = 32;
    const MaskVolume reference = voxelizeMesh(sphere, options);
    const MaskVolume mask = voxelizeMesh(withLines, options);
    ASSERT_EQ(mask.dims(), reference.dims());
    EXPECT_TRUE(std::equal(mask.values().begin(), mask.values().end(), reference.values().begin()));
    // Open meshes take the shell path: the same holds there.
    TriangleMesh open = sphere, openWithLines = withLines;
    for (TriangleMesh* m : {&open, &openWithLines}) {
        m->triangles.erase(m->triangles.begin());
        m->triangleFace.erase(m->triangleFace.begin());
    }
    const MaskVolume openReference = voxelizeMesh(open, options);
    const MaskVolume openMask = voxelizeMesh(openWithLines, options);
    ASSERT_EQ(openMask.dims(), openReference.dims());
    EXPECT_TRUE(std::equal(openMask.values().begin(), openMask.values().end(),
                           openReference.values().begin()));
}

TEST(MeshVoxelizer, OpenSphereIsStillSolid) {
    const double radius = 1.0;
    TriangleMesh sphere = icosphere(4, radius, {0, 0, 0});
    const TriangleMesh closed = sphere;
    // Punch a small hole (about 3 voxels wide): drop the 3 triangles whose
    // centroids are highest.
    std::vector<std::pair<double, std::size_t>> heights;
    for (std::size_t t = 0; t < sphere.triangles.size(); ++t) {
        double y = 0;
        for (auto v : sphere.triangles[t]) y += sphere.vertices[v][1];
        heights.emplace_back(y, t);
    }
    std::sort(heights.rbegin(), heights.rend());
    std::vector<std::array<std::uint32_t, 3>> kept;
    for (std::size_t k = 3; k < heights.size(); ++k)
        kept.push_back(sphere.triangles[heights[k].second]);
    sphere.triangles = kept;
    sphere.triangleFace.resize(kept.size());
    std::iota(sphere.triangleFace.begin(), sphere.triangleFace.end(), 0u);
    sphere.faceCount = kept.size();
    ASSERT_FALSE(checkMesh(sphere).closed);

    // Filled, not just a shell; a little fatter than the closed one.
    const double small = solidShareOfClosed(sphere, closed, 48);
    EXPECT_GT(small, 0.99);
    EXPECT_LT(small, 1.10);

    // A hole far wider than the default closing (a cap of about 10 voxels
    // across) is bridged by the retries with a larger closing.
    const double wide = solidShareOfClosed(withoutCap(closed, 0.97 * radius), closed, 48);
    EXPECT_GT(wide, 0.9);
    EXPECT_LT(wide, 1.10);
}

TEST(MeshVoxelizer, HoleThatNeedsTheWidestClosingStillGivesASolid) {
    // A cap about 23 voxels across missing (as under the scanned Stanford
    // bunny): a closing of 8 leaks, and the shell it leaves after growing
    // back is thick enough where the surface runs diagonally to pass for an
    // inside; only 16 seals the hole.
    const double radius = 1.0;
    const TriangleMesh closed = icosphere(5, radius, {0, 0, 0});
    const TriangleMesh open = withoutCap(closed, 0.97 * radius);
    ASSERT_FALSE(checkMesh(open).closed);
    const double share = solidShareOfClosed(open, closed, 96);
    EXPECT_GT(share, 0.9);
    EXPECT_LT(share, 1.15);
}

TEST(MeshVoxelizer, TheWidestHoleClosingIsAShareOfTheShapeAbove192) {
    // 16 voxels up to resolution 192 (the retries as they were), then the
    // same share of the longest side, so that a hole bridged at 192 is
    // bridged at any finer resolution, up to 48 voxels.
    EXPECT_EQ(widestHoleClosing(8), 16.0);
    EXPECT_EQ(widestHoleClosing(96), 16.0);
    EXPECT_EQ(widestHoleClosing(192), 16.0);
    for (const int resolution : {256, 320, 400, 512, 576})
        EXPECT_DOUBLE_EQ(widestHoleClosing(resolution) / resolution, 16.0 / 192) << resolution;
    EXPECT_EQ(widestHoleClosing(1024), 48.0);
    EXPECT_EQ(widestHoleClosing(2048), 48.0);
}

TEST(MeshVoxelizer, FlatSheetBecomesAPlate) {
    TriangleMesh sheet;
    sheet.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    sheet.triangles = {{0, 1, 2}, {0, 2, 3}};
    sheet.triangleFace = {0, 0};
    sheet.faceCount = 1;
    VoxelizeOptions options;
    options.resolution = 16;
    const MaskVolume mask = voxelizeMesh(sheet, options);
    EXPECT_EQ(mask.dims().z, 1 + 2 * options.margin);
    const std::size_t count = solidCount(mask);
    EXPECT_GE(count, 16u * 16u);
    EXPECT_LE(count, 20u * 20u * 3u);
}

// The geometry rule of the volume readers (VolumeGeometry::problemOver):
// a mesh whose voxels are finer than 2^-40 of its world coordinates is
// refused; the same mesh nearer the origin is voxelised.
TEST(MeshVoxelizer, RefusesAMeshTooFarOutForItsVoxels) {
    const TriangleMesh sphere = icosphere(2, 1.0, {0, 0, 0});
    VoxelizeOptions options;
    options.resolution = 64;
    const auto movedBy = [&](double offset) {
        TriangleMesh moved = sphere;
        for (auto& v : moved.vertices)
            for (double& c : v) c += offset;
        return moved;
    };
    // Voxels of 1/32: 2^-40 of 1e10 is 0.009, under the step; of 1e11,
    // 0.09, over it.
    EXPECT_NO_THROW(voxelGridFor(movedBy(1.0e10), options));
    try {
        voxelGridFor(movedBy(1.0e11), options);
        ADD_FAILURE() << "a mesh at 1e11 with voxels of 1/32 was voxelised";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("2^-40 of them"), std::string::npos) << e.what();
    }
}

TEST(MeshVoxelizer, RejectsBadOptionsAndHonoursInterrupts) {
    const TriangleMesh sphere = icosphere(2, 1.0, {0, 0, 0});
    VoxelizeOptions options;
    options.resolution = 4;
    EXPECT_THROW(voxelizeMesh(sphere, options), UsageError);
    options.resolution = 4096;
    EXPECT_THROW(voxelizeMesh(sphere, options), UsageError);
    options.resolution = 2048;  // a cube-like box of 2052^3 voxels is over kMaxVoxels
    EXPECT_THROW(voxelGridFor(sphere, options), UsageError);
    TriangleMesh point = sphere;
    for (auto& v : point.vertices) v = {1, 1, 1};
    EXPECT_THROW(voxelGridFor(point, VoxelizeOptions{}), UsageError);

    struct StopAtOnce : Interrupter {
        std::atomic<int> starts{0}, ends{0};
        void start(const char*) override { ++starts; }
        void end() override { ++ends; }
        bool wasInterrupted(double) override { return true; }
    } stop;
    options.resolution = 32;
    EXPECT_THROW(voxelizeMesh(sphere, options, stop), InterruptedError);
    EXPECT_EQ(stop.starts.load(), 1);
    EXPECT_EQ(stop.ends.load(), 1);
}

TEST(MeshVoxelizer, KnownClosednessSelectsTheMethodWithoutRechecking) {
    // A caller that has run checkMesh() passes its answer: the same answer
    // gives the same mask; a closed mesh declared open goes through the shell
    // method instead (fatter by the closing, so the masks differ).
    const TriangleMesh sphere = icosphere(3, 1.0, {0, 0, 0});
    VoxelizeOptions options;
    options.resolution = 40;
    const MaskVolume unset = voxelizeMesh(sphere, options);
    options.meshIsClosed = true;
    const MaskVolume declaredClosed = voxelizeMesh(sphere, options);
    EXPECT_TRUE(unset.values() == declaredClosed.values());
    options.meshIsClosed = false;
    const MaskVolume declaredOpen = voxelizeMesh(sphere, options);
    EXPECT_FALSE(unset.values() == declaredOpen.values());
    EXPECT_GE(solidCount(declaredOpen), solidCount(unset));
}

TEST(MeshVoxelizer, AStopAnsweredOnceAtAnyPollThrows) {
    // A closed sphere takes the signed conversion, an open one the shell.
    const TriangleMesh closed = icosphere(3, 1.5, {0, 0, 0});
    const TriangleMesh open = withoutCap(closed, 1.2);
    for (const TriangleMesh* mesh : {&closed, &open}) {
        SCOPED_TRACE(mesh == &closed ? "closed" : "open");
        VoxelizeOptions options;
        options.resolution = 16;
        EXPECT_GT(
            test::expectAStopAtAnyPollThrows(
                [&](Interrupter& interrupter) { voxelizeMesh(*mesh, options, interrupter); }, 16),
            3);
    }
}

}  // namespace
}  // namespace skelseg
