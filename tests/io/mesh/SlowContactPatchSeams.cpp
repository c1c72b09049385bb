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

/// The plate at resolution 16 voxelised with both later steps off and then
/// with `enable` applied to the contact options, threaded and serially.
struct PlateRuns {
    MeshVoxelization without, with;
};

PlateRuns voxelizePlate(void (*enable)(ContactSeparationOptions&)) {
    const TriangleMesh mesh = earOnHead();
    VoxelizeOptions options;
    options.resolution = 16;
    options.keepMeshTopology = true;
    options.contactOptions.grownSeams = false;
    PlateRuns runs;
    runs.without = voxelizeMeshWithContacts(mesh, options);
    enable(options.contactOptions);
    runs.with = voxelizeMeshWithContacts(mesh, options);
    // The later steps run serially; the rest of the stage is tested for
    // serial = threaded in TestContactSeparation.cpp.
    options.threaded = false;
    EXPECT_EQ(voxelizeMeshWithContacts(mesh, options).mask.values(), runs.with.mask.values())
        << "serial must equal threaded";
    return runs;
}

/// The plate fused without the step; with it, parted and still one object
/// without a cavity (the plate not cut loose), one contact more separated.
void expectPlateParted(const PlateRuns& runs) {
    ASSERT_EQ(voxelTopology(runs.without.mask).genus, 1) << "the plate must fuse without it";
    ASSERT_GE(runs.without.contacts.contactsKept, 1u);
    const VoxelTopology topology = voxelTopology(runs.with.mask);
    EXPECT_EQ(topology.genus, 0);
    EXPECT_EQ(topology.objects, 1u) << "the plate must not be cut loose";
    EXPECT_EQ(topology.cavities, 0u);
    EXPECT_EQ(runs.with.contacts.contacts, runs.without.contacts.contacts + 1);
    EXPECT_EQ(runs.with.contacts.contactsKept + 1, runs.without.contacts.contactsKept);
}

TEST(ContactPatchSeams, PartAnEarFromTheHeadWithoutCuttingItLoose) {
    // At resolution 16 the gap is a sixteenth of a voxel and the plate under
    // two voxels thick: the pairs at the plate's rim are missed, and the seam
    // of the pairs found would punch a hole, so the box check keeps the
    // contact whole. The seam between the two patches reaches the rim.
    ASSERT_EQ(meshTopology(earOnHead()).genus, 0);
    const PlateRuns runs = voxelizePlate([](ContactSeparationOptions& o) { o.patchSeams = true; });
    expectPlateParted(runs);
    EXPECT_EQ(runs.with.contacts.contactsPatchSeamed, 1u);
    EXPECT_EQ(runs.with.contacts.contactsGrown, 0u);
}

TEST(ContactGrownSeams, PartAnEarFromTheHeadWithoutCuttingItLoose) {
    // The same plate: the seam of the pairs found, grown by one voxel into
    // the model, reaches past the rim the pairs missed.
    const PlateRuns runs = voxelizePlate([](ContactSeparationOptions& o) { o.grownSeams = true; });
    expectPlateParted(runs);
    EXPECT_EQ(runs.without.contacts.contactsGrown, 0u);
    EXPECT_EQ(runs.with.contacts.contactsGrown, 1u);
    EXPECT_EQ(runs.with.contacts.contactsPatchSeamed, 0u);
}

}  // namespace
}  // namespace skelseg
