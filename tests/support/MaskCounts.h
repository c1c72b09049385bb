// Counting set voxels, the first check of every reader and writer test.
#pragma once

#include <cstddef>

#include "kernels/base/Volume.h"

namespace skelseg::test {

/// Number of voxels of `mask` that are not 0.
inline std::size_t countNonzero(const MaskVolume& mask) {
    std::size_t count = 0;
    for (auto value : mask.values()) count += value != 0;
    return count;
}

}  // namespace skelseg::test
