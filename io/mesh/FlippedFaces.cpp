#include "io/mesh/FlippedFaces.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include <fmt/format.h>

namespace skelseg {
namespace {

/// Whether triangle `corners` runs along its edge from `from` to `to`.
bool runsFrom(const std::array<std::uint32_t, 3>& corners, std::uint32_t from, std::uint32_t to) {
    for (std::size_t k = 0; k < 3; ++k)
        if (corners[k] == from && corners[(k + 1) % 3] == to) return true;
    return false;
}

}  // namespace

std::optional<MeshWithFlippedFacesTurned> withFlippedFacesTurned(const TriangleMesh& mesh) {
    const std::size_t count = mesh.triangles.size();
    const std::vector<std::array<std::uint32_t, 3>> corners = canonicalTriangles(mesh);
    const std::vector<EdgeUse> uses = sortedEdgeUses(corners);
    // Neighbours across edges of two triangles, with whether the neighbour
    // must be turned relative to the triangle (both run the edge one way).
    struct Neighbour {
        std::uint32_t triangle;
        bool opposite;
    };
    std::vector<std::uint32_t> degree(count + 1, 0);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    std::vector<char> pairOpposite;
    forEachRun(uses, sameEdge, [&](std::size_t first, std::size_t n) {
        if (n != 2) return;
        const EdgeUse &a = uses[first], &b = uses[first + 1];
        if (a.triangle == b.triangle) return;
        const bool aForward = runsFrom(corners[a.triangle], a.low, a.high);
        const bool bForward = runsFrom(corners[b.triangle], b.low, b.high);
        pairs.emplace_back(a.triangle, b.triangle);
        pairOpposite.push_back(aForward == bForward);
        ++degree[a.triangle + 1];
        ++degree[b.triangle + 1];
    });
    if (std::find(pairOpposite.begin(), pairOpposite.end(), 1) == pairOpposite.end())
        return std::nullopt;
    for (std::size_t t = 0; t < count; ++t) degree[t + 1] += degree[t];
    std::vector<Neighbour> neighbours(degree[count]);
    {
        std::vector<std::uint32_t> next(degree.begin(), degree.end() - 1);
        for (std::size_t p = 0; p < pairs.size(); ++p) {
            const auto [a, b] = pairs[p];
            neighbours[next[a]++] = {b, pairOpposite[p] != 0};
            neighbours[next[b]++] = {a, pairOpposite[p] != 0};
        }
    }

    // Two-colour each sheet from its first triangle: 1 = turned against it.
    constexpr std::int8_t kUnseen = -1;
    std::vector<std::int8_t> turned(count, kUnseen);
    std::vector<std::uint32_t> sheet, stack;
    bool anyTurned = false;
    for (std::uint32_t seed = 0; seed < std::uint32_t(count); ++seed) {
        if (turned[seed] != kUnseen) continue;
        sheet.clear();
        stack.assign(1, seed);
        turned[seed] = 0;
        bool orientable = true;
        double area = 0.0, turnedArea = 0.0;
        while (!stack.empty()) {
            const std::uint32_t t = stack.back();
            stack.pop_back();
            sheet.push_back(t);
            const double triangle = triangleArea(mesh, t);
            area += triangle;
            if (turned[t]) turnedArea += triangle;
            for (std::uint32_t k = degree[t]; k < degree[t + 1]; ++k) {
                const Neighbour& n = neighbours[k];
                const std::int8_t wanted = std::int8_t(turned[t] ^ std::int8_t(n.opposite));
                if (turned[n.triangle] == kUnseen) {
                    turned[n.triangle] = wanted;
                    stack.push_back(n.triangle);
                } else if (turned[n.triangle] != wanted) {
                    orientable = false;
                }
            }
        }
        // Keep the winding most of the sheet's area has; a sheet that cannot
        // be wound one way is left as read.
        const bool invert = orientable && turnedArea > area - turnedArea;
        for (const std::uint32_t t : sheet) {
            turned[t] = std::int8_t(orientable && (turned[t] != 0) != invert);
            anyTurned |= turned[t] != 0;
        }
    }
    if (!anyTurned) return std::nullopt;

    MeshWithFlippedFacesTurned result;
    result.mesh = mesh;
    double area = 0.0, turnedArea = 0.0;
    std::vector<char> faceTurned(mesh.faceCount, 0);
    for (std::size_t t = 0; t < count; ++t) {
        const double triangle = triangleArea(mesh, t);
        area += triangle;
        if (!turned[t]) continue;
        turnedArea += triangle;
        std::swap(result.mesh.triangles[t][1], result.mesh.triangles[t][2]);
        faceTurned[mesh.triangleFace[t]] = 1;
    }
    for (const char f : faceTurned) result.turnedFaces += f != 0;
    result.turnedAreaShare = area > 0.0 ? turnedArea / area : 0.0;
    result.diagnostics = checkMesh(result.mesh);
    return result;
}

std::string flippedFacesWarning(const std::string& file, const MeshWithFlippedFacesTurned& turned) {
    const bool one = turned.turnedFaces == 1;
    return fmt::format(
        "{}: {} face{} wound against the faces around {} (flipped; {:.2g}% of its area): {} "
        "turned for its voxel model, so that surfaces touching there are told apart",
        file, turned.turnedFaces, one ? " was" : "s were", one ? "it" : "them",
        100.0 * turned.turnedAreaShare, one ? "it is" : "they are");
}

}  // namespace skelseg
