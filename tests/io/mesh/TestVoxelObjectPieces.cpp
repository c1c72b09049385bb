// voxelObjectPieces: the mesh piece of each voxel object, by a vote of the
// nearest triangles of its voxels (io/mesh/VoxelObjectPieces.h).
#include "io/mesh/VoxelObjectPieces.h"

#include <gtest/gtest.h>

#include "kernels/ConnectedObjects.h"

namespace skelseg {
namespace {

/// Two triangles that share no position: two pieces (numbered by their
/// lowest vertex, 0 and 3).
TriangleMesh twoPieces() {
    TriangleMesh mesh;
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 5, 5}, {6, 5, 5}, {5, 6, 5}};
    mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
    mesh.triangleFace = {0, 1};
    mesh.faceCount = 2;
    return mesh;
}

TEST(VoxelObjectPieces, EachObjectTakesThePieceMostOfItsVoxelsAreNearest) {
    const TriangleMesh mesh = twoPieces();
    MaskVolume mask(Dims{20, 6, 6}, 0);
    std::vector<std::int32_t> nearest(mask.size(), -1);
    // Object A (x 1..5): four voxels near triangle 0, one near triangle 1
    // (a contact); object B (x 8..10): near triangle 1; object C (x 14..15):
    // no nearest triangle anywhere (deep inside, beyond the band).
    for (int x = 1; x <= 5; ++x) {
        mask(x, 2, 2) = 1;
        nearest[mask.index(x, 2, 2)] = x == 5 ? 1 : 0;
    }
    for (int x = 8; x <= 10; ++x) {
        mask(x, 3, 3) = 1;
        nearest[mask.index(x, 3, 3)] = 1;
    }
    mask(14, 1, 1) = mask(15, 1, 1) = 1;
    const std::vector<ObjectSource> sources = voxelObjectPieces(mesh, mask, nearest, false);
    ASSERT_EQ(sources.size(), 2u);  // C has no source
    const ConnectedObjects found = findConnectedObjects(mask, {false});
    const std::uint32_t objectA = found.componentAt(1, 2, 2), objectB = found.componentAt(8, 3, 3);
    for (const ObjectSource& source : sources) {
        const std::uint32_t object =
            found.componentAt(source.voxel[0], source.voxel[1], source.voxel[2]);
        ASSERT_TRUE(object == objectA || object == objectB) << "object " << object;
        EXPECT_EQ(source.piece, object == objectA ? 0u : 3u) << "object " << object;
    }
    const auto parallel = voxelObjectPieces(mesh, mask, nearest, true);
    ASSERT_EQ(parallel.size(), sources.size());
    for (std::size_t k = 0; k < sources.size(); ++k) {
        EXPECT_EQ(parallel[k].voxel, sources[k].voxel);
        EXPECT_EQ(parallel[k].piece, sources[k].piece);
    }
    // One object, or a nearest-triangle array of another grid: nothing.
    MaskVolume one(Dims{20, 6, 6}, 0);
    one(3, 3, 3) = 1;
    EXPECT_TRUE(voxelObjectPieces(mesh, one, nearest, false).empty());
    EXPECT_TRUE(voxelObjectPieces(mesh, mask, {}, false).empty());
}

}  // namespace
}  // namespace skelseg
