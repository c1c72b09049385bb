#include "io/mesh/MeshGenus.h"

#include <algorithm>
#include <array>
#include <utility>
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
    // Every use of an edge with its triangle, sorted so that the uses of one
    // edge are adjacent.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> uses;
    uses.reserve(std::size_t(count) * 3);
    for (std::uint32_t i = 0; i < count; ++i)
        for (int k = 0; k < 3; ++k)
            uses.emplace_back(undirectedEdgeKey(triangles[i][std::size_t(k)],
                                                triangles[i][std::size_t((k + 1) % 3)]),
                              i);
    std::sort(uses.begin(), uses.end());

    // Pieces: triangles joined through shared edges. Fans: the corners at a
    // vertex joined through the edges at it (corner 3i + k is corner k of
    // triangle i). A vertex where fans meet only at the point (a pinch: two
    // parts that touch in one vertex) counts once per fan, as if pulled
    // apart, so a closed piece's V - E + F is that of a surface; counted as
    // one vertex it made chi odd and the piece was left out of the genus.
    DisjointSets piece(count), fan(std::size_t(count) * 3);
    const auto corner = [&](std::uint32_t t, std::uint32_t vertex) {
        const auto& c = triangles[t];
        return 3 * t + (c[0] == vertex ? 0u : c[1] == vertex ? 1u : 2u);
    };
    std::vector<std::array<std::uint32_t, 2>> edgeRuns;  // first use, use count
    for (std::size_t first = 0; first < uses.size();) {
        std::size_t last = first + 1;
        while (last < uses.size() && uses[last].first == uses[first].first) ++last;
        for (std::size_t u = first + 1; u < last; ++u)
            piece.unite(uses[first].second, uses[u].second);
        if (last - first == 2) {
            const std::uint64_t key = uses[first].first;
            for (const auto vertex : {std::uint32_t(key >> 32), std::uint32_t(key)})
                fan.unite(corner(uses[first].second, vertex),
                          corner(uses[first + 1].second, vertex));
        }
        edgeRuns.push_back({std::uint32_t(first), std::uint32_t(last - first)});
        first = last;
    }

    struct PieceCounts {
        std::int64_t fans = 0, edges = 0, faces = 0;
        bool manifold = true;
    };
    std::vector<PieceCounts> pieces(count);  // by the piece's root triangle
    for (std::uint32_t t = 0; t < count; ++t) {
        PieceCounts& p = pieces[piece.find(t)];
        ++p.faces;
        for (std::uint32_t k = 0; k < 3; ++k)
            if (fan.find(3 * t + k) == 3 * t + k) ++p.fans;
    }
    for (const auto& [first, useCount] : edgeRuns) {
        PieceCounts& p = pieces[piece.find(uses[first].second)];
        ++p.edges;
        if (useCount != 2) p.manifold = false;
    }

    MeshTopology topology;
    for (std::uint32_t t = 0; t < count; ++t) {
        if (piece.find(t) != t) continue;
        const PieceCounts& p = pieces[t];
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
