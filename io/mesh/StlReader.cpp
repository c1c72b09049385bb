#include "io/mesh/StlReader.h"

#include <cmath>
#include <cstring>
#include <unordered_map>
#include <vector>

#include "io/files/ForeignContent.h"
#include "io/files/TextFile.h"
#include "io/files/TextTokenizer.h"
#include "io/mesh/MeshBuilder.h"
#include "kernels/base/Error.h"

namespace skelseg {

namespace {

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
            const double x = double(readFloatLittleEndian(record + 12 * corner));
            const double y = double(readFloatLittleEndian(record + 12 * corner + 4));
            const double z = double(readFloatLittleEndian(record + 12 * corner + 8));
            if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
                builder.fail("triangle " + std::to_string(t) + " has a non-finite coordinate");
            polygon[std::size_t(corner)] = welder.add(x, y, z);
        }
        builder.addFace(polygon, kCheckLater);
    }
    return builder.finish();
}

TriangleMesh readAsciiStl(const std::string& name, const char* data, std::size_t size) {
    MeshBuilder builder(name, 0);
    VertexWelder welder(builder);
    TextTokenizer tokens(data, size);
    auto where = [&] { return "line " + std::to_string(tokens.lineNumber()) + ": "; };
    auto expect = [&](const char* word) {
        const std::string_view token = tokens.nextToken();
        if (lowercase(token) != word)
            builder.fail(where() + "expected '" + word + "', found " +
                         (token.empty() ? "the end of the file" : quote(token)));
    };
    std::vector<std::int64_t> polygon;
    for (;;) {
        const std::string_view token = tokens.nextToken();
        if (token.empty()) break;
        const std::string word = lowercase(token);
        if (word == "solid" || word == "endsolid") {
            tokens.skipLine();  // the solid's name
            continue;
        }
        if (word != "facet")
            builder.fail(where() + "expected 'facet' or 'endsolid', found " + quote(token));
        // "normal nx ny nz": the normal is recomputed from the corners.
        expect("normal");
        for (int c = 0; c < 3; ++c) {
            double ignored = 0;
            const std::string_view value = tokens.nextToken();
            if (!parseReal(value, ignored))
                builder.fail(where() + "bad facet normal " + quote(value));
        }
        expect("outer");
        expect("loop");
        polygon.clear();
        for (;;) {
            const std::string_view vertexWord = tokens.nextToken();
            const std::string lower = lowercase(vertexWord);
            if (lower == "endloop") break;
            if (lower != "vertex")
                builder.fail(where() + "expected 'vertex' or 'endloop', found " +
                             (vertexWord.empty() ? "the end of the file" : quote(vertexWord)));
            double xyz[3];
            for (double& coordinate : xyz) {
                const std::string_view value = tokens.nextToken();
                if (!parseReal(value, coordinate))
                    builder.fail(where() + "bad vertex coordinate " + quote(value));
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

}  // namespace

TriangleMesh readStl(const std::string& name, const std::uint8_t* data, std::size_t size) {
    // Binary when the size matches the triangle count in the header: many
    // binary files also begin with "solid" in their 80-byte comment.
    if (size >= 84) {
        const std::uint64_t triangleCount =
            std::uint64_t(data[80]) | (std::uint64_t(data[81]) << 8) |
            (std::uint64_t(data[82]) << 16) | (std::uint64_t(data[83]) << 24);
        if (84 + 50 * triangleCount == size) return readBinaryStl(name, data, triangleCount);
    }
    const std::size_t bom =
        textContentStart(name, std::string_view(reinterpret_cast<const char*>(data), size));
    std::size_t start = bom;
    while (start < size && isSpace(char(data[start]))) ++start;
    // ASCII STL starts with "solid" and holds no NUL byte; binary data almost
    // always does (zero attribute bytes, small floats), so a binary file whose
    // size is wrong is reported as such and not as bad ASCII.
    const bool looksAscii =
        size - start >= 5 &&
        lowercase(std::string_view(reinterpret_cast<const char*>(data) + start, 5)) == "solid" &&
        std::memchr(data, 0, size) == nullptr;
    if (looksAscii)
        return readAsciiStl(name, reinterpret_cast<const char*>(data) + bom, size - bom);
    // Every file that is neither is taken for a binary STL of the wrong size
    // below; text of another kind is more likely.
    refuseForeignContent(name, std::string_view(reinterpret_cast<const char*>(data), size), "STL");
    if (size < 84)
        throw InputError(name, "not an STL file (too short for binary, no 'solid' for ASCII)");
    const std::uint64_t triangleCount = std::uint64_t(data[80]) | (std::uint64_t(data[81]) << 8) |
                                        (std::uint64_t(data[82]) << 16) |
                                        (std::uint64_t(data[83]) << 24);
    throw InputError(name, "binary STL header says " + std::to_string(triangleCount) +
                               " triangles (" + std::to_string(84 + 50 * triangleCount) +
                               " bytes) but the file has " + std::to_string(size) + " bytes");
}

}  // namespace skelseg
