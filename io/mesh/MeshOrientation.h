// skelseg: which side of each triangle is the outside of a closed mesh, for
// the voxeliser's local inside tests (ContactSeparation.h, ThinPartFill.h).
//
// A piece (triangles joined through shared canonical vertices) is
// consistently oriented when no directed edge is used twice (triangles with a
// repeated corner, which have no area, are not counted); its normals
// (right-hand rule) then point out of the solid when the signed volume it
// encloses is positive, into it when negative. Pieces that are not
// consistently oriented, or enclose no volume, give 0: callers skip the
// rules that need a side there.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "io/mesh/MeshIO.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// Per triangle: +1 when its normal points out of the solid, -1 when in, 0
/// when its piece is not consistently oriented. `triangles`: #triangles
/// canonical corner triples; `points`: #vertices positions (any frame that
/// keeps handedness); `piece`: #triangles piece ids.
std::vector<std::int8_t> triangleOrientation(
    const std::vector<std::array<std::uint32_t, 3>>& triangles,
    const std::vector<std::array<double, 3>>& points, const std::vector<std::uint32_t>& piece);

/// The mesh's triangles with canonical corners (canonicalVertices), their
/// pieces, and their vertices in the voxel index space of `geometry`.
struct CanonicalSurface {
    std::vector<std::array<double, 3>> points;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<std::uint32_t> piece;
};
CanonicalSurface canonicalSurface(const TriangleMesh& mesh, const VolumeGeometry& geometry);

}  // namespace skelseg
