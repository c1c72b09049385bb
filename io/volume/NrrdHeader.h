// skelseg: the NRRD header, parsed and checked (internal to io/volume/).
//
// NrrdIO.cpp decodes the samples that follow a header, NrrdWriter.cpp writes
// one; both share the sample types declared here. parseNrrdHeader() checks
// every field the reader needs (docs/formats.md lists the rules) and turns
// "space directions", "space origin" or "spacings" into the VolumeGeometry.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "kernels/base/Volume.h"

namespace skelseg::nrrd {

enum class SampleType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float, Double };
enum class Encoding { Raw, Gzip };

/// Bytes per sample of `type` (1 to 8).
std::size_t sampleBytes(SampleType type);

/// Our name of `type` in messages ("int8", ..., "double").
const char* sampleTypeName(SampleType type);

constexpr bool hostIsBigEndian() {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
    return true;
#else
    return false;
#endif
}

/// The fields of a header that matter to us; the optional ones stay empty
/// when the header lacks them.
struct NrrdHeader {
    std::optional<int> dimension;
    std::optional<SampleType> type;
    std::optional<std::vector<std::int64_t>> sizes;
    std::optional<Encoding> encoding;
    std::optional<bool> bigEndian;
    std::optional<std::string> dataFile;
    std::optional<std::string> space;
    std::optional<std::vector<std::array<double, 3>>> spaceDirections;
    std::optional<std::array<double, 3>> spaceOrigin;
    std::optional<std::vector<double>> spacings;
    bool endsWithBlankLine = false;
    std::size_t dataOffset = 0;  // where attached data starts
    /// Bytes before the samples: of the raw data, or of the decompressed
    /// data for gzip (as teem reads them); -1 (raw only): the samples are the
    /// data's last bytes, after a header of any length (a detached header
    /// over another format's file).
    std::int64_t byteSkip = 0;
    Dims dims;
    VolumeGeometry geometry;
};

/// Parses and checks the header at the start of `size` bytes; `name` is used
/// in messages only. On return dimension, type, sizes and encoding are set,
/// bigEndian is set for multi-byte samples, and dataOffset is where attached
/// data starts. @throw InputError(name, problem) for any header problem.
NrrdHeader parseNrrdHeader(const std::string& name, const std::uint8_t* bytes, std::size_t size);

}  // namespace skelseg::nrrd
