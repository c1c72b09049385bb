// skelseg: turning a triangle mesh into a solid voxel mask.
//
// Grid: the longest side of the mesh's bounding box spans `resolution` voxels
// of size h = longest side / resolution; every axis gets ceil(extent / h)
// voxels (at least 1) plus `margin` empty voxels on each side, and the shape is
// centred in the grid. The geometry is VolumeGeometry::uniform(h, origin), where
// index (i, j, k) is the CENTRE of that voxel:
//     world = origin + h * (i, j, k),     index = (world - origin) / h.
// worldToIndex() gives the inverse (continuous indices; round to get the voxel
// that contains a point), so voxels, skeletons and labels map back onto the mesh.
//
// Inside/outside (see docs/meshes.md):
//  - closed meshes (MeshCheck: every edge used an even number of times):
//    OpenVDB's meshToVolume builds a narrow-band signed distance field; a
//    voxel is solid when the signed distance at its centre is negative.
//  - open meshes (or when the signed conversion finds no inside at all): an
//    unsigned distance field gives a shell of voxels within
//    holeClosing + 0.5 voxels of the surface; a 6-connected flood fill from
//    the grid's border finds the outside, which then grows back up to
//    holeClosing + 1 voxels towards the surface (never into the half-voxel
//    surface layer). Everything not outside is solid. Holes narrower than
//    about 2 * holeClosing voxels are bridged; the solid keeps the outer
//    half-voxel layer, so it is a few percent larger than for a closed mesh.
//    When a wider hole lets the outside in (the solid is then hardly more
//    than the surface layer), holeClosing is doubled, up to
//    widestHoleClosing(resolution), and the pass repeated. A single open
//    sheet becomes a thin plate.
// Thin parts (closed meshes only; see ThinPartFill.h): the voxels the middle
// of a part thinner than a voxel or so passes through are made solid, so that
// such a part is neither perforated nor broken into islands.
// Mesh topology (closed meshes only; see ContactSeparation.h): surfaces far
// apart on the mesh but closer than a voxel or two in space are separated
// again by clearing a one-voxel seam, using the nearest triangle OpenVDB
// reports for every voxel of its narrow band.
// Degenerate faces are harmless (OpenVDB ignores their area). Several pieces
// are voxelised together; overlapping closed pieces give their union.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "io/mesh/ContactSeparation.h"
#include "io/mesh/MeshIO.h"
#include "io/mesh/SelfOverlapSeparation.h"
#include "io/mesh/ThinPartFill.h"
#include "kernels/Islands.h"
#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// The widest hole closing tried for an open mesh at `resolution` (voxels
/// along the longest side): 16 voxels up to resolution 192, above it a
/// twelfth of the longest side, so that the same holes are bridged at every
/// resolution, up to 48 voxels (resolution 576; each pass computes distances
/// in a band that wide round the whole surface).
double widestHoleClosing(int resolution);

struct VoxelizeOptions {
    /// Voxels along the longest side of the mesh's bounding box, in [8, 2048].
    int resolution = 256;
    /// Empty voxels added on every side, in [0, 64].
    int margin = 2;
    /// Open meshes only: how far (in voxels) the surface is thickened before
    /// the outside is flood-filled, i.e. half the width of the widest hole
    /// that is bridged. In [0, 16].
    double holeClosing = 2.0;
    /// false: every phase runs on the calling thread (OpenVDB's mesh
    /// conversion has no serial switch, so it runs in a one-thread TBB arena).
    bool threaded = true;
    /// Whether the mesh is closed (checkMesh().closed), when the caller has
    /// already checked it; unset: voxelizeMesh() checks (a full edge count,
    /// so a caller that runs checkMesh() for its warnings passes the answer).
    std::optional<bool> meshIsClosed;
    /// Closed meshes: separate surfaces that touch in the voxel model but are
    /// far apart on the mesh (ContactSeparation.h), and parts of the mesh that
    /// pass through each other (SelfOverlapSeparation.h).
    bool keepMeshTopology = true;
    /// Closed meshes: half-width, in voxels, of the band of distances
    /// OpenVDB computes around the surface, in [1, 4]. Its cost per triangle
    /// grows as the cube of the width (a triangle smaller than a voxel
    /// visits (2 width + 1)^3 voxels). The contact separation needs 2; inside
    /// and outside alone (keepMeshTopology off: the --time-budget probe) need 1.
    double bandWidth = 2.0;
    ContactSeparationOptions contactOptions;
    /// Closed meshes: how wide places where the mesh passes through itself
    /// are cleared (SelfOverlapSeparation.h); `threaded` comes from above.
    SelfOverlapOptions selfOverlapOptions;
    /// Closed meshes: make solid the voxels the middle of every part thinner
    /// than a voxel or so passes through (ThinPartFill.h), before contacts
    /// are separated. Off by default: the engine fills only where that closes
    /// handles the mesh does not have (SegmentInput.cpp, docs/meshes.md).
    bool fillThinParts = false;
    ThinPartOptions thinPartOptions;
};

