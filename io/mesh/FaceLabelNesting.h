// skelseg: face labels of a finer level that nest in the coarser level's
// (levels of a hierarchy run, docs/algorithm.md "Levels").
//
// Every level's faces are voted on by labelFaces (FaceLabels.h) from that
// level's label volume. The volumes nest voxel by voxel, but a face's vote
// at the finer level may go to a segment whose parent is not the face's
// coarse segment (a face straddling a coarse boundary weighs the pieces
// differently). Such faces are re-labelled, round by round, with the most
// common fine label among their edge neighbours whose parent is the face's
// coarse segment (ties: smaller label); faces no such neighbour reaches take
// `fallbackChild` of their coarse segment (its largest child). Afterwards
// parentLabel[fine] == coarse on every face.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "io/mesh/MeshIO.h"

namespace skelseg {

/// Repairs `fineVoxelLabels` (per face, the fine level's voxel label 1..K)
/// against `coarseVoxelLabels` (per face, the next coarser level's label).
/// parentLabel[l - 1]: the coarse label of fine label l; fallbackChild[c - 1]:
/// a fine label whose parent is coarse label c. Faces with label 0 at either
/// level are left alone. Returns the number of faces changed.
/// @throw UsageError if the sizes do not match the mesh or a label has no entry.
std::size_t nestFaceLabels(const TriangleMesh& mesh, std::vector<std::uint32_t>& fineVoxelLabels,
                           const std::vector<std::uint32_t>& coarseVoxelLabels,
                           const std::vector<std::uint16_t>& parentLabel,
                           const std::vector<std::uint16_t>& fallbackChild);

/// Per-face voxel labels as segmentation.seg numbers them: 0..K-1 by
/// ascending voxel label (label 0 faces stay 0).
std::vector<std::uint32_t> renumberFaceLabels(const std::vector<std::uint32_t>& voxelLabels);

}  // namespace skelseg
