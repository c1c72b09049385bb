// Closed box meshes at any orientation, for tests of the voxeliser's
// handling of thin parts (sheets and spikes thinner than a voxel).
#pragma once

#include <array>
#include <vector>

#include "io/mesh/MeshIO.h"

namespace skelseg::test {

using Rotation = std::array<std::array<double, 3>, 3>;

/// Rotation by `degrees` about the (normalised) axis.
Rotation rotation(std::array<double, 3> axis, double degrees);

/// Appends the closed box [-size/2, size/2] (outward normals), rotated and
/// moved to `centre`, as a separate piece.
void addBox(TriangleMesh& mesh, const std::array<double, 3>& size, const Rotation& r,
            const std::array<double, 3>& centre = {0, 0, 0});

/// Unit cubes (addBox) at the given lower corners. Every cube is split
/// along the same diagonals, so a face two cubes share is written twice
/// with the same triangles, wound opposite ways.
TriangleMesh unitCubes(const std::vector<std::array<double, 3>>& corners);

/// Eight unit cubes round a square hole (a 3 x 3 layer without its middle
/// one, lower corners (0..2, 0..2, 0)), each sharing whole faces with its
/// neighbours: a solid torus, genus 1. `crossOneSharedFace`: the face the
/// cube at the origin shares with the one at (1, 0, 0) is split along its
/// other diagonal in the first cube only, so its two copies differ.
TriangleMesh ringOfUnitCubes(bool crossOneSharedFace = false);

}  // namespace skelseg::test
