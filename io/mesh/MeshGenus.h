// skelseg: the genus of a triangle mesh, from the Euler characteristic of
// each of its closed pieces (V - E + F = 2 - 2g), to compare with the genus
// of its voxel model (kernels/VoxelGenus.h).
//
// Vertices at identical positions count as one (canonicalVertices), so seams where a writer
// duplicated vertices do not open the surface, and two triangles on the same corners with
// opposite windings (a double-sided face, or a face two solids share) are left out. Such faces
// that form a free sheet (an edge no other triangle uses) other than a disk are counted as a
// piece of unknown genus: the voxel model holds the sheet thickened, with whatever handles
// or cavity that gives. A piece is
// the set of triangles joined through shared edges; it is closed when each of its edges is used by
// exactly two triangles (a manifold without border). A vertex where a piece's triangles meet in
// several fans joined only at that point (a pinch), or where two pieces touch, counts once per fan,
// as if pulled apart. An edge of more than two triangles is pulled apart too: round the edge, each
// triangle is paired with its neighbour across the wedge its winding says is inside (solids that
// touch along the edge come apart; the winding's sense is the sign of the enclosed volume). Open
// pieces, and pieces with an edge whose triangles cannot be paired that way (an odd count,
// windings that do not alternate round it, two at one angle), have no genus in this sense:
// they are counted apart and left out of the sum. The sum is the voxel shape's genus only when the
// pieces neither intersect each other nor themselves (overlapping closed pieces are voxelised as
// their union, whose genus the pieces do not tell).
#pragma once

#include <cstddef>
#include <cstdint>

#include "io/mesh/MeshIO.h"

namespace skelseg {

struct MeshTopology {
    /// Pieces (triangles joined through edges) whose every edge is used by
    /// exactly two triangles.
    std::size_t closedPieces = 0;
    /// Pieces with border edges, or with edges of more than two triangles
    /// that could not be paired, and free sheets of double-sided faces other
    /// than disks: pieces whose genus is unknown.
    std::size_t otherPieces = 0;
    /// Sum of (2 - chi) / 2 over the closed pieces.
    std::int64_t genus = 0;
    /// Sum of V - E + F over the closed pieces, V counting a vertex once per
    /// fan of triangles around it.
    std::int64_t eulerCharacteristic = 0;
};

/// Pieces, Euler characteristic and genus of `mesh` (edges counted in a
/// sorted list: n log n). Triangles with two equal (canonical) corners are ignored.
MeshTopology meshTopology(const TriangleMesh& mesh);

}  // namespace skelseg
