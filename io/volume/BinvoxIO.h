// skelseg: binvox voxel files (Patrick Min's binvox / viewvox format).
//
// A binvox file is a short text header ("#binvox 1", "dim", optional
// "translate" and "scale", "data") followed by run-length pairs (value byte,
// count byte). binvox stores voxel (x, y, z) at index x*d1*d2 + z*d2 + y, where
// "dim d0 d1 d2" lists the extents of x, z and y: y runs fastest, then z, then
// x. The readers transpose this into our x-fastest layout keeping binvox's
// axis names, so voxel (x, y, z) in binvox is voxel (x, y, z) here, and
// writeBinvox() is the exact inverse.
//
// Geometry follows the binvox documentation: the centre of voxel (i, j, k) is
// at translate + scale * ((i, j, k) + 0.5) / max(d0, d1, d2). Our geometry
// maps voxel indices to voxel centres, so voxel size = scale / max(dims) and
// origin = translate + half a voxel.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "io/volume/ReadGuards.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// Reads a binvox file (version 1, or 2 whose set voxels may hold any nonzero
/// value) as an object mask: nonzero voxels become 1. `guards.checkGrid`
/// sees the grid once the runs are known to be able to cover it, before it
/// is allocated (ReadGuards.h).
/// @throw InputError naming the file and the problem.
MaskVolume readBinvox(const std::filesystem::path& file, const VolumeReadGuards& guards = {});

/// As readBinvox() for a file already in memory; `name` is used in messages.
MaskVolume readBinvoxFromMemory(const std::string& name, const std::uint8_t* bytes,
                                std::size_t size, const VolumeReadGuards& guards = {});

/// Writes `mask` as a version 1 binvox file (nonzero -> 1), atomically.
/// binvox has one uniform voxel size and no rotation: the voxel size written
/// is mask.geometry.voxelSize() and the directions are otherwise dropped.
/// @throw OutputError naming the file.
void writeBinvox(const std::filesystem::path& file, const MaskVolume& mask);

}  // namespace skelseg
