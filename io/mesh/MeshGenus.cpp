#include "io/mesh/MeshGenus.h"

#include <algorithm>
#include <numeric>
#include <vector>

#include "io/mesh/MeshCheck.h"

namespace skelseg {

MeshTopology meshTopology(const TriangleMesh& mesh) {
    const std::vector<std::uint32_t> canonical = canonicalVertices(mesh);
    const std::size_t vertexCount = mesh.vertices.size();

    // Pieces: union-find over canonical vertices joined by triangles.
    std::vector<std::uint32_t> parent(vertexCount);
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    std::vector<std::array<std::uint32_t, 3>> triangles;
    triangles.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) {
        const std::array<std::uint32_t, 3> c{canonical[t[0]], canonical[t[1]], canonical[t[2]]};
        if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
        triangles.push_back(c);
        for (int k = 1; k < 3; ++k) {
            const std::uint32_t a = find(c[0]), b = find(c[std::size_t(k)]);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
    }

    struct PieceCounts {
        std::int64_t vertices = 0, edges = 0, faces = 0;
        bool manifold = true;
    };
    // Indexed by the piece's root vertex; edge uses are counted in a sorted
    // list (forEachEdgeUseCount).
    std::vector<PieceCounts> pieces(vertexCount);
    std::vector<char> isPiece(vertexCount, 0);
    std::vector<char> used(vertexCount, 0);
    std::vector<std::uint64_t> edgeKeys;
    edgeKeys.reserve(triangles.size() * 3);
    for (const auto& t : triangles) {
        const std::uint32_t root = find(t[0]);
        isPiece[root] = 1;
        ++pieces[root].faces;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[std::size_t(k)], b = t[std::size_t((k + 1) % 3)];
            if (!used[a]) {
                used[a] = 1;
                ++pieces[find(a)].vertices;
            }
            edgeKeys.push_back(undirectedEdgeKey(a, b));
        }
    }
    forEachEdgeUseCount(edgeKeys, [&](std::uint64_t key, std::size_t uses) {
        PieceCounts& piece = pieces[find(std::uint32_t(key >> 32))];
        ++piece.edges;
        if (uses != 2) piece.manifold = false;
    });

    MeshTopology topology;
    for (std::size_t root = 0; root < vertexCount; ++root) {
        if (!isPiece[root]) continue;
        const PieceCounts& piece = pieces[root];
        const std::int64_t chi = piece.vertices - piece.edges + piece.faces;
        if (!piece.manifold || chi % 2 != 0) {
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
