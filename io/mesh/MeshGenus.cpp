#include "io/mesh/MeshGenus.h"

#include <algorithm>
#include <array>
#include <vector>

#include "io/mesh/MeshCheck.h"
#include "kernels/DisjointSets.h"

namespace skelseg {

MeshTopology meshTopology(const TriangleMesh& mesh) {
    const std::vector<std::uint32_t> canonical = canonicalVertices(mesh);
    std::vector<std::array<std::uint32_t, 3>> triangles;
    triangles.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) {
        const std::array<std::uint32_t, 3> c{canonical[t[0]], canonical[t[1]], canonical[t[2]]};
        if (c[0] != c[1] && c[1] != c[2] && c[0] != c[2]) triangles.push_back(c);
    }
    const auto count = std::uint32_t(triangles.size());
    // Every use of an edge by a triangle, sorted so that the uses of one edge
    // are adjacent (12 bytes a use: a mesh's own size, not a hash map's).
    struct EdgeUse {
        std::uint32_t low, high, triangle;
    };
    std::vector<EdgeUse> uses;
    uses.reserve(std::size_t(count) * 3);
    for (std::uint32_t i = 0; i < count; ++i)
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t a = triangles[i][k], b = triangles[i][(k + 1) % 3];
            uses.push_back({std::min(a, b), std::max(a, b), i});
        }
    std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
        return x.low != y.low     ? x.low < y.low
               : x.high != y.high ? x.high < y.high
                                  : x.triangle < y.triangle;
    });
    const auto forEachEdge = [&](auto&& visit) {  // visit(first use, use count)
        forEachRun(
            uses,
            [](const EdgeUse& x, const EdgeUse& y) { return x.low == y.low && x.high == y.high; },
            visit);
    };

    // Pieces: triangles joined through shared edges. Fans: the corners at a
    // vertex joined through the edges at it (corner 3i + k is corner k of
    // triangle i). A vertex where fans meet only at the point (a pinch: two
    // parts that touch in one vertex) counts once per fan, as if pulled
    // apart, so a closed piece's V - E + F is that of a surface (counted as
    // one vertex, a pinch makes it odd and the piece has no genus).
    DisjointSets piece(count), fan(std::size_t(count) * 3);
    const auto corner = [&](std::uint32_t t, std::uint32_t vertex) {
        const auto& c = triangles[t];
        return 3 * t + (c[0] == vertex ? 0u : c[1] == vertex ? 1u : 2u);
    };
    forEachEdge([&](std::size_t first, std::size_t useCount) {
        for (std::size_t u = first + 1; u < first + useCount; ++u)
            piece.unite(uses[first].triangle, uses[u].triangle);
        if (useCount == 2)
            for (const std::uint32_t vertex : {uses[first].low, uses[first].high})
                fan.unite(corner(uses[first].triangle, vertex),
                          corner(uses[first + 1].triangle, vertex));
    });

    struct PieceCounts {
        std::int64_t fans = 0, edges = 0, faces = 0;
        bool manifold = true;
    };
    // The pieces in order of their root (smallest) triangle.
    std::vector<std::uint32_t> pieceOfRoot(count, 0);
    std::vector<PieceCounts> pieces;
    for (std::uint32_t t = 0; t < count; ++t)
        if (piece.find(t) == t)
            pieceOfRoot[t] = std::uint32_t(pieces.size()), pieces.emplace_back();
    forEachEdge([&](std::size_t first, std::size_t useCount) {
        PieceCounts& p = pieces[pieceOfRoot[piece.find(uses[first].triangle)]];
        ++p.edges;
        if (useCount != 2) p.manifold = false;
    });
    uses = {};
    for (std::uint32_t t = 0; t < count; ++t) {
        PieceCounts& p = pieces[pieceOfRoot[piece.find(t)]];
        ++p.faces;
        for (std::uint32_t k = 0; k < 3; ++k)
            if (fan.find(3 * t + k) == 3 * t + k) ++p.fans;
    }

    MeshTopology topology;
    for (const PieceCounts& p : pieces) {
        const std::int64_t chi = p.fans - p.edges + p.faces;
        if (!p.manifold || chi % 2 != 0) {
            ++topology.otherPieces;
            continue;
        }
        ++topology.closedPieces;
        topology.eulerCharacteristic += chi;
        topology.genus += (2 - chi) / 2;
    }
    return topology;
}

}  // namespace skelseg
