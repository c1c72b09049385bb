#include "io/volume/NrrdIO.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <set>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "io/files/OutputDirectory.h"
#include "io/volume/VolumeReader.h"
#include "kernels/base/Error.h"

namespace fs = std::filesystem;

namespace skelseg {

namespace {

// ---------------------------------------------------------------------------
// Sample types and header fields
// ---------------------------------------------------------------------------

enum class SampleType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float, Double };
enum class Encoding { Raw, Gzip };

std::size_t sampleBytes(SampleType type) {
    switch (type) {
        case SampleType::Int8:
        case SampleType::UInt8:
            return 1;
        case SampleType::Int16:
        case SampleType::UInt16:
            return 2;
        case SampleType::Int32:
        case SampleType::UInt32:
        case SampleType::Float:
            return 4;
        case SampleType::Int64:
        case SampleType::UInt64:
        case SampleType::Double:
            return 8;
    }
    return 1;
}

const char* sampleTypeName(SampleType type) {
    switch (type) {
        case SampleType::Int8:
            return "int8";
        case SampleType::UInt8:
            return "uint8";
        case SampleType::Int16:
            return "int16";
        case SampleType::UInt16:
            return "uint16";
        case SampleType::Int32:
            return "int32";
        case SampleType::UInt32:
            return "uint32";
        case SampleType::Int64:
            return "int64";
        case SampleType::UInt64:
            return "uint64";
        case SampleType::Float:
            return "float";
        case SampleType::Double:
            return "double";
    }
    return "?";
}

std::string lowercase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return text;
}

std::string trim(const std::string& text) {
    const char* space = " \t\r\n\v\f";
    const auto first = text.find_first_not_of(space);
    if (first == std::string::npos) return {};
    const auto last = text.find_last_not_of(space);
    return text.substr(first, last - first + 1);
}

std::vector<std::string> splitWhitespace(const std::string& text) {
    std::vector<std::string> tokens;
    std::size_t i = 0;
    while (i < text.size()) {
        while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
        std::size_t start = i;
        while (i < text.size() && !std::isspace(static_cast<unsigned char>(text[i]))) ++i;
        if (i > start) tokens.push_back(text.substr(start, i - start));
    }
    return tokens;
}

/// A header fragment safe to quote in a one-line message: printable ASCII
/// only, shortened.
std::string quote(const std::string& text) {
    std::string shown;
    for (char c : text) {
        if (shown.size() >= 40) {
            shown += "...";
            break;
        }
        shown += (c >= 0x20 && c < 0x7f) ? c : '?';
    }
    return "'" + shown + "'";
}

/// All spellings teem's nrrdType enum accepts, with internal whitespace
/// collapsed to one space.
std::optional<SampleType> parseSampleType(const std::string& text) {
    const std::string name = lowercase([&] {
        std::string joined;
        for (const auto& token : splitWhitespace(text))
            joined += (joined.empty() ? "" : " ") + token;
        return joined;
    }());
    static const std::pair<const char*, SampleType> kNames[] = {
        {"signed char", SampleType::Int8},
        {"int8", SampleType::Int8},
        {"int8_t", SampleType::Int8},
        {"uchar", SampleType::UInt8},
        {"unsigned char", SampleType::UInt8},
        {"uint8", SampleType::UInt8},
        {"uint8_t", SampleType::UInt8},
        {"short", SampleType::Int16},
        {"short int", SampleType::Int16},
        {"signed short", SampleType::Int16},
        {"signed short int", SampleType::Int16},
        {"int16", SampleType::Int16},
        {"int16_t", SampleType::Int16},
        {"ushort", SampleType::UInt16},
        {"unsigned short", SampleType::UInt16},
        {"unsigned short int", SampleType::UInt16},
        {"uint16", SampleType::UInt16},
        {"uint16_t", SampleType::UInt16},
        {"int", SampleType::Int32},
        {"signed int", SampleType::Int32},
        {"int32", SampleType::Int32},
        {"int32_t", SampleType::Int32},
        {"uint", SampleType::UInt32},
        {"unsigned int", SampleType::UInt32},
        {"uint32", SampleType::UInt32},
        {"uint32_t", SampleType::UInt32},
        {"longlong", SampleType::Int64},
        {"long long", SampleType::Int64},
        {"long long int", SampleType::Int64},
        {"signed long long", SampleType::Int64},
        {"signed long long int", SampleType::Int64},
        {"int64", SampleType::Int64},
        {"int64_t", SampleType::Int64},
        {"ulonglong", SampleType::UInt64},
        {"unsigned long long", SampleType::UInt64},
        {"unsigned long long int", SampleType::UInt64},
        {"uint64", SampleType::UInt64},
        {"uint64_t", SampleType::UInt64},
        {"float", SampleType::Float},
        {"double", SampleType::Double},
    };
    for (const auto& [spelling, type] : kNames)
        if (name == spelling) return type;
    return std::nullopt;
}

