// skelseg: the genus of a voxel shape, to check that voxelising a mesh kept
// its topology (docs/meshes.md, "Mesh topology is kept").
//
// The shape is the union of the object voxels as closed unit cubes, so voxels
// that share only an edge or a corner are joined: the 26-connectivity the
// engine gives objects (ConnectedObjects.h). Its Euler characteristic
// chi = vertices - edges - ... of that cubical complex (V - E + F - C) is a
// sum of local terms: every lattice point owns the cube, the three faces,
// the three edges and the vertex that start at it, and whether each is
// present depends only on the 2x2x2 voxels around the point, so chi is one
// table lookup per lattice point.
//
// The genus reported is the total genus of the boundary surfaces (what the
// Euler characteristic of a mesh's closed components gives, see
// io/mesh/MeshGenus.h): a solid with c components and k cavities has
// c + k boundary surfaces whose Euler characteristics add up to 2 * chi, so
// their genera add up to c + k - chi. Cavities are the 6-connected background
// components that do not reach the grid's border (6 for the background is the
// complement of 26 for the objects). Where cubes touch along an edge only,
// the boundary is not a surface; the formula then still counts the tunnel
// such a contact closes, which is what the skeleton sees.
//
// All three counts work on the mask's x-runs (kernels/VoxelRuns.h), read
// once: the lattice points between two run boundaries of a row share one
// table entry, and objects and cavities are union-finds over runs, so no
// array per voxel of the grid is made.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

struct VoxelTopology {
    /// Euler characteristic of the union of closed object cubes.
    std::int64_t eulerCharacteristic = 0;
    /// 26-connected object components.
    std::size_t objects = 0;
    /// 6-connected background components enclosed by objects.
    std::size_t cavities = 0;
    /// Total genus of the boundary surfaces: objects + cavities - chi.
    std::int64_t genus = 0;
};

struct VoxelTopologyOptions {
    /// false: everything runs on the calling thread (the result is the same:
    /// integer sums and run components that do not depend on the split).
    bool threaded = true;
};

/// Topology of the nonzero voxels of `mask`.
/// @throw InterruptedError when asked to stop.
VoxelTopology voxelTopology(const MaskVolume& mask, const VoxelTopologyOptions& options = {},
                            Interrupter& interrupter = nullInterrupter());

/// Euler characteristic alone (the union of closed object cubes).
std::int64_t voxelEulerCharacteristic(const MaskVolume& mask, bool threaded = true,
                                      Interrupter& interrupter = nullInterrupter());

/// Whether setting `cells` (x, y, z) of `mask` to `value` would add topology
/// around them: judged on the box around the cells, `margin` voxels wider
/// (clipped to the grid, with one empty voxel around it so that its border
/// closes no cavity), the genus grows or a cavity appears. The local check of
/// the voxeliser's separations (io/mesh/ContactSeparation.h,
/// SelfOverlapSeparation.h): clearing voxels to separate two surfaces must not
/// punch a hole or leave a cavity instead. Serial: the boxes are small.
bool changeAddsTopology(const MaskVolume& mask, const std::vector<std::array<int, 3>>& cells,
                        std::uint8_t value, int margin = 2);

}  // namespace skelseg
