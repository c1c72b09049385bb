#include "io/mesh/OffReader.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include "io/files/ForeignContent.h"
#include "io/files/OffKeyword.h"
#include "io/files/TextFile.h"
#include "io/files/TextTokenizer.h"
#include "io/mesh/MeshBuilder.h"
#include "kernels/base/Error.h"

namespace skelseg {

namespace {

/// Parses one face ("count i0 i1 ..." and an optional colour) and adds the
/// polygon to `builder`. The colour is the rest of the line where the last
/// index stands, ignored: OFF allows one per face (an integer colour-map
/// index, or 3 or 4 integers 0..255 or reals 0..1, "3 0 2 1 255 0 0"). `line` is the face's first
/// line; when it ends before the count's indices do, the indices go on on the next significant
/// lines of `lines`, as OFF is free-format in its tokens (Geomview reads it so, and writers that
/// wrap long lines, e.g. libigl's quad-mesh test data, rely on it). Only the
/// file's end stops a short face.
void addFace(MeshBuilder& builder, TextTokenizer& lines, std::string_view line, std::uint64_t face,
             std::uint64_t vertexCount, std::vector<std::int64_t>& polygon) {
    const std::size_t firstLine = lines.lineNumber();
    TextTokenizer tokens(line);
    const std::string_view countToken = tokens.nextToken();
    std::int64_t corners = 0;
    if (!parseInteger(countToken, corners) || corners < 0)
        builder.fail("line " + std::to_string(firstLine) + ": face " + std::to_string(face) +
                     " has a bad vertex count " + quote(countToken));
    polygon.clear();
    for (std::int64_t c = 0; c < corners; ++c) {
        std::string_view token = tokens.nextToken();
        while (token.empty()) {
            std::string_view nextLine;
            if (!lines.nextSignificantLine(nextLine))
                builder.fail("line " + std::to_string(firstLine) + ": face " +
                             std::to_string(face) + " lists " + std::to_string(c) + " of its " +
                             std::to_string(corners) + " vertex indices");
            tokens = TextTokenizer(nextLine);
            token = tokens.nextToken();
        }
        std::int64_t index = 0;
        if (!parseInteger(token, index))
            builder.fail("line " + std::to_string(lines.lineNumber()) + ": face " +
                         std::to_string(face) + " has a bad vertex index " + quote(token));
        polygon.push_back(index);
    }
    builder.addFace(polygon, vertexCount);
}

/// Number of tokens on `line` when all of them are numbers, 0 otherwise.
std::size_t realTokenCount(std::string_view line) {
    TextTokenizer tokens(line);
    std::size_t count = 0;
    double value = 0;
    for (std::string_view token = tokens.nextToken(); !token.empty(); token = tokens.nextToken()) {
        if (!parseReal(token, value)) return 0;
        ++count;
    }
    return count;
}

/// True when more than `count` significant lines follow the position of
/// `lines` (a copy is advanced; at most count + 1 lines are read).
bool holdsMoreLines(TextTokenizer lines, std::uint64_t count) {
    std::string_view line;
    for (std::uint64_t n = 0; n <= count; ++n)
        if (!lines.nextSignificantLine(line)) return false;
    return true;
}

/// Reads the data of a binary OFF file (Geomview's "OFF BINARY"): 32-bit
/// counts, float coordinates and integer faces. Geomview writes them
/// big-endian with a colour count (and colours) after each face's indices;
/// pmp-library's files leave the colour count out, and its older ones are
/// little-endian. The layout taken is the one whose faces end exactly at the
/// file's end, which a wrong guess practically never does.
class BinaryOffData {
public:
    /// `prefix`: the keyword's letters before "OFF" (they say what each
    /// vertex holds besides x, y, z).
    BinaryOffData(MeshBuilder& builder, std::string_view prefix, const char* data, std::size_t size)
        : mBuilder(builder), mData(reinterpret_cast<const unsigned char*>(data)), mSize(size) {
        mHomogeneous = prefix.find('4') != std::string_view::npos;
        mHasDimension = prefix.find('n') != std::string_view::npos;
        mFloatsPerVertex = 3 + (mHomogeneous ? 1u : 0u) +
                           (prefix.find('N') != std::string_view::npos ? 3u : 0u) +
                           (prefix.find('C') != std::string_view::npos ? 4u : 0u) +
                           (prefix.find("ST") != std::string_view::npos ? 2u : 0u);
    }