/// Dimension of the NRRD "space" names (teem's nrrdSpace enum), or 0 if unknown.
int spaceDimension(const std::string& space) {
    static const std::pair<const char*, int> kSpaces[] = {
        {"right-anterior-superior", 3},
        {"ras", 3},
        {"left-anterior-superior", 3},
        {"las", 3},
        {"left-posterior-superior", 3},
        {"lps", 3},
        {"right-anterior-superior-time", 4},
        {"rast", 4},
        {"left-anterior-superior-time", 4},
        {"last", 4},
        {"left-posterior-superior-time", 4},
        {"lpst", 4},
        {"scanner-xyz", 3},
        {"scanner-xyz-time", 4},
        {"3d-right-handed", 3},
        {"3d-left-handed", 3},
        {"3d-right-handed-time", 4},
        {"3d-left-handed-time", 4},
    };
    const std::string name = lowercase(space);
    for (const auto& [spelling, dimension] : kSpaces)
        if (name == spelling) return dimension;
    return 0;
}

// ---------------------------------------------------------------------------
// Header parsing
// ---------------------------------------------------------------------------

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
    Dims dims;
    VolumeGeometry geometry;
};

/// Parses the header of an in-memory NRRD and checks every field it needs.
class HeaderParser {
public:
    HeaderParser(const std::string& name, const std::uint8_t* bytes, std::size_t size)
        : mName(name), mText(reinterpret_cast<const char*>(bytes)), mSize(size) {}

    NrrdHeader parse() {
        if (mSize == 0) fail("file is empty");
        parseMagic(nextLine());
        while (mPosition < mSize) {
            const std::string line = nextLine();
            if (line.empty()) {
                mHeader.endsWithBlankLine = true;
                break;
            }
            parseLine(line);
        }
        mHeader.dataOffset = mPosition;
        finish();
        return mHeader;
    }

private:
    [[noreturn]] void fail(const std::string& problem) const { throw InputError(mName, problem); }

    /// The next line without its "\n" or "\r\n"; the last line may lack one.
    std::string nextLine() {
        const char* begin = mText + mPosition;
        const void* newline = std::memchr(begin, '\n', mSize - mPosition);
        const std::size_t length =
            newline ? std::size_t(static_cast<const char*>(newline) - begin) : mSize - mPosition;
        mPosition += length + (newline ? 1 : 0);
        std::string line(begin, length);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        return line;
    }

    void parseMagic(const std::string& line) {
        if (line.size() == 8 && line.compare(0, 7, "NRRD000") == 0) {
            if (line[7] >= '1' && line[7] <= '5') return;
            fail("unsupported NRRD version " + quote(line) + " (supported: NRRD0001 to NRRD0005)");
        }
        fail("not a NRRD file: wrong magic " + quote(line.substr(0, 16)) +
             ", expected NRRD0001 to NRRD0005");
    }

