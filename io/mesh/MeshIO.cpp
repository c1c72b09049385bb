#include "io/mesh/MeshIO.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <string_view>
#include <unordered_map>

#include "io/files/OutputDirectory.h"
#include "io/volume/VolumeReader.h"
#include "kernels/base/Error.h"

namespace skelseg {

namespace {

// Vertex and face indices are stored as uint32; keep one value free.
constexpr std::uint64_t kMaxElementCount = 0xFFFFFFFEull;
// MeshBuilder::addFace: the vertex count is not known yet, check in finish().
constexpr std::uint64_t kCheckLater = ~std::uint64_t(0);

std::string toLower(std::string_view text) {
    std::string out(text);
    for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

bool isBlank(char c) noexcept {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}
bool isSpace(char c) noexcept {
    return isBlank(c) || c == '\n';
}

/// Shortens a token for an error message (garbage input can hold anything).
std::string quoted(std::string_view token) {
    std::string out;
    // Printable ASCII only: garbage bytes must not reach the terminal.
    for (char c : token.substr(0, 40)) {
        const auto byte = static_cast<unsigned char>(c);
        out += (byte < 32 || byte >= 127) ? '?' : c;
    }
    if (token.size() > 40) out += "...";
    return "'" + out + "'";
}

bool parseInteger(std::string_view token, std::int64_t& value) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty()) return false;
    const auto result = std::from_chars(token.data(), token.data() + token.size(), value);
    return result.ec == std::errc() && result.ptr == token.data() + token.size();
}

bool parseReal(std::string_view token, double& value) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty()) return false;
    const auto result = std::from_chars(token.data(), token.data() + token.size(), value);
    return result.ec == std::errc() && result.ptr == token.data() + token.size();
}

/// Splits one line into whitespace-separated tokens without copying.
class LineTokens {
public:
    explicit LineTokens(std::string_view line) : mLine(line) {}
    /// Next token, empty at the end of the line.
    std::string_view next() noexcept {
        while (mPosition < mLine.size() && isBlank(mLine[mPosition])) ++mPosition;
        const std::size_t begin = mPosition;
        while (mPosition < mLine.size() && !isBlank(mLine[mPosition])) ++mPosition;
        return mLine.substr(begin, mPosition - begin);
    }

private:
    std::string_view mLine;
    std::size_t mPosition = 0;
};

/// Walks a text buffer line by line, counting line numbers for messages.
class LineReader {
public:
    LineReader(const char* data, std::size_t size) : mText(data, size) {}
    /// Next line without its terminator and without a '#' comment (when
    /// stripComments). False at the end of the buffer.
    bool next(std::string_view& line, bool stripComments) {
        if (mPosition >= mText.size()) return false;
        std::size_t end = mText.find('\n', mPosition);
        if (end == std::string_view::npos) end = mText.size();
        line = mText.substr(mPosition, end - mPosition);
        mPosition = end + 1;
        ++mLineNumber;
        if (stripComments) {
            const std::size_t hash = line.find('#');
            if (hash != std::string_view::npos) line = line.substr(0, hash);
        }
        return true;
    }
    /// Next line holding a token (comments and blank lines skipped).
    bool nextSignificant(std::string_view& line) {
        while (next(line, true)) {
            for (char c : line)
                if (!isBlank(c)) return true;
        }
        return false;
    }
    std::size_t lineNumber() const noexcept { return mLineNumber; }
    std::size_t bytesLeft() const noexcept {
        return mPosition >= mText.size() ? 0 : mText.size() - mPosition;
    }

private:
    std::string_view mText;
    std::size_t mPosition = 0;
    std::size_t mLineNumber = 0;
};

/// Collects vertices and polygons, validates them and fan-triangulates.
class MeshBuilder {
public:
    /// indexBase: how the format numbers vertices in messages (OBJ from 1).
    MeshBuilder(const std::string& name, int indexBase) : mName(name), mIndexBase(indexBase) {}

    [[noreturn]] void fail(const std::string& problem) const { throw InputError(mName, problem); }

    /// Reserves only for counts already checked against the bytes available.
    void reserve(std::uint64_t vertices, std::uint64_t faces) {
        mMesh.vertices.reserve(std::size_t(vertices));
        mMesh.triangles.reserve(std::size_t(faces));
        mMesh.triangleFace.reserve(std::size_t(faces));
    }

    void addVertex(double x, double y, double z) {
        if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
            fail("vertex " + std::to_string(mMesh.vertices.size() + std::size_t(mIndexBase)) +
                 " has a non-finite coordinate");
        if (mMesh.vertices.size() >= kMaxElementCount) fail("too many vertices");
        mMesh.vertices.push_back({x, y, z});
    }

    std::size_t vertexCount() const noexcept { return mMesh.vertices.size(); }
    std::size_t faceCount() const noexcept { return mMesh.faceCount; }

