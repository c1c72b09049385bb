#include "io/mesh/ContactSeparation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "io/mesh/MeshGenus.h"
#include "io/mesh/MeshVoxelizer.h"
#include "kernels/VoxelGenus.h"
#include "tests/support/ShapeMeshes.h"
#include "tests/support/StopAtOnce.h"
#include "tests/support/TestPaths.h"

namespace skelseg {
namespace {

/// A square ring cut open on one side, its two ends facing each other across
/// exactly one fine voxel (the layer z = 0), 61 fine voxels wide: at
/// resolution 20 the gap is a third of a voxel.
TriangleMesh cutRing() {
    Shape s;
    s.box({0, 0, 24.5}, {30.5, 12.5, 6});
    s.box({0, 0, -24.5}, {30.5, 12.5, 6});
    s.box({-24.5, 0, 0}, {6, 12.5, 30.5});
    s.box({24.5, 0, 15.5}, {6, 12.5, 15});
    s.box({24.5, 0, -15.5}, {6, 12.5, 15});
    return test::meshOfShape(s, {-32, -14, -32}, {32, 14, 32});
}

VoxelizeOptions coarse(bool keepTopology, bool threaded = true) {
    VoxelizeOptions options;
    options.resolution = 20;
    options.keepMeshTopology = keepTopology;
    options.threaded = threaded;
    return options;
}

TEST(ContactSeparation, CutRingStaysOpen) {
    const TriangleMesh mesh = cutRing();
    ASSERT_EQ(meshTopology(mesh).genus, 0);
    ASSERT_EQ(voxelTopology(voxelizeMesh(mesh, coarse(false))).genus, 1)
        << "the ring's ends must fuse without the separation";
    const MeshVoxelization kept = voxelizeMeshWithContacts(mesh, coarse(true));
    EXPECT_EQ(kept.contacts.contacts, 1u);
    EXPECT_GT(kept.contacts.voxelsCleared, 0u);
    const VoxelTopology topology = voxelTopology(kept.mask);
    EXPECT_EQ(topology.genus, 0);
    EXPECT_EQ(topology.objects, 1u);
}

TEST(ContactSeparation, TouchingKneesStayApartAtEveryResolution) {
    // camel.off's front knees touch, and over part of the contact the two
    // walls cross by a tenth of a voxel: there each voxel lies outside its
    // nearest wall, which belongs to the other leg, and the seam of the
    // shallower voxels steps from one side to the other. Both must still be
    // parted (voxel genus 1 at 128 and 320 before).
    if (!test::hasSharedData()) GTEST_SKIP() << "no shared data at " << test::sharedDataDir();
    const auto path = test::sharedDataDir() / "shapes" / "camel.off";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "no " << path;
    const TriangleMesh mesh = readMesh(path);
    ASSERT_EQ(meshTopology(mesh).genus, 0);
    for (int resolution : {128, 320}) {
        VoxelizeOptions options;
        options.resolution = resolution;
        const MeshVoxelization voxelised = voxelizeMeshWithContacts(mesh, options);
        EXPECT_EQ(voxelTopology(voxelised.mask).genus, 0) << "resolution " << resolution;
        EXPECT_EQ(voxelised.contacts.contactsKept, 0u) << "resolution " << resolution;
    }
}

TEST(ContactSeparation, KeptConversionSeparatesTheSame) {
    const TriangleMesh mesh = cutRing();
    SignedVoxelization kept;
    const MeshVoxelization first =
        voxelizeMeshWithContacts(mesh, coarse(true), nullInterrupter(), &kept);
    ASSERT_FALSE(kept.nearestTriangle.empty());
    const MeshVoxelization again =
        voxelizeMeshWithContacts(mesh, coarse(true), nullInterrupter(), &kept);
    EXPECT_EQ(first.contacts.contacts, 1u);
    EXPECT_EQ(again.contacts.contacts, first.contacts.contacts);
    EXPECT_EQ(again.contacts.voxelsCleared, first.contacts.voxelsCleared);
    EXPECT_EQ(again.mask.values(), first.mask.values());
    // Kept without the nearest triangles, it cannot serve a separation.
    SignedVoxelization signOnly;
    voxelizeMeshWithContacts(mesh, coarse(false), nullInterrupter(), &signOnly);
    ASSERT_FALSE(signOnly.mask.empty());
    EXPECT_FALSE(signOnly.fits(mesh, voxelGridFor(mesh, coarse(true)), coarse(true)));
    EXPECT_EQ(
        voxelizeMeshWithContacts(mesh, coarse(true), nullInterrupter(), &signOnly).mask.values(),
        first.mask.values());
}

TEST(ContactSeparation, ThinPlateAndTorusAreLeftAlone) {
    Shape plate;
    plate.box({0, 0, 0}, {60.5, 40.5, 2.5});  // 5 fine voxels: under 2 voxels thick
    const TriangleMesh plateMesh = test::meshOfShape(plate, {-62, -42, -4}, {62, 42, 4});
    VoxelizeOptions options = coarse(true);
    options.resolution = 48;
    const MeshVoxelization voxelised = voxelizeMeshWithContacts(plateMesh, options);
    EXPECT_EQ(voxelised.contacts.voxelsCleared, 0u);
    EXPECT_EQ(voxelTopology(voxelised.mask).genus, 0);

    Shape torus;
    torus.torus({0, 0, 0}, {0, 0, 1}, 30, 10);
    const TriangleMesh torusMesh = test::meshOfShape(torus, {-42, -42, -12}, {42, 42, 12});
    options.resolution = 24;
    const MeshVoxelization torusVoxels = voxelizeMeshWithContacts(torusMesh, options);
    EXPECT_EQ(torusVoxels.contacts.voxelsCleared, 0u);
    EXPECT_EQ(voxelTopology(torusVoxels.mask).genus, 1);
}

/// Rows of voxels across the gap plane of test::barsOnABase(1) (x = 0 in
/// fine voxels) that are solid from one bar into the other, counted over the
/// contact less a voxel at its ends and two above the base.
std::size_t rowsJoinedAcrossTheGap(const MaskVolume& mask) {
    const Dims d = mask.dims();
    std::size_t joined = 0;
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y) {
            const auto at = mask.geometry.indexToWorld(0.0, double(y), double(z));
            if (at[1] < 14.5 + 6.0 || at[1] > 239.5 - 3.0 || std::abs(at[2]) > 30.5 - 3.0) continue;
            const auto gapIndex = worldToIndex(mask.geometry, {0.0, at[1], at[2]});
            const int gapX = int(std::lround(gapIndex[0]));
            bool open = false;
            for (int x = gapX - 1; x <= gapX + 1; ++x) open = open || mask(x, y, z) == 0;
            if (!open) ++joined;
        }
    return joined;
}

TEST(ContactSeparation, AContactAcrossWholeOpenVdbLeavesIsPartedAlongItsLength) {
    // OpenVDB's mesh conversion, by default, switches off the band voxels
    // between walls closer than a voxel and prunes the leaves left empty,
    // nearest triangles included; the middle of this contact (20 voxels
    // deep) kept no nearest triangle, and stayed fused there.
    const TriangleMesh mesh = test::barsOnABase(1);
    ASSERT_EQ(meshTopology(mesh).genus, 0);
    VoxelizeOptions options = coarse(false);
    options.resolution = 80;
    const MaskVolume fused = voxelizeMesh(mesh, options);
    ASSERT_GT(rowsJoinedAcrossTheGap(fused), 500u) << "the bars must fuse without the separation";
    options.keepMeshTopology = true;
    const MeshVoxelization kept = voxelizeMeshWithContacts(mesh, options);
    EXPECT_EQ(rowsJoinedAcrossTheGap(kept.mask), 0u)
        << "pairs " << kept.contacts.contactPairs << " cleared " << kept.contacts.voxelsCleared;
    EXPECT_EQ(kept.contacts.contacts, 1u);
    EXPECT_EQ(voxelTopology(kept.mask).objects, 1u);
}

/// A thick slab with a thin rod lying on it across one fine voxel: the rod
/// is joined to the slab at one end (x = 25..31) and runs along the slab's
/// top (z = 0..1, two fine voxels high) and on past the slab's far end
/// (x = -30) into a free tip. At resolutions 22 and 26 the rod is under a
/// voxel thick and the seam along the contact takes its whole cross section.
TriangleMesh rodOnSlab() {
    Shape s;
    s.box({0, 0, -10}, {30.5, 12.5, 8.5});  // slab: z = -18..-2
    s.box({-7, 0, 0.5}, {38.5, 2.5, 1});    // rod: x = -45..31, z = 0..1
    s.box({28, 0, -1}, {3.5, 2.5, 1.5});    // joint: z = -1 at x = 25..31
    return test::meshOfShape(s, {-48, -15, -21}, {34, 15, 8});
}

TEST(ContactSeparation, ASeamNeverCutsALimbLoose) {
    const TriangleMesh mesh = rodOnSlab();
    ASSERT_EQ(meshTopology(mesh).genus, 0);
    for (int resolution : {22, 26}) {
        VoxelizeOptions options = coarse(true);
        options.resolution = resolution;
        VoxelizeOptions plain = coarse(false);
        plain.resolution = resolution;
        ASSERT_EQ(voxelTopology(voxelizeMesh(mesh, plain)).objects, 1u)
            << "the rod must be whole before the separation, resolution " << resolution;
        const MeshVoxelization kept = voxelizeMeshWithContacts(mesh, options);
        EXPECT_EQ(voxelTopology(kept.mask).objects, 1u) << "resolution " << resolution;
        EXPECT_EQ(kept.contacts.contactsRejoined, 1u) << "resolution " << resolution;
    }
}

TEST(ContactSeparation, TheFaceOrderChangesNothing) {
    // Where several triangles are nearest to a voxel (at a vertex or an edge
    // they share), the one used must not be the first in the file: the same
    // surface written in another order must give the same voxel model.
    struct Case {
        const char* name;
        TriangleMesh mesh;
        int resolution;
    };
    // (The figure with its hand on its hip is the scene test's:
    // SceneMeshTopology.TheFaceOrderGivesTheSameFaceLabels.)
    const std::vector<Case> cases{{"cut ring", cutRing(), 20}, {"rod on slab", rodOnSlab(), 26}};
    for (const Case& c : cases) {
        VoxelizeOptions options = coarse(true);
        options.resolution = c.resolution;
        const MeshVoxelization original = voxelizeMeshWithContacts(c.mesh, options);
        ASSERT_GT(original.contacts.contactPairs, 0u) << c.name << ": no contact to separate";
        for (unsigned seed : {1u, 2u}) {
            const MeshVoxelization again =
                voxelizeMeshWithContacts(test::reorderedTriangles(c.mesh, seed), options);
            EXPECT_EQ(again.contacts.contactPairs, original.contacts.contactPairs)
                << c.name << ", seed " << seed;
            EXPECT_EQ(again.contacts.voxelsCleared, original.contacts.voxelsCleared)
                << c.name << ", seed " << seed;
            EXPECT_TRUE(again.mask.values() == original.mask.values())
                << c.name << ", seed " << seed;
        }
    }
}

TEST(ContactSeparation, SerialEqualsParallel) {
    const TriangleMesh mesh = cutRing();
    const MeshVoxelization serial = voxelizeMeshWithContacts(mesh, coarse(true, false));
    const MeshVoxelization parallel = voxelizeMeshWithContacts(mesh, coarse(true, true));
    EXPECT_EQ(serial.mask.values(), parallel.mask.values());
    EXPECT_EQ(serial.contacts.contacts, parallel.contacts.contacts);
    EXPECT_EQ(serial.contacts.voxelsCleared, parallel.contacts.voxelsCleared);
    EXPECT_EQ(serial.contacts.contactPairs, parallel.contacts.contactPairs);
}

TEST(ContactSeparation, RefusesAMismatchedTriangleGrid) {
    MaskVolume mask(Dims{4, 4, 4}, 1);
    const std::vector<std::int32_t> tooShort(10, -1);
    EXPECT_THROW(separateContacts(cutRing(), mask, tooShort), UsageError);
}

TEST(ContactSeparation, AStopAnsweredOnceAtAnyPollThrows) {
    const TriangleMesh mesh = cutRing();
    SignedVoxelization conversion;
    voxelizeMeshWithContacts(mesh, coarse(true), nullInterrupter(), &conversion);
    ASSERT_FALSE(conversion.nearestTriangle.empty());
    for (const bool threaded : {false, true}) {
        SCOPED_TRACE(threaded ? "threaded" : "serial");
        ContactSeparationOptions options;
        options.threaded = threaded;
        MaskVolume separated = conversion.mask;
        ASSERT_EQ(separateContacts(mesh, separated, conversion.nearestTriangle, options).contacts,
                  1u);
        EXPECT_GT(test::expectAStopAtAnyPollThrows(
                      [&](Interrupter& interrupter) {
                          MaskVolume mask = conversion.mask;
                          separateContacts(mesh, mask, conversion.nearestTriangle, options,
                                           interrupter);
                      },
                      12),
                  1);
    }
}

}  // namespace
}  // namespace skelseg