    void parseLine(const std::string& line) {
        if (line[0] == '#') return;  // comment
        const auto colon = line.find(':');
        if (colon == std::string::npos) fail("malformed header line " + quote(line) + " (no ':')");
        if (colon + 1 < line.size() && line[colon + 1] == '=') return;  // key:=value pair
        const std::string field = lowercase(trim(line.substr(0, colon)));
        const std::string value = trim(line.substr(colon + 1));
        if (!mSeenFields.insert(field).second)
            fail("field " + quote(field) + " appears twice in the header");
        parseField(field, value);
    }

    void parseField(const std::string& field, const std::string& value) {
        if (field == "dimension") {
            // Clamped only so that the int holds it; anything but 3 is rejected later.
            mHeader.dimension =
                int(std::clamp<std::int64_t>(parseInteger(field, value), -1000, 1000));
        } else if (field == "type") {
            mHeader.type = parseSampleType(value);
            if (!mHeader.type)
                fail("unsupported type " + quote(value) +
                     " (supported: int8, uint8, int16, uint16, int32, uint32, int64, uint64, "
                     "float, double)");
        } else if (field == "sizes") {
            std::vector<std::int64_t> sizes;
            for (const auto& token : splitWhitespace(value))
                sizes.push_back(parseInteger("size", token));
            mHeader.sizes = sizes;
        } else if (field == "encoding") {
            const std::string encoding = lowercase(value);
            if (encoding == "raw")
                mHeader.encoding = Encoding::Raw;
            else if (encoding == "gzip" || encoding == "gz")
                mHeader.encoding = Encoding::Gzip;
            else
                fail("unsupported encoding " + quote(value) + " (supported: raw, gzip)");
        } else if (field == "endian") {
            const std::string endian = lowercase(value);
            if (endian == "little")
                mHeader.bigEndian = false;
            else if (endian == "big")
                mHeader.bigEndian = true;
            else
                fail("unknown endian " + quote(value) + " (expected little or big)");
        } else if (field == "byte skip" || field == "byteskip") {
            if (parseInteger(field, value) != 0)
                fail("byte skip " + quote(value) + " is not supported (only 0)");
        } else if (field == "line skip" || field == "lineskip") {
            if (parseInteger(field, value) != 0)
                fail("line skip " + quote(value) + " is not supported (only 0)");
        } else if (field == "data file" || field == "datafile") {
            if (value.empty()) fail("'data file' field is empty");
            if (value.compare(0, 4, "LIST") == 0 || value.find('%') != std::string::npos)
                fail("data file " + quote(value) + ": multiple data files are not supported");
            mHeader.dataFile = value;
        } else if (field == "space") {
            const int dimension = spaceDimension(value);
            if (dimension == 0) fail("unknown space " + quote(value));
            if (dimension != 3)
                fail("space " + quote(value) + " has " + std::to_string(dimension) +
                     " dimensions; only 3D spaces are supported");
            mHeader.space = value;
        } else if (field == "space dimension") {
            if (parseInteger(field, value) != 3)
                fail("space dimension " + quote(value) + " is not supported (only 3)");
        } else if (field == "space directions") {
            mHeader.spaceDirections = parseDirections(value);
        } else if (field == "space origin") {
            mHeader.spaceOrigin = parseVector(field, value);
        } else if (field == "spacings") {
            std::vector<double> spacings;
            for (const auto& token : splitWhitespace(value))
                spacings.push_back(parseReal(field, token, true));
            mHeader.spacings = spacings;
        }
        // Every other field (kinds, centers, units, content, min, max,
        // thicknesses, labels, measurement frame, ...) does not change which
        // voxels are object or where they are, and is ignored.
    }

    std::int64_t parseInteger(const std::string& what, const std::string& text) const {
        const char* first = text.data();
        const char* last = text.data() + text.size();
        if (first != last && *first == '+') ++first;
        std::int64_t value = 0;
        const auto [end, error] = std::from_chars(first, last, value);
        if (error == std::errc::result_out_of_range)
            fail(what + " " + quote(text) + " is too large (overflows a 64-bit integer)");
        if (error != std::errc() || end != last || first == last)
            fail(what + " " + quote(text) + " is not an integer");
        return value;
    }

