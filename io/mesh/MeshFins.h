// skelseg: fins, the open sheets that keep an otherwise closed mesh open.
//
// Exporters and modellers leave small sheets on a closed surface: a stray
// triangle standing on an edge of the surface, a flap along a seam, a loose
// face touching it at a corner or floating beside it. Such a sheet has a
// free border (edges of one triangle). One of them makes the whole mesh "not
// closed", and an open mesh is voxelised by the shell method, which neither
// keeps touching surfaces apart nor compares genera (MeshVoxelizer.h). A fin
// encloses no volume, so the surface without it is the shape: where dropping
// the fins leaves a closed mesh and they hold a small share of its area, that
// mesh is the one voxelised, and the fins' faces take the labels of the parts
// they touch (docs/meshes.md, "Fins").
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "io/mesh/MeshCheck.h"
#include "io/mesh/MeshIO.h"

namespace skelseg {

/// The largest share of a mesh's area its fins may hold and still be
/// dropped: a third of the default tau (3%). Their two sides together then
/// hold under 2% of the surface, under tau, so no fin could have been a part;
/// a larger open sheet (a wing modelled as one layer) keeps the shell method.
constexpr double kMaxFinAreaShare = 0.01;

/// Per triangle: 1 for the triangles of sheets with a free border, the fins
/// where the rest is closed. A sheet is a set of triangles joined across
/// edges of exactly two triangles (vertices at identical positions count as
/// one, canonicalVertices); its border is free where an edge is used by one
/// triangle only. On an open mesh with holes, the sheets round the holes
/// are marked too: closedWithoutFins() then finds the rest not closed, or
/// the sheets too large.
std::vector<char> finTriangles(const TriangleMesh& mesh);

/// Per triangle: the number of its open sheet (sheets as for finTriangles,
/// numbered 0, 1, ... in the order of their first triangles), or
/// kNotInOpenSheet for the triangles of sheets without a free border.
constexpr std::uint32_t kNotInOpenSheet = UINT32_MAX;
std::vector<std::uint32_t> openSheets(const TriangleMesh& mesh);

/// A mesh that is closed once its fins are dropped.
struct MeshWithoutFins {
    /// The triangles that are not fins, with the input's vertices; faces
    /// renumbered in order over the faces kept (faceCount counts them).
    TriangleMesh mesh;
    /// Input faces (polygons) whose every triangle is a fin's.
    std::size_t finFaces = 0;
    /// The fins' area over the whole mesh's.
    double finAreaShare = 0.0;
    /// checkMesh() of `mesh`, made to find it closed.
    MeshDiagnostics diagnostics;
};

/// The mesh without its fins, when it has fins, the rest is closed
/// (checkMesh: every edge used an even number of times) and not flat, and the fins hold
/// at most kMaxFinAreaShare of the area; std::nullopt otherwise.
std::optional<MeshWithoutFins> closedWithoutFins(const TriangleMesh& mesh);

/// The mesh without the triangles marked in `fin` (one entry per triangle),
/// when some are marked, some are left, and the marked ones hold at most
/// kMaxFinAreaShare of the area; std::nullopt otherwise. Its diagnostics
/// are checkMesh()'s of what is left, closed or not: closedWithoutFins()
/// is this with every open sheet marked, and the rest found closed.
std::optional<MeshWithoutFins> withoutTriangles(const TriangleMesh& mesh,
                                                const std::vector<char>& fin);

/// "2 faces lie", "1 face lies", or "parts of faces lie" where every face
/// with a fin's triangle is partly kept: the start of a fins warning.
std::string finFacesLie(const MeshWithoutFins& withoutFins);

/// "FILE: 2 faces lie on fins (...)": the warning for a mesh whose fins were
/// dropped (closedWithoutFins), in place of its "not closed" and
/// "non-manifold" warnings.
std::string finsWarning(const std::string& file, const MeshWithoutFins& withoutFins);

}  // namespace skelseg
