#include "io/mesh/MeshFins.h"

#include <algorithm>
#include <cstdint>
#include <utility>

#include <fmt/format.h>

#include "io/mesh/MeshCheck.h"
#include "kernels/DisjointSets.h"

namespace skelseg {

std::vector<char> finTriangles(const TriangleMesh& mesh) {
    const std::vector<std::uint32_t> canonical = canonicalVertices(mesh);
    const std::size_t count = mesh.triangles.size();
    // (edge, triangle) pairs: one sort gives each edge's triangles side by side.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> uses;
    uses.reserve(count * 3);
    for (std::uint32_t t = 0; t < std::uint32_t(count); ++t)
        for (std::size_t corner = 0; corner < 3; ++corner) {
            const std::uint32_t a = canonical[mesh.triangles[t][corner]];
            const std::uint32_t b = canonical[mesh.triangles[t][(corner + 1) % 3]];
            if (a != b) uses.emplace_back(undirectedEdgeKey(a, b), t);
        }
    std::sort(uses.begin(), uses.end());
    DisjointSets sheets(count);
    std::vector<char> hasFreeEdge(count, 0), hasSharedEdge(count, 0);
    forEachRun(
        uses, [](const auto& x, const auto& y) { return x.first == y.first; },
        [&](std::size_t first, std::size_t n) {
            if (n == 2) sheets.unite(uses[first].second, uses[first + 1].second);
            for (std::size_t i = first; i < first + n; ++i) {
                if (n == 1) hasFreeEdge[uses[i].second] = 1;
                if (n > 2) hasSharedEdge[uses[i].second] = 1;
            }
        });
    std::vector<char> sheetFree(count, 0), sheetShared(count, 0);
    for (std::uint32_t t = 0; t < std::uint32_t(count); ++t) {
        const std::uint32_t sheet = sheets.find(t);
        sheetFree[sheet] |= hasFreeEdge[t];
        sheetShared[sheet] |= hasSharedEdge[t];
    }
    std::vector<char> fin(count, 0);
    for (std::uint32_t t = 0; t < std::uint32_t(count); ++t) {
        const std::uint32_t sheet = sheets.find(t);
        fin[t] = sheetFree[sheet] && sheetShared[sheet];
    }
    return fin;
}

std::optional<MeshWithoutFins> closedWithoutFins(const TriangleMesh& mesh) {
    const std::vector<char> fin = finTriangles(mesh);
    if (std::find(fin.begin(), fin.end(), 1) == fin.end()) return std::nullopt;
    MeshWithoutFins result;
    result.mesh.vertices = mesh.vertices;
    double finArea = 0.0, area = 0.0;
    // Input faces whose triangles are all fins, and the kept faces' new numbers.
    std::vector<std::uint32_t> keptFace(mesh.faceCount, UINT32_MAX);
    std::vector<char> faceHasFin(mesh.faceCount, 0);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const double triangle = triangleArea(mesh, t);
        area += triangle;
        const std::uint32_t face = mesh.triangleFace[t];
        if (fin[t]) {
            finArea += triangle;
            faceHasFin[face] = 1;
            continue;
        }
        if (keptFace[face] == UINT32_MAX) keptFace[face] = std::uint32_t(result.mesh.faceCount++);
        result.mesh.triangles.push_back(mesh.triangles[t]);
        result.mesh.triangleFace.push_back(keptFace[face]);
    }
    // A polygon's triangles are joined across its fan diagonals, so they
    // lie in one sheet, unless a diagonal is also another face's edge: such
    // a face, partly kept, is not counted as a fin's.
    for (std::size_t face = 0; face < mesh.faceCount; ++face)
        result.finFaces += faceHasFin[face] && keptFace[face] == UINT32_MAX;
    result.finAreaShare = area > 0.0 ? finArea / area : 1.0;
    if (!(result.finAreaShare <= kMaxFinAreaShare) || result.mesh.triangles.empty())
        return std::nullopt;
    const MeshDiagnostics rest = checkMesh(result.mesh);
    if (!rest.closed || rest.flat) return std::nullopt;
    return result;
}

std::string finsWarning(const std::string& file, const MeshWithoutFins& withoutFins) {
    const bool one = withoutFins.finFaces == 1;
    return fmt::format(
        "{}: {} face{} on fins (sheets with a free border, joined to the surface only along "
        "edges of more than two faces; {:.2g}% of its area): the mesh is closed without them, "
        "so they are left out of its voxel model and take the labels of the parts they touch",
        file, withoutFins.finFaces, one ? " lies" : "s lie", 100.0 * withoutFins.finAreaShare);
}

}  // namespace skelseg
