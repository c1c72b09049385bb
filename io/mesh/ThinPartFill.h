// skelseg: keeping parts thinner than a voxel whole when a closed mesh is
// voxelised (docs/meshes.md, "Parts thinner than a voxel").
//
// The signed voxelisation makes a voxel solid when its centre lies inside the
// mesh. A sheet or a tube thinner than a voxel (an elephant's ear, the tip of
// a trunk or a tail) contains only some voxel centres: the sheet comes out
// perforated (every hole is a handle of the voxel shape that the mesh does
// not have) and the tube breaks into islands. This fill adds the voxels that
// the middle of such a part passes through:
//  - the surface is sampled at the centroids of m x m sub-triangles of every
//    triangle (spacing at most sampleSpacing voxels);
//  - from each sample a ray goes into the solid (against the triangle's
//    outward normal, MeshOrientation.h) up to maxThickness voxels; when it
//    leaves the solid again through a wall facing the other way (the two
//    outward normals' cosine below opposingCosine), the part is thin there;
//  - every voxel whose cube comes within coverRadius of the middle of that
//    chord becomes solid. The middles of a thin part's chords lie on its
//    mid-surface (a sheet) or near its axis (a tube); the voxels they pass
//    through form one connected layer that no 6-connected path of
//    background voxels crosses, so the part has the mesh's topology.
// Thick parts are left alone: their chords are longer than maxThickness,
// and where they are not (at a sharp convex edge) the walls do not face
// each other. Only voxels inside the part's walls or within a voxel of them
// are added, so a surface across a gap is not reached unless it is closer
// than about a voxel; ContactSeparation.h, which runs after this, separates
// such contacts.
// Triangles of pieces that are not consistently oriented have no inside
// direction and are skipped. The rays are tested against the triangles
// binned on a sparse grid of 2-voxel cells (the rays are short).
#pragma once

#include <cstddef>

#include "io/mesh/MeshIO.h"
#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

struct ThinPartOptions {
    /// Parts thinner than this (voxels) along the inward normal are filled.
    double maxThickness = 1.5;
    /// The wall where a chord leaves the solid must face away from the wall
    /// where it entered: cosine of their outward normals below this.
    double opposingCosine = -0.5;
    /// Largest distance between surface samples (voxels).
    double sampleSpacing = 0.35;
    /// Voxels whose cube comes this close (voxels) to a chord's middle are
    /// filled; covers the gaps between samples.
    double coverRadius = 0.25;
    /// false: everything runs on the calling thread (same result).
    bool threaded = true;
    /// true: every sample's ray is tested exactly against every triangle,
    /// instead of against those binned in the cells it crosses that its
    /// plane test keeps (same result, quadratic): the reference the tests
    /// compare with.
    bool testEveryTriangle = false;
};

struct ThinPartFill {
    /// Surface samples whose inward chord was thin.
    std::size_t thinSamples = 0;
    /// Voxels that were empty and became solid.
    std::size_t voxelsAdded = 0;
};

/// Makes solid the voxels of `mask` that the middle of every part of `mesh`
/// thinner than options.maxThickness passes through (see above). The mask's
/// geometry must be the uniform grid the mesh was voxelised on
/// (voxelGridFor).
/// @throw InterruptedError.
ThinPartFill fillThinParts(const TriangleMesh& mesh, MaskVolume& mask,
                           const ThinPartOptions& options = {},
                           Interrupter& interrupter = nullInterrupter());

}  // namespace skelseg
