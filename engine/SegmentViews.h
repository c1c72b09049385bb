// skelseg: segments.glb and viewer.html of a run, from its results.
//
// The glue between a segmentation and the two viewers' writers
// (io/render/GltfWriter.h, io/render/ViewerWriter.h): it names the segments
// (id, size in voxels), picks the title (the input's file name) and the
// facts shown under it, and hands over the labelled surface that
// segments.ply was written from, so all three show the same surface.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/Segmenter.h"
#include "io/files/OutputDirectory.h"
#include "io/render/PlyWriter.h"

namespace skelseg {

/// What a run has drawn by the time its surfaces exist.
struct SegmentViewInputs {
    const SegmentationResult* result = nullptr;
    /// The segments.ply surface: positions (world), triangles, labels 1..K.
    const std::vector<std::array<double, 3>>* vertices = nullptr;
    const std::vector<std::array<std::uint32_t, 3>>* triangles = nullptr;
    const std::vector<std::uint32_t>* triangleLabels = nullptr;
    const std::vector<SkeletonPointRecord>* skeletonPoints = nullptr;
    const std::vector<std::array<std::uint32_t, 2>>* skeletonEdges = nullptr;
    const std::vector<std::vector<std::array<double, 3>>>* cutLoops = nullptr;
    /// Page title (the input's file name) and the lines under it.
    std::string title;
    std::vector<std::string> facts;
    std::string tau;
    /// Hierarchy runs: the surface's labels (1..K, as labels.nrrd) at every
    /// level, finest first, the last the coarsest; empty for one level
    /// (triangleLabels then). Levels follow result->finerLevels.
    std::vector<std::vector<std::uint32_t>> levelTriangleLabels;
    /// Hierarchy runs: every level's cut loops (world), finest first.
    const std::vector<std::vector<std::vector<std::array<double, 3>>>>* levelCutLoops = nullptr;
};

/// Stages segments.glb and viewer.html in `out` (both written concurrently).
/// @throw OutputError if a file cannot be written.
void writeSegmentViews(OutputDirectory& out, const SegmentViewInputs& inputs);

}  // namespace skelseg
