// skelseg: which piece of a mesh each object of its voxel model comes from
// (issue 12).
//
// A closed mesh piece thinner than a voxel across a whole section voxelises
// into two or more objects. The segmenter cannot tell such a broken-off
// object from a shape of its own; the voxeliser can, from the nearest
// triangle it keeps for every voxel near the surface: an object's piece is
// the piece of the triangles most of its surface voxels are nearest to
// (a vote: a voxel of a contact between two pieces may be nearer the other).
// kernels/Islands.h (findFragments) decides which of them are parts.
#pragma once

#include <cstdint>
#include <vector>

#include "io/mesh/MeshIO.h"
#include "kernels/Islands.h"
#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// Per 26-connected object of `mask` (kernels/ConnectedObjects.h) that has
/// a voxel with a nearest triangle: one of its voxels and its piece (pieces
/// are the mesh's triangles joined through shared positions, numbered by
/// their lowest vertex). Empty when the mask has fewer than two objects or
/// `nearestTriangle` does not match it (one entry per voxel, x fastest; -1
/// where no triangle is recorded). Identical for any thread count.
/// @throw InterruptedError when asked to stop.
std::vector<ObjectSource> voxelObjectPieces(const TriangleMesh& mesh, const MaskVolume& mask,
                                            const std::vector<std::int32_t>& nearestTriangle,
                                            bool threaded = true,
                                            Interrupter& interrupter = nullInterrupter());

}  // namespace skelseg
