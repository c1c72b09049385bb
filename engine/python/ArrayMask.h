// skelseg: a numpy array (any layout, any numeric dtype) as the engine's mask.
//
// The caller's array is read in place through its strides, once, into the
// engine's own MaskVolume (1 byte a voxel, x fastest): the engine's kernels
// own their input, and this is the only copy the Python call makes. There is
// no intermediate numpy array, whatever the dtype or the memory order.
//
// Axis convention: array axis 0 is the engine's x, axis 1 its y, axis 2 its
// z, for C and Fortran order alike, so the result does not depend on the
// memory layout and labels come back with the caller's shape and axis order.
// It is the NRRD and pynrrd convention (x fastest), so read_volume() returns
// the file's voxels in file order and labels equal the CLI's labels.nrrd.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "kernels/base/Volume.h"

namespace skelseg {

/// Element types a mask may have. Integers and bools: nonzero is object (any
/// byte order). Floats: nonzero is object; NaN is refused.
enum class MaskElement { Integer, Float16, Float32, Float64 };

/// A strided 3-D array in memory (numpy's view of it, without numpy).
struct ArrayView {
    const std::uint8_t* data = nullptr;
    std::array<std::int64_t, 3> shape{};
    std::array<std::int64_t, 3> strides{};  // bytes; may be negative or zero
    MaskElement element = MaskElement::Integer;
    int itemSize = 1;  // bytes: 1, 2, 4 or 8
};

/// Number of nonzero elements.
/// @throw InputError(NAME, "NaN at index [i, j, k] ...") for a float NaN.
std::uint64_t countObjectVoxels(const ArrayView& array, const std::string& name,
                                bool threaded = true);

/// The mask (1 = object) on a grid of shape[0] x shape[1] x shape[2] voxels,
/// unit geometry.
/// @throw InputError(NAME, ...) for an empty or oversized shape and for a
/// NaN (as countObjectVoxels).
MaskVolume maskFromArray(const ArrayView& array, const std::string& name, bool threaded = true);

}  // namespace skelseg
