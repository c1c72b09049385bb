// skelseg: a mask as x-runs, and the connected components of the runs.
//
// The whole-grid stages outside the skeleton (objects, islands, the voxel
// genus) need connectivity, not a value per voxel: a row of a 400^3 grid
// holds a handful of runs, so a run-length code is a few MB where a label
// per voxel is 256 MB that must be allocated, zeroed and filled. The mask is
// read once (rows in parallel), and the components are a union-find over
// runs: slabs of z-planes join their own runs in parallel, the seams between
// slabs are joined after. Every union links the larger run id to the
// smaller, so a component's root is its first run in voxel order whatever
// the thread count, and objects numbered by their roots come in the order
// of their first voxel (the order a serial scan-and-flood gives).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// Voxels x0 .. x1 (inclusive) of one row.
struct VoxelRun {
    int x0 = 0, x1 = 0;
    bool operator==(const VoxelRun& o) const noexcept { return x0 == o.x0 && x1 == o.x1; }
};

/// The maximal x-runs of one kind of voxel, row by row in voxel order: the
/// runs of row (y, z) are runs[rowStart[r]] .. runs[rowStart[r + 1] - 1]
/// with r = rowOf(y, z), by increasing x.
struct VoxelRuns {
    Dims dims;
    std::vector<std::uint32_t> rowStart;  // rowCount() + 1 entries
    std::vector<VoxelRun> runs;

    std::size_t rowCount() const noexcept { return std::size_t(dims.y) * std::size_t(dims.z); }
    std::size_t rowOf(int y, int z) const noexcept {
        return std::size_t(z) * std::size_t(dims.y) + std::size_t(y);
    }
    std::uint32_t runCount() const noexcept { return std::uint32_t(runs.size()); }
};

/// Runs of the nonzero voxels of `mask`. Identical for any thread count.
/// @throw InterruptedError when asked to stop.
VoxelRuns objectRuns(const MaskVolume& mask, bool threaded = true,
                     Interrupter& interrupter = nullInterrupter());

/// Runs of the voxels of the grid that no run of `objects` covers (the
/// background of the mask `objects` was made from).
VoxelRuns backgroundRuns(const VoxelRuns& objects, bool threaded = true);

/// Which voxels touch: 6 = a shared face (the background's connectivity),
/// 26 = a shared face, edge or corner (the objects').
enum class VoxelAdjacency { Face6, Full26 };

/// Per run of `runs`: the id of the first run (in voxel order) of its
/// connected component, runs joined where two of their voxels touch under
/// `adjacency`. A run is its component's first run exactly when the entry
/// is its own id. Identical for any thread count.
/// @throw InterruptedError when asked to stop.
std::vector<std::uint32_t> runComponents(const VoxelRuns& runs, VoxelAdjacency adjacency,
                                         bool threaded = true,
                                         Interrupter& interrupter = nullInterrupter());

}  // namespace skelseg
