// skelseg: checks of a mesh's soundness before it is voxelised.
//
// The voxeliser decides inside from outside; that is exact only for a closed
// surface. checkMesh() counts what can make it inexact and meshWarnings()
// turns the counts into one-line warnings for the user. Vertices at identical
// positions count as one vertex here (STL-like soups and seams where a writer
// duplicated vertices are still closed surfaces). Edges and positions are
// counted in sorted lists (n log n), faster than hashing on large meshes.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "io/mesh/MeshIO.h"

namespace skelseg {

struct MeshDiagnostics {
    /// Input faces with (numerically) zero area.
    std::size_t degenerateFaces = 0;
    /// Edges used by exactly one triangle (holes, open borders).
    std::size_t boundaryEdges = 0;
    /// Edges used by more than two triangles.
    std::size_t nonManifoldEdges = 0;
    /// Edges of two triangles that run along them the same way: one of the
    /// two is wound against the other (a flipped face). The voxeliser's
    /// rules that need a piece's outside skip such pieces (MeshOrientation.h).
    std::size_t misorientedEdges = 0;
    /// Connected pieces (triangles joined through shared vertices).
    std::size_t pieces = 0;
    /// Vertices no face uses (they take no part in the shape, its size or
    /// its voxel grid).
    std::size_t unusedVertices = 0;
    /// True when every edge is used by an even number (>= 2) of triangles:
    /// the surface encloses a volume and inside/outside is well defined.
    bool closed = false;
    /// True when some face has area and every vertex the faces use lies in
    /// the plane of the face with the largest area (within 1e-9 of the box's
    /// diagonal): a flat mesh bounds no volume, closed or not.
    bool flat = false;
};

/// Counts degenerate faces, boundary and non-manifold edges and pieces.
MeshDiagnostics checkMesh(const TriangleMesh& mesh);

/// Per triangle: 1 where it is degenerate by checkMesh()'s measure (area at
/// most 1e-14 of the squared diagonal of the box of the vertices faces use).
/// Such a triangle bounds nothing; the voxeliser leaves it out, as
/// rasterised it is a line segment, and one between two far corners (a
/// face "1 1 2") drew a line of voxels across the shape.
std::vector<char> degenerateTriangles(const TriangleMesh& mesh);

/// The key of the undirected edge between vertices a and b.
inline std::uint64_t undirectedEdgeKey(std::uint32_t a, std::uint32_t b) noexcept {
    return a < b ? (std::uint64_t(a) << 32) | b : (std::uint64_t(b) << 32) | a;
}

/// Calls visit(first, count) once per run of adjacent elements of `values`
/// that same(a, b) holds equal, in order: on a sorted list, once per
/// distinct value with its count.
template <class T, class Same, class Visit>
void forEachRun(const std::vector<T>& values, Same&& same, Visit&& visit) {
    for (std::size_t first = 0; first < values.size();) {
        std::size_t last = first + 1;
        while (last < values.size() && same(values[last], values[first])) ++last;
        visit(first, last - first);
        first = last;
    }
}

/// Sorts `edgeKeys` (undirected edges, undirectedEdgeKey) and calls
/// visit(key, uses) once per distinct edge in key order: equal keys are
/// adjacent after sorting, which counts a million edges faster than a hash
/// map. checkMesh() counts edge uses with it.
template <class Visit>
void forEachEdgeUseCount(std::vector<std::uint64_t>& edgeKeys, Visit&& visit) {
    std::sort(edgeKeys.begin(), edgeKeys.end());
    forEachRun(edgeKeys, std::equal_to<>{},
               [&](std::size_t first, std::size_t uses) { visit(edgeKeys[first], uses); });
}

/// One use of the undirected edge (low, high) by a triangle: 12 bytes, a
/// mesh's own size, not a hash map's.
struct EdgeUse {
    std::uint32_t low, high, triangle;
};

inline bool sameEdge(const EdgeUse& x, const EdgeUse& y) {
    return x.low == y.low && x.high == y.high;
}

/// Every use of an edge by one of `triangles` (vertex triples, triangle =
/// index in the list), sorted by edge and then triangle, so that the uses of
/// one edge are adjacent (forEachRun with sameEdge). Edges between equal
/// corners are left out, as checkMesh() leaves them out.
std::vector<EdgeUse> sortedEdgeUses(const std::vector<std::array<std::uint32_t, 3>>& triangles);

/// "its only face has zero area" or "all N faces have zero area": the start
/// of a refusal of a mesh none of whose faces has an area.
std::string noFaceHasArea(std::size_t faceCount);

/// One line per problem found, each starting with "FILE: ", e.g.
/// "hand.off: mesh is not closed (124 boundary edges); the inside is estimated".
/// Empty for a sound mesh.
std::vector<std::string> meshWarnings(const MeshDiagnostics& diagnostics, const std::string& file);

/// For every vertex, the smallest index of a vertex at the bitwise-same
/// position (-0 = +0): #vertices entries. Lets adjacency be computed on
/// meshes whose writers duplicated vertices.
std::vector<std::uint32_t> canonicalVertices(const TriangleMesh& mesh);

/// The triangles of `mesh` with every corner its canonical vertex
/// (canonicalVertices): triangles that meet at a position share the corner.
std::vector<std::array<std::uint32_t, 3>> canonicalTriangles(const TriangleMesh& mesh);

/// The corner (0, 1 or 2) of triangle t with the smallest position (x, then
/// y, then z). Where skelseg starts a triangle, winding kept, so that what is
/// computed on it rounds the same whichever corner the file starts it at
/// (docs/meshes.md, "The same mesh in another face order").
inline std::size_t smallestCorner(const TriangleMesh& mesh, std::size_t t) {
    const auto& c = mesh.triangles[t];
    std::size_t first = 0;
    for (std::size_t k = 1; k < 3; ++k)
        if (mesh.vertices[c[k]] < mesh.vertices[c[first]]) first = k;
    return first;
}

}  // namespace skelseg