    /// Adds one polygon of 0-based vertex indices. vertexLimit: the number of
    /// vertices the indices must stay below, or kCheckLater to check in
    /// finish() (formats whose faces may come before their vertices).
    void addFace(const std::vector<std::int64_t>& polygon, std::uint64_t vertexLimit) {
        const std::size_t face = mMesh.faceCount;
        if (polygon.size() < 3)
            fail("face " + std::to_string(face) + " has " + std::to_string(polygon.size()) +
                 " vertices; a face needs at least 3");
        if (face >= kMaxElementCount) fail("too many faces");
        for (std::int64_t index : polygon) {
            if (index < 0)
                fail("face " + std::to_string(face) + " references vertex " +
                     std::to_string(index + mIndexBase) + ", which does not exist");
            const std::uint64_t limit = vertexLimit == kCheckLater ? kMaxElementCount : vertexLimit;
            if (std::uint64_t(index) >= limit) failIndex(face, std::uint64_t(index), limit);
        }
        for (std::size_t corner = 1; corner + 1 < polygon.size(); ++corner) {
            mMesh.triangles.push_back({std::uint32_t(polygon[0]), std::uint32_t(polygon[corner]),
                                       std::uint32_t(polygon[corner + 1])});
            mMesh.triangleFace.push_back(std::uint32_t(face));
        }
        ++mMesh.faceCount;
    }

    TriangleMesh finish() {
        if (mMesh.faceCount == 0) fail("the mesh has no faces");
        const std::uint64_t vertexLimit = mMesh.vertices.size();
        for (std::size_t t = 0; t < mMesh.triangles.size(); ++t)
            for (std::uint32_t index : mMesh.triangles[t])
                if (index >= vertexLimit) failIndex(mMesh.triangleFace[t], index, vertexLimit);
        return std::move(mMesh);
    }

private:
    [[noreturn]] void failIndex(std::size_t face, std::uint64_t index,
                                std::uint64_t vertexLimit) const {
        fail("face " + std::to_string(face) + " references vertex " +
             std::to_string(index + std::uint64_t(mIndexBase)) + " but there are " +
             std::to_string(vertexLimit) + " vertices");
    }

    const std::string& mName;
    int mIndexBase;
    TriangleMesh mMesh;
};

// ---------------------------------------------------------------------------
// OFF

TriangleMesh readOff(const std::string& name, const char* data, std::size_t size) {
    MeshBuilder builder(name, 0);
    LineReader lines(data, size);
    std::string_view line;
    if (!lines.nextSignificant(line)) builder.fail("empty file");

    // Header keyword: [ST][C][N][4][n]OFF, optionally followed by the counts on
    // the same line. Some writers leave the keyword out and start with counts.
    LineTokens headerTokens(line);
    std::string_view keyword = headerTokens.next();
    std::vector<std::int64_t> counts;
    auto collectCounts = [&](LineTokens& tokens, std::string_view first) {
        for (std::string_view token = first; !token.empty(); token = tokens.next()) {
            std::int64_t value = 0;
            if (!parseInteger(token, value) || value < 0)
                builder.fail("line " + std::to_string(lines.lineNumber()) +
                             ": expected vertex, face and edge counts, found " + quoted(token));
            counts.push_back(value);
        }
    };
    const std::string lowerKeyword = toLower(keyword);
    if (lowerKeyword.size() >= 3 && lowerKeyword.compare(lowerKeyword.size() - 3, 3, "off") == 0) {
        // The prefix is case-sensitive: 'N' = normals, 'n' = dimension given.
        const std::string_view prefix = keyword.substr(0, keyword.size() - 3);
        if (prefix.find('4') != std::string_view::npos ||
            prefix.find('n') != std::string_view::npos)
            builder.fail("OFF files with other than 3 dimensions (" + quoted(keyword) +
                         ") are not supported");
        for (char c : prefix)
            if (c != 'S' && c != 'T' && c != 'C' && c != 'N')
                builder.fail("not an OFF file (header " + quoted(keyword) + ")");
        std::string_view token = headerTokens.next();
        if (toLower(token) == "binary") builder.fail("binary OFF files are not supported");
        collectCounts(headerTokens, token);
        if (counts.empty()) {
            if (!lines.nextSignificant(line))
                builder.fail("file ends before the vertex and face counts");
            LineTokens countTokens(line);
            collectCounts(countTokens, countTokens.next());
        }
    } else if (std::int64_t value = 0; parseInteger(keyword, value)) {
        collectCounts(headerTokens, keyword);
    } else {
        builder.fail("not an OFF file (it starts with " + quoted(keyword) + ")");
    }
    if (counts.size() < 2 || counts.size() > 3)
        builder.fail("line " + std::to_string(lines.lineNumber()) +
                     ": expected vertex, face and edge counts, found " +
                     std::to_string(counts.size()) + " numbers");

    const std::uint64_t vertexCount = std::uint64_t(counts[0]);
    const std::uint64_t faceCount = std::uint64_t(counts[1]);
    // The shortest vertex line is "0 0 0\n" (6 bytes), the shortest face line
    // "3 0 0 0\n" (8 bytes): refuse counts the rest of the file cannot hold
    // before reserving memory for them.
    const std::uint64_t bytesLeft = lines.bytesLeft() + 1;
    if (vertexCount > kMaxElementCount || faceCount > kMaxElementCount ||
        vertexCount * 6 + faceCount * 8 > bytesLeft)
        builder.fail("header says " + std::to_string(vertexCount) + " vertices and " +
                     std::to_string(faceCount) + " faces but only " +
                     std::to_string(lines.bytesLeft()) + " bytes follow");
    if (faceCount == 0) builder.fail("the mesh has no faces");
    builder.reserve(vertexCount, faceCount);

    for (std::uint64_t v = 0; v < vertexCount; ++v) {
        if (!lines.nextSignificant(line))
            builder.fail("file ends after " + std::to_string(v) + " of " +
                         std::to_string(vertexCount) + " vertices");
        LineTokens tokens(line);
        double xyz[3];
        for (double& coordinate : xyz) {
            const std::string_view token = tokens.next();
            if (!parseReal(token, coordinate))
                builder.fail("line " + std::to_string(lines.lineNumber()) + ": vertex " +
                             std::to_string(v) +
                             (token.empty() ? " has fewer than 3 coordinates"
                                            : " has a bad coordinate " + quoted(token)));
        }
        builder.addVertex(xyz[0], xyz[1], xyz[2]);
    }

    std::vector<std::int64_t> polygon;
    for (std::uint64_t f = 0; f < faceCount; ++f) {
        if (!lines.nextSignificant(line))
            builder.fail("file ends after " + std::to_string(f) + " of " +
                         std::to_string(faceCount) + " faces");
        LineTokens tokens(line);
        const std::string_view countToken = tokens.next();
        std::int64_t corners = 0;
        if (!parseInteger(countToken, corners) || corners < 0)
            builder.fail("line " + std::to_string(lines.lineNumber()) + ": face " +
                         std::to_string(f) + " has a bad vertex count " + quoted(countToken));
        polygon.clear();
        // Read at most what the line holds, whatever the count claims.
        for (std::int64_t c = 0; c < corners; ++c) {
            const std::string_view token = tokens.next();
            std::int64_t index = 0;
            if (token.empty())
                builder.fail("line " + std::to_string(lines.lineNumber()) + ": face " +
                             std::to_string(f) + " lists " + std::to_string(c) + " of its " +
                             std::to_string(corners) + " vertex indices");
            if (!parseInteger(token, index))
                builder.fail("line " + std::to_string(lines.lineNumber()) + ": face " +
                             std::to_string(f) + " has a bad vertex index " + quoted(token));
            polygon.push_back(index);
        }
        builder.addFace(polygon, vertexCount);
    }
    return builder.finish();
}

