// skelseg: separating the parts of a mesh that pass through themselves.
//
// An animated character's mesh often intersects itself where a limb sinks
// into the body (a hand inside a hip, a knee inside the other thigh): one
// closed surface encloses the same space twice. Voxelised, the two parts are
// one solid there, the skeleton gets a loop the mesh does not have and the
// limb stops being a part. The contact separation (ContactSeparation.h) does
// not help: its walls face each other across a gap; here they cross.
//
// Where a closed surface overlaps itself, its winding number is 2 or more:
// the voxels it encloses twice are found exactly from the mesh, whatever the
// resolution. They are counted along rays parallel to x through every row of
// voxel centres: the winding number of a point is the sum of the signs of the
// surface crossings beyond it (+1 where the surface, oriented outwards,
// leaves through the crossing), so sorting each row's crossings gives every
// voxel's winding number in one sweep. Pieces (triangles joined by shared
// vertices) count separately: separate pieces that overlap are meant to be
// voxelised as their union (MeshVoxelizer.h) and are left alone. Vertices at
// one position count as one (canonicalVertices, MeshCheck.h), so a triangle
// soup is the welded surface; a triangle with a repeated corner has no area
// and is left out of the pieces and of the closedness test.
//
// Each 26-connected group of doubly enclosed voxels is cleared together with
// its neighbours up to `clearance` voxels away: the buried part of the limb
// and a layer of the part it sinks into, which leaves a pocket in the host and
// a gap between the two surfaces. A group is cleared
// only if that adds no topology in the box around it (genus and cavities do
// not grow), as for contacts; a refused group is tried again one voxel wider
// at a time, within the bounds `maxClearance` describes. The buried faces
// then take the label of the nearest part (FaceLabels.h). A clearing after
// which the voxels around it lie in two objects of the whole mask (a limb that
// passes through another is cut where it crosses) is counted, and set back
// only when `rejoinSevered` is on (kernels/SeveredObjects.h).
//
// Limits: open pieces and pieces not consistently oriented have no winding
// number and are left alone; where two surfaces cross at a grazing angle the
// doubly enclosed region can be thinner than a voxel centre spacing and is
// then not seen.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "io/mesh/MeshIO.h"
#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

struct SelfOverlapOptions {
    /// Voxels cleared around each doubly enclosed group (26-neighbour steps):
    /// two leave a gap where the two surfaces cross at the group's rim, which
    /// one does not (docs/meshes.md, "Parts that pass through each other").
    int clearance = 2;
    /// A group whose clearing adds topology in its box is tried again one
    /// voxel wider at a time, up to this many (at most `clearance`: never),
    /// but no wider than the group is thick (the narrowest side of its
    /// bounding box), and a wider clearing is kept only where it lowers the
    /// genus of the whole mask: one that removes no handle only carves the
    /// parts around a crossing, and one much wider than a grazing crossing
    /// frees a handle in some poses of a character and not in others
    /// (docs/meshes.md, "Places kept fused on posed characters").
    int maxClearance = 4;
    /// Set back a clearing that cuts an object in two. Off: where a limb
    /// passes through another, clearing the crossing cuts the limb and
    /// setting it back keeps the false handle; on the posed characters
    /// measured, the handle costs more parts than the loose piece
    /// (docs/meshes.md, "A separation never cuts a limb loose").
    bool rejoinSevered = false;
    /// false: everything runs on the calling thread (same result).
    bool threaded = true;
};

struct SelfOverlapSeparation {
    /// Places (26-connected groups of doubly enclosed voxels) separated.
    std::size_t overlaps = 0;
    /// Places found but left joined: clearing them would have added topology
    /// or cut an object in two.
    std::size_t overlapsKept = 0;
    /// Places whose clearing cut an object in two (kernels/SeveredObjects.h):
    /// set back (and counted in overlapsKept) when rejoinSevered is on, else
    /// left cleared.
    std::size_t overlapsSevering = 0;
    /// Voxel centres enclosed twice or more by one piece.
    std::size_t overlapVoxels = 0;
    /// Object voxels cleared.
    std::size_t voxelsCleared = 0;
};

/// Indices (x fastest) of the voxel centres of a grid of `dims` placed by
/// `geometry` that one closed, consistently oriented piece of `mesh` encloses
/// twice or more, in increasing order.
/// @throw InterruptedError.
std::vector<std::uint64_t> selfOverlapVoxels(const TriangleMesh& mesh, const Dims& dims,
                                             const VolumeGeometry& geometry, bool threaded = true,
                                             Interrupter& interrupter = nullInterrupter());

/// Clears the doubly enclosed voxels of `mask` and their surroundings (see
/// above). The mask's geometry must place it in the mesh's frame (the grid
/// voxelGridFor() makes).
/// @throw InterruptedError.
SelfOverlapSeparation separateSelfOverlaps(const TriangleMesh& mesh, MaskVolume& mask,
                                           const SelfOverlapOptions& options = {},
                                           Interrupter& interrupter = nullInterrupter());

}  // namespace skelseg
