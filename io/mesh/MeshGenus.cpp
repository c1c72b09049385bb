#include "io/mesh/MeshGenus.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "io/mesh/MeshCheck.h"
#include "kernels/DisjointSets.h"

namespace skelseg {

namespace {

using Triangles = std::vector<std::array<std::uint32_t, 3>>;

Eigen::Vector3d point(const TriangleMesh& mesh, std::uint32_t vertex) {
    return Eigen::Vector3d::Map(mesh.vertices[vertex].data());
}

/// Six times the volume the triangles enclose, positive when they face
/// outwards (measured from the first vertex, which keeps the terms small).
double signedVolume(const TriangleMesh& mesh, const Triangles& triangles) {
    if (triangles.empty()) return 0;
    const Eigen::Vector3d origin = point(mesh, triangles[0][0]);
    double volume = 0;
    for (const auto& t : triangles)
        volume += (point(mesh, t[0]) - origin)
                      .dot((point(mesh, t[1]) - origin).cross(point(mesh, t[2]) - origin));
    return volume;
}

/// Drops every pair of triangles on the same three corners with opposite
/// windings: a sheet of no thickness (a writer's double-sided face, or the
/// face two solids share) that encloses nothing, and whose edges would
/// otherwise be used by more than two triangles with nothing to tell the
/// pairs apart. Appends one triangle of each pair dropped to `sheet`.
void dropDoubleSidedTriangles(Triangles& triangles, Triangles& sheet) {
    struct Corners {
        std::array<std::uint32_t, 3> sorted;
        bool flipped;  // winding opposite to the sorted corners'
        std::uint32_t triangle;
    };
    std::vector<Corners> corners(triangles.size());
    for (std::uint32_t i = 0; i < triangles.size(); ++i) {
        auto t = triangles[i];
        std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
        const bool flipped = t[1] > t[2];
        if (flipped) std::swap(t[1], t[2]);
        corners[i] = {t, flipped, i};
    }
    std::sort(corners.begin(), corners.end(), [](const Corners& a, const Corners& b) {
        return a.sorted != b.sorted     ? a.sorted < b.sorted
               : a.flipped != b.flipped ? a.flipped < b.flipped
                                        : a.triangle < b.triangle;
    });
    std::vector<bool> dropped(triangles.size(), false);
    forEachRun(
        corners, [](const Corners& a, const Corners& b) { return a.sorted == b.sorted; },
        [&](std::size_t first, std::size_t count) {
            std::size_t firstFlipped = first;
            while (firstFlipped < first + count && !corners[firstFlipped].flipped) ++firstFlipped;
            const std::size_t pairs = std::min(firstFlipped - first, first + count - firstFlipped);
            for (std::size_t k = 0; k < pairs; ++k) {
                dropped[corners[first + k].triangle] = dropped[corners[firstFlipped + k].triangle] =
                    true;
                sheet.push_back(triangles[corners[first + k].triangle]);
            }
        });
    if (sheet.empty()) return;
    std::size_t out = 0;
    for (std::size_t i = 0; i < triangles.size(); ++i)
        if (!dropped[i]) triangles[out++] = triangles[i];
    triangles.resize(out);
}

/// Of the sheets of dropped double-sided faces (`sheet`, one triangle per
/// face; `kept`: the sorted edge uses of the triangles kept), how many have
/// a genus the count cannot tell. A sheet whose every edge the kept surface
/// still uses lies between solids, and the kept surface is their union's. A
/// free sheet (some edge no kept triangle uses) is a part thinner than the
/// voxels, which the voxel model holds thickened: a disk (V - E + F = 1, a
/// fin) thickens to a ball and adds no handle; any other sheet (a strip
/// with a hole, a closed surface written double-sided) adds handles or a
/// cavity that no count of its triangles tells.
std::size_t sheetsOfUnknownGenus(const Triangles& sheet, const std::vector<EdgeUse>& kept) {
    if (sheet.empty()) return 0;
    const std::vector<EdgeUse> uses = sortedEdgeUses(sheet);
    DisjointSets component(sheet.size());
    forEachRun(uses, sameEdge, [&](std::size_t first, std::size_t count) {
        for (std::size_t u = first + 1; u < first + count; ++u)
            component.unite(uses[first].triangle, uses[u].triangle);
    });
    struct SheetCounts {
        std::int64_t vertices = 0, edges = 0, faces = 0;
        bool free = false;
    };
    std::vector<SheetCounts> counts(sheet.size());
    const auto usedByKept = [&](const EdgeUse& e) {
        return std::binary_search(kept.begin(), kept.end(), e,
                                  [](const EdgeUse& x, const EdgeUse& y) {
                                      return x.low != y.low ? x.low < y.low : x.high < y.high;
                                  });
    };
    forEachRun(uses, sameEdge, [&](std::size_t first, std::size_t) {
        SheetCounts& c = counts[component.find(uses[first].triangle)];
        ++c.edges;
        if (!usedByKept(uses[first])) c.free = true;
    });
    std::vector<std::pair<std::uint32_t, std::uint32_t>> vertexOfComponent;
    for (std::uint32_t t = 0; t < sheet.size(); ++t) {
        ++counts[component.find(t)].faces;
        for (const std::uint32_t v : sheet[t]) vertexOfComponent.push_back({component.find(t), v});
    }
    std::sort(vertexOfComponent.begin(), vertexOfComponent.end());
    vertexOfComponent.erase(std::unique(vertexOfComponent.begin(), vertexOfComponent.end()),
                            vertexOfComponent.end());
    for (const auto& [root, vertex] : vertexOfComponent) ++counts[root].vertices;
    std::size_t unknown = 0;
    for (std::uint32_t t = 0; t < sheet.size(); ++t) {
        const SheetCounts& c = counts[t];
        if (component.find(t) == t && c.free && c.vertices - c.edges + c.faces != 1) ++unknown;
    }
    return unknown;
}

/// The triangles of one edge used by more than two, paired as the surfaces
/// of solids that touch along the edge, pulled apart: in their order round
/// the edge, each triangle with the neighbour across the wedge its
/// orientation says is inside (`outward`: the mesh's triangles face
/// outwards). On success `pairing` holds positions in `run`, two by two.
/// False (no pairing) for an odd count, a triangle with no direction away
/// from the edge, two at the same angle, or orientations that do not
/// alternate round the edge: the geometry does not tell which surface goes
/// on where.
bool pairTrianglesAroundEdge(const TriangleMesh& mesh, const Triangles& triangles,
                             const EdgeUse* run, std::size_t useCount, bool outward,
                             std::vector<std::uint32_t>& pairing) {
    if (useCount % 2 != 0) return false;
    const Eigen::Vector3d low = point(mesh, run[0].low);
    const Eigen::Vector3d axis = point(mesh, run[0].high) - low;
    if (!(axis.squaredNorm() > 0)) return false;
    struct Side {
        double angle;
        bool insideAhead;  // the inside lies at larger angles
        std::uint32_t use;
    };
    std::vector<Side> sides(useCount);
    Eigen::Vector3d reference = Eigen::Vector3d::Zero();
    for (std::uint32_t u = 0; u < useCount; ++u) {
        const auto& c = triangles[run[u].triangle];
        const std::size_t at = c[0] == run[u].low ? 0 : c[1] == run[u].low ? 1 : 2;
        const bool forward = c[(at + 1) % 3] == run[u].high;  // low -> high in its winding
        const std::uint32_t apex = c[(at + (forward ? 2 : 1)) % 3];
        const Eigen::Vector3d toApex = point(mesh, apex) - low;
        const Eigen::Vector3d away = toApex - toApex.dot(axis) / axis.squaredNorm() * axis;
        if (!(away.squaredNorm() > 0)) return false;
        if (u == 0) reference = away;
        // A forward triangle's normal, axis x away, lies a quarter turn
        // ahead of it round the axis: facing outwards, its inside is behind.
        sides[u] = {std::atan2(axis.dot(reference.cross(away)), reference.dot(away)),
                    forward != outward, u};
        if (sides[u].angle < 0) sides[u].angle += 2 * M_PI;
    }
    std::sort(sides.begin(), sides.end(),
              [](const Side& a, const Side& b) { return a.angle < b.angle; });
    for (std::size_t k = 1; k < useCount; ++k)
        if (!(sides[k].angle > sides[k - 1].angle)) return false;
    const std::size_t start = sides[0].insideAhead ? 0 : 1;
    pairing.clear();
    for (std::size_t k = 0; k < useCount; k += 2) {
        const Side& opening = sides[(start + k) % useCount];  // the inside wedge between
        const Side& closing = sides[(start + k + 1) % useCount];
        if (!opening.insideAhead || closing.insideAhead) return false;
        pairing.push_back(opening.use);
        pairing.push_back(closing.use);
    }
    return true;
}

}  // namespace

MeshTopology meshTopology(const TriangleMesh& mesh) {
    const std::vector<std::uint32_t> canonical = canonicalVertices(mesh);
    Triangles triangles;
    triangles.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) {
        const std::array<std::uint32_t, 3> c{canonical[t[0]], canonical[t[1]], canonical[t[2]]};
        if (c[0] != c[1] && c[1] != c[2] && c[0] != c[2]) triangles.push_back(c);
    }
    // Every use of an edge by a triangle, sorted so that the uses of one edge
    // are adjacent.
    std::vector<EdgeUse> uses = sortedEdgeUses(triangles);
    bool anyEdgeOfMoreThanTwo = false;
    forEachRun(uses, sameEdge,
               [&](std::size_t, std::size_t useCount) { anyEdgeOfMoreThanTwo |= useCount > 2; });
    // Only such edges can be a double-sided face's: most meshes skip the sort.
    Triangles sheet;
    if (anyEdgeOfMoreThanTwo) dropDoubleSidedTriangles(triangles, sheet);
    if (!sheet.empty()) uses = sortedEdgeUses(triangles);
    const std::size_t unknownSheets = sheetsOfUnknownGenus(sheet, uses);
    sheet = {};
    const auto count = std::uint32_t(triangles.size());
    const auto forEachEdge = [&](auto&& visit) {  // visit(first use, use count)
        forEachRun(uses, sameEdge, visit);
    };

