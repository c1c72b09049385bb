// skelseg: carrying voxel segment labels back onto the input mesh's faces.
//
// The output of the engine is a label per voxel; the benchmark and the user
// want a label per input face (the Princeton .seg convention: line i = face i
// of the input file, labels 0..K-1). The rule, which is deterministic and
// linear in the number of faces:
//  1. Samples: every triangle is cut into m x m equal sub-triangles
//     (m = ceil(sqrt(area) / voxel size), clamped to [2, 6]) and each
//     sub-triangle's centroid is a sample (4 to 36 per triangle; for m = 2
//     one of them is the triangle's centroid). Each sample carries the
//     sub-triangle's area as its weight.
//  2. Each sample takes the label of the nearest labelled voxel (label > 0)
//     whose centre lies within `searchRadius` voxels (a growing cube around
//     the sample; nearest voxel centre wins, ties to the smaller label), or
//     no label if there is none.
//  3. A face takes the label with the largest summed weight over the samples
//     of all its triangles (ties: the larger sample count, then the smaller
//     label).
//  4. Faces without any labelled sample take, round by round, the most
//     common label of their already labelled edge neighbours (ties: smaller
//     label); faces never reached (a piece without labels) take the label of
//     the nearest labelled voxel to their centroid, found by a breadth-first
//     sweep through the volume. Without any labelled voxel every face gets 0.
//  5. The labels used are renumbered 0..K-1 in ascending order of voxel label.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "io/mesh/MeshIO.h"
#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

struct FaceLabelOptions {
    /// How far (in voxels, cube radius) a sample looks for a labelled voxel.
    int searchRadius = 3;
    /// false: run on the calling thread. The result is identical either way.
    bool threaded = true;
};

/// How the faces got their labels (for reports and warnings).
struct FaceLabelStatistics {
    std::size_t votedFaces = 0;         ///< by their own samples (step 3)
    std::size_t propagatedFaces = 0;    ///< from neighbouring faces (step 4)
    std::size_t nearestVoxelFaces = 0;  ///< from the nearest labelled voxel (step 4)
    std::size_t segments = 0;           ///< K: distinct labels in the result
    /// The voxel label of each face label 0..K-1 (ascending; empty when no
    /// voxel is labelled).
    std::vector<std::uint32_t> voxelLabels;
};

/// Per input face (mesh.faceCount entries) a label in 0..K-1, no gaps.
/// `labels`: 0 = background, its geometry maps voxel index to the mesh's
/// world coordinates (as voxelizeMesh makes it).
/// @throw UsageError for a searchRadius outside [0, 16] or an empty volume;
/// InterruptedError.
std::vector<std::uint32_t> labelFaces(const TriangleMesh& mesh, const LabelVolume& labels,
                                      const FaceLabelOptions& options = {},
                                      Interrupter& interrupter = nullInterrupter(),
                                      FaceLabelStatistics* statistics = nullptr);

}  // namespace skelseg
