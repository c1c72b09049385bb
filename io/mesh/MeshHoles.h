// skelseg: small holes, which keep an otherwise closed mesh open.
//
// Scans and exported characters often miss a few faces: a gap the scanner
// did not see, eye sockets and a mouth left open. One such hole makes the
// mesh "not closed", and an open mesh is voxelised by the shell method
// (MeshVoxelizer.h), whose closing fills every concave gap a few voxels
// wide (a limb held near the body fuses with it) and which neither keeps
// touching surfaces apart nor compares genera. Where every hole is small
// beside the surface it opens, the mesh with each hole capped by a fan is
// the shape: that mesh is the one voxelised, and the input's faces are
// labelled as before (docs/meshes.md, "Small holes").
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "io/mesh/MeshCheck.h"
#include "io/mesh/MeshIO.h"

namespace skelseg {

/// The largest share of a piece's area the caps of its holes may hold. A
/// piece whose holes are larger is an open sheet (a mask, a wing modelled
/// as one layer, a half shell), whose inside the caps would invent: the mesh
/// then keeps the shell method.
constexpr double kMaxHoleCapAreaShare = 0.05;

/// A mesh that is closed once its holes are capped.
struct MeshWithHolesCapped {
    /// The input's vertices and triangles, then per hole one vertex (the
    /// mean of the hole's corners) and the fan of triangles joining it to
    /// the hole's border, wound as the triangles along the border; each
    /// cap is one more face.
    TriangleMesh mesh;
    /// Holes capped (closed loops of edges used by one triangle).
    std::size_t holes = 0;
    /// The caps' area over the input's.
    double capAreaShare = 0.0;
    /// checkMesh() of `mesh`, made to find it closed.
    MeshDiagnostics diagnostics;
};

/// The mesh with its holes capped, when it has holes, every border vertex
/// starts one border edge (no two holes meet in a vertex), the caps of each
/// piece (triangles joined across edges) hold at most kMaxHoleCapAreaShare
/// of its area, and the capped mesh is closed (checkMesh) and not flat;
/// std::nullopt otherwise.
std::optional<MeshWithHolesCapped> closedWithHolesCapped(const TriangleMesh& mesh);

/// "FILE: the mesh has 3 holes (...)": the warning for a mesh whose holes
/// were capped (closedWithHolesCapped), in place of its "not closed"
/// warning.
std::string holesWarning(const std::string& file, const MeshWithHolesCapped& capped);

}  // namespace skelseg
