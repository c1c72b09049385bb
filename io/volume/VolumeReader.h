// skelseg: reading a voxel shape from any supported volume file.
//
// readVolume() picks the reader by file extension (NRRD, binvox, OpenVDB) and
// returns a binary mask plus the geometry that maps its voxels to the file's
// world space. Every failure is an InputError whose what() reads
// "FILE: PROBLEM" on one line. The per-format readers live in NrrdIO.h,
// BinvoxIO.h and VdbIO.h; docs/formats.md describes what each accepts. The
// file checks every reader shares (checkReadableFile, readFileBytes) live in
// io/files/TextFile.h.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "io/files/TextFile.h"  // checkReadableFile, readFileBytes, kMaxInputFileBytes
#include "io/volume/ReadGuards.h"
#include "kernels/base/Volume.h"

namespace skelseg {

enum class VolumeFormat { Nrrd, Binvox, Vdb, Unknown };

struct VolumeReadOptions {
    /// OpenVDB only: the grid to read; empty = the first grid in the file.
    std::string gridName;
    /// A say on the grid before it is allocated, and OpenVDB's parse limits.
    VolumeReadGuards guards;
};

/// The format implied by the file extension, case-insensitively:
/// .nrrd/.nhdr -> Nrrd, .binvox -> Binvox, .vdb -> Vdb, anything else -> Unknown.
VolumeFormat volumeFormatFromPath(const std::filesystem::path& file);

/// Reads the object mask stored in `file` (nonzero = object) and its geometry.
/// @throw InputError "no such file", "is a directory", "is not a regular file",
///        "cannot be read: permission denied", an unknown extension (the message
///        lists the supported ones), or any problem the format's reader finds.
/// @throw UsageError if options.gridName is set for a file that is not .vdb.
MaskVolume readVolume(const std::filesystem::path& file, const VolumeReadOptions& options = {});

/// Every file reading `file` reads: `file`, and a detached NRRD header's
/// data files (any other path, a mesh included, reads only itself). A command checks them against
/// its outputs so that --force never replaces what it reads.
std::vector<std::filesystem::path> volumeInputFiles(const std::filesystem::path& file);

}  // namespace skelseg
