// skelseg: the objects of a volume (docs/algorithm.md §1): 26-connected
// components of the object voxels, each segmented on its own.
//
// Labelled through x-runs of object voxels and a union-find over runs: runs
// are found and joined slab by slab in parallel (a slab only joins its own
// runs), then the few slab seams are joined serially. Every union links the
// larger run id to the smaller, so a component's root is its first run in
// voxel order, and objects are numbered in the order of their first voxel
// whatever the thread count (the order a serial scan-and-flood would give).
// The flood fill it replaced was the largest serial stage at 400^3 (1 s).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

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
    /// Per voxel of the grid: object id + 1, or 0 for background.
    std::vector<std::uint32_t> component;
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
