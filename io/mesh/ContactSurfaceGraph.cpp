#include "io/mesh/ContactSurfaceGraph.h"

#include <algorithm>
#include <functional>
#include <numeric>
#include <queue>
#include <unordered_map>
#include <utility>

#include "io/mesh/MeshCheck.h"
#include "io/mesh/MeshOrientation.h"

namespace skelseg {

using vec3::distance;
using vec3::Vec3;

bool SurfaceGraph::nearOnMesh(std::int32_t ta, const Vec3& pa, std::int32_t tb, const Vec3& pb,
                              double limit) const {
    const auto& A = triangles[std::size_t(ta)];
    const auto& B = triangles[std::size_t(tb)];
    for (std::uint32_t u : A)
        for (std::uint32_t v : B)
            if (u == v || adjacent(u, v)) return true;
    std::unordered_map<std::uint32_t, double> settled, best;
    using Entry = std::pair<double, std::uint32_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    for (std::uint32_t u : A) {
        const double d = distance(pa, points[u]);
        auto [it, inserted] = best.emplace(u, d);
        if (inserted || d < it->second) {
            it->second = d;
            queue.emplace(d, u);
        }
    }
    while (!queue.empty()) {
        const auto [d, u] = queue.top();
        queue.pop();
        if (d > limit) return false;
        if (!settled.emplace(u, d).second) continue;
        for (std::uint32_t v : B)
            if (u == v && d + distance(points[v], pb) <= limit) return true;
        for (std::uint32_t n = firstNeighbour[u]; n < firstNeighbour[u + 1]; ++n) {
            const std::uint32_t v = neighbours[n];
            if (settled.count(v)) continue;
            const double candidate = d + distance(points[u], points[v]);
            if (candidate > limit) continue;
            auto [it, inserted] = best.emplace(v, candidate);
            if (inserted || candidate < it->second) {
                it->second = candidate;
                queue.emplace(candidate, v);
            }
        }
    }
    return false;
}

SurfaceGraph buildSurfaceGraph(const TriangleMesh& mesh, const VolumeGeometry& geometry) {
    SurfaceGraph graph;
    const std::vector<std::uint32_t> canonical = canonicalVertices(mesh);
    const double inverseVoxel = 1.0 / geometry.voxelSize();
    graph.points.resize(mesh.vertices.size());
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
        for (std::size_t c = 0; c < 3; ++c)
            graph.points[v][c] = (mesh.vertices[v][c] - geometry.origin[c]) * inverseVoxel;
    std::vector<std::uint32_t> parent(mesh.vertices.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    edges.reserve(mesh.triangles.size() * 6);
    graph.triangles.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) {
        const std::array<std::uint32_t, 3> c{canonical[t[0]], canonical[t[1]], canonical[t[2]]};
        graph.triangles.push_back(c);
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t u = c[k], v = c[(k + 1) % 3];
            if (u == v) continue;
            edges.emplace_back(u, v);
            edges.emplace_back(v, u);
            const std::uint32_t ru = find(u), rv = find(v);
            if (ru != rv) parent[std::max(ru, rv)] = std::min(ru, rv);
        }
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    graph.firstNeighbour.assign(mesh.vertices.size() + 1, 0);
    for (const auto& e : edges) ++graph.firstNeighbour[e.first + 1];
    std::partial_sum(graph.firstNeighbour.begin(), graph.firstNeighbour.end(),
                     graph.firstNeighbour.begin());
    graph.neighbours.reserve(edges.size());
    for (const auto& e : edges) graph.neighbours.push_back(e.second);
    graph.piece.reserve(graph.triangles.size());
    for (const auto& c : graph.triangles) graph.piece.push_back(find(c[0]));

    graph.orientation = triangleOrientation(graph.triangles, graph.points, graph.piece);
    return graph;
}

}  // namespace skelseg