// ---------------------------------------------------------------------------
// OBJ

TriangleMesh readObj(const std::string& name, const char* data, std::size_t size) {
    MeshBuilder builder(name, 1);
    LineReader lines(data, size);
    std::string_view line;
    std::vector<std::int64_t> polygon;
    while (lines.nextSignificant(line)) {
        LineTokens tokens(line);
        const std::string_view keyword = tokens.next();
        if (keyword == "v") {
            double xyz[3];
            for (double& coordinate : xyz) {
                const std::string_view token = tokens.next();
                if (!parseReal(token, coordinate))
                    builder.fail("line " + std::to_string(lines.lineNumber()) +
                                 (token.empty() ? ": vertex has fewer than 3 coordinates"
                                                : ": bad vertex coordinate " + quoted(token)));
            }
            builder.addVertex(xyz[0], xyz[1], xyz[2]);
        } else if (keyword == "f" || keyword == "fo") {
            polygon.clear();
            for (std::string_view token = tokens.next(); !token.empty(); token = tokens.next()) {
                // v, v/vt, v//vn or v/vt/vn: only the position index matters.
                const std::string_view vertexPart = token.substr(0, token.find('/'));
                std::int64_t index = 0;
                if (!parseInteger(vertexPart, index) || index == 0)
                    builder.fail("line " + std::to_string(lines.lineNumber()) +
                                 ": bad face vertex " + quoted(token));
                if (index < 0) {
                    // Negative: relative to the vertices defined so far.
                    const std::int64_t resolved = std::int64_t(builder.vertexCount()) + index;
                    if (resolved < 0)
                        builder.fail("line " + std::to_string(lines.lineNumber()) + ": face " +
                                     std::to_string(builder.faceCount()) + " references vertex " +
                                     std::to_string(index) + " but only " +
                                     std::to_string(builder.vertexCount()) +
                                     " vertices precede it");
                    polygon.push_back(resolved);
                } else {
                    polygon.push_back(index - 1);
                }
            }
            builder.addFace(polygon,
                            kCheckLater);  // positive indices may point forward: checked at the end
        }
        // Every other statement (vt, vn, g, o, s, usemtl, mtllib, l, p, ...) is ignored.
    }
    return builder.finish();
}

// ---------------------------------------------------------------------------
// STL