    void read() {
        for (const bool bigEndian : {true, false})
            for (const bool faceColours : {true, false})
                if (fits(bigEndian, faceColours)) return build(bigEndian, faceColours);
        Counts counts;
        if (!readCounts(true, counts) && !readCounts(false, counts))
            mBuilder.fail("binary OFF: the header's counts do not fit the " +
                          std::to_string(mSize) + " bytes that follow it");
        mBuilder.fail(
            "binary OFF: its faces end before or after the file's end, with or without "
            "a colour count per face");
    }

private:
    struct Counts {
        std::uint64_t vertices = 0, faces = 0, dataStart = 0;
    };

    bool word(std::uint64_t position, bool bigEndian, std::uint32_t& value) const {
        if (position > mSize || mSize - position < 4) return false;
        const unsigned char* b = mData + position;
        value = bigEndian ? std::uint32_t(b[0]) << 24 | std::uint32_t(b[1]) << 16 |
                                std::uint32_t(b[2]) << 8 | b[3]
                          : std::uint32_t(b[3]) << 24 | std::uint32_t(b[2]) << 16 |
                                std::uint32_t(b[1]) << 8 | b[0];
        return true;
    }

    /// The counts, when the vertices they announce fit in the data.
    bool readCounts(bool bigEndian, Counts& counts) const {
        std::uint64_t position = 0;
        std::uint32_t dimension = 3, vertices = 0, faces = 0, edges = 0;
        if (mHasDimension && !word(position, bigEndian, dimension)) return false;
        if (mHasDimension) position += 4;
        if (dimension != 3 || !word(position, bigEndian, vertices) ||
            !word(position + 4, bigEndian, faces) || !word(position + 8, bigEndian, edges))
            return false;
        counts = {vertices, faces, position + 12};
        return vertices <= kMaxElementCount && faces <= kMaxElementCount &&
               counts.dataStart + counts.vertices * mFloatsPerVertex * 4 <= mSize;
    }

    /// True when the faces of this layout end exactly at the end of the data.
    bool fits(bool bigEndian, bool faceColours) const {
        Counts counts;
        if (!readCounts(bigEndian, counts) || counts.faces == 0) return false;
        std::uint64_t position = counts.dataStart + counts.vertices * mFloatsPerVertex * 4;
        for (std::uint64_t f = 0; f < counts.faces; ++f) {
            std::uint32_t corners = 0, colours = 0;
            if (!word(position, bigEndian, corners) || corners > (mSize - position) / 4)
                return false;
            position += 4 + std::uint64_t(corners) * 4;
            if (!faceColours) continue;
            if (!word(position, bigEndian, colours) || colours > 4) return false;
            position += 4 + std::uint64_t(colours) * 4;
        }
        return position == mSize;
    }

    void build(bool bigEndian, bool faceColours) {
        Counts counts;
        readCounts(bigEndian, counts);
        mBuilder.reserve(counts.vertices, counts.faces);
        std::uint64_t position = counts.dataStart;
        std::uint32_t value = 0;
        auto nextFloat = [&] {
            word(position, bigEndian, value);
            position += 4;
            float real = 0;
            std::memcpy(&real, &value, 4);
            return double(real);
        };
        for (std::uint64_t v = 0; v < counts.vertices; ++v) {
            const std::uint64_t vertexEnd = position + mFloatsPerVertex * 4;
            const double x = nextFloat(), y = nextFloat(), z = nextFloat();
            const double w = mHomogeneous ? nextFloat() : 1.0;
            if (w == 0)
                mBuilder.fail("binary OFF: vertex " + std::to_string(v) +
                              " has the homogeneous coordinate 0 (a point at infinity)");
            mBuilder.addVertex(x / w, y / w, z / w);
            position = vertexEnd;
        }
        std::vector<std::int64_t> polygon;
        for (std::uint64_t f = 0; f < counts.faces; ++f) {
            std::uint32_t corners = 0, colours = 0;
            word(position, bigEndian, corners);
            position += 4;
            polygon.clear();
            for (std::uint32_t c = 0; c < corners; ++c, position += 4) {
                word(position, bigEndian, value);
                polygon.push_back(std::int32_t(value));
            }
            mBuilder.addFace(polygon, counts.vertices);
            if (!faceColours) continue;
            word(position, bigEndian, colours);
            position += 4 + std::uint64_t(colours) * 4;
        }
    }

