#include "io/mesh/SelfOverlapSeparation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

#include "io/mesh/MeshGenus.h"
#include "io/mesh/MeshVoxelizer.h"
#include "kernels/ConnectedObjects.h"
#include "kernels/VoxelGenus.h"
#include "tests/support/CurledTube.h"
#include "tests/support/Pi.h"

namespace skelseg {
namespace {

using test::kPi;

VoxelizeOptions atResolution(int resolution, bool keepTopology = true, bool threaded = true) {
    VoxelizeOptions options;
    options.resolution = resolution;
    options.keepMeshTopology = keepTopology;
    options.threaded = threaded;
    return options;
}

// Tubes whose end is as thick as 0.75 of their beginning, wound 1.2 and 2
// radians beyond a turn, at 64 and 96 voxels: at some of them clearing 2
// voxels around the crossing adds a ring in its box and is refused.
struct WoundTubeCase {
    double extraAngle;
    int resolution;
    test::CurledTube tube;
};

std::vector<WoundTubeCase> tubesWoundBeyondATurn() {
    std::vector<WoundTubeCase> cases;
    for (double extraAngle : {1.2, 2.0})
        for (int resolution : {64, 96}) {
            test::CurledTube tube;
            tube.endRadius = 0.3;
            tube.extraAngle = extraAngle;
            cases.push_back({extraAngle, resolution, tube});
        }
    return cases;
}

// Whether the 2-voxel clearing alone (no retry) keeps a place of `mask` fused.
bool firstClearingRefuses(const TriangleMesh& mesh, MaskVolume mask) {
    SelfOverlapOptions noRetry;
    noRetry.maxClearance = noRetry.clearance;
    return separateSelfOverlaps(mesh, mask, noRetry).overlapsKept > 0;
}

std::array<double, 3> centreOf(std::uint64_t index, const Dims& dims,
                               const VolumeGeometry& geometry) {
    const std::uint64_t nx = std::uint64_t(dims.x), ny = std::uint64_t(dims.y);
    return geometry.indexToWorld(double(index % nx), double((index / nx) % ny),
                                 double(index / (nx * ny)));
}

TEST(SelfOverlap, FindsWhereTheCurledTubeRunsInsideItself) {
    const test::CurledTube tube;
    const TriangleMesh mesh = tube.mesh();
    ASSERT_EQ(meshTopology(mesh).genus, 0);
    const VoxelGrid grid = voxelGridFor(mesh, atResolution(96));
    const double h = grid.geometry.directions[0][0];
    const auto voxels = selfOverlapVoxels(mesh, grid.dims, grid.geometry);
    ASSERT_FALSE(voxels.empty());
    // Every voxel found lies inside both windings of the tube: at its angle
    // around the circle (the beginning) and one turn further (the end).
    for (std::uint64_t v : voxels) {
        const auto p = centreOf(v, grid.dims, grid.geometry);
        double angle = std::atan2(p[1], p[0]);
        if (angle < 0) angle += 2.0 * kPi;
        ASSERT_TRUE(tube.insideAt(p, angle, h)) << "not in the beginning: voxel " << v;
        ASSERT_TRUE(tube.insideAt(p, angle + 2.0 * kPi, h)) << "not in the end: voxel " << v;
    }
    // Their volume is the volume both windings share: the integral over the
    // extra angle of pi min(r_begin, r_end)^2 R d(angle).
    double shared = 0.0;
    const int steps = 2000;
    for (int i = 0; i < steps; ++i) {
        const double angle = tube.extraAngle * (i + 0.5) / steps;
        const double r = std::min(tube.radiusAt(angle), tube.radiusAt(angle + 2.0 * kPi));
        shared += kPi * r * r * tube.bendRadius * tube.extraAngle / steps;
    }
    EXPECT_NEAR(double(voxels.size()) * h * h * h, shared, 0.1 * shared);
}

TEST(SelfOverlap, VoxelGenusEqualsMeshGenusOnlyWithTheSeparation) {
    const TriangleMesh mesh = test::CurledTube{}.mesh();
    ASSERT_GE(voxelTopology(voxelizeMesh(mesh, atResolution(96, false))).genus, 1)
        << "without the separation the two windings must fuse into a ring";
    const MeshVoxelization kept = voxelizeMeshWithContacts(mesh, atResolution(96));
    EXPECT_GE(kept.selfOverlaps.overlaps, 1u);
    EXPECT_GT(kept.selfOverlaps.voxelsCleared, kept.selfOverlaps.overlapVoxels / 2);
    const VoxelTopology topology = voxelTopology(kept.mask);
    EXPECT_EQ(topology.genus, 0);
    EXPECT_EQ(topology.objects, 1u);
}

TEST(SelfOverlap, ClearsEveryObjectVoxelWithinItsReachOfThePlaceAndNothingElse) {
    // The clearing is a cube of half-width `clearance` around every doubly
    // enclosed voxel, cut to the object: checked against a direct listing.
    const TriangleMesh mesh = test::CurledTube{}.mesh();
    const MaskVolume before = voxelizeMesh(mesh, atResolution(96, false));
    const Dims dims = before.dims();
    const auto voxels = selfOverlapVoxels(mesh, dims, before.geometry);
    ASSERT_FALSE(voxels.empty());
    for (int clearance : {1, 2, 3}) {
        MaskVolume mask = before;
        std::vector<std::uint8_t> expected(before.values().size(), 0);
        const std::uint64_t nx = std::uint64_t(dims.x), nxy = nx * std::uint64_t(dims.y);
        for (std::uint64_t v : voxels) {
            const int x = int(v % nx), y = int((v / nx) % std::uint64_t(dims.y)), z = int(v / nxy);
            for (int dz = -clearance; dz <= clearance; ++dz)
                for (int dy = -clearance; dy <= clearance; ++dy)
                    for (int dx = -clearance; dx <= clearance; ++dx) {
                        const int xx = x + dx, yy = y + dy, zz = z + dz;
                        if (xx < 0 || yy < 0 || zz < 0 || xx >= dims.x || yy >= dims.y ||
                            zz >= dims.z || !before(xx, yy, zz))
                            continue;
                        expected[std::uint64_t(xx) + std::uint64_t(yy) * nx +
                                 std::uint64_t(zz) * nxy] = 1;
                    }
        }
        SelfOverlapOptions options;
        options.clearance = clearance;
        options.maxClearance = clearance;
        const SelfOverlapSeparation separation = separateSelfOverlaps(mesh, mask, options);
        ASSERT_EQ(separation.overlapsKept, 0u) << "clearance " << clearance;
        std::size_t cleared = 0, wrong = 0;
        for (std::size_t i = 0; i < expected.size(); ++i) {
            cleared += expected[i];
            wrong += (mask.values()[i] != (expected[i] ? 0 : before.values()[i])) ? 1 : 0;
        }
        EXPECT_GT(cleared, voxels.size()) << "clearance " << clearance;
        EXPECT_EQ(separation.voxelsCleared, cleared) << "clearance " << clearance;
        EXPECT_EQ(wrong, 0u) << "clearance " << clearance;
    }
}

TEST(SelfOverlap, AWiderClearingSeparatesWhereTheFirstIsRefused) {
    // Tubes whose end is as thick as 0.75 of their beginning, wound 1.2 to 2
    // radians beyond a turn: at some resolutions clearing 2 voxels around
    // the crossing would add a ring in its box and is refused, and the two
    // windings stay fused (voxel genus 1, mesh genus 0). With the default
    // retry (up to 4 voxels wide), every case separates.
    int refusedAtFirstClearing = 0;
    for (const auto& [extraAngle, resolution, tube] : tubesWoundBeyondATurn()) {
        const TriangleMesh mesh = tube.mesh();
        const VoxelizeOptions options = atResolution(resolution, false);
        MaskVolume mask = voxelizeMesh(mesh, options);
        if (firstClearingRefuses(mesh, mask)) {
            ++refusedAtFirstClearing;
            EXPECT_EQ(voxelTopology(mask).genus, 1);
        }
        const SelfOverlapSeparation separation = separateSelfOverlaps(mesh, mask);
        EXPECT_EQ(separation.overlapsKept, 0u)
            << "extra angle " << extraAngle << ", resolution " << resolution;
        EXPECT_GE(separation.overlaps, 1u);
        const VoxelTopology topology = voxelTopology(mask);
        EXPECT_EQ(topology.genus, 0)
            << "extra angle " << extraAngle << ", resolution " << resolution;
        EXPECT_EQ(topology.cavities, 0u);
        // What the wider clearing cuts loose of the buried end are crumbs
        // (islands, kernels/Islands.h), not pieces of the tube.
        const ConnectedObjects objects = findConnectedObjects(mask);
        std::uint64_t total = 0, largest = 0;
        for (const ObjectExtent& o : objects.objects) {
            total += o.voxels;
            largest = std::max(largest, o.voxels);
        }
        EXPECT_GE(double(largest), 0.998 * double(total))
            << "extra angle " << extraAngle << ", resolution " << resolution << ": "
            << objects.objects.size() << " objects";
    }
    // Without cases the first clearing refuses, this test tests nothing.
    EXPECT_GE(refusedAtFirstClearing, 2);
}

TEST(SelfOverlap, AWiderClearingIsKeptOnlyWhereItRemovesAHandle) {
    // The tubes of the test above, fused where their end runs inside their
    // beginning, with the ring cut open half a turn away from the crossing:
    // the crossing then closes no loop (voxel genus 0), and clearing it
    // wider than 2 voxels would only carve the tube around it. Where the
    // 2-voxel clearing is refused, nothing may be cleared.
    int refusedAtFirstClearing = 0;
    for (const auto& [extraAngle, resolution, tube] : tubesWoundBeyondATurn()) {
        const TriangleMesh mesh = tube.mesh();
        MaskVolume mask = voxelizeMesh(mesh, atResolution(resolution, false));
        const Dims dims = mask.dims();
        for (int z = 0; z < dims.z; ++z)
            for (int y = 0; y < dims.y; ++y)
                for (int x = 0; x < dims.x; ++x) {
                    const auto p = mask.geometry.indexToWorld(double(x), double(y), double(z));
                    if (p[0] < 0 && std::abs(p[1]) < 0.1 * tube.bendRadius) mask(x, y, z) = 0;
                }
        ASSERT_EQ(voxelTopology(mask).genus, 0) << "the ring must be cut open";
        if (!firstClearingRefuses(mesh, mask)) continue;
        ++refusedAtFirstClearing;
        const MaskVolume before = mask;
        const SelfOverlapSeparation separation = separateSelfOverlaps(mesh, mask);
        EXPECT_GE(separation.overlapsKept, 1u)
            << "extra angle " << extraAngle << ", resolution " << resolution;
        EXPECT_EQ(separation.voxelsCleared, 0u)
            << "extra angle " << extraAngle << ", resolution " << resolution;
        EXPECT_TRUE(mask.values() == before.values())
            << "extra angle " << extraAngle << ", resolution " << resolution;
    }
    // Without cases the first clearing refuses, this test tests nothing.
    EXPECT_GE(refusedAtFirstClearing, 1);
}

TEST(SelfOverlap, SeparatePiecesOpenPiecesAndCleanMeshesAreLeftAlone) {
    // Two spheres overlapping: two pieces, voxelised as their union.
    TriangleMesh pair = test::sphereMesh({0, 0, 0}, 1.0);
    const TriangleMesh second = test::sphereMesh({1.2, 0, 0}, 0.8);
    const auto offset = std::uint32_t(pair.vertices.size());
    pair.vertices.insert(pair.vertices.end(), second.vertices.begin(), second.vertices.end());
    for (auto t : second.triangles) {
        pair.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
        pair.triangleFace.push_back(std::uint32_t(pair.faceCount++));
    }
    const VoxelGrid pairGrid = voxelGridFor(pair, atResolution(48));
    EXPECT_TRUE(selfOverlapVoxels(pair, pairGrid.dims, pairGrid.geometry).empty());
    const MeshVoxelization union_ = voxelizeMeshWithContacts(pair, atResolution(48));
    EXPECT_EQ(union_.selfOverlaps.voxelsCleared, 0u);
    EXPECT_EQ(voxelTopology(union_.mask).objects, 1u);

    // A clean closed mesh.
    const TriangleMesh sphere = test::sphereMesh({0, 0, 0}, 1.0);
    const VoxelGrid sphereGrid = voxelGridFor(sphere, atResolution(48));
    EXPECT_TRUE(selfOverlapVoxels(sphere, sphereGrid.dims, sphereGrid.geometry).empty());

    // The curled tube opened (one triangle less): no winding number.
    TriangleMesh open = test::CurledTube{}.mesh();
    open.triangles.pop_back();
    open.triangleFace.pop_back();
    const VoxelGrid openGrid = voxelGridFor(open, atResolution(96));
    EXPECT_TRUE(selfOverlapVoxels(open, openGrid.dims, openGrid.geometry).empty());
}

// `mesh` written as a triangle soup: three own vertices per triangle, at the
// same positions as the shared ones (an unwelded OBJ/OFF/PLY export).
TriangleMesh soupOf(const TriangleMesh& mesh) {
    TriangleMesh soup;
    soup.triangleFace = mesh.triangleFace;
    soup.faceCount = mesh.faceCount;
    for (const auto& t : mesh.triangles) {
        const auto first = std::uint32_t(soup.vertices.size());
        for (std::uint32_t v : t) soup.vertices.push_back(mesh.vertices[v]);
        soup.triangles.push_back({first, first + 1, first + 2});
    }
    return soup;
}

TEST(SelfOverlap, ATriangleSoupIsTheWeldedSurface) {
    // Vertices at one position count as one: the soup has the welded mesh's
    // pieces and winding numbers (before: every triangle an open piece of its
    // own, and no overlap found).
    const TriangleMesh mesh = test::CurledTube{}.mesh();
    const TriangleMesh soup = soupOf(mesh);
    const VoxelGrid grid = voxelGridFor(mesh, atResolution(96));
    const auto welded = selfOverlapVoxels(mesh, grid.dims, grid.geometry);
    ASSERT_FALSE(welded.empty());
    EXPECT_EQ(selfOverlapVoxels(soup, grid.dims, grid.geometry), welded);
    const MaskVolume before = voxelizeMesh(mesh, atResolution(96, false));
    MaskVolume weldedMask = before, soupMask = before;
    const SelfOverlapSeparation fromWelded = separateSelfOverlaps(mesh, weldedMask);
    const SelfOverlapSeparation fromSoup = separateSelfOverlaps(soup, soupMask);
    EXPECT_EQ(fromSoup.overlapVoxels, fromWelded.overlapVoxels);
    EXPECT_EQ(fromSoup.overlaps, fromWelded.overlaps);
    EXPECT_EQ(fromSoup.voxelsCleared, fromWelded.voxelsCleared);
    EXPECT_TRUE(soupMask.values() == weldedMask.values());
}

TEST(SelfOverlap, AFaceWithARepeatedVertexChangesNothing) {
    // A zero-area face on an existing edge (`f 1 1 2`), and one on a single
    // vertex, bound nothing: the piece keeps its winding number (before: a
    // repeated vertex and an edge used twice one way made the whole piece
    // "without winding number"). Also in a soup, where the repeat is by
    // position only.
    const TriangleMesh mesh = test::CurledTube{}.mesh();
    const VoxelGrid grid = voxelGridFor(mesh, atResolution(96));
    const auto clean = selfOverlapVoxels(mesh, grid.dims, grid.geometry);
    ASSERT_FALSE(clean.empty());
    const MaskVolume before = voxelizeMesh(mesh, atResolution(96, false));
    MaskVolume cleanMask = before;
    const SelfOverlapSeparation fromClean = separateSelfOverlaps(mesh, cleanMask);
    const MeshVoxelization cleanModel = voxelizeMeshWithContacts(mesh, atResolution(96));
    auto withDegenerateFaces = [](TriangleMesh m) {
        const auto t = m.triangles.front();
        for (const std::array<std::uint32_t, 3> face :
             {std::array<std::uint32_t, 3>{t[0], t[0], t[1]},
              std::array<std::uint32_t, 3>{t[2], t[2], t[2]}}) {
            m.triangles.push_back(face);
            m.triangleFace.push_back(std::uint32_t(m.faceCount++));
        }
        return m;
    };
    for (const TriangleMesh& degenerate :
         {withDegenerateFaces(mesh), soupOf(withDegenerateFaces(mesh))}) {
        EXPECT_EQ(selfOverlapVoxels(degenerate, grid.dims, grid.geometry), clean);
        MaskVolume mask = before;
        const SelfOverlapSeparation separation = separateSelfOverlaps(degenerate, mask);
        EXPECT_EQ(separation.overlapVoxels, fromClean.overlapVoxels);
        EXPECT_EQ(separation.overlaps, fromClean.overlaps);
        EXPECT_EQ(separation.voxelsCleared, fromClean.voxelsCleared);
        EXPECT_TRUE(mask.values() == cleanMask.values());
        // The whole voxel model too: the contact separation and the
        // thin-part fill read the sides of triangles (MeshOrientation.h).
        EXPECT_TRUE(voxelizeMeshWithContacts(degenerate, atResolution(96)).mask.values() ==
                    cleanModel.mask.values());
    }
}

TEST(SelfOverlap, InwardOrientationGivesTheSameVoxels) {
    TriangleMesh mesh = test::CurledTube{}.mesh();
    const VoxelGrid grid = voxelGridFor(mesh, atResolution(64));
    const auto outward = selfOverlapVoxels(mesh, grid.dims, grid.geometry);
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
    EXPECT_EQ(selfOverlapVoxels(mesh, grid.dims, grid.geometry), outward);
    EXPECT_FALSE(outward.empty());
}

TEST(SelfOverlap, SerialEqualsParallel) {
    const TriangleMesh mesh = test::CurledTube{}.mesh();
    const VoxelGrid grid = voxelGridFor(mesh, atResolution(80));
    EXPECT_EQ(selfOverlapVoxels(mesh, grid.dims, grid.geometry, false),
              selfOverlapVoxels(mesh, grid.dims, grid.geometry, true));
    const MeshVoxelization serial = voxelizeMeshWithContacts(mesh, atResolution(80, true, false));
    const MeshVoxelization parallel = voxelizeMeshWithContacts(mesh, atResolution(80, true, true));
    EXPECT_EQ(serial.mask.values(), parallel.mask.values());
    EXPECT_EQ(serial.selfOverlaps.voxelsCleared, parallel.selfOverlaps.voxelsCleared);
    EXPECT_EQ(serial.selfOverlaps.overlaps, parallel.selfOverlaps.overlaps);
}

/// Says stop at the first poll.
class StopNow final : public Interrupter {
public:
    bool wasInterrupted(double) override { return ++polls > 0; }
    std::atomic<int> polls{0};
};

TEST(SelfOverlap, StopsWhenAsked) {
    const TriangleMesh mesh = test::CurledTube{}.mesh();
    const VoxelGrid grid = voxelGridFor(mesh, atResolution(64));
    StopNow stop;
    EXPECT_THROW(selfOverlapVoxels(mesh, grid.dims, grid.geometry, true, stop), InterruptedError);
    EXPECT_GT(stop.polls.load(), 0);
}

}  // namespace
}  // namespace skelseg
