#include "io/render/SegmentMeshes.h"

#include <algorithm>
#include <limits>
#include <string>

#include "kernels/base/Error.h"

namespace skelseg {

std::vector<SegmentMesh> splitSegmentMeshes(
    const std::vector<std::array<double, 3>>& vertices,
    const std::vector<std::array<std::uint32_t, 3>>& triangles,
    const std::vector<std::uint32_t>& triangleLabels) {
    if (triangleLabels.size() != triangles.size())
        throw UsageError("splitSegmentMeshes: " + std::to_string(triangleLabels.size()) +
                         " labels for " + std::to_string(triangles.size()) + " triangles");
    for (const auto& t : triangles)
        for (std::uint32_t v : t)
            if (v >= vertices.size())
                throw UsageError("splitSegmentMeshes: vertex index " + std::to_string(v) +
                                 " out of range (" + std::to_string(vertices.size()) +
                                 " vertices)");

    std::vector<std::uint32_t> labels(triangleLabels);
    std::sort(labels.begin(), labels.end());
    labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
    std::vector<SegmentMesh> meshes(labels.size());
    for (std::size_t s = 0; s < labels.size(); ++s) meshes[s].label = labels[s];

    // One pass per segment over its own triangles: the vertex map is reset by
    // walking the segment's triangles again, not by clearing V entries.
    constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> localIndex(vertices.size(), kUnused);
    std::vector<std::vector<std::uint32_t>> trianglesOf(labels.size());
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const auto s = std::size_t(
            std::lower_bound(labels.begin(), labels.end(), triangleLabels[t]) - labels.begin());
        trianglesOf[s].push_back(std::uint32_t(t));
    }
    for (std::size_t s = 0; s < labels.size(); ++s) {
        SegmentMesh& mesh = meshes[s];
        mesh.triangles.reserve(trianglesOf[s].size());
        for (std::uint32_t t : trianglesOf[s]) {
            std::array<std::uint32_t, 3> local{};
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t v = triangles[t][c];
                if (localIndex[v] == kUnused) {
                    localIndex[v] = std::uint32_t(mesh.positions.size());
                    mesh.positions.push_back(
                        {float(vertices[v][0]), float(vertices[v][1]), float(vertices[v][2])});
                }
                local[c] = localIndex[v];
            }
            mesh.triangles.push_back(local);
        }
        for (std::uint32_t t : trianglesOf[s])
            for (std::uint32_t v : triangles[t]) localIndex[v] = kUnused;
    }
    return meshes;
}

std::size_t triangleCount(const std::vector<SegmentMesh>& meshes) noexcept {
    std::size_t count = 0;
    for (const auto& m : meshes) count += m.triangles.size();
    return count;
}

}  // namespace skelseg
