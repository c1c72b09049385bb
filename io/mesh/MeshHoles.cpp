#include "io/mesh/MeshHoles.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "kernels/DisjointSets.h"

namespace skelseg {
namespace {

using Point = std::array<double, 3>;

double areaOf(const Point& a, const Point& b, const Point& c) {
    const Point u{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const Point v{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const Point n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

}  // namespace

std::optional<MeshWithHolesCapped> closedWithHolesCapped(const TriangleMesh& mesh) {
    const std::size_t count = mesh.triangles.size();
    const std::vector<std::array<std::uint32_t, 3>> corners = canonicalTriangles(mesh);
    const std::vector<EdgeUse> uses = sortedEdgeUses(corners);
    DisjointSets pieces(count);
    // A hole's border runs against the windings of the triangles along it:
    // the cap triangle across the edge u -> v of triangle t has v -> u.
    // Per border vertex v: u, and t (whose piece the hole opens).
    std::unordered_map<std::uint32_t, std::pair<std::uint32_t, std::uint32_t>> borderNext;
    bool pinched = false;
    forEachRun(uses, sameEdge, [&](std::size_t first, std::size_t n) {
        for (std::size_t k = 1; k < n; ++k)
            pieces.unite(uses[first].triangle, uses[first + k].triangle);
        if (n != 1) return;
        const EdgeUse& use = uses[first];
        const auto& c = corners[use.triangle];
        std::uint32_t from = use.low, to = use.high;  // the triangle's direction
        for (std::size_t k = 0; k < 3; ++k)
            if (c[k] == use.high && c[(k + 1) % 3] == use.low) std::swap(from, to);
        if (!borderNext.emplace(to, std::make_pair(from, use.triangle)).second) pinched = true;
    });
    if (borderNext.empty() || pinched) return std::nullopt;

    std::vector<double> pieceArea(count, 0.0), capArea(count, 0.0);
    double area = 0.0;
    for (std::uint32_t t = 0; t < std::uint32_t(count); ++t) {
        const double triangle = triangleArea(mesh, t);
        pieceArea[pieces.find(t)] += triangle;
        area += triangle;
    }
    MeshWithHolesCapped result;
    result.mesh = mesh;
    // Walk each border loop once, from its smallest vertex, so that the
    // caps do not depend on the order of the faces in the file.
    std::vector<std::uint32_t> starts;
    starts.reserve(borderNext.size());
    for (const auto& [vertex, next] : borderNext) starts.push_back(vertex);
    std::sort(starts.begin(), starts.end());
    std::unordered_set<std::uint32_t> walked;
    double capTotal = 0.0;
    for (const std::uint32_t start : starts) {
        if (walked.count(start)) continue;
        std::vector<std::uint32_t> loop;
        for (std::uint32_t v = start;;) {
            walked.insert(v);
            loop.push_back(v);
            const auto next = borderNext.find(v);
            if (next == borderNext.end()) return std::nullopt;  // a border that does not close
            v = next->second.first;
            if (v == start) break;
            if (walked.count(v) || loop.size() > borderNext.size()) return std::nullopt;
        }
        if (loop.size() < 3) return std::nullopt;
        Point centre{0.0, 0.0, 0.0};
        for (const std::uint32_t v : loop)
            for (std::size_t k = 0; k < 3; ++k) centre[k] += mesh.vertices[v][k];
        for (std::size_t k = 0; k < 3; ++k) centre[k] /= double(loop.size());
        const auto centreIndex = std::uint32_t(result.mesh.vertices.size());
        result.mesh.vertices.push_back(centre);
        const auto face = std::uint32_t(result.mesh.faceCount++);
        double cap = 0.0;
        for (std::size_t k = 0; k < loop.size(); ++k) {
            const std::uint32_t a = loop[k], b = loop[(k + 1) % loop.size()];
            result.mesh.triangles.push_back({a, b, centreIndex});
            result.mesh.triangleFace.push_back(face);
            cap += areaOf(mesh.vertices[a], mesh.vertices[b], centre);
        }
        capArea[pieces.find(borderNext.at(start).second)] += cap;
        capTotal += cap;
        ++result.holes;
    }
    // Areas beyond a double: an infinite cap passes its piece's test
    // (inf <= inf), and the share inf / inf, a NaN, refuses the caps.
    for (std::size_t p = 0; p < count; ++p)
        if (capArea[p] > 0.0 && !(capArea[p] <= kMaxHoleCapAreaShare * pieceArea[p]))
            return std::nullopt;
    result.capAreaShare = area > 0.0 ? capTotal / area : 1.0;
    if (!(result.capAreaShare <= kMaxHoleCapAreaShare)) return std::nullopt;
    result.diagnostics = checkMesh(result.mesh);
    if (!result.diagnostics.closed || result.diagnostics.flat) return std::nullopt;
    return result;
}

std::string holesWarning(const std::string& file, const MeshWithHolesCapped& capped) {
    const bool one = capped.holes == 1;
    return fmt::format(
        "{}: the mesh has {} hole{} (free borders; capped, {:.2g}% of its area): its voxel model "
        "is made with {} capped, as for a closed mesh, and only the mesh's own faces are "
        "labelled",
        file, capped.holes, one ? "" : "s", 100.0 * capped.capAreaShare, one ? "it" : "them");
}

}  // namespace skelseg
