// skelseg: a result segmented on another grid than the input's, brought back
// to the input's grid.
//
// Two runs segment a grid other than the one they read: a volume coarsened
// by --time-budget (engine/TimeBudget.h) and a volume of anisotropic voxels
// resampled to cubic ones (kernels/CubicVoxels.h). Their outputs must still
// line up with the input voxel for voxel: every label volume (one per level)
// is mapped onto the input's grid, every voxel position of the result
// (skeleton, junctions, critical points, cuts, joint candidates, cut loops,
// object boxes) is moved to
// the input voxel that holds it, and the segments' voxel counts are counted
// again on the input's grid.
#pragma once

#include <array>
#include <functional>

#include "engine/Segmenter.h"
#include "kernels/CubicVoxels.h"
#include "kernels/base/Interrupter.h"

namespace skelseg {

/// Maps every label volume of `result` with `labelsOnInput` and every voxel
/// position with `voxelOnInput`, then recounts the segments' voxels. Levels
/// are mapped the same way as the top-level labels, so they still nest.
void moveResultToInputGrid(
    SegmentationResult& result, const std::function<LabelVolume(const LabelVolume&)>& labelsOnInput,
    const std::function<std::array<int, 3>(const std::array<int, 3>&)>& voxelOnInput);

/// A result segmented on `grid`'s cubic voxels, on the input's anisotropic
/// grid (labelsOnInputGrid; positions to within half an input voxel).
/// @throw InterruptedError.
void cubicResultOnInputGrid(SegmentationResult& result, const CubicGrid& grid,
                            Interrupter& interrupter = nullInterrupter());

}  // namespace skelseg
