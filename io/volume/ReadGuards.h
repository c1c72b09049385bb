// skelseg: what a caller asks of a volume reader beyond reading the file.
//
// A reader knows the grid's extents long before it allocates the dense mask
// (a byte per voxel), and a file of a few bytes may claim billions of voxels:
// gzip expands up to 1032 to 1, bzip2 millions to 1, binvox's runs 127 to 1,
// and one OpenVDB tile covers 4096^3 voxels. The readers call checkGrid once
// the file is known to be able to hold the grid (their own refusals come
// first, so bad input stays bad input) and before they allocate it; a command
// passes its --max-memory test (engine/SegmentInput.h). The OpenVDB reader
// parses in a child process (io/files/IsolatedCall.h) and uses the other two
// guards there: the memory the parse may take, and a way to stop it.
#pragma once

#include <cstdint>
#include <functional>

#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

struct VolumeReadGuards {
    /// Called with the mask's extents before the reader allocates it; throws
    /// to refuse the grid. Empty: every grid is accepted.
    std::function<void(const Dims&)> checkGrid;
    /// OpenVDB: bytes its parse of the file may allocate (MemoryLimitError
    /// beyond them); 0: no limit.
    std::uint64_t memoryLimit = 0;
    /// OpenVDB: polled while the parse runs; it stops the parse when asked.
    Interrupter* interrupter = nullptr;
};

}  // namespace skelseg
