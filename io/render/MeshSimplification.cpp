#include "io/render/MeshSimplification.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>

namespace skelseg {

namespace {

constexpr float kTargetError = 0.05f;  // relative to the segment's extent

/// How far above the corner count hasCrowdedVertices lets the
/// simplifier's scans go: ordinary surfaces, about six triangles a vertex,
/// stay far below, and a segment within it costs a bounded multiple of its
/// corners.
constexpr std::uint64_t kScansPerCorner = 64;

/// True when vertices shared by very many triangles would make the
/// edge-collapse simplifier slow: meshoptimizer (0.18) scans a vertex's
/// whole list of edges for each edge that reaches it and for each collapse
/// it tries from it, about the sum over vertices of (triangles at the
/// vertex)^2 in all, quadratic in the triangles of a fan (a cone's apex
/// among 100,000 triangles). Vertices are counted by position, as
/// meshoptimizer welds them.
bool hasCrowdedVertices(const SegmentMesh& mesh) {
    // By bits, as meshoptimizer compares them (and NaN would not sort).
    std::vector<std::array<std::uint32_t, 3>> bits(mesh.positions.size());
    std::memcpy(bits.data(), mesh.positions.data(), bits.size() * sizeof(bits[0]));
    std::vector<std::uint32_t> byPosition(bits.size());
    std::iota(byPosition.begin(), byPosition.end(), 0u);
    std::sort(byPosition.begin(), byPosition.end(),
              [&](std::uint32_t a, std::uint32_t b) { return bits[a] < bits[b]; });
    std::vector<std::uint32_t> group(bits.size());
    for (std::size_t i = 0, g = 0; i < byPosition.size(); ++i) {
        if (i > 0 && bits[byPosition[i]] != bits[byPosition[i - 1]]) ++g;
        group[byPosition[i]] = std::uint32_t(g);
    }
    std::vector<std::uint64_t> trianglesAt(mesh.positions.size(), 0);
    for (const auto& t : mesh.triangles)
        for (std::uint32_t v : t) ++trianglesAt[group[v]];
    std::uint64_t scans = 0;
    for (std::uint64_t count : trianglesAt) scans += count * count;
    return scans > kScansPerCorner * 3 * std::uint64_t(mesh.triangles.size());
}

void simplifySegment(SegmentMesh& mesh, std::size_t targetTriangles) {
    if (mesh.triangles.size() <= targetTriangles) return;
    const std::size_t indexCount = 3 * mesh.triangles.size();
    const auto* indices = reinterpret_cast<const unsigned int*>(mesh.triangles.data());
    const auto* positions = reinterpret_cast<const float*>(mesh.positions.data());
    std::vector<unsigned int> kept(indexCount);
    std::size_t keptCount = 0;
    if (hasCrowdedVertices(mesh))
        keptCount = meshopt_simplifySloppy(kept.data(), indices, indexCount, positions,
                                           mesh.positions.size(), sizeof(mesh.positions[0]),
                                           3 * targetTriangles, 1.0f, nullptr);
    else
        keptCount = meshopt_simplify(kept.data(), indices, indexCount, positions,
                                     mesh.positions.size(), sizeof(mesh.positions[0]),
                                     3 * targetTriangles, kTargetError, 0, nullptr);
    if (keptCount > 3 * targetTriangles + 3 * targetTriangles / 2) {
        std::vector<unsigned int> input(kept.begin(), kept.begin() + std::ptrdiff_t(keptCount));
        keptCount = meshopt_simplifySloppy(kept.data(), input.data(), input.size(), positions,
                                           mesh.positions.size(), sizeof(mesh.positions[0]),
                                           3 * targetTriangles, 1.0f, nullptr);
    }
    if (keptCount == 0) return;  // never lose a segment from the picture
    constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> newIndex(mesh.positions.size(), kUnused);
    SegmentMesh out;
    out.label = mesh.label;
    out.triangles.resize(keptCount / 3);
    for (std::size_t i = 0; i < keptCount; ++i) {
        const unsigned int v = kept[i];
        if (newIndex[v] == kUnused) {
            newIndex[v] = std::uint32_t(out.positions.size());
            out.positions.push_back(mesh.positions[v]);
        }
        out.triangles[i / 3][i % 3] = newIndex[v];
    }
    mesh = std::move(out);
}

}  // namespace

void simplifyForDisplay(std::vector<SegmentMesh>& meshes, std::size_t maxTriangles) {
    const std::size_t total = triangleCount(meshes);
    if (total <= maxTriangles) return;
    for (SegmentMesh& mesh : meshes) {
        const double share = double(maxTriangles) * double(mesh.triangles.size()) / double(total);
        simplifySegment(mesh, std::max(kMinTrianglesPerSegment, std::size_t(share)));
    }
}

}  // namespace skelseg
