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
#include "io/volume/NrrdIO.h"
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

/// A word of a per-axis field ("kinds", "centers") without its quotes, in
/// lower case.
std::string unquotedLowercase(std::string word) {
    if (word.size() >= 2 && word.front() == '"' && word.back() == '"')
        word = word.substr(1, word.size() - 2);
    return lowercase(word);
}

/// "domain" and "space" say an axis is spatial; "???" and "none" say
/// nothing, and are taken as spatial, as a header without kinds is.
bool isSpatialKind(const std::string& kind) {
    const std::string name = unquotedLowercase(kind);
    return name == "domain" || name == "space";
}

bool isUnknownKind(const std::string& kind) {
    const std::string name = unquotedLowercase(kind);
    return name == "???" || name == "none";
}

/// "0", "0 and 3", "0, 1 and 3".
std::string axisList(const std::vector<int>& axes) {
    std::string text;
    for (std::size_t i = 0; i < axes.size(); ++i)
        text += (i == 0 ? "" : i + 1 == axes.size() ? " and " : ", ") + std::to_string(axes[i]);
    return text;
}

/// The most data files a list or a pattern may name: every one is opened,
/// and a pattern's names are made before the first is read.
constexpr std::uint64_t kMaxDataFiles = std::uint64_t(1) << 20;

/// A data file name pattern ("slice%03d.raw"): the text around its one
/// integer conversion. The header's text never reaches printf: format()
/// writes the number itself, as printf would.
struct NamePattern {
    std::string prefix;
    std::string suffix;
    std::string flags;  // of "-+ #0"
    int width = 0;
    int precision = -1;  // -1: none given
    char conversion = 'd';

    bool hasFlag(char flag) const { return flags.find(flag) != std::string::npos; }

    bool isSigned() const { return conversion == 'd' || conversion == 'i'; }

    std::string format(std::int64_t index) const {
        const bool negative = index < 0;
        const std::uint64_t magnitude =
            negative ? std::uint64_t(0) - std::uint64_t(index) : std::uint64_t(index);
        const int base = conversion == 'o' ? 8 : conversion == 'x' || conversion == 'X' ? 16 : 10;
        char buffer[32];
        const auto result = std::to_chars(buffer, buffer + sizeof(buffer), magnitude, base);
        std::string digits(buffer, result.ptr);
        if (conversion == 'X')
            std::transform(digits.begin(), digits.end(), digits.begin(),
                           [](unsigned char c) { return char(std::toupper(c)); });
        if (precision == 0 && magnitude == 0) digits.clear();
        if (precision > int(digits.size()))
            digits.insert(0, std::size_t(precision) - digits.size(), '0');
        std::string lead = negative                     ? "-"
                           : isSigned() && hasFlag('+') ? "+"
                           : isSigned() && hasFlag(' ') ? " "
                                                        : "";
        if (hasFlag('#') && conversion == 'o' && (digits.empty() || digits[0] != '0'))
            digits.insert(0, "0");
        if (hasFlag('#') && (conversion == 'x' || conversion == 'X') && magnitude != 0)
            lead += conversion == 'x' ? "0x" : "0X";
        std::string body = lead + digits;
        if (std::size_t(width) > body.size()) {
            const std::size_t pad = std::size_t(width) - body.size();
            if (hasFlag('-'))
                body.append(pad, ' ');
            else if (hasFlag('0') && precision < 0)
                body.insert(lead.size(), pad, '0');
            else
                body.insert(0, pad, ' ');
        }
        return prefix + body + suffix;
    }
};

