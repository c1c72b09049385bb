// Scene: a figure whose hand rests on its hip with a gap of a third of a
// voxel, written as a mesh, keeps the mesh's topology in the voxel model and
// segments like the same figure with the hand held away, and like itself
// with its faces in another order.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "engine/Segmenter.h"
#include "io/mesh/FaceLabels.h"
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

TEST(SceneMeshTopology, TheFaceOrderGivesTheSameFaceLabels) {
    // The same figure written by another exporter (its triangles in another
    // order, each started at another corner) must give the same parts, face
    // for face: the contact at the hip is where the order used to matter.
    const TriangleMesh mesh = test::figureMesh(true);
    const TriangleMesh shuffled = test::reorderedTriangles(mesh, 5);
    const VoxelizeOptions options = thirdOfAVoxelGap(mesh, true);
    const MeshVoxelization original = voxelizeMeshWithContacts(mesh, options);
    const MeshVoxelization again = voxelizeMeshWithContacts(shuffled, options);
    ASSERT_GE(original.contacts.contacts, 1u);
    EXPECT_TRUE(again.mask.values() == original.mask.values());
    const SegmentationResult originalResult = segmentVolume(original.mask, {});
    const SegmentationResult againResult = segmentVolume(again.mask, {});
    const std::vector<std::uint32_t> originalFaces = labelFaces(mesh, originalResult.labels);
    const std::vector<std::uint32_t> againFaces = labelFaces(shuffled, againResult.labels);
    EXPECT_GE(originalResult.segments.size(), 6u);
    EXPECT_EQ(againResult.segments.size(), originalResult.segments.size());
    EXPECT_TRUE(againFaces == originalFaces);
}

}  // namespace
}  // namespace skelseg