    // Pieces: triangles joined through shared edges. Fans: the corners at a
    // vertex joined through the edges at it (corner 3i + k is corner k of
    // triangle i). A vertex where fans meet only at the point (a pinch: two
    // parts that touch in one vertex) counts once per fan, as if pulled
    // apart, so a closed piece's V - E + F is that of a surface (counted as
    // one vertex, a pinch makes it odd and the piece has no genus). An edge
    // of more than two triangles is pulled apart the same way where their
    // geometry tells how (pairTrianglesAroundEdge): each pair is an edge.
    DisjointSets piece(count), fan(std::size_t(count) * 3);
    const auto corner = [&](std::uint32_t t, std::uint32_t vertex) {
        const auto& c = triangles[t];
        return 3 * t + (c[0] == vertex ? 0u : c[1] == vertex ? 1u : 2u);
    };
    const auto joinThroughEdge = [&](const EdgeUse& a, const EdgeUse& b) {
        piece.unite(a.triangle, b.triangle);
        for (const std::uint32_t vertex : {a.low, a.high})
            fan.unite(corner(a.triangle, vertex), corner(b.triangle, vertex));
    };
    int outward = -1;  // the triangles face outwards (1) or in (0); -1: not needed yet
    std::vector<std::uint32_t> pairing;
    // Pairs the triangles of a run of more than two uses (pairTrianglesAroundEdge).
    const auto paired = [&](const EdgeUse* run, std::size_t useCount) {
        if (outward < 0) outward = signedVolume(mesh, triangles) >= 0;
        return pairTrianglesAroundEdge(mesh, triangles, run, useCount, outward == 1, pairing);
    };
    forEachEdge([&](std::size_t first, std::size_t useCount) {
        const EdgeUse* run = uses.data() + first;
        if (useCount == 2) {
            joinThroughEdge(run[0], run[1]);
        } else if (useCount > 2 && paired(run, useCount)) {
            for (std::size_t k = 0; k < useCount; k += 2)
                joinThroughEdge(run[pairing[k]], run[pairing[k + 1]]);
        } else {
            for (std::size_t u = 1; u < useCount; ++u)
                piece.unite(run[0].triangle, run[u].triangle);
        }
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
    const auto pieceOf = [&](std::uint32_t t) -> PieceCounts& {
        return pieces[pieceOfRoot[piece.find(t)]];
    };
    forEachEdge([&](std::size_t first, std::size_t useCount) {
        const EdgeUse* run = uses.data() + first;
        if (useCount == 2) {
            ++pieceOf(run[0].triangle).edges;
        } else if (useCount > 2 && paired(run, useCount)) {  // one edge per pair
            for (std::size_t k = 0; k < useCount; k += 2) ++pieceOf(run[pairing[k]].triangle).edges;
        } else {
            PieceCounts& p = pieceOf(run[0].triangle);
            ++p.edges;
            p.manifold = false;
        }
    });
    uses = {};
    for (std::uint32_t t = 0; t < count; ++t) {
        PieceCounts& p = pieceOf(t);
        ++p.faces;
        for (std::uint32_t k = 0; k < 3; ++k)
            if (fan.find(3 * t + k) == 3 * t + k) ++p.fans;
    }

    MeshTopology topology;
    topology.otherPieces = unknownSheets;
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