    double parseReal(const std::string& what, const std::string& text, bool allowNan) const {
        const char* first = text.data();
        const char* last = text.data() + text.size();
        if (first != last && *first == '+') ++first;
        double value = 0.0;
        const auto [end, error] = std::from_chars(first, last, value);
        if (error != std::errc() || end != last || first == last)
            fail(what + ": " + quote(text) + " is not a number");
        if (std::isinf(value) || (std::isnan(value) && !allowNan))
            fail(what + ": " + quote(text) + " is not a finite number");
        return value;
    }

    /// "(a,b,c)" with optional spaces inside.
    std::array<double, 3> parseVector(const std::string& what, const std::string& text) const {
        const std::string body = trim(text);
        if (body.size() < 2 || body.front() != '(' || body.back() != ')')
            fail(what + ": " + quote(text) + " is not a vector like (1,0,0)");
        std::vector<std::string> parts;
        std::string inner = body.substr(1, body.size() - 2);
        std::size_t start = 0;
        for (;;) {
            const auto comma = inner.find(',', start);
            parts.push_back(
                trim(inner.substr(start, comma == std::string::npos ? comma : comma - start)));
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        if (parts.size() != 3)
            fail(what + ": vector " + quote(text) + " has " + std::to_string(parts.size()) +
                 " components; only 3D spaces are supported");
        return {parseReal(what, parts[0], false), parseReal(what, parts[1], false),
                parseReal(what, parts[2], false)};
    }

    std::vector<std::array<double, 3>> parseDirections(const std::string& text) const {
        std::vector<std::array<double, 3>> directions;
        std::size_t i = 0;
        while (i < text.size()) {
            if (std::isspace(static_cast<unsigned char>(text[i]))) {
                ++i;
                continue;
            }
            if (text[i] == '(') {
                const auto close = text.find(')', i);
                if (close == std::string::npos)
                    fail("space directions: unclosed '(' in " + quote(text));
                directions.push_back(
                    parseVector("space directions", text.substr(i, close - i + 1)));
                i = close + 1;
            } else if (text.compare(i, 4, "none") == 0) {
                fail("space directions: an axis is 'none'; all 3 axes must be spatial");
            } else {
                fail("space directions: " + quote(text.substr(i)) +
                     " is not a vector like (1,0,0)");
            }
        }
        return directions;
    }

    void finish() {
        if (!mHeader.dimension) fail("missing required field 'dimension'");
        if (*mHeader.dimension != 3)
            fail("dimension " + std::to_string(*mHeader.dimension) +
                 " is not supported (only 3D volumes)");
        if (!mHeader.type) fail("missing required field 'type'");
        if (!mHeader.sizes) fail("missing required field 'sizes'");
        if (!mHeader.encoding) fail("missing required field 'encoding'");
        const auto& sizes = *mHeader.sizes;
        if (sizes.size() != 3)
            fail("sizes lists " + std::to_string(sizes.size()) + " values for a dimension of 3");
        mHeader.dims = Dims::checked(sizes[0], sizes[1], sizes[2], mName);
        if (sampleBytes(*mHeader.type) > 1 && !mHeader.bigEndian)
            fail(std::string("missing field 'endian' (required for type ") +
                 sampleTypeName(*mHeader.type) + ")");
        if (!mHeader.dataFile && !mHeader.endsWithBlankLine)
            fail(
                "header does not end with a blank line before the data, and has no 'data file' "
                "field");

        VolumeGeometry& geometry = mHeader.geometry;
        if (mHeader.spaceDirections) {
            if (mHeader.spaceDirections->size() != 3)
                fail("space directions lists " + std::to_string(mHeader.spaceDirections->size()) +
                     " vectors for a dimension of 3");
            for (int axis = 0; axis < 3; ++axis)
                geometry.directions[axis] = (*mHeader.spaceDirections)[axis];
        } else if (mHeader.spacings) {
            if (mHeader.spacings->size() != 3)
                fail("spacings lists " + std::to_string(mHeader.spacings->size()) +
                     " values for a dimension of 3");
            for (int axis = 0; axis < 3; ++axis) {
                const double spacing = (*mHeader.spacings)[axis];
                // NaN marks a non-spatial axis in NRRD; treat it as unit spacing.
                geometry.directions[axis] = {0.0, 0.0, 0.0};
                geometry.directions[axis][axis] = std::isnan(spacing) ? 1.0 : spacing;
            }
        }
        if (mHeader.spaceOrigin) geometry.origin = *mHeader.spaceOrigin;
        if (mHeader.space) geometry.spaceName = *mHeader.space;
    }

    const std::string& mName;
    const char* mText;
    std::size_t mSize;
    std::size_t mPosition = 0;
    std::set<std::string> mSeenFields;
    NrrdHeader mHeader;
};

// ---------------------------------------------------------------------------
// Sample decoding
// ---------------------------------------------------------------------------

constexpr bool hostIsBigEndian() {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
    return true;
#else
    return false;
#endif
}

template <typename Sample>
Sample loadSample(const std::uint8_t* bytes, bool swapBytes) {
    std::uint8_t buffer[sizeof(Sample)];
    std::memcpy(buffer, bytes, sizeof(Sample));
    if (swapBytes) std::reverse(buffer, buffer + sizeof(Sample));
    Sample sample;
    std::memcpy(&sample, buffer, sizeof(Sample));
    return sample;
}

/// Receives the sample bytes in any chunking (gzip output arrives in pieces
/// that need not end on a sample boundary) and converts them into the
/// volume, in file order.
template <typename T>
class SampleSink {
public:
    SampleSink(Volume<T>& volume, SampleType type, bool swapBytes, bool keepValues)
        : mOutput(volume.data()),
          mCapacity(volume.size()),
          mType(type),
          mSampleBytes(sampleBytes(type)),
          mSwap(swapBytes),
          mKeepValues(keepValues) {}

