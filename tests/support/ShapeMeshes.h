// Closed triangle meshes of synthetic shapes, for tests that must exercise
// the mesh voxeliser (scene tests of mesh topology, genus tests).
//
// A shape given in fine-voxel units (voxel centres at integer coordinates)
// is sampled at the voxel centres of a fine grid and meshed with
// extractSegmentSurfaces (no smoothing): every surface lies on voxel faces,
// so two parts of the shape separated by exactly one empty voxel are exactly
// one fine voxel apart in the mesh, whatever the coarse grid it is voxelised
// on later. The result is a single closed surface per connected solid.
#pragma once

#include <array>

#include "io/mesh/MeshIO.h"
#include "io/shapes/SyntheticShapes.h"

namespace skelseg::test {

/// Mesh of the voxels of the box [lo, hi] (inclusive integer corners, fine
/// voxel units) whose centres lie inside `shape`. World units = fine voxels.
TriangleMesh meshOfShape(const Shape& shape, const std::array<int, 3>& lo,
                         const std::array<int, 3>& hi);

/// A standing figure (body box, neck, head, two legs, two arms bent at the
/// elbow) in fine voxels, about 360 tall. handOnHip: the right hand (a flat
/// box at the end of the forearm) rests against the side of the body with a
/// gap of exactly one fine voxel; otherwise it is held away from the body.
Shape figureWithHand(bool handOnHip);

/// meshOfShape over the bounding box of figureWithHand.
TriangleMesh figureMesh(bool handOnHip);

/// figureWithHand (hand held away) whose left leg is folded: its thigh, a
/// flat box fused to the body only at the hip, lies forward under the body
/// with a gap of exactly one fine voxel between its top face and the body's
/// bottom face, and its shin hangs from the knee in front of the body (a
/// horse's hind leg drawn up under its belly). legFolded false: the leg
/// hangs from the hip as the other one does.
TriangleMesh figureWithLegMesh(bool legFolded);

/// Two square bars (60 x 225 x 61 fine voxels) standing on one base,
/// facing each other across `gap` empty fine-voxel layers (the first at
/// x = 0) over their whole height and depth: a U, 240 tall along y. At
/// resolution 80 a gap of 1 is a third of a voxel, and the contact it makes
/// is 75 voxels tall and 20 deep, so it crosses whole 8^3 leaves of
/// OpenVDB's grids with no other surface in them.
TriangleMesh barsOnABase(int gap);

/// The same surface with its triangles shuffled (a permutation drawn from
/// `seed`) and each triangle's corners rotated: what another exporter of the
/// same mesh could write. triangleFace follows its triangle.
TriangleMesh reorderedTriangles(const TriangleMesh& mesh, unsigned seed);

}  // namespace skelseg::test
