// skelseg: OpenVDB files (input masks and the labels.vdb output).
//
// Only VdbIO.cpp includes OpenVDB headers (they take ~20 s to compile), so
// this header exposes plain skelseg types.
//
// Reading: BoolGrid and MaskGrid -> the active voxels (and active tiles) are
// the object. FloatGrid and DoubleGrid -> level sets: values below zero are
// the object, including the inactive interior (openvdb::tools::sdfInteriorMask);
// a grid whose class is "fog volume" instead has its active values above
// zero as the object. Other grid types are rejected. The dense mask covers
// exactly the bounding box of the object voxels; its geometry maps our voxel
// (0,0,0) to the VDB index-space minimum of that box, so world positions are
// unchanged. A grid without object voxels gives a 1x1x1 volume with no object.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "io/volume/ReadGuards.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// Reads grid `gridName` (or the first grid, if empty) of a .vdb file as a mask.
/// OpenVDB parses the file first in a child process (io/files/IsolatedCall.h),
/// with `guards.memoryLimit` and `guards.interrupter`: a file on which
/// OpenVDB's reader crashes is an InputError, not the end of this process.
/// `guards.checkGrid` sees the dense mask's extents (the object's bounding
/// box), known once the sparse tree is read, before the mask is allocated
/// (ReadGuards.h); what it throws passes through.
/// @throw InputError naming the file: not a VDB file, truncated, no grids,
///        no grid of that name (the message lists the grids), unsupported grid
///        type, non-linear transform, a bounding box over kMaxVoxels, or a
///        file OpenVDB's reader crashes on.
/// @throw MemoryLimitError when the parse needs more than guards.memoryLimit.
/// @throw InterruptedError when guards.interrupter stops the parse.
MaskVolume readVdbMask(const std::filesystem::path& file, const std::string& gridName = "",
                       const VolumeReadGuards& guards = {});

/// As readVdbMask() for a file already in memory; `name` is used in messages.
/// Parses in this process (the fuzzers' entry; only `guards.checkGrid` applies).
MaskVolume readVdbMaskFromMemory(const std::string& name, const std::uint8_t* bytes,
                                 std::size_t size, const std::string& gridName = "",
                                 const VolumeReadGuards& guards = {});

/// The one test of whether OpenVDB can hold a grid of `dims` voxels placed by
/// `geometry` (writeVdbLabels() checks it, and the mesh voxeliser measures its
/// distances in world units only where it holds). It asks OpenVDB itself:
/// true when OpenVDB builds the linear transform writeVdbLabels() gives the
/// grid and that transform puts every corner voxel at a finite world
/// position. OpenVDB's linear maps refuse a voxel whose volume (the
/// determinant of the directions) is below 3e-15 world units cubed, e.g.
/// 10 um voxels given in metres; the caller then leaves labels.vdb out.
bool vdbCanHoldVoxelVolume(const Dims& dims, const VolumeGeometry& geometry);

/// Writes `labels` as one Int32Grid named "labels": background 0, active where
/// the label is above 0. The transform reproduces labels.geometry (a uniform
/// scale and translation when the directions are axis aligned and isotropic,
/// an affine map otherwise). Atomic: written under a temporary name, then
/// renamed. @throw OutputError naming the file, also when
/// vdbCanHoldVoxelVolume() is false.
void writeVdbLabels(const std::filesystem::path& file, const LabelVolume& labels);

}  // namespace skelseg
