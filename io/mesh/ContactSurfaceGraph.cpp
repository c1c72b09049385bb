#include "io/mesh/ContactSurfaceGraph.h"

#include <algorithm>
#include <array>
#include <cmath>
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

std::int32_t SurfaceGraph::nearestOfTied(std::int32_t t, const Vec3& p) const {
    // Distances are in voxels: ties within this are ties (the same point
    // reached through two triangles differs by rounding only).
    constexpr double kTied = 1e-7;
    const auto& c = triangles[std::size_t(t)];
    const Vec3 q = vec3::closestPointOnTriangle(p, points[c[0]], points[c[1]], points[c[2]]);
    const double d = distance(p, q);
    if (d < kTied) return t;
    // The corners of t at q: one (a vertex) or two (an edge); none: inside.
    std::array<std::uint32_t, 2> at{};
    int corners = 0;
    for (std::size_t k = 0; k < 3 && corners == 0; ++k)
        if (distance(q, points[c[k]]) < kTied) at[corners++] = c[k];
    for (std::size_t k = 0; k < 3 && corners == 0; ++k) {
        const Vec3& a = points[c[k]];
        const Vec3& b = points[c[(k + 1) % 3]];
        const Vec3 ab = vec3::sub(b, a);
        const double length2 = vec3::dot(ab, ab);
        if (!(length2 > 0)) continue;
        const double s = std::clamp(vec3::dot(vec3::sub(q, a), ab) / length2, 0.0, 1.0);
        if (distance(q, vec3::along(a, ab, s)) < kTied) {
            at[corners++] = c[k];
            at[corners++] = c[(k + 1) % 3];
        }
    }
    if (corners == 0) return t;
    // An edge's triangles are at both its corners, in the same (ascending)
    // order in each list: walk the shorter one, so that an edge to a vertex
    // shared by 100,000 triangles (a cone's apex) does not cost a scan of
    // them all at every voxel near the edge.
    const auto triangleCountAt = [&](std::uint32_t v) {
        return firstTriangle[v + 1] - firstTriangle[v];
    };
    if (corners == 2 && triangleCountAt(at[1]) < triangleCountAt(at[0])) std::swap(at[0], at[1]);
    auto sortedCorners = [&](std::uint32_t u) {
        std::array<Vec3, 3> corner{points[triangles[u][0]], points[triangles[u][1]],
                                   points[triangles[u][2]]};
        std::sort(corner.begin(), corner.end());
        return corner;
    };
    std::int32_t best = t;
    double bestCos = -1, bestDistance = d;
    std::array<Vec3, 3> bestCorners{};
    bool bestKnown = false;
    for (std::uint32_t k = firstTriangle[at[0]]; k < firstTriangle[at[0] + 1]; ++k) {
        const std::uint32_t u = vertexTriangles[k];
        const auto& cu = triangles[u];
        if (corners == 2 && cu[0] != at[1] && cu[1] != at[1] && cu[2] != at[1]) continue;
        const Vec3 qu =
            vec3::closestPointOnTriangle(p, points[cu[0]], points[cu[1]], points[cu[2]]);
        const Vec3 away = vec3::sub(p, qu);
        const double du = std::sqrt(vec3::dot(away, away));
        if (du > bestDistance + kTied) continue;
        const Vec3 normal = vec3::cross(vec3::sub(points[cu[1]], points[cu[0]]),
                                        vec3::sub(points[cu[2]], points[cu[0]]));
        const double normalLength = std::sqrt(vec3::dot(normal, normal));
        const double cosine =
            normalLength > 0 ? std::abs(vec3::dot(normal, away)) / (normalLength * du) : 0.0;
        const bool nearer = du < bestDistance - kTied;
        if (!nearer && bestKnown) {
            if (cosine < bestCos - 1e-12) continue;
            if (cosine <= bestCos + 1e-12) {
                const auto corner = sortedCorners(u);
                if (!(corner < bestCorners)) continue;
            }
        }
        best = std::int32_t(u);
        bestCos = cosine;
        bestDistance = std::min(bestDistance, du);
        bestCorners = sortedCorners(u);
        bestKnown = true;
    }
    return best;
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
    for (std::size_t triangle = 0; triangle < mesh.triangles.size(); ++triangle) {
        // From the smallest corner: nearest points round the same whichever
        // corner the file starts the triangle at.
        const auto& t = mesh.triangles[triangle];
        const std::size_t first = smallestCorner(mesh, triangle);
        const std::array<std::uint32_t, 3> c{canonical[t[first]], canonical[t[(first + 1) % 3]],
                                             canonical[t[(first + 2) % 3]]};
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
    // A triangle is listed once at each distinct corner.
    const auto distinctCorner = [](const std::array<std::uint32_t, 3>& c, std::size_t k) {
        return k == 0 || (c[k] != c[0] && (k == 1 || c[k] != c[1]));
    };
    graph.firstTriangle.assign(mesh.vertices.size() + 1, 0);
    for (const auto& c : graph.triangles)
        for (std::size_t k = 0; k < 3; ++k)
            if (distinctCorner(c, k)) ++graph.firstTriangle[c[k] + 1];
    std::partial_sum(graph.firstTriangle.begin(), graph.firstTriangle.end(),
                     graph.firstTriangle.begin());
    graph.vertexTriangles.resize(graph.firstTriangle.back());
    {
        std::vector<std::uint32_t> next(graph.firstTriangle.begin(), graph.firstTriangle.end() - 1);
        for (std::uint32_t t = 0; t < graph.triangles.size(); ++t) {
            const auto& c = graph.triangles[t];
            for (std::size_t k = 0; k < 3; ++k)
                if (distinctCorner(c, k)) graph.vertexTriangles[next[c[k]]++] = t;
        }
    }
    graph.piece.reserve(graph.triangles.size());
    for (const auto& c : graph.triangles) graph.piece.push_back(find(c[0]));

    graph.orientation = triangleOrientation(graph.triangles, graph.points, graph.piece);
    return graph;
}

}  // namespace skelseg
