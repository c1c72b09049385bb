#include "io/mesh/MeshFinsAndHoles.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

#include <fmt/format.h>

namespace skelseg {
namespace {

/// The triangles `members` of `mesh` as a mesh of their own, holding only
/// the vertices they use, so that trying every sheet costs the size of the
/// sheets and not their number times the mesh's.
TriangleMesh subMesh(const TriangleMesh& mesh, const std::vector<std::uint32_t>& members,
                     std::vector<std::uint32_t>& newIndex) {
    TriangleMesh part;
    for (const std::uint32_t t : members) {
        std::array<std::uint32_t, 3> corners{};
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t v = mesh.triangles[t][k];
            if (newIndex[v] == UINT32_MAX) {
                newIndex[v] = std::uint32_t(part.vertices.size());
                part.vertices.push_back(mesh.vertices[v]);
            }
            corners[k] = newIndex[v];
        }
        part.triangles.push_back(corners);
        part.triangleFace.push_back(std::uint32_t(part.faceCount++));
    }
    for (const std::uint32_t t : members)
        for (const std::uint32_t v : mesh.triangles[t]) newIndex[v] = UINT32_MAX;
    return part;
}

}  // namespace

std::optional<MeshWithFinsDroppedAndHolesCapped> closedWithoutFinsAndHoles(
    const TriangleMesh& mesh) {
    const std::vector<std::uint32_t> sheet = openSheets(mesh);
    std::vector<std::vector<std::uint32_t>> members;
    for (std::uint32_t t = 0; t < std::uint32_t(sheet.size()); ++t) {
        if (sheet[t] == kNotInOpenSheet) continue;
        if (sheet[t] >= members.size()) members.resize(sheet[t] + 1);
        members[sheet[t]].push_back(t);
    }
    std::vector<double> sheetArea(members.size(), 0.0);
    double area = 0.0;
    for (std::uint32_t t = 0; t < std::uint32_t(sheet.size()); ++t) {
        const double triangle = triangleArea(mesh, t);
        area += triangle;
        if (sheet[t] != kNotInOpenSheet) sheetArea[sheet[t]] += triangle;
    }
    // Largest sheets first, and a stop once the fins found hold more than
    // their share: a triangle soup is refused after about its first
    // hundredth instead of trying every triangle.
    std::vector<std::uint32_t> order(members.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return sheetArea[a] > sheetArea[b]; });
    std::vector<char> fin(sheet.size(), 0);
    std::vector<std::uint32_t> newIndex(mesh.vertices.size(), UINT32_MAX);
    double finArea = 0.0;
    for (const std::uint32_t s : order) {
        if (closedWithHolesCapped(subMesh(mesh, members[s], newIndex))) continue;
        for (const std::uint32_t t : members[s]) fin[t] = 1;
        finArea += sheetArea[s];
        if (!(finArea <= kMaxFinAreaShare * area)) return std::nullopt;
    }
    std::optional<MeshWithoutFins> withoutFins = withoutTriangles(mesh, fin);
    if (!withoutFins) return std::nullopt;
    std::optional<MeshWithHolesCapped> capped = closedWithHolesCapped(withoutFins->mesh);
    if (!capped) return std::nullopt;
    return MeshWithFinsDroppedAndHolesCapped{std::move(*withoutFins), std::move(*capped)};
}

std::string finsAndHolesWarning(const std::string& file, const MeshWithoutFins& withoutFins,
                                const MeshWithHolesCapped& capped) {
    const std::size_t holes = capped.holes;
    return fmt::format(
        "{}: {} on fins (open pieces whose openings are too large to cap; {:.2g}% of its "
        "area) and the rest has {} hole{} (capped, {:.2g}% of its area): its voxel model is "
        "made without the fins and with the hole{} capped, as for a closed mesh; every face "
        "of the mesh is labelled, the fins' from the parts they touch",
        file, finFacesLie(withoutFins), 100.0 * withoutFins.finAreaShare, holes,
        holes == 1 ? "" : "s", 100.0 * capped.capAreaShare, holes == 1 ? "" : "s");
}

}  // namespace skelseg
