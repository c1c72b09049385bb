#include "io/render/MeshSimplification.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <limits>

namespace skelseg {

namespace {

constexpr float kTargetError = 0.05f;  // relative to the segment's extent

void simplifySegment(SegmentMesh& mesh, std::size_t targetTriangles) {
    if (mesh.triangles.size() <= targetTriangles) return;
    const std::size_t indexCount = 3 * mesh.triangles.size();
    const auto* indices = reinterpret_cast<const unsigned int*>(mesh.triangles.data());
    const auto* positions = reinterpret_cast<const float*>(mesh.positions.data());
    std::vector<unsigned int> kept(indexCount);
    std::size_t keptCount =
        meshopt_simplify(kept.data(), indices, indexCount, positions, mesh.positions.size(),
                         sizeof(mesh.positions[0]), 3 * targetTriangles, kTargetError, 0, nullptr);
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
