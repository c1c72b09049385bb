#include "io/mesh/MeshFins.h"

#include <algorithm>
#include <array>
#include <cstdint>

#include <fmt/format.h>

#include "kernels/DisjointSets.h"

namespace skelseg {

std::vector<std::uint32_t> openSheets(const TriangleMesh& mesh) {
    const std::size_t count = mesh.triangles.size();
    const std::vector<EdgeUse> uses = sortedEdgeUses(canonicalTriangles(mesh));
    DisjointSets sheets(count);
    std::vector<char> hasFreeEdge(count, 0);
    forEachRun(uses, sameEdge, [&](std::size_t first, std::size_t n) {
        if (n == 2) sheets.unite(uses[first].triangle, uses[first + 1].triangle);
        if (n == 1) hasFreeEdge[uses[first].triangle] = 1;
    });
    std::vector<char> sheetIsOpen(count, 0);
    for (std::uint32_t t = 0; t < std::uint32_t(count); ++t)
        sheetIsOpen[sheets.find(t)] |= hasFreeEdge[t];
    // Numbered by first triangle, so that the numbers do not depend on how
    // the union-find happened to pick its roots.
    std::vector<std::uint32_t> numberOfRoot(count, kNotInOpenSheet), sheet(count, kNotInOpenSheet);
    std::uint32_t next = 0;
    for (std::uint32_t t = 0; t < std::uint32_t(count); ++t) {
        const std::uint32_t root = std::uint32_t(sheets.find(t));
        if (!sheetIsOpen[root]) continue;
        if (numberOfRoot[root] == kNotInOpenSheet) numberOfRoot[root] = next++;
        sheet[t] = numberOfRoot[root];
    }
    return sheet;
}

std::vector<char> finTriangles(const TriangleMesh& mesh) {
    const std::vector<std::uint32_t> sheet = openSheets(mesh);
    std::vector<char> fin(sheet.size(), 0);
    for (std::size_t t = 0; t < sheet.size(); ++t) fin[t] = sheet[t] != kNotInOpenSheet;
    return fin;
}

std::optional<MeshWithoutFins> withoutTriangles(const TriangleMesh& mesh,
                                                const std::vector<char>& fin) {
    double finArea = 0.0, area = 0.0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const double triangle = triangleArea(mesh, t);
        area += triangle;
        if (fin[t]) finArea += triangle;
    }
    // Checked before the rest is copied: an open mesh with holes, whose
    // sheets round them are most of it, costs one pass more than its check.
    // A mesh without area, or of an area too large for a double, has no
    // share to compare (1 or NaN refuse it).
    const double share = area > 0.0 ? finArea / area : 1.0;
    if (std::find(fin.begin(), fin.end(), 1) == fin.end() || !(share <= kMaxFinAreaShare))
        return std::nullopt;
    MeshWithoutFins result;
    result.finAreaShare = share;
    result.mesh.vertices = mesh.vertices;
    // The kept faces' new numbers, and the faces with a fin's triangle.
    std::vector<std::uint32_t> keptFace(mesh.faceCount, UINT32_MAX);
    std::vector<char> faceHasFin(mesh.faceCount, 0);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const std::uint32_t face = mesh.triangleFace[t];
        if (fin[t]) {
            faceHasFin[face] = 1;
            continue;
        }
        if (keptFace[face] == UINT32_MAX) keptFace[face] = std::uint32_t(result.mesh.faceCount++);
        result.mesh.triangles.push_back(mesh.triangles[t]);
        result.mesh.triangleFace.push_back(keptFace[face]);
    }
    if (result.mesh.triangles.empty()) return std::nullopt;
    // A polygon's triangles are joined across its fan diagonals, so they
    // lie in one sheet, unless a diagonal is also another face's edge: such
    // a face, partly kept, is not counted as a fin's.
    for (std::size_t face = 0; face < mesh.faceCount; ++face)
        result.finFaces += faceHasFin[face] && keptFace[face] == UINT32_MAX;
    result.diagnostics = checkMesh(result.mesh);
    return result;
}

std::optional<MeshWithoutFins> closedWithoutFins(const TriangleMesh& mesh) {
    std::optional<MeshWithoutFins> result = withoutTriangles(mesh, finTriangles(mesh));
    if (!result || !result->diagnostics.closed || result->diagnostics.flat) return std::nullopt;
    return result;
}

std::string finFacesLie(const MeshWithoutFins& withoutFins) {
    // Fin triangles of faces partly kept (finFaces counts whole faces only).
    if (withoutFins.finFaces == 0) return "parts of faces lie";
    return fmt::format("{} face{}", withoutFins.finFaces,
                       withoutFins.finFaces == 1 ? " lies" : "s lie");
}

std::string finsWarning(const std::string& file, const MeshWithoutFins& withoutFins) {
    return fmt::format(
        "{}: {} on fins (open sheets standing on the surface or loose beside it; "
        "{:.2g}% of its area): the mesh is closed without them, so they are left out of its "
        "voxel model and take the labels of the parts they touch",
        file, finFacesLie(withoutFins), 100.0 * withoutFins.finAreaShare);
}

}  // namespace skelseg
