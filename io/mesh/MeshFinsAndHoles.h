// skelseg: fins and small holes on one mesh, the two rules together.
//
// An exported character can have both: a body closed but for a hole or two
// (eye sockets, a neck left open) and, beside it, small open pieces that
// enclose nothing (a tongue or an eyelid modelled as a shell with an
// opening, a loose sheet). Neither rule alone takes such a mesh: the fin
// rule would drop the body, whose sheet has a free border too, and the hole
// rule refuses the open pieces, whose caps would be most of their area. So
// the whole mesh went to the shell method (MeshVoxelizer.h), which keeps no
// touching surfaces apart. Here every open sheet whose holes can be capped
// is capped, and the others are dropped as fins when they hold at most
// kMaxFinAreaShare of the area (docs/meshes.md, "Fins and holes together").
#pragma once

#include <optional>
#include <string>

#include "io/mesh/MeshFins.h"
#include "io/mesh/MeshHoles.h"
#include "io/mesh/MeshIO.h"

namespace skelseg {

/// A mesh that is closed once its fins are dropped and then its holes
/// capped.
struct MeshWithFinsDroppedAndHolesCapped {
    /// The input without its fins (still open: diagnostics of that mesh).
    MeshWithoutFins withoutFins;
    /// withoutFins.mesh with its holes capped: the mesh to voxelise, closed.
    MeshWithHolesCapped capped;
};

/// The two rules together, for a mesh that neither closedWithoutFins() nor
/// closedWithHolesCapped() takes alone. Each open sheet (openSheets) is
/// tried on its own with closedWithHolesCapped(); the sheets it refuses are
/// the fins. The result is taken when there are such fins and they hold at
/// most kMaxFinAreaShare of the area (withoutTriangles), and the mesh
/// without them passes closedWithHolesCapped() as a whole; std::nullopt
/// otherwise.
std::optional<MeshWithFinsDroppedAndHolesCapped> closedWithoutFinsAndHoles(
    const TriangleMesh& mesh);

/// "FILE: 300 faces lie on fins (...) and the rest has 1 hole (...)": the
/// one warning for a mesh both rules closed, in place of finsWarning() and
/// holesWarning().
std::string finsAndHolesWarning(const std::string& file, const MeshWithoutFins& withoutFins,
                                const MeshWithHolesCapped& capped);

}  // namespace skelseg
