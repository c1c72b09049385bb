// Scene: a figure whose hand rests on its hip with a gap of a third of a
// voxel, written as a mesh, keeps the mesh's topology in the voxel model and
// segments like the same figure with the hand held away.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/Segmenter.h"
#include "io/mesh/MeshGenus.h"
#include "io/mesh/MeshVoxelizer.h"
#include "kernels/VoxelGenus.h"
#include "tests/support/SceneSupport.h"
#include "tests/support/ShapeMeshes.h"

namespace skelseg {
namespace {

/// The coarse resolution at which one fine voxel (the gap) is a third of a voxel.
VoxelizeOptions thirdOfAVoxelGap(const TriangleMesh& mesh, bool keepTopology) {
    double low = HUGE_VAL, high = -HUGE_VAL;
    for (const auto& p : mesh.vertices) {
        low = std::min(low, p[2]);
        high = std::max(high, p[2]);
    }
    VoxelizeOptions options;
    options.resolution = int(std::lround((high - low) / 3.0));  // z is the longest side
    options.keepMeshTopology = keepTopology;
    return options;
}

TEST(SceneMeshTopology, HandOnHipKeepsGenusAndParts) {
    const TriangleMesh touching = test::figureMesh(true);
    const TriangleMesh away = test::figureMesh(false);
    ASSERT_EQ(meshTopology(touching).genus, 0);
    ASSERT_EQ(meshTopology(touching).closedPieces, 1u);

    // Without the contact separation the hand fuses with the hip: a loop.
    const MaskVolume fused = voxelizeMesh(touching, thirdOfAVoxelGap(touching, false));
    ASSERT_EQ(voxelTopology(fused).genus, 1) << "the test figure must fuse when voxelised";

    const MeshVoxelization kept =
        voxelizeMeshWithContacts(touching, thirdOfAVoxelGap(touching, true));
    EXPECT_GE(kept.contacts.contacts, 1u)
        << "pairs " << kept.contacts.contactPairs << " kept " << kept.contacts.contactsKept;
    const VoxelTopology keptTopology = voxelTopology(kept.mask);
    EXPECT_EQ(keptTopology.genus, 0);
    EXPECT_EQ(keptTopology.objects, 1u);

    const MaskVolume apart = voxelizeMesh(away, thirdOfAVoxelGap(away, true));
    EXPECT_EQ(voxelTopology(apart).genus, 0);

    const SegmentationResult touchingResult = segmentVolume(kept.mask, {});
    const SegmentationResult awayResult = segmentVolume(apart, {});
    EXPECT_EQ(touchingResult.segments.size(), awayResult.segments.size());
    const auto touchingAdjacency = test::segmentAdjacency(touchingResult.labels);
    const auto awayAdjacency = test::segmentAdjacency(awayResult.labels);
    const int count = int(awayResult.segments.size());
    EXPECT_EQ(test::degreeSequence(touchingAdjacency, count),
              test::degreeSequence(awayAdjacency, count));
    EXPECT_GE(count, 6);  // body, head, two arms, two legs at least
}

}  // namespace
}  // namespace skelseg
