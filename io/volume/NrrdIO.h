// skelseg: NRRD volumes (the input mask and the labels.nrrd output).
//
// A strict hand-written reader for 3D NRRD files (NRRD0001..NRRD0005), and
// 4D ones whose fourth, non-spatial axis has size 1 (it is dropped):
// attached or detached (.nhdr + "data file", one file, a LIST or a name
// pattern such as "slice%03d.raw 0 15 1") headers; int8, uint8, int16,
// uint16, int32, uint32, int64, uint64, float and double samples in the raw,
// ascii, hex, gzip and bzip2 encodings, either endianness, with line and
// byte skips. The first axis runs fastest and becomes
// our x; axes are never permuted. "space", "space directions", "space origin"
// (or "spacings") become the VolumeGeometry, and the writers repeat them, so
// labels.nrrd overlays the input in any viewer.
//
// Every size is validated before anything is allocated, and allocation is
// bounded by what the data can actually hold, so the memory readers are safe
// to call from a fuzzer. See docs/formats.md for the full list of rules.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/volume/ReadGuards.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// Reads a 3D NRRD file of any supported sample type as an object mask:
/// nonzero samples become 1, zero samples 0. `guards.checkGrid` sees the
/// grid once the data is known to be able to hold it, before it is allocated
/// (ReadGuards.h).
/// @throw InputError naming the file (or the detached data file) and the problem.
MaskVolume readNrrdMask(const std::filesystem::path& file, const VolumeReadGuards& guards = {});

/// As readNrrdMask() for a file already in memory; `name` is used in error
/// messages. A detached header ("data file:") cannot be read this way and
/// fails with an InputError.
MaskVolume readNrrdMaskFromMemory(const std::string& name, const std::uint8_t* bytes,
                                  std::size_t size);

/// The longest NRRD header read: room for a LIST of a million data files
/// with names of 64 bytes. A longer one is refused, so that the checks that
/// read only a header's list (nrrdDetachedDataFiles) see what the reader
/// reads.
constexpr std::size_t kMaxNrrdHeaderBytes = std::size_t(64) << 20;

/// The data files a detached header (`data file:`, a LIST or a name pattern)
/// names, resolved against the header's directory as the readers resolve
/// them; none for an attached header, and for a header the readers would
/// refuse anyway (they say why). Lets a command make sure that no output
/// replaces a file it reads.
std::vector<std::filesystem::path> nrrdDetachedDataFiles(const std::filesystem::path& header);

/// Reads a 3D NRRD file of uint8 or uint16 samples as labels (values kept).
/// @throw InputError as readNrrdMask(), and for any other sample type.
LabelVolume readNrrdLabels(const std::filesystem::path& file);

/// As readNrrdLabels() for a file already in memory.
LabelVolume readNrrdLabelsFromMemory(const std::string& name, const std::uint8_t* bytes,
                                     std::size_t size);

/// Writes `labels` as a gzip-encoded uint16 NRRD with labels.geometry (space,
/// space directions, space origin). Atomic: the final name appears complete
/// or not at all. @throw OutputError naming the file.
void writeNrrdLabels(const std::filesystem::path& file, const LabelVolume& labels);

/// Writes `mask` as a gzip-encoded uint8 NRRD, as writeNrrdLabels(). Values
/// are written as they are (a mask holds 0 and 1).
void writeNrrdMask(const std::filesystem::path& file, const MaskVolume& mask);

}  // namespace skelseg