/// Merges STL vertices at bitwise-identical positions: STL stores every facet's
/// corners separately, and a mesh without shared vertices would look like a
/// soup of open triangles to the mesh checks.
class VertexWelder {
public:
    explicit VertexWelder(MeshBuilder& builder) : mBuilder(builder) {}
    std::int64_t add(double x, double y, double z) {
        // -0 and +0 are the same position.
        if (x == 0.0) x = 0.0;
        if (y == 0.0) y = 0.0;
        if (z == 0.0) z = 0.0;
        const Key key{x, y, z};
        const auto found = mIndices.find(key);
        if (found != mIndices.end()) return found->second;
        const std::int64_t index = std::int64_t(mBuilder.vertexCount());
        mBuilder.addVertex(x, y, z);
        mIndices.emplace(key, index);
        return index;
    }

private:
    struct Key {
        double x, y, z;
        bool operator==(const Key& o) const noexcept { return x == o.x && y == o.y && z == o.z; }
    };
    struct KeyHash {
        std::size_t operator()(const Key& key) const noexcept {
            std::uint64_t bits[3];
            std::memcpy(&bits[0], &key.x, 8);
            std::memcpy(&bits[1], &key.y, 8);
            std::memcpy(&bits[2], &key.z, 8);
            std::uint64_t h = 1469598103934665603ull;
            for (std::uint64_t b : bits) h = (h ^ b) * 1099511628211ull + (h >> 29);
            return std::size_t(h);
        }
    };
    MeshBuilder& mBuilder;
    std::unordered_map<Key, std::int64_t, KeyHash> mIndices;
};

float readFloatLittleEndian(const std::uint8_t* bytes) noexcept {
    const std::uint32_t bits = std::uint32_t(bytes[0]) | (std::uint32_t(bytes[1]) << 8) |
                               (std::uint32_t(bytes[2]) << 16) | (std::uint32_t(bytes[3]) << 24);
    float value;
    std::memcpy(&value, &bits, 4);
    return value;
}

TriangleMesh readBinaryStl(const std::string& name, const std::uint8_t* data,
                           std::uint64_t triangleCount) {
    MeshBuilder builder(name, 0);
    if (triangleCount == 0) builder.fail("the mesh has no faces");
    if (triangleCount > kMaxElementCount) builder.fail("too many triangles");
    builder.reserve(0, triangleCount);
    VertexWelder welder(builder);
    std::vector<std::int64_t> polygon(3);
    for (std::uint64_t t = 0; t < triangleCount; ++t) {
        const std::uint8_t* record = data + 84 + 50 * t + 12;  // skip the normal
        for (int corner = 0; corner < 3; ++corner) {
            const double x = readFloatLittleEndian(record + 12 * corner);
            const double y = readFloatLittleEndian(record + 12 * corner + 4);
            const double z = readFloatLittleEndian(record + 12 * corner + 8);
            if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
                builder.fail("triangle " + std::to_string(t) + " has a non-finite coordinate");
            polygon[std::size_t(corner)] = welder.add(x, y, z);
        }
        builder.addFace(polygon, kCheckLater);
    }
    return builder.finish();
}

/// Whitespace-separated tokens over a whole buffer, tracking line numbers.
class TokenReader {
public:
    TokenReader(const char* data, std::size_t size) : mText(data, size) {}
    /// Next token, empty at the end.
    std::string_view next() noexcept {
        while (mPosition < mText.size() && isSpace(mText[mPosition])) {
            if (mText[mPosition] == '\n') ++mLineNumber;
            ++mPosition;
        }
        const std::size_t begin = mPosition;
        while (mPosition < mText.size() && !isSpace(mText[mPosition])) ++mPosition;
        return mText.substr(begin, mPosition - begin);
    }
    void skipLine() noexcept {
        while (mPosition < mText.size() && mText[mPosition] != '\n') ++mPosition;
    }
    std::size_t lineNumber() const noexcept { return mLineNumber; }
    std::size_t position() const noexcept { return mPosition; }
    std::size_t bytesLeft() const noexcept { return mText.size() - mPosition; }

private:
    std::string_view mText;
    std::size_t mPosition = 0;
    std::size_t mLineNumber = 1;
};

TriangleMesh readAsciiStl(const std::string& name, const char* data, std::size_t size) {
    MeshBuilder builder(name, 0);
    VertexWelder welder(builder);
    TokenReader tokens(data, size);
    auto where = [&] { return "line " + std::to_string(tokens.lineNumber()) + ": "; };
    auto expect = [&](const char* word) {
        const std::string_view token = tokens.next();
        if (toLower(token) != word)
            builder.fail(where() + "expected '" + word + "', found " +
                         (token.empty() ? "the end of the file" : quoted(token)));
    };
    std::vector<std::int64_t> polygon;
    for (;;) {
        const std::string_view token = tokens.next();
        if (token.empty()) break;
        const std::string word = toLower(token);
        if (word == "solid" || word == "endsolid") {
            tokens.skipLine();  // the solid's name
            continue;
        }
        if (word != "facet")
            builder.fail(where() + "expected 'facet' or 'endsolid', found " + quoted(token));
        // "normal nx ny nz": the normal is recomputed from the corners.
        expect("normal");
        for (int c = 0; c < 3; ++c) {
            double ignored = 0;
            const std::string_view value = tokens.next();
            if (!parseReal(value, ignored))
                builder.fail(where() + "bad facet normal " + quoted(value));
        }
        expect("outer");
        expect("loop");
        polygon.clear();
        for (;;) {
            const std::string_view vertexWord = tokens.next();
            const std::string lower = toLower(vertexWord);
            if (lower == "endloop") break;
            if (lower != "vertex")
                builder.fail(where() + "expected 'vertex' or 'endloop', found " +
                             (vertexWord.empty() ? "the end of the file" : quoted(vertexWord)));
            double xyz[3];
            for (double& coordinate : xyz) {
                const std::string_view value = tokens.next();
                if (!parseReal(value, coordinate))
                    builder.fail(where() + "bad vertex coordinate " + quoted(value));
                if (!std::isfinite(coordinate))
                    builder.fail(where() + "facet " + std::to_string(builder.faceCount()) +
                                 " has a non-finite coordinate");
            }
            polygon.push_back(welder.add(xyz[0], xyz[1], xyz[2]));
        }
        expect("endfacet");
        builder.addFace(polygon, kCheckLater);
    }
    return builder.finish();
}