/// Parses `text` into `pattern`: "%%" is a '%', and there must be exactly one
/// conversion, of an integer (d, i, u, o, x or X, with flags, a width and a
/// precision of up to 3 digits each). Returns the problem, or "".
std::string parseNamePattern(const std::string& text, NamePattern& pattern) {
    int conversions = 0;
    std::string* literal = &pattern.prefix;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] != '%') {
            *literal += text[i];
            continue;
        }
        if (i + 1 < text.size() && text[i + 1] == '%') {
            *literal += '%';
            ++i;
            continue;
        }
        const std::size_t start = i++;
        std::string flags;
        while (i < text.size() && std::string_view("-+ #0").find(text[i]) != std::string_view::npos)
            flags += text[i++];
        const auto number = [&](int& value) {
            int digits = 0;
            value = 0;
            for (; i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i)
                if (++digits <= 3) value = value * 10 + (text[i] - '0');
            return digits <= 3;
        };
        int width = 0;
        int precision = -1;
        bool small = number(width);
        if (small && i < text.size() && text[i] == '.') {
            ++i;
            small = number(precision);
        }
        const std::string spec = text.substr(start, std::min(text.size(), i + 1) - start);
        if (!small) return "has a width or precision of more than 3 digits in " + quote(spec);
        if (i >= text.size() || std::string_view("diuoxX").find(text[i]) == std::string_view::npos)
            return "has " + quote(spec) +
                   ", which is not an integer conversion (such as %d or %03d)";
        ++conversions;
        pattern.flags = flags;
        pattern.width = width;
        pattern.precision = precision;
        pattern.conversion = text[i];
        literal = &pattern.suffix;
    }
    if (conversions != 1)
        return "has " + std::to_string(conversions) +
               " conversions; it must have exactly one integer conversion (such as %03d)";
    return {};
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
            if (mListing)
                addListedFile(line);
            else
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
            // Clamped only so that the int holds it; anything but 3 and 4 is rejected later.
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
            // The system ends a file name at its first NUL byte: "d.raw\0x"
            // would read d.raw, a file the header does not name.
            if (value.find('\0') != std::string::npos)
                fail("data file " + quote(value) + ": the name holds a NUL byte");
            mHeader.dataFileField = value;
            parseDataFile(value);
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
            mHeader.spacings = parseReals(field, value);
        } else if (field == "axis mins" || field == "axismins") {
            mHeader.axisMins = parseReals(field, value);
        } else if (field == "axis maxs" || field == "axismaxs") {
            mHeader.axisMaxs = parseReals(field, value);
        } else if (field == "centers" || field == "centerings") {
            mHeader.centers = splitWhitespace(value);
        }
        // Every other field (units, content, min, max, thicknesses, labels,
        // measurement frame, ...) does not change which voxels are object or
        // where they are, and is ignored.
    }

    /// A NRRD of three axes with a kind such as RGB-color, 3-vector or time
    /// is an image of two dimensions (or a series): its samples along that
    /// axis are components, not voxels, and were segmented as a slab of
    /// voxels without a word. Unknown kinds ("???", "none") are taken as
    /// spatial, as a header without kinds is. `axes`: the volume's axes.
    void checkKinds(const std::vector<std::string>& kinds, const std::array<int, 3>& axes) const {
        if (kinds.size() != std::size_t(*mHeader.dimension))
            fail("kinds lists " + std::to_string(kinds.size()) + " values for a dimension of " +
                 std::to_string(*mHeader.dimension));
        for (const int axis : axes) {
            const std::string& kind = kinds[std::size_t(axis)];
            if (!isSpatialKind(kind) && !isUnknownKind(kind))
                fail("axis " + std::to_string(axis) + " is of kind " + quote(kind) +
                     ", not a spatial axis; only 3-D volumes can be segmented");
        }
    }

    /// The axis of a 4-D header that is no axis of the volume: the one
    /// "kinds" gives a kind that is not spatial ("scalar", "vector", "list",
    /// "time", ...), else the one whose space direction is "none", else the
    /// one of size 1 (among those "kinds" does not call spatial). It must
    /// have size 1: more samples along it are a series, or the components of
    /// a colour or vector volume, several volumes of which the user picks.
    int nonSpatialAxis() const {
        const auto& sizes = *mHeader.sizes;
        if (mKinds && mKinds->size() != 4)
            fail("kinds lists " + std::to_string(mKinds->size()) + " values for a dimension of 4");
        const auto& directions = mHeader.spaceDirections;
        if (directions && directions->size() != 4)
            fail("space directions lists " + std::to_string(directions->size()) +
                 " vectors for a dimension of 4");
        std::vector<int> byKind, byDirection, ofSizeOne;
        for (int axis = 0; axis < 4; ++axis) {
            const std::string* kind = mKinds ? &(*mKinds)[std::size_t(axis)] : nullptr;
            if (kind && !isSpatialKind(*kind) && !isUnknownKind(*kind)) byKind.push_back(axis);
            if (directions && !(*directions)[std::size_t(axis)]) byDirection.push_back(axis);
            if (sizes[std::size_t(axis)] == 1 && !(kind && isSpatialKind(*kind)))
                ofSizeOne.push_back(axis);
        }
        const std::string several =
            "several 3-D volumes (a time series, or the components of a colour or vector "
            "volume), not one";
        int axis = -1;
        if (byKind.size() > 1)
            fail("axes " + axisList(byKind) +
                 " are of kinds that are not spatial; only 3-D volumes can be segmented");
        if (byKind.size() == 1) {
            axis = byKind[0];
        } else if (byDirection.size() > 1) {
            fail("space directions: axes " + axisList(byDirection) +
                 " are 'none'; only one axis of a 4-D volume may be (the one of size 1)");
        } else if (byDirection.size() == 1) {
            axis = byDirection[0];
        } else if (ofSizeOne.size() == 1) {
            axis = ofSizeOne[0];
        } else if (ofSizeOne.empty() && std::count(sizes.begin(), sizes.end(), 1) > 0) {
            fail(
                "kinds gives every axis of size 1 a spatial kind, and all 4 axes cannot be "
                "spatial; give the one that is not the kind 'scalar'");
        } else if (ofSizeOne.empty()) {
            std::string sizesText;
            for (const auto size : sizes)
                sizesText += (sizesText.empty() ? "" : " ") + std::to_string(size);
            fail("dimension 4 with no axis of size 1 (sizes " + sizesText + "): the file holds " +
                 several +
                 "; keep one with 'unu slice -a AXIS -p 0' (AXIS its axis that is not "
                 "spatial) and segment that");
        } else {
            fail("axes " + axisList(ofSizeOne) +
                 " have size 1, and neither 'kinds' nor 'space directions' says which is not "
                 "spatial; give it the kind 'scalar' in 'kinds' or the direction 'none'");
        }
        const std::int64_t size = sizes[std::size_t(axis)];
        if (size != 1)
            fail("axis " + std::to_string(axis) +
                 (mKinds ? " (kind " + quote((*mKinds)[std::size_t(axis)]) + ")" : std::string()) +
                 " has size " + std::to_string(size) + ": the file holds " + several +
                 "; keep one with 'unu slice -a " + std::to_string(axis) +
                 " -p 0' (or take one component) and segment that");
        return axis;
    }

    void parseDataFile(const std::string& value) {
        const std::vector<std::string> words = splitWhitespace(value);
        if (words[0] == "LIST") {
            if (words.size() > 2)
                fail("data file " + quote(value) +
                     ": LIST takes one number at most (the dimension of each file's data)");
            if (words.size() == 2)
                mDataFileDimension = parseInteger("data file LIST dimension", words[1]);
            // The names follow, one a line, to the end of the header.
            mListing = true;
            mHeader.severalDataFiles = true;
            return;
        }
        if (words[0].find('%') == std::string::npos) {
            mHeader.dataFiles = {value};
            return;
        }
        const std::string what = "data file pattern " + quote(value);
        if (words.size() < 4 || words.size() > 5)
            fail(what +
                 ": a pattern takes its first and last number and a step, and the "
                 "dimension of each file's data at most (as 'slice%03d.raw 0 15 1')");
        const std::string problem = parseNamePattern(words[0], mPattern);
        if (!problem.empty()) fail(what + " " + problem);
        const auto number = [&](const char* name, const std::string& text) {
            const std::int64_t n = parseInteger(what + " " + name, text);
            if (n < -2147483647 || n > 2147483647)
                fail(what + ": its " + name + " " + quote(text) + " is out of range");
            return n;
        };
        mPatternFirst = number("first number", words[1]);
        mPatternLast = number("last number", words[2]);
        mPatternStep = number("step", words[3]);
        if (words.size() == 5) mDataFileDimension = parseInteger(what + " dimension", words[4]);
        if (mPatternStep == 0) fail(what + ": the step is 0");
        if ((mPatternStep > 0 && mPatternLast < mPatternFirst) ||
            (mPatternStep < 0 && mPatternLast > mPatternFirst))
            fail(what + ": names no file (a step of " + std::to_string(mPatternStep) +
                 " never goes from " + std::to_string(mPatternFirst) + " to " +
                 std::to_string(mPatternLast) + ")");
        if (!mPattern.isSigned() && std::min(mPatternFirst, mPatternLast) < 0)
            fail(what + ": a negative number cannot be written with %" +
                 std::string(1, mPattern.conversion));
        mHeader.severalDataFiles = true;
    }

    void addListedFile(const std::string& line) {
        if (line.find('\0') != std::string::npos)
            fail("data file " + quote(line) + " (of the LIST): the name holds a NUL byte");
        if (mListedFiles.size() >= kMaxDataFiles)
            fail("data file LIST names more than " + std::to_string(kMaxDataFiles) + " files");
        mListedFiles.push_back(line);
    }

    /// The names of a list or a pattern, once the sizes say how many files
    /// the data is in: one per piece of as many axes as each file's data
    /// has (by default all but the slowest, a slice a file); or, when each
    /// file's data has every axis, equal runs of slices of the slowest axis.
    void expandDataFiles() {
        if (!mHeader.severalDataFiles) return;
        const std::string what = "data file " + quote(*mHeader.dataFileField);
        if (mListing && mListedFiles.empty())
            fail(what + ": no file names follow it (one a line, to the end of the header)");
        const int dimension = *mHeader.dimension;
        const auto& sizes = *mHeader.sizes;
        const std::int64_t fileDimension = mDataFileDimension.value_or(dimension - 1);
        if (fileDimension < 1 || fileDimension > dimension)
            fail(what + ": the dimension of each file's data, " + std::to_string(fileDimension) +
                 ", is not between 1 and " + std::to_string(dimension));
        const std::uint64_t count =
            mListing ? mListedFiles.size()
                     : std::uint64_t((mPatternLast - mPatternFirst) / mPatternStep) + 1;
        std::string sizesText;
        for (const auto size : sizes)
            sizesText += (sizesText.empty() ? "" : " ") + std::to_string(size);
        const std::string files = std::to_string(count) + (count == 1 ? " file" : " files");
        if (fileDimension < dimension) {
            std::uint64_t pieces = 1;
            for (int axis = int(fileDimension); axis < dimension; ++axis)
                pieces *= std::uint64_t(sizes[std::size_t(axis)]);
            if (count != pieces)
                fail(what + " names " + files + ", but sizes " + sizesText + " are " +
                     std::to_string(pieces) + " pieces of " + std::to_string(fileDimension) +
                     " dimensions, one a file");
        } else {
            const std::uint64_t slices = std::uint64_t(sizes[std::size_t(dimension - 1)]);
            if (count > slices || slices % count != 0)
                fail(what + " names " + files + ", but the " + std::to_string(slices) +
                     " slices of the slowest axis do not split into as many equal runs");
        }
        if (count > kMaxDataFiles)
            fail(what + " names " + std::to_string(count) + " files; at most " +
                 std::to_string(kMaxDataFiles) + " are read");
        if (mListing) {
            mHeader.dataFiles = mListedFiles;
            return;
        }
        mHeader.dataFiles.reserve(std::size_t(count));
        for (std::uint64_t i = 0; i < count; ++i)
            mHeader.dataFiles.push_back(
                mPattern.format(mPatternFirst + std::int64_t(i) * mPatternStep));
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

    /// One real per axis, "nan" allowed (an axis without the value).
    std::vector<double> parseReals(const std::string& what, const std::string& text) const {
        std::vector<double> values;
        for (const auto& token : splitWhitespace(text))
            values.push_back(parseReal(what, token, true));
        return values;
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

    std::vector<std::optional<std::array<double, 3>>> parseDirections(
        const std::string& text) const {
        std::vector<std::optional<std::array<double, 3>>> directions;
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
                directions.emplace_back();
                i += 4;
            } else {
                fail("space directions: " + quote(text.substr(i)) +
                     " is not a vector like (1,0,0)");
            }
        }
        return directions;
    }

    void finish() {
        if (mHeader.dataOffset >= kMaxNrrdHeaderBytes)
            fail("the header is " + std::to_string(mHeader.dataOffset) + " bytes long; at most " +
                 std::to_string(kMaxNrrdHeaderBytes - 1) +
                 " are read (a LIST of that many data files is more than one volume needs)");
        if (!mHeader.dimension) fail("missing required field 'dimension'");
        const int dimension = *mHeader.dimension;
        if (dimension != 3 && dimension != 4)
            fail("dimension " + std::to_string(dimension) +
                 " is not supported (only 3D volumes, and 4D ones with one axis of size 1)");
        if (!mHeader.type) fail("missing required field 'type'");
        if (!mHeader.sizes) fail("missing required field 'sizes'");
        if (!mHeader.encoding) fail("missing required field 'encoding'");
        const auto& sizes = *mHeader.sizes;
        if (sizes.size() != std::size_t(dimension))
            fail("sizes lists " + std::to_string(sizes.size()) + " values for a dimension of " +
                 std::to_string(dimension));
        std::array<int, 3> axes = {0, 1, 2};
        if (dimension == 4) {
            for (int axis = 0; axis < 4; ++axis)
                if (sizes[std::size_t(axis)] < 1)
                    fail("grid size " + std::to_string(sizes[std::size_t(axis)]) + " along axis " +
                         std::to_string(axis) + " is not positive");
            mHeader.droppedAxis = nonSpatialAxis();
            for (int axis = 0, kept = 0; axis < 4; ++axis)
                if (axis != mHeader.droppedAxis) axes[std::size_t(kept++)] = axis;
        }
        const auto sizeOf = [&](int axis) { return sizes[std::size_t(axis)]; };
        mHeader.dims = Dims::checked(sizeOf(axes[0]), sizeOf(axes[1]), sizeOf(axes[2]), mName);
        if (sampleBytes(*mHeader.type) > 1 && encodingHasByteOrder(*mHeader.encoding) &&
            !mHeader.bigEndian)
            fail(std::string("missing field 'endian' (required for type ") +
                 sampleTypeName(*mHeader.type) + ")");
        if (!mHeader.dataFileField && !mHeader.endsWithBlankLine)
            fail(
                "header does not end with a blank line before the data, and has no 'data file' "
                "field");

        if (mKinds) checkKinds(*mKinds, axes);

        VolumeGeometry& geometry = mHeader.geometry;
        if (mHeader.spaceDirections) {
            const auto& directions = *mHeader.spaceDirections;
            if (directions.size() != std::size_t(dimension))
                fail("space directions lists " + std::to_string(directions.size()) +
                     " vectors for a dimension of " + std::to_string(dimension));
            for (int i = 0; i < 3; ++i) {
                const auto& direction = directions[std::size_t(axes[std::size_t(i)])];
                if (!direction && dimension == 3)
                    fail("space directions: an axis is 'none'; all 3 axes must be spatial");
                if (!direction)
                    fail("space directions: axis " + std::to_string(axes[std::size_t(i)]) +
                         " is 'none', but only axis " + std::to_string(mHeader.droppedAxis) +
                         " is not spatial");
                geometry.directions[std::size_t(i)] = *direction;
            }
        } else if (mHeader.spacings) {
            if (mHeader.spacings->size() != std::size_t(dimension))
                fail("spacings lists " + std::to_string(mHeader.spacings->size()) +
                     " values for a dimension of " + std::to_string(dimension));
            for (int i = 0; i < 3; ++i) {
                const double spacing = (*mHeader.spacings)[std::size_t(axes[std::size_t(i)])];
                // NaN marks a non-spatial axis in NRRD; treat it as unit spacing.
                geometry.directions[std::size_t(i)] = {0.0, 0.0, 0.0};
                geometry.directions[std::size_t(i)][std::size_t(i)] =
                    std::isnan(spacing) ? 1.0 : spacing;
            }
        }
        if (mHeader.spaceOrigin)
            geometry.origin = *mHeader.spaceOrigin;
        else if (!mHeader.spaceDirections && mHeader.axisMins)
            placeByAxisMins(axes, dimension, geometry);
        if (mHeader.space) geometry.spaceName = *mHeader.space;
        const std::string problem = geometry.problemOver(mHeader.dims);
        if (!problem.empty()) fail(problem);
        expandDataFiles();
    }

    /// The per-axis way of placing a volume, as teem reads it: "axis mins"
    /// is where each axis's range starts; a cell-centred axis (teem's
    /// default) has its first sample half a step inside the range, a
    /// node-centred one on its start. Without "spacings", the step is the
    /// range ("axis maxs" minus "axis mins") over the samples (cell) or the
    /// intervals (node). Only read where the header has neither "space
    /// directions" nor "space origin", which replace these fields in NRRD.
    void placeByAxisMins(const std::array<int, 3>& axes, int dimension,
                         VolumeGeometry& geometry) const {
        const auto checkCount = [&](const char* what, std::size_t count) {
            if (count != std::size_t(dimension))
                fail(std::string(what) + " lists " + std::to_string(count) +
                     " values for a dimension of " + std::to_string(dimension));
        };
        checkCount("axis mins", mHeader.axisMins->size());
        if (mHeader.axisMaxs) checkCount("axis maxs", mHeader.axisMaxs->size());
        if (mHeader.centers) checkCount("centers", mHeader.centers->size());
        for (int i = 0; i < 3; ++i) {
            const auto axis = std::size_t(axes[std::size_t(i)]);
            const double axisMin = (*mHeader.axisMins)[axis];
            if (std::isnan(axisMin)) continue;
            bool nodeCentred = false;
            if (mHeader.centers) {
                const std::string center = unquotedLowercase((*mHeader.centers)[axis]);
                if (center == "node")
                    nodeCentred = true;
                else if (center != "cell" && center != "???" && center != "none")
                    fail("centers: unknown centering " + quote((*mHeader.centers)[axis]) +
                         " (expected cell, node, ??? or none)");
            }
            double& step = geometry.directions[std::size_t(i)][std::size_t(i)];
            const bool spacingGiven = mHeader.spacings && !std::isnan((*mHeader.spacings)[axis]);
            const std::int64_t samples = (*mHeader.sizes)[axis];
            const std::int64_t intervals = nodeCentred ? samples - 1 : samples;
            if (!spacingGiven && mHeader.axisMaxs && !std::isnan((*mHeader.axisMaxs)[axis]) &&
                intervals > 0)
                step = ((*mHeader.axisMaxs)[axis] - axisMin) / double(intervals);
            geometry.origin[std::size_t(i)] = nodeCentred ? axisMin : axisMin + step / 2.0;
        }
    }

    const std::string& mName;
    std::string_view mBytes;
    std::size_t mSize;
    TextTokenizer mLines;
    std::set<std::string> mSeenFields;
    std::optional<std::vector<std::string>> mKinds;
    bool mListing = false;  // the lines left in the header name data files
    std::vector<std::string> mListedFiles;
    NamePattern mPattern;
    std::int64_t mPatternFirst = 0;
    std::int64_t mPatternLast = 0;
    std::int64_t mPatternStep = 1;
    std::optional<std::int64_t> mDataFileDimension;
    NrrdHeader mHeader;
};

}  // namespace

NrrdHeader parseNrrdHeader(const std::string& name, const std::uint8_t* bytes, std::size_t size) {
    return HeaderParser(name, bytes, size).parse();
}

}  // namespace skelseg::nrrd
