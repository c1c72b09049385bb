// skelseg: keeping a mesh's topology when it is voxelised: surfaces that are
// far apart on the mesh but closer than a voxel or two in space (a hand
// resting on a hip, a leg folded against the body) are separated again in
// the voxel model (docs/meshes.md, "Mesh topology is kept").
//
// Input: the solid mask and, for the voxels near the surface, the mesh
// triangle nearest to each voxel centre (OpenVDB's closest-primitive index,
// see MeshVoxelizer.cpp). Where several triangles are as near (the nearest
// point is a vertex or an edge they share), OpenVDB returns the first in face
// order; the one used is chosen by geometry instead
// (SurfaceGraph::nearestOfTied), so the same mesh with its faces in another
// order gives the same voxel model. Two 26-neighbouring object voxels a and b with
// nearest triangles ta, tb are a contact when
//  1. each lies beyond the other's surface: with pa the point of ta nearest
//     to a, (b - pa) . (a - pa) < 0, and the same with a and b swapped. Inside
//     a thin part (both voxels under one wall, or under two walls facing away
//     from each other) this never holds; across a gap between two walls that
//     face each other it always does;
//  2. the surface points pa and pb are far apart on the mesh: no path along
//     mesh edges joins them within farOnMesh + farOnMeshRatio * |pa - pb|
//     (voxels). Concave creases pass test 1 but fail this one: their walls
//     meet a short way off. Triangles that share a vertex, or whose vertices
//     are joined by an edge, count as near whatever their size;
//  3. ta and tb lie on the same mesh piece. Separate pieces that overlap are
//     meant to be voxelised as their union (MeshVoxelizer.h); the buried walls
//     inside such an overlap would otherwise pass 1 and 2 everywhere.
// OpenVDB's sign fill marks voxels inside a gap narrower than a voxel as
// solid. Where a piece is consistently oriented (no directed edge used twice),
// the nearest triangle's normal shows such a voxel to lie outside its
// surface: it then counts as facing the wall across the gap (its inward
// direction is reversed) and with a negative depth, so it is cleared first.
// For each contact pair, the one of a, b nearer to its surface is to be
// cleared (both on a tie): a gap of about one voxel between the two walls,
// which removes every contact pair found, and takes the thinner side of the
// seam. The voxels to clear form groups (26-connected), one per place where
// surfaces touch; a group is cleared only if that adds no topology in the box
// around it (its genus must not grow, no cavity may appear): a contact of
// which some pairs were missed would otherwise get a hole punched through
// it instead of being separated. A contact separates two surfaces, it never
// cuts a piece of the shape loose: a seam after which the voxels around it
// lie in two objects of the whole mask (a thin limb cut next to the contact)
// is set back (kernels/SeveredObjects.h).
//
// Patch seams (ContactSeparationOptions::patchSeams, off by default): step
// 7, seams for the contacts the box check keeps, between the contact's two
// mesh patches (io/mesh/ContactPatchSeams.h).
//
// Grown seams (ContactSeparationOptions::grownSeams, on by default): step 8,
// each contact still kept is tried once more with its two-voxel seam grown by
// one voxel (26-neighbours) into the object. The pairs found stop short of
// the contact's rim, where the walls part and test 1 misses pairs, so the
// seam of the pairs alone leaves links there; one voxel more reaches past
// them. Judged on the whole model, not the box: kept only where the model's
// genus drops and no object or cavity is added, so it frees a handle the
// mesh does not have and never cuts a sheet or a limb loose. Tried only while
// the model has a handle.
//
// Limits: a mesh that intersects itself can have contacts detected where it
// crosses itself; pieces that merely touch stay joined (rule 3); a contact
// whose walls are parallel to a voxel diagonal may leave single corner links
// that no pair found (the genus check in the report shows them).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "io/mesh/MeshIO.h"
#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

struct ContactSeparationOptions {
    /// Surface points closer than this along the mesh (voxels), plus
    /// farOnMeshRatio times their distance in space, are near on the mesh.
    double farOnMesh = 3.0;
    double farOnMeshRatio = 2.0;
    /// Seams between the two mesh patches of a contact kept (see above).
    bool patchSeams = false;
    /// Step 8: a kept contact's seam grown by one voxel, kept where the whole
    /// model loses a handle and gains no object or cavity (see above).
    bool grownSeams = true;
    /// How far each side's triangles are grown along the mesh into its
    /// patch, and the greatest distance (voxels) from each patch at which a
    /// voxel is given a side. Growth must stay under farOnMesh, or the two
    /// sides of a pair could be joined.
    double patchGrowth = 2.5;
    double patchReach = 2.5;
    /// false: everything runs on the calling thread (same result).
    bool threaded = true;
};

struct ContactSeparation {
    /// Places where surfaces touched that were separated (26-connected groups
    /// of cleared voxels).
    std::size_t contacts = 0;
    /// Places found but left joined: clearing them would have added topology
    /// or cut an object in two.
    std::size_t contactsKept = 0;
    /// Of contactsKept: cleared, then set back because the seam cut an object
    /// in two (kernels/SeveredObjects.h).
    std::size_t contactsRejoined = 0;
    /// Of contacts: separated by a seam between the contact's two mesh
    /// patches (ContactSeparationOptions::patchSeams).
    std::size_t contactsPatchSeamed = 0;
    /// Of contacts: separated by their seam grown by one voxel
    /// (ContactSeparationOptions::grownSeams).
    std::size_t contactsGrown = 0;
    /// Object voxels cleared.
    std::size_t voxelsCleared = 0;
    /// Neighbouring voxel pairs found to be contacts.
    std::size_t contactPairs = 0;
};

/// Clears the voxels of `mask` that join surfaces far apart on `mesh` (see
/// above). `nearestTriangle` has one entry per voxel of the mask (x fastest):
/// the index into mesh.triangles of the triangle nearest to the voxel centre,
/// or -1 where unknown (far from the surface). The mask's geometry must be the
/// uniform grid the mesh was voxelised on (voxelGridFor).
/// @throw UsageError when nearestTriangle does not match the mask,
/// InterruptedError.
ContactSeparation separateContacts(const TriangleMesh& mesh, MaskVolume& mask,
                                   const std::vector<std::int32_t>& nearestTriangle,
                                   const ContactSeparationOptions& options = {},
                                   Interrupter& interrupter = nullInterrupter());

}  // namespace skelseg
