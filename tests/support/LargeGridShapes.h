// A small shape in a large, mostly empty grid: where segmenting a coarser
// grid saves most of a volume's memory (engine/SegmentInput.h
// volumeRunMemory), since the outputs drawn on the input's grid grow with its
// boundary, not with its voxels.
#pragma once

#include "kernels/base/Volume.h"

namespace skelseg::test {

/// The synthetic figure rasterised 64 voxels tall, in the middle of a
/// 160^3 grid.
MaskVolume figureInALargeGrid();

}  // namespace skelseg::test