/// Size and placement of the grid voxelizeMesh() makes, without voxelising.
/// @throw UsageError for options out of range, a grid over kMaxVoxels, a
/// mesh without extent (all vertices at one point), or a grid whose voxel
/// step is too small for its world coordinates (VolumeGeometry::problemOver).
struct VoxelGrid {
    Dims dims;
    VolumeGeometry geometry;
};
VoxelGrid voxelGridFor(const TriangleMesh& mesh, const VoxelizeOptions& options);

/// Solid mask of the mesh (1 inside, 0 outside) on the grid of
/// voxelGridFor(); x fastest: index = x + nx * (y + ny * z).
/// Polls the interrupter between phases and inside OpenVDB's conversion.
/// @throw UsageError (see voxelGridFor), InterruptedError.
MaskVolume voxelizeMesh(const TriangleMesh& mesh, const VoxelizeOptions& options,
                        Interrupter& interrupter = nullInterrupter());

/// The mask and what keeping the mesh's topology changed.
struct MeshVoxelization {
    MaskVolume mask;
    /// Zero unless the mesh is closed and keepMeshTopology is set.
    ContactSeparation contacts;
    /// Where the mesh passes through itself (SelfOverlapSeparation.h); zero
    /// unless the mesh is closed and keepMeshTopology is set.
    SelfOverlapSeparation selfOverlaps;
    /// Zero unless the mesh is closed and fillThinParts is set.
    ThinPartFill thinParts;
    /// The mesh piece of each object of `mask` (VoxelObjectPieces.h): empty
    /// unless the mesh is closed, keepMeshTopology is set and the mask has
    /// two objects or more.
    std::vector<ObjectSource> objectSources;
};

/// The signed voxelisation of a closed mesh as OpenVDB gives it, before thin
/// parts are filled and surfaces separated. The conversion is most of a
/// voxelisation's cost and depends only on the mesh, the grid and the band
/// width, so a second voxelisation of the same mesh with other fill options
/// (the engine's retry with thin parts filled) starts from it.
struct SignedVoxelization {
    const TriangleMesh* mesh = nullptr;  // what it was made from; null: nothing kept
    Dims dims;
    VolumeGeometry geometry;
    double bandWidth = 0.0;
    MaskVolume mask;                            // 1 where the signed distance is negative
    std::vector<std::int32_t> nearestTriangle;  // empty unless made with keepMeshTopology

    /// Whether a voxelisation of `mesh` with `options` on `grid` can start here.
    bool fits(const TriangleMesh& forMesh, const VoxelGrid& grid,
              const VoxelizeOptions& options) const noexcept;
};

/// voxelizeMesh() that also reports the contacts it separated.
/// signedVoxels: when not null, the voxelisation starts from it if it fits
/// (same mesh object, grid and band width; the nearest triangles when
/// keepMeshTopology is set), and otherwise converts the mesh and keeps the
/// conversion there (closed meshes whose conversion found an inside; else
/// it is left empty). The result is the same either way.
MeshVoxelization voxelizeMeshWithContacts(const TriangleMesh& mesh, const VoxelizeOptions& options,
                                          Interrupter& interrupter = nullInterrupter(),
                                          SignedVoxelization* signedVoxels = nullptr);

/// World point -> continuous voxel index (voxel centres at integers) for any
/// VolumeGeometry; the inverse of VolumeGeometry::indexToWorld. The matrix is
/// inverted once, so use this for many points.
class WorldToIndex {
public:
    explicit WorldToIndex(const VolumeGeometry& geometry);
    std::array<double, 3> operator()(const std::array<double, 3>& world) const noexcept;
    /// False when the geometry's directions are singular (every result NaN).
    bool isValid() const noexcept { return mValid; }

private:
    std::array<double, 3> mOrigin{};
    std::array<std::array<double, 3>, 3> mInverse{};  // [index axis][world component]
    bool mValid = false;
};

/// One-off form of WorldToIndex.
std::array<double, 3> worldToIndex(const VolumeGeometry& geometry,
                                   const std::array<double, 3>& world);

/// The voxel whose cell contains the world point (rounded index; may lie
/// outside the volume).
Coord voxelContaining(const VolumeGeometry& geometry, const std::array<double, 3>& world);

}  // namespace skelseg
