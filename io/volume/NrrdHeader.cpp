#include "io/volume/NrrdHeader.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <set>

#include "io/files/CompressedContent.h"
#include "io/files/ForeignContent.h"
#include "io/files/TextFile.h"
#include "io/files/TextTokenizer.h"
#include "kernels/base/Error.h"

namespace skelseg::nrrd {

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

const char* encodingName(Encoding encoding) {
    switch (encoding) {
        case Encoding::Raw:
            return "raw";
        case Encoding::Ascii:
            return "ascii";
        case Encoding::Hex:
            return "hex";
        case Encoding::Gzip:
            return "gzip";
        case Encoding::Bzip2:
            return "bzip2";
    }
    return "?";
}

bool encodingHasByteOrder(Encoding encoding) {
    return encoding != Encoding::Ascii;
}

namespace {

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

/// Parses the header of an in-memory NRRD and checks every field it needs.
class HeaderParser {
public:
    HeaderParser(const std::string& name, const std::uint8_t* bytes, std::size_t size)
        : mName(name),
          mBytes(reinterpret_cast<const char*>(bytes), size),
          mSize(size),
          mLines(reinterpret_cast<const char*>(bytes), size) {}

    NrrdHeader parse() {
        if (mSize == 0) fail("file is empty");
        // A gzipped .nrrd is no NRRD with gzip encoding: say so, not "wrong magic".
        refuseCompressedContent(mName, mBytes);
        // A detached header is written by hand, and Windows editors save it
        // with a UTF-8 byte order mark: skipped, as the mesh readers skip it
        // (teem refuses such a header with "wrong magic").
        std::string magic = nextLine();
        magic.erase(0, utf8BomLength(magic));
        parseMagic(magic);
        while (mLines.bytesLeft() > 0) {
            const std::string line = nextLine();
            if (line.empty()) {
                mHeader.endsWithBlankLine = true;
                break;
            }
            parseLine(line);
        }
        mHeader.dataOffset = mSize - mLines.bytesLeft();
        finish();
        return mHeader;
    }

private:
    [[noreturn]] void fail(const std::string& problem) const { throw InputError(mName, problem); }

    /// The next line without its "\n" or "\r\n"; the last line may lack one.
    std::string nextLine() {
        std::string_view view;
        mLines.nextLine(view, false);
        std::string line(view);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        return line;
    }

    void parseMagic(const std::string& line) {
        if (line.size() == 8 && line.compare(0, 7, "NRRD000") == 0) {
            if (line[7] >= '1' && line[7] <= '5') return;
            fail("unsupported NRRD version " + quote(line) + " (supported: NRRD0001 to NRRD0005)");
        }
        // A header saved as UTF-16 or with classic Mac OS line ends (one line
        // then holds the whole header): the text readers' message says how
        // to save it instead.
        const bool utf16 = mBytes.size() >= 2 &&
                           (mBytes.substr(0, 2) == "\xFF\xFE" || mBytes.substr(0, 2) == "\xFE\xFF");
        if (utf16 || (line.compare(0, 7, "NRRD000") == 0 && line.find('\r') != std::string::npos))
            textContentStart(mName, mBytes);
        refuseForeignContent(mName, mBytes, "NRRD");
        fail("not a NRRD file: wrong magic " + quote(line.substr(0, 16)) +
             ", expected NRRD0001 to NRRD0005");
    }

