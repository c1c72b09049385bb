// skelseg: how much memory an input will need, before reading it.
//
// The batch admits a shape into flight only while the estimates of the shapes
// in flight fit in --max-memory. It must decide before reading the shape (the
// reading is what it bounds), so it estimates from what is cheap to know:
//   meshes: a cube of --resolution voxels a side (the longest side is
//     `resolution`; the others are at most that), plus the parsed mesh at
//     about 4x the file;
//   NRRD and binvox: the grid size from the text header (the first 4 KiB);
//   anything else (VDB: sparse, its dense size is not in a header): a grid of
//     as many voxels as the file has bytes (a raw 8-bit volume's size).
// segmentVolume's own estimate (estimateSegmentationMemory) does the rest, at
// a quarter of the grid as object voxels, the figure `segment` uses for
// meshes. `segment` then checks its finer estimate against the same limit,
// so a shape too big on its own still fails cleanly with exit code 4.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "engine/SegmentCommand.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// Grid extents from an NRRD ("sizes:") or binvox ("dim") header; nullopt
/// for other formats, a header that does not give them, or a path that is
/// not a regular file (a FIFO would block the batch before the input fails).
std::optional<Dims> peekVolumeDims(const std::filesystem::path& file);

/// Estimated peak bytes of segmenting `input` with `options` on `threads` threads.
std::uint64_t estimateInputMemory(const std::filesystem::path& input,
                                  const SegmentCommandOptions& options, int threads);

}  // namespace skelseg
