// skelseg: the allocator policy of a batch process: memory freed by one
// shape is kept for the next instead of being handed back to the kernel.
//
// Every shape allocates its largest buffers afresh: the preview alone allocates
// its canvases, depth and line layers (three panels, supersampled) at a fixed size,
// whatever the size of the shape. glibc serves blocks of that size with
// mmap(2), or trims them off the heap when they are freed, so the next shape
// took every page again through a page fault that zero-fills it. On inputs
// of a few thousand voxels that was most of the run (docs/scale-out.md,
// "Batches of thousands"). A batch runs thousands of shapes of similar
// sizes in one process, so the freed memory is worth keeping. glibc only; a
// no-op elsewhere.
#pragma once

#include <cstddef>

namespace skelseg {

/// Blocks below this many bytes come from the heap, not from mmap(2).
constexpr std::size_t kBatchMmapThresholdBytes = std::size_t(32) << 20;
/// Free memory at the top of a heap is kept up to this many bytes.
constexpr std::size_t kBatchTrimThresholdBytes = std::size_t(128) << 20;

/// Sets the process's allocator to keep freed memory for reuse (the two
/// thresholds above). Returns false where the allocator is not glibc's or
/// refused a setting.
bool keepFreedMemoryForReuse();

}  // namespace skelseg
