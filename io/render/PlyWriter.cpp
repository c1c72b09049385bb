#include "io/render/PlyWriter.h"

#include <climits>
#include <cstring>
#include <string>

#include "io/files/OutputDirectory.h"
#include "io/render/Palette.h"
#include "kernels/base/Error.h"

namespace skelseg {

namespace {

/// Appends values in little-endian byte order whatever the host order is: the
/// header promises binary_little_endian, so the bytes are composed by shifts.
class LittleEndianBuffer {
public:
    explicit LittleEndianBuffer(std::string header, std::size_t bodyBytes)
        : mBytes(std::move(header)) {
        mBytes.reserve(mBytes.size() + bodyBytes);
    }
    void putUint8(std::uint8_t value) { mBytes.push_back(char(value)); }
    void putUint32(std::uint32_t value) {
        const char bytes[4] = {char(value & 0xFFu), char((value >> 8) & 0xFFu),
                               char((value >> 16) & 0xFFu), char((value >> 24) & 0xFFu)};
        mBytes.append(bytes, 4);
    }
    void putInt32(std::int32_t value) { putUint32(std::uint32_t(value)); }
    void putFloat(float value) {
        std::uint32_t bits = 0;
        static_assert(sizeof(bits) == sizeof(value), "PLY float is IEEE binary32");
        std::memcpy(&bits, &value, sizeof(bits));
        putUint32(bits);
    }
    void putPosition(const std::array<double, 3>& position) {
        for (double coordinate : position) putFloat(float(coordinate));
    }
    const std::string& bytes() const noexcept { return mBytes; }

private:
    std::string mBytes;
};

std::string headerStart(const char* comment) {
    return std::string("ply\nformat binary_little_endian 1.0\ncomment skelseg ") + comment + "\n";
}

/// PLY "int" indices are signed 32-bit: larger lists cannot be written.
void checkCountFitsInt(const std::filesystem::path& file, std::size_t count, const char* what) {
    if (count > std::size_t(INT_MAX))
        throw OutputError(file.string() + ": too many " + what + " for a PLY int index (" +
                          std::to_string(count) + ")");
}

}  // namespace

void writeSkeletonPly(const std::filesystem::path& file,
                      const std::vector<SkeletonPointRecord>& points,
                      const std::vector<std::array<std::uint32_t, 2>>& edges) {
    checkCountFitsInt(file, points.size(), "skeleton points");
    for (std::size_t e = 0; e < edges.size(); ++e)
        for (std::uint32_t end : edges[e])
            if (end >= points.size())
                throw OutputError(file.string() + ": skeleton edge " + std::to_string(e) +
                                  " refers to point " + std::to_string(end) + " but there are " +
                                  std::to_string(points.size()) + " points");

    std::string header = headerStart("curve skeleton (world coordinates)");
    header += "element vertex " + std::to_string(points.size()) + "\n";
    header +=
        "property float x\nproperty float y\nproperty float z\n"
        "property float rho_s\nproperty float rho_c\nproperty float sigma\n"
        "property uchar junction\nproperty uchar critical\n";
    header += "element edge " + std::to_string(edges.size()) + "\n";
    header += "property int vertex1\nproperty int vertex2\nend_header\n";

    LittleEndianBuffer buffer(std::move(header), points.size() * 26 + edges.size() * 8);
    for (const auto& point : points) {
        buffer.putPosition(point.position);
        buffer.putFloat(point.rhoS);
        buffer.putFloat(point.rhoC);
        buffer.putFloat(point.sigma);
        buffer.putUint8(point.junction ? 1 : 0);
        buffer.putUint8(point.critical ? 1 : 0);
    }
    for (const auto& edge : edges) {
        buffer.putInt32(std::int32_t(edge[0]));
        buffer.putInt32(std::int32_t(edge[1]));
    }
    writeFileAtomically(file, buffer.bytes());
}

void writeCutsPly(const std::filesystem::path& file,
                  const std::vector<std::vector<std::array<double, 3>>>& loops) {
    std::size_t vertexCount = 0, edgeCount = 0;
    for (const auto& loop : loops) {
        vertexCount += loop.size();
        edgeCount += loop.size() >= 3 ? loop.size() : loop.size() == 2 ? 1 : 0;
    }
    checkCountFitsInt(file, vertexCount, "cut loop points");
    checkCountFitsInt(file, loops.size(), "cut loops");

    std::string header =
        headerStart("cut loops: closed polylines, property cut = loop index (world coordinates)");
    header += "element vertex " + std::to_string(vertexCount) + "\n";
    header += "property float x\nproperty float y\nproperty float z\nproperty int cut\n";
    header += "element edge " + std::to_string(edgeCount) + "\n";
    header += "property int vertex1\nproperty int vertex2\nproperty int cut\nend_header\n";

    LittleEndianBuffer buffer(std::move(header), vertexCount * 16 + edgeCount * 12);
    for (std::size_t l = 0; l < loops.size(); ++l)
        for (const auto& point : loops[l]) {
            buffer.putPosition(point);
            buffer.putInt32(std::int32_t(l));
        }
    std::size_t first = 0;
    for (std::size_t l = 0; l < loops.size(); ++l) {
        const std::size_t n = loops[l].size();
        // A two-point "loop" would otherwise get the same edge twice.
        const std::size_t edgesOfLoop = n >= 3 ? n : n == 2 ? 1 : 0;
        for (std::size_t i = 0; i < edgesOfLoop; ++i) {
            buffer.putInt32(std::int32_t(first + i));
            buffer.putInt32(std::int32_t(first + (i + 1) % n));
            buffer.putInt32(std::int32_t(l));
        }
        first += n;
    }
    writeFileAtomically(file, buffer.bytes());
}

void writeColouredMeshPly(const std::filesystem::path& file,
                          const std::vector<std::array<double, 3>>& vertices,
                          const std::vector<std::array<std::uint32_t, 3>>& triangles,
                          const std::vector<std::uint32_t>& triangleLabels) {
    if (triangleLabels.size() != triangles.size())
        throw OutputError(file.string() + ": " + std::to_string(triangles.size()) +
                          " triangles but " + std::to_string(triangleLabels.size()) +
                          " triangle labels");
    checkCountFitsInt(file, vertices.size(), "vertices");
    for (std::size_t t = 0; t < triangles.size(); ++t)
        for (std::uint32_t corner : triangles[t])
            if (corner >= vertices.size())
                throw OutputError(file.string() + ": triangle " + std::to_string(t) +
                                  " refers to vertex " + std::to_string(corner) +
                                  " but there are " + std::to_string(vertices.size()) +
                                  " vertices");
    for (std::size_t t = 0; t < triangleLabels.size(); ++t)
        if (triangleLabels[t] > std::uint32_t(INT_MAX))
            throw OutputError(file.string() + ": triangle " + std::to_string(t) + " has label " +
                              std::to_string(triangleLabels[t]) + ", too large for a PLY int");

    std::string header = headerStart(
        "segments: face colour and property segment = segment label (world coordinates)");
    header += "element vertex " + std::to_string(vertices.size()) + "\n";
    header += "property float x\nproperty float y\nproperty float z\n";
    header += "element face " + std::to_string(triangles.size()) + "\n";
    header +=
        "property list uchar int vertex_indices\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\n"
        "property int segment\nend_header\n";

    LittleEndianBuffer buffer(std::move(header), vertices.size() * 12 + triangles.size() * 20);
    for (const auto& vertex : vertices) buffer.putPosition(vertex);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        buffer.putUint8(3);
        for (std::uint32_t corner : triangles[t]) buffer.putInt32(std::int32_t(corner));
        const auto colour = segmentColour(triangleLabels[t]);
        for (std::uint8_t channel : colour) buffer.putUint8(channel);
        buffer.putInt32(std::int32_t(triangleLabels[t]));
    }
    writeFileAtomically(file, buffer.bytes());
}

}  // namespace skelseg
