// Edits of small test meshes: opening holes in them and putting pieces
// beside them, as the tests of the fin and hole rules need.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "io/mesh/MeshIO.h"

namespace skelseg::test {

/// `mesh` without the triangles `drop(t)` says to drop, one face per triangle.
template <typename Drop>
TriangleMesh withoutTrianglesWhere(const TriangleMesh& mesh, Drop drop) {
    TriangleMesh out;
    out.vertices = mesh.vertices;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        if (drop(t)) continue;
        out.triangles.push_back(mesh.triangles[t]);
        out.triangleFace.push_back(std::uint32_t(out.faceCount++));
    }
    return out;
}

/// Height of the centre of triangle t.
inline double centroidZ(const TriangleMesh& mesh, std::size_t t) {
    const auto& c = mesh.triangles[t];
    return (mesh.vertices[c[0]][2] + mesh.vertices[c[1]][2] + mesh.vertices[c[2]][2]) / 3.0;
}

/// Appends `piece` to `mesh` as more vertices and one face per triangle.
inline void appendPiece(TriangleMesh& mesh, const TriangleMesh& piece) {
    const auto offset = std::uint32_t(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(), piece.vertices.begin(), piece.vertices.end());
    for (const auto& t : piece.triangles) {
        mesh.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
        mesh.triangleFace.push_back(std::uint32_t(mesh.faceCount++));
    }
}

/// A cup: the cube of side `side` at `low` without its top (+z) face, ten
/// outward triangles, one face each. Its cap would be a fifth of its area,
/// so it is an open piece, not a piece with a hole.
inline TriangleMesh openCup(const std::array<double, 3>& low, double side) {
    TriangleMesh cup;
    for (int corner = 0; corner < 8; ++corner)
        cup.vertices.push_back({low[0] + side * (corner & 1), low[1] + side * ((corner >> 1) & 1),
                                low[2] + side * ((corner >> 2) & 1)});
    // Corner bits: x 1, y 2, z 4. Quads wound outward; the top (4 5 7 6) left out.
    const std::uint32_t quads[5][4] = {
        {0, 2, 3, 1}, {0, 1, 5, 4}, {1, 3, 7, 5}, {3, 2, 6, 7}, {2, 0, 4, 6}};
    for (const auto& q : quads) {
        cup.triangles.push_back({q[0], q[1], q[2]});
        cup.triangles.push_back({q[0], q[2], q[3]});
    }
    for (std::uint32_t t = 0; t < 10; ++t) cup.triangleFace.push_back(t);
    cup.faceCount = 10;
    return cup;
}

}  // namespace skelseg::test
