// skelseg: triangle surfaces of the segments of a label volume.
//
// Used for segments.ply and for the preview picture when the input was a
// volume (no mesh to colour). Meshing is OpenVDB's volumeToMesh (dual
// contouring, adaptivity 0) on a sparse grid built per label, cropped to the
// label's bounding box: voxels of the label are inside, everything else
// (other labels, background, beyond the volume's border) outside, so each
// surface is closed and passes half way between the label's boundary voxels
// and their outside neighbours (on the voxel faces, with bevelled edges and
// corners). Vertices are mapped to world coordinates by the volume's
// VolumeGeometry; triangles keep the orientation volumeToMesh gives level sets
// (normals point out of the segment) also under a mirroring geometry.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// A triangle soup of one or more closed surfaces, each triangle tagged.
struct LabelledSurface {
    /// V world positions.
    std::vector<std::array<double, 3>> vertices;
    /// T triples of 0-based indices into `vertices`, counter-clockwise seen from
    /// outside.
    std::vector<std::array<std::uint32_t, 3>> triangles;
    /// T labels (label-volume convention: 1..K segments).
    std::vector<std::uint32_t> triangleLabels;
};

struct SegmentSurfaceOptions {
    /// Mesh labels in parallel (tbb). false runs everything, OpenVDB's own
    /// loops included, on the calling thread; the output is identical.
    bool threaded = true;
    /// Taubin smoothing passes (lambda 0.5, mu -0.53, in voxel index space)
    /// applied to each surface. 0 keeps the surface on the voxel faces; about
    /// 10 removes the voxel terraces that otherwise show as contour rings in
    /// pictures, moving vertices well under a voxel and keeping the volume.
    int smoothingIterations = 0;
};

/// One closed surface per label 1..K present in `labels`, concatenated in
/// increasing label order; vertices are not shared between labels, so two
/// touching segments each have their own wall. Labels absent from the volume
/// produce nothing.
/// @throw InterruptedError if `interrupter` asks to stop (polled per label and
///        per slab of the grid build); the result is then not returned.
LabelledSurface extractSegmentSurfaces(const LabelVolume& labels,
                                       const SegmentSurfaceOptions& options,
                                       Interrupter& interrupter = nullInterrupter());
LabelledSurface extractSegmentSurfaces(const LabelVolume& labels,
                                       Interrupter& interrupter = nullInterrupter());

/// The outer surface of the whole object (all nonzero labels together), with
/// no walls between segments: the better picture of a segmented volume. Each
/// triangle is tagged with the label of the object voxel nearest to its
/// centroid, so segment boundaries follow voxel boundaries to within one
/// voxel.
LabelledSurface extractObjectSurface(const LabelVolume& labels,
                                     const SegmentSurfaceOptions& options = {},
                                     Interrupter& interrupter = nullInterrupter());

/// The surface of a binary mask (nonzero = object); every triangle labelled 1.
LabelledSurface extractObjectSurface(const MaskVolume& mask,
                                     const SegmentSurfaceOptions& options = {},
                                     Interrupter& interrupter = nullInterrupter());

}  // namespace skelseg