    MeshBuilder& mBuilder;
    const unsigned char* mData;
    std::uint64_t mSize;
    bool mHomogeneous = false;
    bool mHasDimension = false;
    std::uint64_t mFloatsPerVertex = 3;
};

}  // namespace

TriangleMesh readOff(const std::string& name, const char* data, std::size_t size) {
    MeshBuilder builder(name, 0);
    const std::size_t bom = textContentStart(name, std::string_view(data, size));
    TextTokenizer lines(data + bom, size - bom);
    std::string_view line;
    if (!lines.nextSignificantLine(line)) builder.fail("empty file");

    // Header keyword: [ST][C][N][4][n]OFF, optionally followed by the counts on
    // the same line. Some writers leave the keyword out and start with counts,
    // and some glue the first count to it ("OFF8 6 12": Geomview matches the
    // keyword's letters and then reads numbers, so it reads that file).
    TextTokenizer headerTokens(line);
    const std::string_view keyword = headerTokens.nextToken();
    std::vector<std::int64_t> counts;
    auto collectCounts = [&](TextTokenizer& tokens, std::string_view first) {
        for (std::string_view token = first; !token.empty(); token = tokens.nextToken()) {
            std::int64_t value = 0;
            if (!parseInteger(token, value) || value < 0)
                builder.fail("line " + std::to_string(lines.lineNumber()) +
                             ": expected vertex, face and edge counts, found " + quote(token));
            counts.push_back(value);
        }
    };
    // 4OFF: each vertex has a fourth, homogeneous coordinate w (the point is
    // (x, y, z) / w). nOFF: the number of coordinates per vertex comes before
    // the counts; only 3 (4 with the '4') is a shape in space.
    bool homogeneous = false;
    if (const std::size_t keywordEnd = offKeywordEnd(keyword); keywordEnd != 0) {
        const std::string_view prefix = keyword.substr(0, keywordEnd - 3);
        if (!isOffKeywordPrefix(prefix)) {
            refuseForeignContent(name, std::string_view(data, size), "OFF");
            builder.fail("not an OFF file (header " + quote(keyword) + ")");
        }
        homogeneous = prefix.find('4') != std::string_view::npos;
        std::string_view token = keyword.substr(keywordEnd);
        if (token.empty()) token = headerTokens.nextToken();
        if (lowercase(token) == "binary") {
            // The binary data starts after the header line's newline.
            if (const std::string_view extra = headerTokens.nextToken(); !extra.empty())
                builder.fail("line " + std::to_string(lines.lineNumber()) + ": " + quote(extra) +
                             " follows 'BINARY' on the header line");
            const std::size_t dataSize = lines.bytesLeft();
            BinaryOffData(builder, prefix, data + (size - dataSize), dataSize).read();
            return builder.finish();
        }
        if (prefix.find('n') != std::string_view::npos) {
            if (token.empty()) {
                if (!lines.nextSignificantLine(line))
                    builder.fail("file ends before the dimension that " + quote(keyword) +
                                 " announces");
                headerTokens = TextTokenizer(line);
                token = headerTokens.nextToken();
            }
            std::int64_t dimension = 0;
            if (!parseInteger(token, dimension) || dimension < 0)
                builder.fail("line " + std::to_string(lines.lineNumber()) + ": expected the " +
                             "vertex dimension that " + quote(keyword) + " announces, found " +
                             quote(token));
            if (dimension != 3)
                builder.fail("line " + std::to_string(lines.lineNumber()) + ": " + quote(keyword) +
                             " gives vertices " + std::to_string(dimension) +
                             " coordinates; only 3-dimensional OFF files are supported");
            token = headerTokens.nextToken();
        }
        collectCounts(headerTokens, token);
    } else if (std::int64_t value = 0; parseInteger(keyword, value)) {
        collectCounts(headerTokens, keyword);
    } else {
        refuseForeignContent(name, std::string_view(data, size), "OFF");
        builder.fail("not an OFF file (it starts with " + quote(keyword) + ")");
    }
    // The counts may stand on the keyword's line, on the next, or one per
    // line with blank and comment lines between (Geomview reads the header
    // as tokens). Lines are taken whole until the vertex and face counts are
    // read; the edge count is optional (many writers leave it out), so a line
    // after them is taken as the edge count only when it holds one number: a
    // vertex line holds at least three.
    while (counts.size() < 2) {
        if (!lines.nextSignificantLine(line))
            builder.fail(counts.empty()
                             ? "file ends before the vertex and face counts"
                             : "file ends after the vertex count, before the face count");
        TextTokenizer countTokens(line);
        collectCounts(countTokens, countTokens.nextToken());
    }
    if (counts.size() == 2) {
        TextTokenizer afterCounts = lines;
        std::string_view edgeLine;
        if (afterCounts.nextSignificantLine(edgeLine) && realTokenCount(edgeLine) == 1) {
            lines = afterCounts;
            TextTokenizer countTokens(edgeLine);
            collectCounts(countTokens, countTokens.nextToken());
        }
    }
    if (counts.size() > 3)
        builder.fail("line " + std::to_string(lines.lineNumber()) +
                     ": expected vertex, face and edge counts, found " +
                     std::to_string(counts.size()) + " numbers");

    const std::uint64_t vertexCount = std::uint64_t(counts[0]);
    const std::uint64_t faceCount = std::uint64_t(counts[1]);
    // The shortest vertex line is "0 0 0\n" (6 bytes), the shortest face line
    // a bare count, "1\n" (2 bytes; such a face is refused when it is read,
    // with its own problem): refuse counts the rest of the file cannot hold.
    // Memory is reserved only for faces of at least "3 0 0 0\n" (8 bytes).
    const std::uint64_t bytesLeft = lines.bytesLeft() + 1;
    if (vertexCount > kMaxElementCount || faceCount > kMaxElementCount ||
        vertexCount * 6 + faceCount * 2 > bytesLeft)
        builder.fail("header says " + std::to_string(vertexCount) + " vertices and " +
                     std::to_string(faceCount) + " faces but only " +
                     std::to_string(lines.bytesLeft()) + " bytes follow");
    if (faceCount == 0) builder.fail("the mesh has no faces");
    builder.reserve(vertexCount, std::min(faceCount, (bytesLeft - vertexCount * 6) / 8));

    std::string_view lastVertexLine;
    for (std::uint64_t v = 0; v < vertexCount; ++v) {
        if (!lines.nextSignificantLine(line))
            builder.fail("file ends after " + std::to_string(v) + " of " +
                         std::to_string(vertexCount) + " vertices");
        TextTokenizer tokens(line);
        double xyzw[4] = {0, 0, 0, 1};
        for (std::size_t c = 0; c < (homogeneous ? 4u : 3u); ++c) {
            const std::string_view token = tokens.nextToken();
            if (!parseReal(token, xyzw[c]))
                builder.fail(
                    "line " + std::to_string(lines.lineNumber()) + ": vertex " + std::to_string(v) +
                    (token.empty() ? " has fewer than " + std::string(homogeneous ? "4" : "3") +
                                         " coordinates"
                                   : " has a bad coordinate " + quote(token)));
        }
        if (xyzw[3] == 0)
            builder.fail("line " + std::to_string(lines.lineNumber()) + ": vertex " +
                         std::to_string(v) + " has the homogeneous coordinate 0 (a point at " +
                         "infinity)");
        builder.addVertex(xyzw[0] / xyzw[3], xyzw[1] / xyzw[3], xyzw[2] / xyzw[3]);
        lastVertexLine = line;
    }

    std::vector<std::int64_t> polygon;
    for (std::uint64_t f = 0; f < faceCount; ++f) {
        if (!lines.nextSignificantLine(line))
            builder.fail("file ends after " + std::to_string(f) + " of " +
                         std::to_string(faceCount) + " faces");
        if (f > 0) {
            addFace(builder, lines, line, f, vertexCount, polygon);
            continue;
        }
        // A vertex the header does not count lands where the first face is
        // expected and fails there as a face; say what is wrong with the file.
        const TextTokenizer afterFirstFaceLine = lines;
        try {
            addFace(builder, lines, line, f, vertexCount, polygon);
        } catch (const InputError&) {
            if (realTokenCount(line) >= 3 &&
                realTokenCount(line) == realTokenCount(lastVertexLine) &&
                holdsMoreLines(afterFirstFaceLine, faceCount - 1))
                builder.fail("line " + std::to_string(lines.lineNumber()) +
                             ": the file holds more vertices than its header declares (" +
                             std::to_string(vertexCount) + ")");
            throw;
        }
    }
    // Blank and comment lines may follow; anything else means the header's
    // counts are wrong, and reading on would drop part of the mesh.
    if (lines.nextSignificantLine(line)) {
        TextTokenizer tokens(line);
        std::int64_t corners = 0;
        if (parseInteger(tokens.nextToken(), corners))
            builder.fail("line " + std::to_string(lines.lineNumber()) +
                         ": the file holds more faces than its header declares (" +
                         std::to_string(faceCount) + ")");
        builder.fail("line " + std::to_string(lines.lineNumber()) + ": " + quote(trim(line)) +
                     " follows the last of the " + std::to_string(faceCount) +
                     " faces the header declares");
    }
    return builder.finish();
}

}  // namespace skelseg
