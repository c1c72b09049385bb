// skelseg: what the outputs of a hierarchy run need beyond the segmentation
// (engine/SegmentationLevels.h makes the levels; SegmentOutput.h writes them).
//
//   labelLevelFaces      mesh inputs: every finer level's face labels, voted
//                        by labelFaces on that level's volume and made to nest
//                        (io/mesh/FaceLabelNesting.h), coarsest level down
//   levelTriangleLabels  the viewer's surface labelled at every level: mesh
//                        triangles by their faces; for volume inputs the
//                        coarsest level's surface, each triangle taking the
//                        finest label of the nearest voxel of its own coarse
//                        segment, and the coarser labels through the parents
//   hierarchyJson        OUT/hierarchy.json (schema: docs/outputs.md)
#pragma once

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/Segmenter.h"
#include "io/mesh/MeshIO.h"
#include "kernels/base/Interrupter.h"

namespace skelseg {

/// Per level, finest first (the coarsest last), of a hierarchy run.
struct LevelOutputs {
    /// Mesh inputs: every face's voxel label (0: none) at each level.
    std::vector<std::vector<std::uint32_t>> faceVoxelLabels;
    /// Mesh inputs: every face's label as segmentation.seg numbers it.
    std::vector<std::vector<std::uint32_t>> faceLabels;
    /// Mesh inputs: faces the nesting repair changed at each finer level.
    std::vector<std::size_t> nestedFaces;
    /// Cut loops in world coordinates.
    std::vector<std::vector<std::vector<std::array<double, 3>>>> cutLoops;
};

/// Fills `levels.faceVoxelLabels`, `faceLabels` and `nestedFaces` for every
/// level; the coarsest level's are given (the run's own face labels and the
/// voxel label of each of them, FaceLabelStatistics::voxelLabels).
/// @throw InterruptedError.
void labelLevelFaces(const TriangleMesh& mesh, const SegmentationResult& result,
                     const std::vector<std::uint32_t>& coarsestFaceLabels,
                     const std::vector<std::uint32_t>& coarsestVoxelLabelOfFaceLabel,
                     LevelOutputs& levels, Interrupter& interrupter);

/// The cut loops of every level in world coordinates, finest first.
std::vector<std::vector<std::vector<std::array<double, 3>>>> levelCutLoops(
    const SegmentationResult& result);

/// The label of the segment at the finest level under `coarsestLabel`
/// through the parents, chained up to the coarsest (finest first): labels of
/// one triangle or face at every level.
/// Volume inputs: `triangleLabels` (coarsest labels of a surface extracted
/// from result.labels, vertices in world coordinates) at every level.
std::vector<std::vector<std::uint32_t>> levelTriangleLabels(
    const SegmentationResult& result, const std::vector<std::array<double, 3>>& vertices,
    const std::vector<std::array<std::uint32_t, 3>>& triangles,
    const std::vector<std::uint32_t>& triangleLabels);

/// report.json's "levels": every level, finest first (one for a single
/// tau): tau, segments and the seconds of its per-level stages; finer
/// levels add the nesting repair's counts (nestedFaces: per level, may be
/// empty for volume inputs).
nlohmann::json reportLevelsJson(const SegmentationResult& result,
                                const std::vector<std::size_t>& nestedFaces);

/// The text of hierarchy.json (indented, ending in a newline).
std::string hierarchyJson(const SegmentationResult& result, const LevelOutputs& levels,
                          bool isMesh);

}  // namespace skelseg
