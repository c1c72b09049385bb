#include "io/mesh/MeshIO.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "io/files/OutputDirectory.h"
#include "io/files/TextFile.h"
#include "io/mesh/ObjReader.h"
#include "io/mesh/OffReader.h"
#include "io/mesh/PlyReader.h"
#include "io/mesh/StlReader.h"
#include "kernels/base/Error.h"

namespace skelseg {

namespace {

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
    const std::string extension = lowercase(path.extension().string());
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
    // What is wrong with the path (missing, a directory, a FIFO, which would
    // block) before what its name says: a directory has no extension to judge.
    checkReadableFile(path);
    const MeshFormat format = meshFormatFromPath(path);
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

ScaledTriangleEdges scaledTriangleEdges(const TriangleMesh& mesh, std::size_t t) {
    const auto& a = mesh.vertices[mesh.triangles[t][0]];
    const auto& b = mesh.vertices[mesh.triangles[t][1]];
    const auto& c = mesh.vertices[mesh.triangles[t][2]];
    ScaledTriangleEdges edges{
        {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, {c[0] - a[0], c[1] - a[1], c[2] - a[2]}, 0, false};
    // Products of the edges are fourth powers of the coordinates' scale:
    // they overflowed for a mesh at 1e80 and underflowed to 0 at 1e-90, well
    // inside the boxes the readers accept (1e-100 to 1e100), and such a
    // sphere was refused as "flat" or "all faces have zero area". Scaling by
    // a power of two is exact: at any other scale the results keep their bits.
    double largest = 0.0;
    for (std::size_t k = 0; k < 3; ++k)
        largest = std::max({largest, std::abs(edges.u[k]), std::abs(edges.v[k])});
    edges.zero = !(largest > 0.0);
    if (edges.zero) return edges;
    edges.exponent = std::isfinite(largest) ? std::ilogb(largest) : 0;
    for (std::size_t k = 0; k < 3; ++k) {
        edges.u[k] = std::ldexp(edges.u[k], -edges.exponent);
        edges.v[k] = std::ldexp(edges.v[k], -edges.exponent);
    }
    return edges;
}

double triangleArea(const TriangleMesh& mesh, std::size_t t) {
    const ScaledTriangleEdges edges = scaledTriangleEdges(mesh, t);
    if (edges.zero) return 0.0;
    const auto& u = edges.u;
    const auto& v = edges.v;
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                         u[0] * v[1] - u[1] * v[0]};
    return std::ldexp(0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), 2 * edges.exponent);
}

VertexBox usedVertexBox(const TriangleMesh& mesh) {
    VertexBox box{{HUGE_VAL, HUGE_VAL, HUGE_VAL}, {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}};
    for (const auto& triangle : mesh.triangles)
        for (std::uint32_t v : triangle)
            for (std::size_t c = 0; c < 3; ++c) {
                box.low[c] = std::min(box.low[c], mesh.vertices[v][c]);
                box.high[c] = std::max(box.high[c], mesh.vertices[v][c]);
            }
    return box;
}

double axisProjectedArea(const TriangleMesh& mesh) {
    const VertexBox box = usedVertexBox(mesh);
    double longest = 0.0;
    for (std::size_t c = 0; c < 3; ++c) longest = std::max(longest, box.high[c] - box.low[c]);
    if (!(longest > 0.0) || !std::isfinite(longest)) return 0.0;
    // In units of the longest side: no product overflows however large the
    // coordinates (a mesh at 1e80).
    const double unit = 1.0 / longest;
    double sum = 0.0;
    for (const auto& triangle : mesh.triangles) {
        const auto& a = mesh.vertices[triangle[0]];
        const auto& b = mesh.vertices[triangle[1]];
        const auto& c = mesh.vertices[triangle[2]];
        const double u[3] = {(b[0] - a[0]) * unit, (b[1] - a[1]) * unit, (b[2] - a[2]) * unit};
        const double v[3] = {(c[0] - a[0]) * unit, (c[1] - a[1]) * unit, (c[2] - a[2]) * unit};
        sum += std::abs(u[1] * v[2] - u[2] * v[1]) + std::abs(u[2] * v[0] - u[0] * v[2]) +
               std::abs(u[0] * v[1] - u[1] * v[0]);
    }
    return 0.5 * sum;
}

std::vector<double> faceAreas(const TriangleMesh& mesh) {
    std::vector<double> areas(mesh.faceCount, 0.0);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        areas[mesh.triangleFace[t]] += triangleArea(mesh, t);
    return areas;
}

}  // namespace skelseg
