// skelseg: the objects of a volume (docs/algorithm.md §1): 26-connected
// components of the object voxels, each segmented on its own.
//
// The labelling is kept run-length coded (kernels/VoxelRuns.h): the object
// voxels' x-runs, each with its object id. Nothing downstream needs a label
// per voxel of the grid (the crop of an object and the islands' boundary
// areas read the runs), and at 400^3 such a label volume is 256 MB to
// allocate, zero and fill. Objects are numbered in the order
// of their first voxel whatever the thread count.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "kernels/VoxelRuns.h"
#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

struct ObjectExtent {
    std::uint32_t id = 0;           // 0, 1, ... in order of the first voxel
    std::uint64_t voxels = 0;       // number of object voxels
    std::array<int, 3> lo{}, hi{};  // inclusive bounding box
};

struct ConnectedObjects {
    std::vector<ObjectExtent> objects;
    /// The object voxels of the grid as x-runs.
    VoxelRuns runs;
    /// Per run of `runs`: the id of its object.
    std::vector<std::uint32_t> objectOfRun;

    /// Object id + 1 of voxel (x, y, z) of the grid, 0 for background.
    std::uint32_t componentAt(int x, int y, int z) const;
};

struct ConnectedObjectsOptions {
    bool threaded = true;
};

/// 26-connected components of the nonzero voxels of `mask`.
/// Throws InterruptedError when asked to stop.
ConnectedObjects findConnectedObjects(const MaskVolume& mask,
                                      const ConnectedObjectsOptions& options = {},
                                      Interrupter& interrupter = nullInterrupter());

}  // namespace skelseg
