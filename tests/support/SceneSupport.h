// Helpers for scene tests: segment a generated shape, inspect the result.
#pragma once

#include <set>
#include <string>
#include <utility>
#include <vector>

#include "engine/Segmenter.h"
#include "io/shapes/SyntheticShapes.h"

namespace skelseg::test {

/// The size (voxels along the longest side) most scene tests rasterise
/// their shapes at.
constexpr int kSceneSize = 112;

struct SceneRun {
    MaskVolume mask;
    SegmentationResult result;
};

/// Number of parts the segmentation found.
inline std::size_t partCount(const SceneRun& run) {
    return run.result.segments.size();
}

/// Rasterises makeShape(name, pose) at `size` (optionally with boundary
/// noise) and segments it with `parameters`.
SceneRun segmentShape(const std::string& name, int size,
                      const SegmentationParameters& parameters = {}, int pose = 0,
                      double noise = 0.0, std::uint64_t seed = 7);

/// Pairs of labels (a < b) whose voxels are 26-adjacent.
std::set<std::pair<int, int>> segmentAdjacency(const LabelVolume& labels);

/// Sorted degree sequence of the adjacency graph on labels 1..count.
std::vector<int> degreeSequence(const std::set<std::pair<int, int>>& adjacency, int count);

/// Model-space point -> voxel coordinates (inverse of the uniform geometry).
std::array<double, 3> modelToVoxel(const VolumeGeometry& geometry,
                                   const std::array<double, 3>& model);

}  // namespace skelseg::test
