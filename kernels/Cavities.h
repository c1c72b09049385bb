// skelseg: cavities, the background enclosed by an object, filled before its
// skeleton is computed (docs/algorithm.md §1, "Cavities").
//
// Parts are parts of an object's outer surface. A cavity (a 6-connected
// background component that does not reach the border of the grid) adds a
// surface inside the object that no part of the outer surface can see, yet
// its feature points, path sets and loops enter every measure near it: one
// missing voxel inside the body of a figure whose four limbs are cut gave
// 3 parts instead of 5, and 1% of missing voxels under the surface (pores of
// a thresholded scan) gave 1 part. So each object is segmented as the solid
// its outer surface bounds. The filled voxels were background in the input:
// they get no label (the caller clears them with clearVoxelRuns), and
// report.json counts them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "kernels/VoxelRuns.h"
#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

struct FilledCavities {
    std::size_t count = 0;     // cavities filled
    std::uint64_t voxels = 0;  // voxels filled
    /// The filled voxels as x-runs (runs of the same row may touch: one per
    /// background run of a cavity).
    VoxelRuns runs;
};

struct CavityFillOptions {
    /// false: everything runs on the calling thread (same result).
    bool threaded = true;
};

/// The background of a mask, split into what reaches the grid's border and
/// what lies in cavities.
struct CavityRuns {
    VoxelRuns background;                // every background voxel as x-runs
    std::vector<std::uint8_t> inCavity;  // per run of `background`
    std::size_t count = 0;               // cavities
};

/// The cavities of the mask whose object runs are `objects`.
/// @throw InterruptedError when asked to stop.
CavityRuns findCavities(const VoxelRuns& objects, bool threaded = true,
                        Interrupter& interrupter = nullInterrupter());

/// Sets every voxel of `mask` that lies in a cavity to 1 and returns them.
/// Objects are 26-connected and the background 6-connected (as in
/// kernels/VoxelGenus.h), so a cavity touches its object by faces only and
/// filling it joins nothing and opens no tunnel. Identical for any thread
/// count. @throw InterruptedError when asked to stop (`mask` is then left
/// unchanged).
FilledCavities fillCavities(MaskVolume& mask, const CavityFillOptions& options = {},
                            Interrupter& interrupter = nullInterrupter());

/// Sets the voxels of `runs` in `volume` to 0.
template <typename T>
void clearVoxelRuns(Volume<T>& volume, const VoxelRuns& runs) {
    for (int z = 0; z < runs.dims.z; ++z)
        for (int y = 0; y < runs.dims.y; ++y) {
            const std::size_t row = runs.rowOf(y, z);
            for (std::uint32_t k = runs.rowStart[row]; k < runs.rowStart[row + 1]; ++k)
                for (int x = runs.runs[k].x0; x <= runs.runs[k].x1; ++x) volume(x, y, z) = T(0);
        }
}

}  // namespace skelseg