    void append(const std::uint8_t* bytes, std::size_t count) {
        if (mPartialCount > 0) {
            // The sizeof bound is implied by mSampleBytes <= 8; spelled out for the compiler.
            const std::size_t take =
                std::min({count, mSampleBytes - mPartialCount, sizeof(mPartial) - mPartialCount});
            std::memcpy(mPartial + mPartialCount, bytes, take);
            mPartialCount += take;
            bytes += take;
            count -= take;
            if (mPartialCount < mSampleBytes) return;
            convert(mPartial, 1);
            mPartialCount = 0;
        }
        const std::size_t whole = count / mSampleBytes;
        convert(bytes, whole);
        bytes += whole * mSampleBytes;
        count -= whole * mSampleBytes;
        mPartialCount = std::min(count, sizeof(mPartial));
        std::memcpy(mPartial, bytes, mPartialCount);
    }

private:
    void convert(const std::uint8_t* bytes, std::size_t count) {
        if (count > mCapacity - mWritten) throw std::logic_error("NRRD sample sink overflow");
        switch (mType) {
            case SampleType::Int8:
                convertAs<std::int8_t>(bytes, count);
                break;
            case SampleType::UInt8:
                convertAs<std::uint8_t>(bytes, count);
                break;
            case SampleType::Int16:
                convertAs<std::int16_t>(bytes, count);
                break;
            case SampleType::UInt16:
                convertAs<std::uint16_t>(bytes, count);
                break;
            case SampleType::Int32:
                convertAs<std::int32_t>(bytes, count);
                break;
            case SampleType::UInt32:
                convertAs<std::uint32_t>(bytes, count);
                break;
            case SampleType::Int64:
                convertAs<std::int64_t>(bytes, count);
                break;
            case SampleType::UInt64:
                convertAs<std::uint64_t>(bytes, count);
                break;
            case SampleType::Float:
                convertAs<float>(bytes, count);
                break;
            case SampleType::Double:
                convertAs<double>(bytes, count);
                break;
        }
        mWritten += count;
    }

