// Patch seams and grown seams of the contact separation
// (ContactSeparationOptions::patchSeams, grownSeams) on a generated ear lying
// on a head. Under the slow label: the staircase mesh has 44,604 triangles,
// and each voxelisation's contact search walks it.
#include <gtest/gtest.h>

#include "io/mesh/ContactSeparation.h"
#include "io/mesh/MeshGenus.h"
#include "io/mesh/MeshVoxelizer.h"
#include "kernels/VoxelGenus.h"
#include "tests/support/ShapeMeshes.h"

namespace skelseg {
namespace {

/// An ear lying on a head: a body whose top has a trench across it, and a
/// plate (8 fine voxels thick) joined to the body by a stalk on one side of
/// the trench and lying on the body's top across one fine voxel on the
/// other, over a large area. Fused there, the plate closes a loop over the
/// trench.
TriangleMesh earOnHead() {
    Shape s;
    s.box({0, 0, -26}, {40.5, 20.5, 6});     // base: z = -32..-20
    s.box({-15, 0, -10}, {25.5, 20.5, 10});  // body under the contact: x = -40..10
    s.box({32, 0, -10}, {8.5, 20.5, 10});    // body under the stalk: x = 24..40
    s.box({33, 0, 1.5}, {4.5, 6.5, 1.5});    // stalk: z = 0..3 (joins z = 1)
    s.box({0, 0, 5.5}, {37.5, 16.5, 3.5});   // plate: z = 2..9, x = -37..37
    return test::meshOfShape(s, {-43, -23, -35}, {43, 23, 12});
}

TEST(ContactPatchSeams, PartAnEarFromTheHeadWithoutCuttingItLoose) {
    // At resolution 16 the gap is a sixteenth of a voxel and the plate under
    // two voxels thick: the pairs at the plate's rim are missed, and the seam
    // of the pairs found would punch a hole, so the box check keeps the
    // contact whole. The seam between the two patches reaches the rim.
    const TriangleMesh mesh = earOnHead();
    ASSERT_EQ(meshTopology(mesh).genus, 0);
    VoxelizeOptions options;
    options.resolution = 16;
    options.keepMeshTopology = true;
    options.contactOptions.grownSeams = false;  // it frees this plate too (next test)
    const MeshVoxelization plain = voxelizeMeshWithContacts(mesh, options);
    ASSERT_EQ(voxelTopology(plain.mask).genus, 1) << "the plate must fuse without patch seams";
    ASSERT_GE(plain.contacts.contactsKept, 1u);
    options.contactOptions.patchSeams = true;
    const MeshVoxelization patched = voxelizeMeshWithContacts(mesh, options);
    const VoxelTopology topology = voxelTopology(patched.mask);
    EXPECT_EQ(topology.genus, 0);
    EXPECT_EQ(topology.objects, 1u) << "the plate must not be cut loose";
    EXPECT_EQ(topology.cavities, 0u);
    EXPECT_EQ(patched.contacts.contactsPatchSeamed, 1u);
    EXPECT_EQ(patched.contacts.contacts, plain.contacts.contacts + 1);
    // The patch seams run serially; the rest of the stage is tested for
    // serial = threaded in TestContactSeparation.cpp.
    options.threaded = false;
    EXPECT_EQ(voxelizeMeshWithContacts(mesh, options).mask.values(), patched.mask.values());
}

TEST(ContactGrownSeams, PartAnEarFromTheHeadWithoutCuttingItLoose) {
    // The same plate: the seam of the pairs found, grown by one voxel into
    // the model, reaches past the rim the pairs missed.
    const TriangleMesh mesh = earOnHead();
    VoxelizeOptions options;
    options.resolution = 16;
    options.keepMeshTopology = true;
    options.contactOptions.grownSeams = false;
    const MeshVoxelization plain = voxelizeMeshWithContacts(mesh, options);
    ASSERT_EQ(voxelTopology(plain.mask).genus, 1) << "the plate must fuse without grown seams";
    EXPECT_EQ(plain.contacts.contactsGrown, 0u);
    options.contactOptions.grownSeams = true;
    const MeshVoxelization grown = voxelizeMeshWithContacts(mesh, options);
    const VoxelTopology topology = voxelTopology(grown.mask);
    EXPECT_EQ(topology.genus, 0);
    EXPECT_EQ(topology.objects, 1u) << "the plate must not be cut loose";
    EXPECT_EQ(topology.cavities, 0u);
    EXPECT_EQ(grown.contacts.contactsGrown, 1u);
    EXPECT_EQ(grown.contacts.contacts, plain.contacts.contacts + 1);
    EXPECT_EQ(grown.contacts.contactsKept + 1, plain.contacts.contactsKept);
    options.threaded = false;
    EXPECT_EQ(voxelizeMeshWithContacts(mesh, options).mask.values(), grown.mask.values());
}

}  // namespace
}  // namespace skelseg
