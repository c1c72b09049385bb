// triangleOrientation: which side of each triangle is the outside, per piece.
#include "io/mesh/MeshOrientation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "io/mesh/MeshVoxelizer.h"
#include "tests/support/CurledTube.h"

namespace skelseg {
namespace {

std::vector<std::int8_t> orientationOf(const TriangleMesh& mesh) {
    const VolumeGeometry geometry = voxelGridFor(mesh, VoxelizeOptions{}).geometry;
    const CanonicalSurface surface = canonicalSurface(mesh, geometry);
    return triangleOrientation(surface.triangles, surface.points, surface.piece);
}

TEST(MeshOrientation, AFaceWithARepeatedVertexKeepsThePiecesSide) {
    // A zero-area face on an existing edge (`f 1 1 2`) uses that edge a
    // second time one way; it bounds nothing and must not take the side of
    // every other triangle of its piece away (hunt3a F10: the contact
    // separation and the thin-part fill of a character changed).
    const TriangleMesh sphere = test::sphereMesh({0, 0, 0}, 1.0);
    const std::vector<std::int8_t> clean = orientationOf(sphere);
    // One side for the whole sphere (its sign depends on the frame's handedness).
    ASSERT_NE(clean.front(), 0);
    ASSERT_TRUE(
        std::all_of(clean.begin(), clean.end(), [&](std::int8_t o) { return o == clean.front(); }));
    TriangleMesh degenerate = sphere;
    const auto t = sphere.triangles.front();
    degenerate.triangles.push_back({t[0], t[0], t[1]});
    degenerate.triangleFace.push_back(std::uint32_t(degenerate.faceCount++));
    std::vector<std::int8_t> withFace = orientationOf(degenerate);
    withFace.pop_back();  // the zero-area face's own side does not matter
    EXPECT_EQ(withFace, clean);
}

}  // namespace
}  // namespace skelseg
