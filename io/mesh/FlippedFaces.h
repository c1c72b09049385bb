// skelseg: flipped faces, wound against the faces around them.
//
// Exporters, hand edits and mesh merges leave patches of faces wound the
// wrong way: across an edge the two faces then run along it in the same
// direction (MeshDiagnostics::misorientedEdges). Such a piece has no
// consistent outside, so the voxeliser's rules that need one (the contact
// separation's side test, the thin-part fill; io/mesh/MeshOrientation.h)
// skip it, and touching limbs of the piece stay joined in its voxel model.
// Where the faces of a sheet can be wound one way, the smaller share (by
// area) is turned to agree with the rest, as mesh repair tools do (CGAL's
// orient_polygon_soup, libigl's bfs_orient), and the turned mesh is the one
// voxelised (docs/meshes.md, "Flipped faces turned").
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "io/mesh/MeshCheck.h"
#include "io/mesh/MeshIO.h"

namespace skelseg {

/// A mesh whose flipped faces have been turned.
struct MeshWithFlippedFacesTurned {
    /// The input with the corners of every turned triangle in reverse
    /// order; vertices, faces and their order are the input's.
    TriangleMesh mesh;
    /// Input faces (polygons) turned.
    std::size_t turnedFaces = 0;
    /// The turned triangles' area over the whole mesh's.
    double turnedAreaShare = 0.0;
    /// checkMesh() of `mesh`.
    MeshDiagnostics diagnostics;
};

/// The mesh with its flipped faces turned, when some are. Sheets are the
/// triangles joined across edges of exactly two triangles (vertices at one
/// position count as one, as in finTriangles); within a sheet, the two
/// triangles of an edge are wound alike when they run along it in opposite
/// directions. A sheet that can be wound one way (no cycle of edges asks a
/// triangle to be both) keeps the winding of the larger part of its area,
/// the first triangle's on a tie, and the rest is turned; a sheet that
/// cannot (a Moebius strip, or edges of three triangles around it) is left
/// as it is. std::nullopt when nothing is turned.
std::optional<MeshWithFlippedFacesTurned> withFlippedFacesTurned(const TriangleMesh& mesh);

/// "FILE: 1594 faces were wound against ...": the warning for a mesh whose
/// flipped faces were turned, in place of its "wound against each other"
/// warning.
std::string flippedFacesWarning(const std::string& file, const MeshWithFlippedFacesTurned& turned);

}  // namespace skelseg
