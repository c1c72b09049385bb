#include "io/mesh/MeshCheck.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>

#include "kernels/DisjointSets.h"

namespace skelseg {

std::vector<std::uint32_t> canonicalVertices(const TriangleMesh& mesh) {
    // Sorting the positions' bit patterns groups equal positions; a stable
    // sort keeps each group in index order, so its first vertex is the
    // smallest index. Several times faster than hashing every position on
    // meshes of 100k vertices and more (docs/performance.md).
    const std::size_t n = mesh.vertices.size();
    std::vector<std::array<std::uint64_t, 3>> bits(n);
    for (std::size_t v = 0; v < n; ++v)
        for (std::size_t c = 0; c < 3; ++c) {
            double coordinate = mesh.vertices[v][c];
            if (coordinate == 0.0) coordinate = 0.0;  // -0 and +0 are one position
            std::memcpy(&bits[v][c], &coordinate, 8);
        }
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return bits[a] < bits[b]; });
    std::vector<std::uint32_t> canonical(n);
    for (std::size_t i = 0; i < n; ++i)
        canonical[order[i]] =
            i > 0 && bits[order[i]] == bits[order[i - 1]] ? canonical[order[i - 1]] : order[i];
    return canonical;
}

std::vector<std::array<std::uint32_t, 3>> canonicalTriangles(const TriangleMesh& mesh) {
    const std::vector<std::uint32_t> canonical = canonicalVertices(mesh);
    std::vector<std::array<std::uint32_t, 3>> corners(mesh.triangles.size());
    for (std::size_t t = 0; t < corners.size(); ++t)
        for (std::size_t k = 0; k < 3; ++k) corners[t][k] = canonical[mesh.triangles[t][k]];
    return corners;
}

namespace {

/// The vertices faces use and the squared diagonal of their box: the size
/// that degenerate faces are measured against, as the voxel grid's box. A
/// vertex no face uses, far away, made every face of a cube "zero area".
struct UsedVertices {
    std::vector<char> isReferenced;
    std::size_t unused = 0;
    double diagonalSquared = 0.0;
};

UsedVertices usedVertices(const TriangleMesh& mesh) {
    UsedVertices used;
    used.isReferenced.assign(mesh.vertices.size(), 0);
    for (const auto& triangle : mesh.triangles)
        for (std::uint32_t v : triangle) used.isReferenced[v] = 1;
    used.unused = std::size_t(std::count(used.isReferenced.begin(), used.isReferenced.end(), 0));
    if (used.unused < mesh.vertices.size()) {
        const VertexBox box = usedVertexBox(mesh);
        for (std::size_t c = 0; c < 3; ++c)
            used.diagonalSquared += (box.high[c] - box.low[c]) * (box.high[c] - box.low[c]);
    }
    return used;
}

/// Zero area relative to the mesh size (absolute zero would miss faces that
/// are zero up to rounding).
double degenerateAreaTolerance(const UsedVertices& used) {
    return 1e-14 * used.diagonalSquared;
}

}  // namespace

std::vector<char> degenerateTriangles(const TriangleMesh& mesh) {
    const double tolerance = degenerateAreaTolerance(usedVertices(mesh));
    std::vector<char> degenerate(mesh.triangles.size(), 0);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        degenerate[t] = !(triangleArea(mesh, t) > tolerance);
    return degenerate;
}