    void parseLine(const std::string& line) {
        if (line[0] == '#') return;  // comment
        const auto colon = line.find(':');
        if (colon == std::string::npos) fail("malformed header line " + quote(line) + " (no ':')");
        if (colon + 1 < line.size() && line[colon + 1] == '=') return;  // key:=value pair
        const std::string field = lowercase(trim(line.substr(0, colon)));
        const std::string value(trim(line.substr(colon + 1)));
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
            else if (encoding == "ascii" || encoding == "text" || encoding == "txt")
                mHeader.encoding = Encoding::Ascii;
            else if (encoding == "hex")
                mHeader.encoding = Encoding::Hex;
            else if (encoding == "gzip" || encoding == "gz")
                mHeader.encoding = Encoding::Gzip;
            else if (encoding == "bzip2" || encoding == "bz2")
                mHeader.encoding = Encoding::Bzip2;
            else
                fail("unsupported encoding " + quote(value) +
                     " (supported: raw, ascii, hex, gzip, bzip2)");
        } else if (field == "endian") {
            const std::string endian = lowercase(value);
            if (endian == "little")
                mHeader.bigEndian = false;
            else if (endian == "big")
                mHeader.bigEndian = true;
            else
                fail("unknown endian " + quote(value) + " (expected little or big)");
        } else if (field == "byte skip" || field == "byteskip") {
            mHeader.byteSkip = parseInteger(field, value);
            if (mHeader.byteSkip < -1)
                fail("byte skip " + quote(value) + " is invalid (it is -1 or at least 0)");
        } else if (field == "line skip" || field == "lineskip") {
            mHeader.lineSkip = parseInteger(field, value);
            if (mHeader.lineSkip < 0)
                fail("line skip " + quote(value) + " is invalid (it is at least 0)");
        } else if (field == "data file" || field == "datafile") {
            if (value.empty()) fail("'data file' field is empty");
            if (value.compare(0, 4, "LIST") == 0 || value.find('%') != std::string::npos)
                fail("data file " + quote(value) + ": multiple data files are not supported");
            // The system ends a file name at its first NUL byte: "d.raw\0x"
            // would read d.raw, a file the header does not name.
            if (value.find('\0') != std::string::npos)
                fail("data file " + quote(value) + ": the name holds a NUL byte");
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
        } else if (field == "kinds") {
            mKinds = splitWhitespace(value);
        } else if (field == "spacings") {
            std::vector<double> spacings;
            for (const auto& token : splitWhitespace(value))
                spacings.push_back(parseReal(field, token, true));
            mHeader.spacings = spacings;
        }
        // Every other field (centers, units, content, min, max,
        // thicknesses, labels, measurement frame, ...) does not change which
        // voxels are object or where they are, and is ignored.
    }

    /// A NRRD of three axes with a kind such as RGB-color, 3-vector or time
    /// is an image of two dimensions (or a series): its samples along that
    /// axis are components, not voxels, and were segmented as a slab of
    /// voxels without a word. Unknown kinds ("???", "none") are taken as
    /// spatial, as a header without kinds is.
    void checkKinds(const std::vector<std::string>& kinds) const {
        if (kinds.size() != 3)
            fail("kinds lists " + std::to_string(kinds.size()) + " values for a dimension of 3");
        for (std::size_t axis = 0; axis < 3; ++axis) {
            std::string kind = kinds[axis];
            if (kind.size() >= 2 && kind.front() == '"' && kind.back() == '"')
                kind = kind.substr(1, kind.size() - 2);
            std::transform(kind.begin(), kind.end(), kind.begin(),
                           [](unsigned char c) { return char(std::tolower(c)); });
            if (kind != "domain" && kind != "space" && kind != "???" && kind != "none")
                fail("axis " + std::to_string(axis) + " is of kind " + quote(kinds[axis]) +
                     ", not a spatial axis; only 3-D volumes can be segmented");
        }
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
        const std::string body(trim(text));
        if (body.size() < 2 || body.front() != '(' || body.back() != ')')
            fail(what + ": " + quote(text) + " is not a vector like (1,0,0)");
        std::vector<std::string> parts;
        std::string inner = body.substr(1, body.size() - 2);
        std::size_t start = 0;
        for (;;) {
            const auto comma = inner.find(',', start);
            parts.emplace_back(
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
            if (isSpace(text[i])) {
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
        if (sampleBytes(*mHeader.type) > 1 && encodingHasByteOrder(*mHeader.encoding) &&
            !mHeader.bigEndian)
            fail(std::string("missing field 'endian' (required for type ") +
                 sampleTypeName(*mHeader.type) + ")");
        if (!mHeader.dataFile && !mHeader.endsWithBlankLine)
            fail(
                "header does not end with a blank line before the data, and has no 'data file' "
                "field");

        if (mKinds) checkKinds(*mKinds);

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
        const std::string problem = geometry.problemOver(mHeader.dims);
        if (!problem.empty()) fail(problem);
    }

    const std::string& mName;
    std::string_view mBytes;
    std::size_t mSize;
    TextTokenizer mLines;
    std::set<std::string> mSeenFields;
    std::optional<std::vector<std::string>> mKinds;
    NrrdHeader mHeader;
};

}  // namespace

NrrdHeader parseNrrdHeader(const std::string& name, const std::uint8_t* bytes, std::size_t size) {
    return HeaderParser(name, bytes, size).parse();
}

}  // namespace skelseg::nrrd