    template <typename Sample>
    void convertAs(const std::uint8_t* bytes, std::size_t count) {
        T* out = mOutput + mWritten;
        if (mKeepValues) {
            for (std::size_t i = 0; i < count; ++i)
                out[i] = T(loadSample<Sample>(bytes + i * sizeof(Sample), mSwap));
        } else {
            // NaN compares unequal to zero, so a NaN sample counts as object.
            for (std::size_t i = 0; i < count; ++i)
                out[i] = loadSample<Sample>(bytes + i * sizeof(Sample), mSwap) != Sample(0) ? T(1)
                                                                                            : T(0);
        }
    }

    T* mOutput;
    std::size_t mCapacity;
    std::size_t mWritten = 0;
    SampleType mType;
    std::size_t mSampleBytes;
    bool mSwap;
    bool mKeepValues;
    std::uint8_t mPartial[8] = {};
    std::size_t mPartialCount = 0;
};

/// Deflate cannot expand more than 1032:1, so a stream of N bytes never
/// inflates to more than about 1032*N. Used to reject a header that claims
/// more data than the file can hold before allocating the volume.
constexpr std::uint64_t kMaxDeflateRatio = 1032;

template <typename T>
void inflateSamples(const std::string& name, const std::uint8_t* data, std::size_t size,
                    std::uint64_t expectedBytes, SampleSink<T>& sink) {
    z_stream stream{};
    // 15 + 32: accept both gzip and zlib headers.
    if (inflateInit2(&stream, 15 + 32) != Z_OK) throw InputError(name, "cannot initialise zlib");
    struct StreamGuard {
        z_stream* stream;
        ~StreamGuard() { inflateEnd(stream); }
    } guard{&stream};

    std::vector<std::uint8_t> chunk(std::size_t(1) << 18);
    std::size_t consumed = 0;  // input bytes handed to zlib so far
    std::uint64_t produced = 0;
    const auto feed = [&] {
        if (stream.avail_in == 0 && consumed < size) {
            const std::size_t piece = std::min<std::size_t>(size - consumed, 1u << 30);
            stream.next_in = const_cast<Bytef*>(data + consumed);
            stream.avail_in = uInt(piece);
            consumed += piece;
        }
    };
    for (;;) {
        feed();
        // Never ask for more than one byte beyond the expected count: enough
        // to detect "too long" without inflating an unbounded stream.
        const std::uint64_t room = expectedBytes + 1 - produced;
        stream.next_out = chunk.data();
        stream.avail_out = uInt(std::min<std::uint64_t>(chunk.size(), room));
        const uInt inputBefore = stream.avail_in;
        const int status = inflate(&stream, Z_NO_FLUSH);
        const std::size_t got = std::size_t(stream.next_out - chunk.data());
        produced += got;
        if (produced > expectedBytes)
            throw InputError(name, "data is too long: gzip data decompresses to more than the " +
                                       std::to_string(expectedBytes) + " bytes the header says");
        sink.append(chunk.data(), got);

        if (status == Z_STREAM_END) {
            const std::size_t remaining = stream.avail_in + (size - consumed);
            if (remaining == 0) break;
            if (produced == expectedBytes)
                throw InputError(name, "data is too long: " + std::to_string(remaining) +
                                           " bytes after the end of the gzip stream");
            inflateReset(&stream);  // another gzip member follows
            continue;
        }
        if (status == Z_DATA_ERROR || status == Z_NEED_DICT || status == Z_STREAM_ERROR)
            throw InputError(name, std::string("corrupt gzip data: ") +
                                       (stream.msg ? stream.msg : "invalid stream"));
        if (status == Z_MEM_ERROR)
            throw InputError(name, "out of memory while decompressing gzip data");
        const bool noProgress = got == 0 && stream.avail_in == inputBefore;
        if (noProgress && stream.avail_in == 0 && consumed == size)
            throw InputError(name, "data is too short: gzip data is truncated after " +
                                       std::to_string(produced) + " bytes, header says " +
                                       std::to_string(expectedBytes));
        if (noProgress && stream.avail_in > 0)  // zlib is stuck: never loop forever on bad input
            throw InputError(name, "corrupt gzip data: decompression makes no progress");
    }
    if (produced < expectedBytes)
        throw InputError(name, "data is too short: gzip data decompresses to " +
                                   std::to_string(produced) + " bytes, header says " +
                                   std::to_string(expectedBytes));
}

template <typename T>
Volume<T> readNrrdVolume(const std::string& name, const std::uint8_t* bytes, std::size_t size,
                         const fs::path* headerDirectory, bool keepValues) {
    const NrrdHeader header = HeaderParser(name, bytes, size).parse();
    const SampleType type = *header.type;
    if (keepValues && type != SampleType::UInt8 && type != SampleType::UInt16)
        throw InputError(name,
                         std::string("labels must be uint8 or uint16 samples, file has type ") +
                             sampleTypeName(type));

    const std::uint8_t* data = bytes + header.dataOffset;
    std::size_t dataSize = size - header.dataOffset;
    std::string detachedBytes;
    if (header.dataFile) {
        if (!headerDirectory)
            throw InputError(name, "detached header (data file " + quote(*header.dataFile) +
                                       ") cannot be read from memory");
        fs::path dataPath(*header.dataFile);
        if (dataPath.is_relative()) dataPath = *headerDirectory / dataPath;
        try {
            detachedBytes = readFileBytes(dataPath);
        } catch (const InputError& error) {
            throw InputError(name, "data file " + quote(*header.dataFile) + ": " + error.problem());
        }
        data = reinterpret_cast<const std::uint8_t*>(detachedBytes.data());
        dataSize = detachedBytes.size();
    }

    const std::uint64_t expectedBytes = header.dims.voxelCount() * sampleBytes(type);
    const bool swapBytes = header.bigEndian.value_or(hostIsBigEndian()) != hostIsBigEndian();
    if (*header.encoding == Encoding::Raw) {
        if (dataSize < expectedBytes)
            throw InputError(name, "data is too short: " + std::to_string(dataSize) +
                                       " bytes, header says " + std::to_string(expectedBytes));
        if (dataSize > expectedBytes)
            throw InputError(name, "data is too long: " + std::to_string(dataSize) +
                                       " bytes, header says " + std::to_string(expectedBytes));
        Volume<T> volume(header.dims);
        SampleSink<T> sink(volume, type, swapBytes, keepValues);
        sink.append(data, dataSize);
        volume.geometry = header.geometry;
        return volume;
    }
    if (expectedBytes > std::uint64_t(dataSize) * kMaxDeflateRatio + 1024)
        throw InputError(name, "data is too short: " + std::to_string(dataSize) +
                                   " bytes of gzip data cannot hold the " +
                                   std::to_string(expectedBytes) + " bytes the header says");
    Volume<T> volume(header.dims);
    SampleSink<T> sink(volume, type, swapBytes, keepValues);
    inflateSamples(name, data, dataSize, expectedBytes, sink);
    volume.geometry = header.geometry;
    return volume;
}

template <typename T>
Volume<T> readNrrdVolumeFile(const fs::path& file, bool keepValues) {
    const std::string bytes = readFileBytes(file);
    const fs::path directory = file.has_parent_path() ? file.parent_path() : fs::path(".");
    return readNrrdVolume<T>(file.string(), reinterpret_cast<const std::uint8_t*>(bytes.data()),
                             bytes.size(), &directory, keepValues);
}

// ---------------------------------------------------------------------------
// Writing
// ---------------------------------------------------------------------------

std::string formatVector(const std::array<double, 3>& v) {
    // {} prints the shortest text that reads back as the same double.
    return fmt::format("({},{},{})", v[0], v[1], v[2]);
}

std::string headerText(const char* type, const Dims& dims, const VolumeGeometry& geometry,
                       bool multiByte) {
    std::string text = "NRRD0004\n";
    text += "# Complete NRRD file format specification at:\n";
    text += "# http://teem.sourceforge.net/nrrd/format.html\n";
    text += std::string("type: ") + type + "\n";
    text += "dimension: 3\n";
    text += geometry.spaceName.empty() ? std::string("space dimension: 3\n")
                                       : "space: " + geometry.spaceName + "\n";
    text += fmt::format("sizes: {} {} {}\n", dims.x, dims.y, dims.z);
    text += "space directions: " + formatVector(geometry.directions[0]) + " " +
            formatVector(geometry.directions[1]) + " " + formatVector(geometry.directions[2]) +
            "\n";
    text += "kinds: domain domain domain\n";
    if (multiByte) text += "endian: little\n";
    text += "encoding: gzip\n";
    text += "space origin: " + formatVector(geometry.origin) + "\n";
    text += "\n";
    return text;
}

/// Appends the gzip stream of `bytes` to `out`. Level 1: labels and masks
/// are long runs, which fast deflate already shrinks well, and output time
/// counts against the run's time budget.
void appendGzip(const std::string& file, const std::uint8_t* bytes, std::size_t size,
                std::string& out) {
    z_stream stream{};
    if (deflateInit2(&stream, 1, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
        throw OutputError(file + ": cannot initialise zlib");
    std::vector<std::uint8_t> chunk(std::size_t(1) << 18);
    std::size_t consumed = 0;
    int status = Z_OK;
    do {
        if (stream.avail_in == 0 && consumed < size) {
            const std::size_t piece = std::min<std::size_t>(size - consumed, 1u << 30);
            stream.next_in = const_cast<Bytef*>(bytes + consumed);
            stream.avail_in = uInt(piece);
            consumed += piece;
        }
        const int flush = (consumed == size && stream.avail_in == 0) ? Z_FINISH : Z_NO_FLUSH;
        stream.next_out = chunk.data();
        stream.avail_out = uInt(chunk.size());
        status = deflate(&stream, flush);
        if (status == Z_STREAM_ERROR) {
            deflateEnd(&stream);
            throw OutputError(file + ": gzip compression failed");
        }
        out.append(reinterpret_cast<const char*>(chunk.data()), chunk.size() - stream.avail_out);
    } while (status != Z_STREAM_END);
    deflateEnd(&stream);
}

}  // namespace

MaskVolume readNrrdMask(const fs::path& file) {
    return readNrrdVolumeFile<std::uint8_t>(file, false);
}

MaskVolume readNrrdMaskFromMemory(const std::string& name, const std::uint8_t* bytes,
                                  std::size_t size) {
    return readNrrdVolume<std::uint8_t>(name, bytes, size, nullptr, false);
}

LabelVolume readNrrdLabels(const fs::path& file) {
    return readNrrdVolumeFile<std::uint16_t>(file, true);
}

LabelVolume readNrrdLabelsFromMemory(const std::string& name, const std::uint8_t* bytes,
                                     std::size_t size) {
    return readNrrdVolume<std::uint16_t>(name, bytes, size, nullptr, true);
}

void writeNrrdLabels(const fs::path& file, const LabelVolume& labels) {
    std::string out = headerText("uint16", labels.dims(), labels.geometry, true);
    if (hostIsBigEndian()) {
        std::vector<std::uint16_t> swapped(labels.values());
        for (auto& value : swapped) value = std::uint16_t((value >> 8) | (value << 8));
        appendGzip(file.string(), reinterpret_cast<const std::uint8_t*>(swapped.data()),
                   swapped.size() * 2, out);
    } else {
        appendGzip(file.string(), reinterpret_cast<const std::uint8_t*>(labels.data()),
                   labels.size() * 2, out);
    }
    writeFileAtomically(file, out);
}

void writeNrrdMask(const fs::path& file, const MaskVolume& mask) {
    std::string out = headerText("uint8", mask.dims(), mask.geometry, false);
    appendGzip(file.string(), mask.data(), mask.size(), out);
    writeFileAtomically(file, out);
}

}  // namespace skelseg
