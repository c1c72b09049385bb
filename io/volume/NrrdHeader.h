// skelseg: the NRRD header, parsed and checked (internal to io/volume/).
//
// NrrdIO.cpp decodes the samples that follow a header, NrrdWriter.cpp writes
// one; both share the sample types declared here. parseNrrdHeader() checks
// every field the reader needs (docs/formats.md lists the rules), turns
// "space directions", "space origin", or "spacings" with "axis mins", "axis
// maxs" and "centers" into the VolumeGeometry,
// finds the axis a 4-D header adds to a volume, and expands "data file: LIST"
// or a name pattern into the data files' names.
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
enum class Encoding { Raw, Ascii, Hex, Gzip, Bzip2 };

/// Bytes per sample of `type` (1 to 8).
std::size_t sampleBytes(SampleType type);

/// Our name of `type` in messages ("int8", ..., "double").
const char* sampleTypeName(SampleType type);

/// Calls `visit(Sample())` with Sample the C++ type of `type` (std::int8_t,
/// ..., double), so that a template serves every sample type.
template <typename Visit>
void visitSampleType(SampleType type, Visit&& visit) {
    switch (type) {
        case SampleType::Int8:
            return visit(std::int8_t());
        case SampleType::UInt8:
            return visit(std::uint8_t());
        case SampleType::Int16:
            return visit(std::int16_t());
        case SampleType::UInt16:
            return visit(std::uint16_t());
        case SampleType::Int32:
            return visit(std::int32_t());
        case SampleType::UInt32:
            return visit(std::uint32_t());
        case SampleType::Int64:
            return visit(std::int64_t());
        case SampleType::UInt64:
            return visit(std::uint64_t());
        case SampleType::Float:
            return visit(float());
        case SampleType::Double:
            return visit(double());
    }
}

/// The encoding's name in messages ("raw", "ascii", "hex", "gzip", "bzip2").
const char* encodingName(Encoding encoding);

/// Whether the encoding's samples are bytes in the file's byte order (all
/// but ascii, whose numbers are text).
bool encodingHasByteOrder(Encoding encoding);

/// Receives decoded sample bytes in any chunking; the decoders of
/// NrrdCompressed.h and NrrdText.h write into one.
class ByteSink {
public:
    virtual ~ByteSink() = default;
    virtual void append(const std::uint8_t* bytes, std::size_t count) = 0;
};

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
    /// The value of a detached header's "data file" field, for messages.
    std::optional<std::string> dataFileField;
    /// The data files of a detached header, in order, as the header names
    /// them; empty for attached data. Several files ("data file: LIST" or a
    /// name pattern) hold consecutive runs of the samples, all of one length
    /// (parseNrrdHeader checked that the sizes split into as many).
    std::vector<std::string> dataFiles;
    /// The data files came from a list or a pattern: messages about one of
    /// them name it, as the header names several.
    bool severalDataFiles = false;
    std::optional<std::string> space;
    /// One per axis; nullopt for an axis whose direction is "none".
    std::optional<std::vector<std::optional<std::array<double, 3>>>> spaceDirections;
    std::optional<std::array<double, 3>> spaceOrigin;
    std::optional<std::vector<double>> spacings;
    /// "axis mins", "axis maxs" (NaN for an axis without one) and "centers"
    /// as written; they place the volume only where the header has neither
    /// "space directions" nor "space origin".
    std::optional<std::vector<double>> axisMins;
    std::optional<std::vector<double>> axisMaxs;
    std::optional<std::vector<std::string>> centers;
    bool endsWithBlankLine = false;
    std::size_t dataOffset = 0;  // where attached data starts
    /// Lines of the data (the data file, or what follows the header) skipped
    /// before the byte skip, as teem does, for every encoding.
    std::int64_t lineSkip = 0;
    /// Bytes before the samples: of the data after the line skip, or of the
    /// decompressed data for gzip and bzip2 (as teem reads them); -1 (raw,
    /// gzip, bzip2): the samples are the data's last bytes, after a header of
    /// any length (a detached header over another format's file).
    std::int64_t byteSkip = 0;
    /// The axis of a 4-D header that is not spatial (its size is 1), dropped
    /// from dims and geometry; -1 for a 3-D header.
    int droppedAxis = -1;
    Dims dims;
    VolumeGeometry geometry;
};

/// Parses and checks the header at the start of `size` bytes; `name` is used
/// in messages only. A 4-D header whose one non-spatial axis has size 1 gives
/// the 3-D volume of the other three axes (droppedAxis). On return dimension,
/// type, sizes and encoding are set,
/// bigEndian is set for multi-byte samples of an encoding with a byte order
/// (encodingHasByteOrder), and dataOffset is where attached
/// data starts. @throw InputError(name, problem) for any header problem.
NrrdHeader parseNrrdHeader(const std::string& name, const std::uint8_t* bytes, std::size_t size);

}  // namespace skelseg::nrrd