MeshDiagnostics checkMesh(const TriangleMesh& mesh) {
    MeshDiagnostics diagnostics;
    const std::vector<std::uint32_t> canonical = canonicalVertices(mesh);

    const UsedVertices usedBox = usedVertices(mesh);
    const std::vector<char>& isReferenced = usedBox.isReferenced;
    diagnostics.unusedVertices = usedBox.unused;
    const double diagonalSquared = usedBox.diagonalSquared;
    const double areaTolerance = degenerateAreaTolerance(usedBox);
    std::vector<double> areas(mesh.faceCount, 0.0);
    // The largest triangle's normal is the best conditioned plane the mesh
    // offers for the flatness test below.
    std::size_t largest = mesh.triangles.size();
    double largestArea = areaTolerance;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const double area = triangleArea(mesh, t);
        areas[mesh.triangleFace[t]] += area;
        if (area > largestArea) largestArea = area, largest = t;
    }
    for (double area : areas)
        if (!(area > areaTolerance)) ++diagnostics.degenerateFaces;

    // Flat: every used vertex in the plane of the largest triangle.
    if (largest < mesh.triangles.size()) {
        const auto& a = mesh.vertices[mesh.triangles[largest][0]];
        // Scaled (exactly) as in triangleArea(): the normal's squared length
        // overflowed for a mesh at 1e80.
        const ScaledTriangleEdges edges = scaledTriangleEdges(mesh, largest);
        const auto& u = edges.u;
        const auto& w = edges.v;
        std::array<double, 3> normal{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                                     u[0] * w[1] - u[1] * w[0]};
        const double length =
            std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
        for (double& n : normal) n /= length;
        const double planeTolerance = 1e-9 * std::sqrt(diagonalSquared);
        diagnostics.flat = true;
        for (std::size_t v = 0; v < mesh.vertices.size() && diagnostics.flat; ++v) {
            if (!isReferenced[v]) continue;
            const auto& p = mesh.vertices[v];
            const double height =
                (p[0] - a[0]) * normal[0] + (p[1] - a[1]) * normal[1] + (p[2] - a[2]) * normal[2];
            diagnostics.flat = std::abs(height) <= planeTolerance;
        }
    }

    // Edges: count uses of every undirected edge between distinct (canonical)
    // vertices. Fan diagonals inside a polygon are used twice, like any
    // interior edge (forEachEdgeUseCount).
    // Each use's key is the undirected edge with its direction in the lowest
    // bit (a < b or not), so that one sort gives both the use counts and
    // whether the two triangles of an edge run along it the same way. Vertex
    // indices stay below 2^31 (2^31 vertices would need 48 GB).
    std::vector<std::uint64_t> edgeKeys;
    edgeKeys.reserve(mesh.triangles.size() * 3);
    DisjointSets pieces(mesh.vertices.size());
    std::vector<char> used(mesh.vertices.size(), 0);
    for (const auto& triangle : mesh.triangles) {
        for (int corner = 0; corner < 3; ++corner) {
            std::uint32_t a = canonical[triangle[std::size_t(corner)]];
            std::uint32_t b = canonical[triangle[std::size_t((corner + 1) % 3)]];
            used[a] = 1;
            if (a == b) continue;
            pieces.unite(a, b);
            edgeKeys.push_back((std::uint64_t(std::min(a, b)) << 33) |
                               (std::uint64_t(std::max(a, b)) << 1) | std::uint64_t(a < b));
        }
    }
    std::sort(edgeKeys.begin(), edgeKeys.end());
    bool everyEdgeEven = true;
    for (std::size_t first = 0; first < edgeKeys.size();) {
        std::size_t last = first + 1;
        while (last < edgeKeys.size() && edgeKeys[last] >> 1 == edgeKeys[first] >> 1) ++last;
        const std::size_t uses = last - first;
        if (uses == 1) ++diagnostics.boundaryEdges;
        if (uses > 2) ++diagnostics.nonManifoldEdges;
        if (uses % 2 != 0) everyEdgeEven = false;
        if (uses == 2 && edgeKeys[first] == edgeKeys[first + 1]) ++diagnostics.misorientedEdges;
        first = last;
    }
    diagnostics.closed = everyEdgeEven && !edgeKeys.empty();
    for (std::uint32_t v = 0; v < std::uint32_t(mesh.vertices.size()); ++v)
        if (used[v] && pieces.find(v) == v) ++diagnostics.pieces;
    return diagnostics;
}

std::vector<EdgeUse> sortedEdgeUses(const std::vector<std::array<std::uint32_t, 3>>& triangles) {
    std::vector<EdgeUse> uses;
    uses.reserve(triangles.size() * 3);
    for (std::uint32_t i = 0; i < triangles.size(); ++i)
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t a = triangles[i][k], b = triangles[i][(k + 1) % 3];
            if (a != b) uses.push_back({std::min(a, b), std::max(a, b), i});
        }
    std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
        return x.low != y.low     ? x.low < y.low
               : x.high != y.high ? x.high < y.high
                                  : x.triangle < y.triangle;
    });
    return uses;
}

std::string noFaceHasArea(std::size_t faceCount) {
    return faceCount == 1 ? std::string("its only face has zero area")
                          : "all " + std::to_string(faceCount) + " faces have zero area";
}

std::vector<std::string> meshWarnings(const MeshDiagnostics& diagnostics, const std::string& file) {
    // "1 edge is", "2 edges are": a count with its noun and verb in number.
    const auto counted = [](std::size_t n, const char* one, const char* many) {
        return std::to_string(n) + (n == 1 ? one : many);
    };
    std::vector<std::string> warnings;
    if (!diagnostics.closed) {
        if (diagnostics.boundaryEdges > 0)
            warnings.push_back(
                file + ": mesh is not closed (" +
                counted(diagnostics.boundaryEdges, " boundary edge", " boundary edges") +
                "); the inside is estimated");
        else
            warnings.push_back(file +
                               ": mesh is not closed (edges shared by an odd number of faces); the "
                               "inside is estimated");
    }
    if (diagnostics.nonManifoldEdges > 0)
        warnings.push_back(file + ": " +
                           counted(diagnostics.nonManifoldEdges, " edge is", " edges are") +
                           " shared by more than two faces (non-manifold)");
    if (diagnostics.misorientedEdges > 0)
        warnings.push_back(file + ": " +
                           counted(diagnostics.misorientedEdges, " edge joins", " edges join") +
                           " faces wound against each other (some faces are flipped); where "
                           "surfaces touch there, they may stay joined in the voxel model");
    if (diagnostics.pieces > 1)
        warnings.push_back(file + ": mesh has " + std::to_string(diagnostics.pieces) +
                           " separate pieces");
    if (diagnostics.degenerateFaces > 0)
        warnings.push_back(file + ": " +
                           counted(diagnostics.degenerateFaces,
                                   " face has zero area; it takes the label of the voxels or "
                                   "faces around it",
                                   " faces have zero area; they take the label of the voxels or "
                                   "faces around them"));
    if (diagnostics.unusedVertices > 0)
        warnings.push_back(file + ": " +
                           counted(diagnostics.unusedVertices,
                                   " vertex is used by no face; it is ignored",
                                   " vertices are used by no face; they are ignored"));
    return warnings;
}

}  // namespace skelseg
