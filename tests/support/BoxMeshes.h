// Closed box meshes at any orientation, for tests of the voxeliser's
// handling of thin parts (sheets and spikes thinner than a voxel).
#pragma once

#include <array>

#include "io/mesh/MeshIO.h"

namespace skelseg::test {

using Rotation = std::array<std::array<double, 3>, 3>;

/// Rotation by `degrees` about the (normalised) axis.
Rotation rotation(std::array<double, 3> axis, double degrees);

/// Appends the closed box [-size/2, size/2] (outward normals), rotated and
/// moved to `centre`, as a separate piece.
void addBox(TriangleMesh& mesh, const std::array<double, 3>& size, const Rotation& r,
            const std::array<double, 3>& centre = {0, 0, 0});

}  // namespace skelseg::test