TriangleMesh readStl(const std::string& name, const std::uint8_t* data, std::size_t size) {
    // Binary when the size matches the triangle count in the header: many
    // binary files also begin with "solid" in their 80-byte comment.
    if (size >= 84) {
        const std::uint64_t triangleCount =
            std::uint64_t(data[80]) | (std::uint64_t(data[81]) << 8) |
            (std::uint64_t(data[82]) << 16) | (std::uint64_t(data[83]) << 24);
        if (84 + 50 * triangleCount == size) return readBinaryStl(name, data, triangleCount);
    }
    std::size_t start = 0;
    while (start < size && isSpace(char(data[start]))) ++start;
    // ASCII STL starts with "solid" and holds no NUL byte; binary data almost
    // always does (zero attribute bytes, small floats), so a binary file whose
    // size is wrong is reported as such and not as bad ASCII.
    const bool looksAscii =
        size - start >= 5 &&
        toLower(std::string_view(reinterpret_cast<const char*>(data) + start, 5)) == "solid" &&
        std::memchr(data, 0, size) == nullptr;
    if (looksAscii) return readAsciiStl(name, reinterpret_cast<const char*>(data), size);
    if (size < 84)
        throw InputError(name, "not an STL file (too short for binary, no 'solid' for ASCII)");
    const std::uint64_t triangleCount = std::uint64_t(data[80]) | (std::uint64_t(data[81]) << 8) |
                                        (std::uint64_t(data[82]) << 16) |
                                        (std::uint64_t(data[83]) << 24);
    throw InputError(name, "binary STL header says " + std::to_string(triangleCount) +
                               " triangles (" + std::to_string(84 + 50 * triangleCount) +
                               " bytes) but the file has " + std::to_string(size) + " bytes");
}

