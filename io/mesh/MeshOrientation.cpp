#include "io/mesh/MeshOrientation.h"

#include <numeric>
#include <unordered_map>
#include <utility>

#include "io/mesh/MeshCheck.h"

namespace skelseg {

std::vector<std::int8_t> triangleOrientation(
    const std::vector<std::array<std::uint32_t, 3>>& triangles,
    const std::vector<std::array<double, 3>>& points, const std::vector<std::uint32_t>& piece) {
    std::unordered_map<std::uint64_t, std::uint32_t> directedUses;
    directedUses.reserve(triangles.size() * 3);
    std::unordered_map<std::uint32_t, std::pair<bool, double>> pieceOrientation;
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const auto& c = triangles[t];
        auto& [consistent, volume] =
            pieceOrientation.try_emplace(piece[t], true, 0.0).first->second;
        // A triangle with a repeated corner has no area and bounds nothing:
        // one on an existing edge (`f 1 1 2`) would use that edge a second
        // time and take the whole piece's side away.
        if (c[0] == c[1] || c[1] == c[2] || c[2] == c[0]) continue;
        for (std::size_t k = 0; k < 3; ++k)
            if (++directedUses[(std::uint64_t(c[k]) << 32) | c[(k + 1) % 3]] > 1)
                consistent = false;
        const auto &p0 = points[c[0]], &p1 = points[c[1]], &p2 = points[c[2]];
        volume += p0[0] * (p1[1] * p2[2] - p1[2] * p2[1]) -
                  p0[1] * (p1[0] * p2[2] - p1[2] * p2[0]) + p0[2] * (p1[0] * p2[1] - p1[1] * p2[0]);
    }
    std::vector<std::int8_t> orientation;
    orientation.reserve(triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const auto& [consistent, volume] = pieceOrientation.at(piece[t]);
        orientation.push_back(!consistent || volume == 0.0 ? 0 : volume > 0.0 ? 1 : -1);
    }
    return orientation;
}

CanonicalSurface canonicalSurface(const TriangleMesh& mesh, const VolumeGeometry& geometry) {
    CanonicalSurface surface;
    const std::vector<std::uint32_t> canonical = canonicalVertices(mesh);
    const double inverseVoxel = 1.0 / geometry.voxelSize();
    surface.points.resize(mesh.vertices.size());
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
        for (std::size_t c = 0; c < 3; ++c)
            surface.points[v][c] = (mesh.vertices[v][c] - geometry.origin[c]) * inverseVoxel;
    std::vector<std::uint32_t> parent(mesh.vertices.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    surface.triangles.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) {
        const std::array<std::uint32_t, 3> c{canonical[t[0]], canonical[t[1]], canonical[t[2]]};
        surface.triangles.push_back(c);
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t ru = find(c[k]), rv = find(c[(k + 1) % 3]);
            if (ru != rv) parent[std::max(ru, rv)] = std::min(ru, rv);
        }
    }
    surface.piece.reserve(surface.triangles.size());
    for (const auto& c : surface.triangles) surface.piece.push_back(find(c[0]));
    return surface;
}

}  // namespace skelseg