// ---------------------------------------------------------------------------
// PLY

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool plyTypeFromName(std::string_view name, PlyType& type) {
    static const std::pair<const char*, PlyType> names[] = {
        {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
        {"uint8", PlyType::UInt8},    {"short", PlyType::Int16},     {"int16", PlyType::Int16},
        {"ushort", PlyType::UInt16},  {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
        {"int32", PlyType::Int32},    {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
        {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64},
        {"float64", PlyType::Float64}};
    for (const auto& entry : names)
        if (name == entry.first) {
            type = entry.second;
            return true;
        }
    return false;
}

std::size_t plyTypeSize(PlyType type) noexcept {
    switch (type) {
        case PlyType::Int8:
        case PlyType::UInt8:
            return 1;
        case PlyType::Int16:
        case PlyType::UInt16:
            return 2;
        case PlyType::Int32:
        case PlyType::UInt32:
        case PlyType::Float32:
            return 4;
        case PlyType::Float64:
            return 8;
    }
    return 1;
}

bool plyTypeIsInteger(PlyType type) noexcept {
    return type != PlyType::Float32 && type != PlyType::Float64;
}

struct PlyProperty {
    std::string name;
    bool isList = false;
    PlyType countType = PlyType::UInt8;  // lists only
    PlyType valueType = PlyType::Float32;
};

struct PlyElement {
    std::string name;
    std::uint64_t count = 0;
    std::vector<PlyProperty> properties;
};

enum class PlyEncoding { Ascii, BinaryLittleEndian, BinaryBigEndian };

/// Reads PLY values one at a time from the data section, in either encoding.
class PlyValueReader {
public:
    PlyValueReader(MeshBuilder& builder, PlyEncoding encoding, const std::uint8_t* data,
                   std::size_t size)
        : mBuilder(builder),
          mEncoding(encoding),
          mData(data),
          mSize(size),
          mTokens(reinterpret_cast<const char*>(data), size) {}

    std::size_t bytesLeft() const noexcept {
        return mEncoding == PlyEncoding::Ascii ? mTokens.bytesLeft() : mSize - mPosition;
    }

    double readReal(PlyType type, const char* what) {
        if (mEncoding == PlyEncoding::Ascii) {
            const std::string_view token = nextToken(what);
            double value = 0;
            if (!parseReal(token, value))
                mBuilder.fail("bad " + std::string(what) + " value " + quoted(token));
            return value;
        }
        return readBinary(type, what);
    }

    std::int64_t readInteger(PlyType type, const char* what) {
        if (mEncoding == PlyEncoding::Ascii) {
            const std::string_view token = nextToken(what);
            std::int64_t value = 0;
            if (!parseInteger(token, value))
                mBuilder.fail("bad " + std::string(what) + " value " + quoted(token));
            return value;
        }
        return std::int64_t(readBinary(type, what));
    }

    /// Skips one property value of any kind.
    void skip(PlyType type, const char* what) {
        if (mEncoding == PlyEncoding::Ascii) {
            nextToken(what);
            return;
        }
        const std::size_t bytes = plyTypeSize(type);
        if (mSize - mPosition < bytes) truncated(what);
        mPosition += bytes;
    }

private:
    [[noreturn]] void truncated(const char* what) const {
        mBuilder.fail(std::string("file ends inside the ") + what + " data");
    }

    std::string_view nextToken(const char* what) {
        const std::string_view token = mTokens.next();
        if (token.empty()) truncated(what);
        return token;
    }

    double readBinary(PlyType type, const char* what) {
        const std::size_t bytes = plyTypeSize(type);
        if (mSize - mPosition < bytes) truncated(what);
        std::uint8_t raw[8];
        std::memcpy(raw, mData + mPosition, bytes);
        mPosition += bytes;
        if (mEncoding == PlyEncoding::BinaryBigEndian)
            std::reverse(raw, raw + bytes);  // host is little-endian
        switch (type) {
            case PlyType::Int8:
                return double(std::int8_t(raw[0]));
            case PlyType::UInt8:
                return double(raw[0]);
            case PlyType::Int16: {
                std::int16_t v;
                std::memcpy(&v, raw, 2);
                return double(v);
            }
            case PlyType::UInt16: {
                std::uint16_t v;
                std::memcpy(&v, raw, 2);
                return double(v);
            }
            case PlyType::Int32: {
                std::int32_t v;
                std::memcpy(&v, raw, 4);
                return double(v);
            }
            case PlyType::UInt32: {
                std::uint32_t v;
                std::memcpy(&v, raw, 4);
                return double(v);
            }
            case PlyType::Float32: {
                float v;
                std::memcpy(&v, raw, 4);
                return double(v);
            }
            case PlyType::Float64: {
                double v;
                std::memcpy(&v, raw, 8);
                return v;
            }
        }
        return 0.0;
    }

    MeshBuilder& mBuilder;
    PlyEncoding mEncoding;
    const std::uint8_t* mData;
    std::size_t mSize;
    std::size_t mPosition = 0;
    TokenReader mTokens;
};

static_assert(sizeof(float) == 4 && sizeof(double) == 8, "IEEE floats expected");

TriangleMesh readPly(const std::string& name, const std::uint8_t* data, std::size_t size) {
    MeshBuilder builder(name, 0);
    LineReader lines(reinterpret_cast<const char*>(data), size);
    std::string_view line;
    if (!lines.next(line, false) || (line != "ply" && line != "ply\r"))
        builder.fail("not a PLY file (no 'ply' line)");

    PlyEncoding encoding = PlyEncoding::Ascii;
    bool haveFormat = false;
    std::vector<PlyElement> elements;
    for (;;) {
        if (!lines.next(line, false)) builder.fail("file ends inside the header (no 'end_header')");
        LineTokens tokens(line);
        const std::string_view keyword = tokens.next();
        const std::string where = "header line " + std::to_string(lines.lineNumber()) + ": ";
        if (keyword == "end_header") break;
        if (keyword.empty() || keyword == "comment" || keyword == "obj_info") continue;
        if (keyword == "format") {
            const std::string_view format = tokens.next();
            if (format == "ascii")
                encoding = PlyEncoding::Ascii;
            else if (format == "binary_little_endian")
                encoding = PlyEncoding::BinaryLittleEndian;
            else if (format == "binary_big_endian")
                encoding = PlyEncoding::BinaryBigEndian;
            else
                builder.fail(where + "unknown format " + quoted(format));
            haveFormat = true;
        } else if (keyword == "element") {
            PlyElement element;
            element.name = std::string(tokens.next());
            const std::string_view countToken = tokens.next();
            std::int64_t count = 0;
            if (element.name.empty() || !parseInteger(countToken, count) || count < 0)
                builder.fail(where + "bad element line");
            element.count = std::uint64_t(count);
            elements.push_back(std::move(element));
        } else if (keyword == "property") {
            if (elements.empty()) builder.fail(where + "property before any element");
            PlyProperty property;
            std::string_view typeName = tokens.next();
            if (typeName == "list") {
                property.isList = true;
                if (!plyTypeFromName(tokens.next(), property.countType) ||
                    !plyTypeIsInteger(property.countType))
                    builder.fail(where + "bad list count type");
                typeName = tokens.next();
            }
            if (!plyTypeFromName(typeName, property.valueType))
                builder.fail(where + "unknown property type " + quoted(typeName));
            property.name = std::string(tokens.next());
            if (property.name.empty()) builder.fail(where + "property without a name");
            elements.back().properties.push_back(std::move(property));
        } else {
            builder.fail(where + "unknown header keyword " + quoted(keyword));
        }
    }
    if (!haveFormat) builder.fail("the header has no 'format' line");

    const std::size_t dataOffset = size - lines.bytesLeft();
    PlyValueReader reader(builder, encoding, data + dataOffset, size - dataOffset);

    // Refuse counts the data section cannot hold before allocating anything:
    // each item needs at least its fixed-size part (binary) or one character
    // and a separator per property (ASCII).
    {
        std::uint64_t available =
            std::uint64_t(reader.bytesLeft()) + 1;  // the last ASCII value needs no separator
        for (const PlyElement& element : elements) {
            std::uint64_t perItem = 0;
            for (const PlyProperty& property : element.properties)
                perItem +=
                    encoding == PlyEncoding::Ascii
                        ? 2
                        : plyTypeSize(property.isList ? property.countType : property.valueType);
            if (element.count > kMaxElementCount ||
                (perItem > 0 && element.count > available / perItem))
                builder.fail("element " + quoted(std::string_view(element.name)) + " claims " +
                             std::to_string(element.count) + " items but the file has only " +
                             std::to_string(reader.bytesLeft()) + " bytes of data");
            available -= perItem * element.count;
        }
    }

    // Faces are checked against the declared vertex count (0 without a vertex
    // element), so the vertex element may come before or after the faces.
    std::uint64_t declaredVertices = 0;
    bool haveFaceElement = false;
    for (const PlyElement& element : elements)
        if (element.name == "vertex") declaredVertices += element.count;

    std::vector<std::int64_t> polygon;
    for (const PlyElement& element : elements) {
        if (element.name == "vertex") {
            int axisProperty[3] = {-1, -1, -1};
            for (std::size_t p = 0; p < element.properties.size(); ++p) {
                const PlyProperty& property = element.properties[p];
                for (int axis = 0; axis < 3; ++axis)
                    if (!property.isList && property.name == std::string(1, char('x' + axis)))
                        axisProperty[axis] = int(p);
            }
            if (axisProperty[0] < 0 || axisProperty[1] < 0 || axisProperty[2] < 0)
                builder.fail("the vertex element lacks one of the properties x, y, z");
            builder.reserve(element.count, 0);
            for (std::uint64_t v = 0; v < element.count; ++v) {
                double xyz[3] = {0, 0, 0};
                for (std::size_t p = 0; p < element.properties.size(); ++p) {
                    const PlyProperty& property = element.properties[p];
                    int axis = -1;
                    for (int a = 0; a < 3; ++a)
                        if (axisProperty[a] == int(p)) axis = a;
                    if (axis >= 0) {
                        xyz[axis] = reader.readReal(property.valueType, "vertex");
                    } else if (property.isList) {
                        const std::int64_t count = reader.readInteger(property.countType, "vertex");
                        if (count < 0 || std::uint64_t(count) > reader.bytesLeft())
                            builder.fail("bad list length in vertex " + std::to_string(v));
                        for (std::int64_t i = 0; i < count; ++i)
                            reader.skip(property.valueType, "vertex");
                    } else {
                        reader.skip(property.valueType, "vertex");
                    }
                }
                builder.addVertex(xyz[0], xyz[1], xyz[2]);
            }
        } else if (element.name == "face") {
            haveFaceElement = true;
            int indexProperty = -1;
            for (std::size_t p = 0; p < element.properties.size(); ++p) {
                const PlyProperty& property = element.properties[p];
                if (property.isList &&
                    (property.name == "vertex_indices" || property.name == "vertex_index"))
                    indexProperty = int(p);
            }
            if (indexProperty < 0) builder.fail("the face element has no 'vertex_indices' list");
            if (!plyTypeIsInteger(element.properties[std::size_t(indexProperty)].valueType))
                builder.fail("face vertex indices are not integers");
            builder.reserve(0, element.count);
            for (std::uint64_t f = 0; f < element.count; ++f) {
                for (std::size_t p = 0; p < element.properties.size(); ++p) {
                    const PlyProperty& property = element.properties[p];
                    if (!property.isList) {
                        reader.skip(property.valueType, "face");
                        continue;
                    }
                    const std::int64_t count = reader.readInteger(property.countType, "face");
                    if (count < 0 || std::uint64_t(count) > reader.bytesLeft())
                        builder.fail("face " + std::to_string(f) + " has a bad list length " +
                                     std::to_string(count));
                    if (int(p) != indexProperty) {
                        for (std::int64_t i = 0; i < count; ++i)
                            reader.skip(property.valueType, "face");
                        continue;
                    }
                    polygon.clear();
                    for (std::int64_t i = 0; i < count; ++i)
                        polygon.push_back(reader.readInteger(property.valueType, "face"));
                }
                builder.addFace(polygon, declaredVertices);
            }
        } else {
            // Any other element (edges, materials, ...): skip it value by value.
            for (std::uint64_t item = 0; item < element.count; ++item)
                for (const PlyProperty& property : element.properties) {
                    if (!property.isList) {
                        reader.skip(property.valueType, "element");
                        continue;
                    }
                    const std::int64_t count = reader.readInteger(property.countType, "element");
                    if (count < 0 || std::uint64_t(count) > reader.bytesLeft())
                        builder.fail("element " + quoted(std::string_view(element.name)) +
                                     " has a bad list length " + std::to_string(count));
                    for (std::int64_t i = 0; i < count; ++i)
                        reader.skip(property.valueType, "element");
                }
        }
    }
    if (!haveFaceElement) builder.fail("the file has no face element");
    return builder.finish();
}

void appendNumber(std::string& out, double value) {
    char buffer[32];
    const auto result =
        std::to_chars(buffer, buffer + sizeof buffer, value);  // shortest exact form
    out.append(buffer, result.ptr);
}

void appendNumber(std::string& out, std::uint64_t value) {
    char buffer[24];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    out.append(buffer, result.ptr);
}

}  // namespace

MeshFormat meshFormatFromPath(const std::filesystem::path& path) {
    const std::string extension = toLower(path.extension().string());
    if (extension == ".off") return MeshFormat::Off;
    if (extension == ".obj") return MeshFormat::Obj;
    if (extension == ".stl") return MeshFormat::Stl;
    if (extension == ".ply") return MeshFormat::Ply;
    throw InputError(path.string(),
                     "unknown mesh format '" + extension + "' (expected .off, .obj, .stl or .ply)");
}

const char* meshFormatName(MeshFormat format) noexcept {
    switch (format) {
        case MeshFormat::Off:
            return "off";
        case MeshFormat::Obj:
            return "obj";
        case MeshFormat::Stl:
            return "stl";
        case MeshFormat::Ply:
            return "ply";
    }
    return "?";
}

TriangleMesh readMeshFromMemory(const std::string& name, MeshFormat format,
                                const std::uint8_t* data, std::size_t size) {
    static const std::uint8_t empty = 0;
    if (data == nullptr) data = &empty, size = 0;
    const char* text = reinterpret_cast<const char*>(data);
    switch (format) {
        case MeshFormat::Off:
            return readOff(name, text, size);
        case MeshFormat::Obj:
            return readObj(name, text, size);
        case MeshFormat::Stl:
            return readStl(name, data, size);
        case MeshFormat::Ply:
            return readPly(name, data, size);
    }
    throw InputError(name, "unknown mesh format");
}

TriangleMesh readMesh(const std::filesystem::path& path) {
    const MeshFormat format = meshFormatFromPath(path);
    // readFileBytes refuses directories, FIFOs and devices before opening them
    // (opening a FIFO would block, a directory "reads" as garbage).
    const std::string bytes = readFileBytes(path);
    return readMeshFromMemory(path.string(), format,
                              reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
}

void writeOff(const std::filesystem::path& path, const TriangleMesh& mesh) {
    // Group triangles by face and decide, per face, whether they form the fan
    // readMesh makes; only then can the polygon be written back.
    const std::size_t triangleCount = mesh.triangles.size();
    std::vector<std::vector<std::uint32_t>> polygons;
    std::size_t t = 0;
    while (t < triangleCount) {
        std::size_t last = t + 1;
        while (last < triangleCount && mesh.triangleFace[last] == mesh.triangleFace[t]) ++last;
        bool isFan = true;
        for (std::size_t k = t + 1; k < last; ++k)
            if (mesh.triangles[k][0] != mesh.triangles[t][0] ||
                mesh.triangles[k][1] != mesh.triangles[k - 1][2])
                isFan = false;
        if (isFan) {
            std::vector<std::uint32_t> polygon = {mesh.triangles[t][0], mesh.triangles[t][1],
                                                  mesh.triangles[t][2]};
            for (std::size_t k = t + 1; k < last; ++k) polygon.push_back(mesh.triangles[k][2]);
            polygons.push_back(std::move(polygon));
        } else {
            for (std::size_t k = t; k < last; ++k)
                polygons.push_back(
                    {mesh.triangles[k][0], mesh.triangles[k][1], mesh.triangles[k][2]});
        }
        t = last;
    }

    std::string out;
    out.reserve(mesh.vertices.size() * 40 + triangleCount * 24 + 64);
    out += "OFF\n";
    appendNumber(out, std::uint64_t(mesh.vertices.size()));
    out += ' ';
    appendNumber(out, std::uint64_t(polygons.size()));
    out += " 0\n";
    for (const auto& vertex : mesh.vertices) {
        for (int c = 0; c < 3; ++c) {
            if (c) out += ' ';
            appendNumber(out, vertex[std::size_t(c)]);
        }
        out += '\n';
    }
    for (const auto& polygon : polygons) {
        appendNumber(out, std::uint64_t(polygon.size()));
        for (std::uint32_t index : polygon) {
            out += ' ';
            appendNumber(out, std::uint64_t(index));
        }
        out += '\n';
    }
    writeFileAtomically(path, out);
}

std::vector<double> faceAreas(const TriangleMesh& mesh) {
    std::vector<double> areas(mesh.faceCount, 0.0);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& a = mesh.vertices[mesh.triangles[t][0]];
        const auto& b = mesh.vertices[mesh.triangles[t][1]];
        const auto& c = mesh.vertices[mesh.triangles[t][2]];
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const double cross[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                                 u[0] * v[1] - u[1] * v[0]};
        areas[mesh.triangleFace[t]] +=
            0.5 * std::sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
    }
    return areas;
}

}  // namespace skelseg
