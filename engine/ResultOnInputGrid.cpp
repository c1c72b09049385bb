#include "engine/ResultOnInputGrid.h"

namespace skelseg {

namespace {
void recountSegmentVoxels(const LabelVolume& labels, std::vector<SegmentInfo>& segments) {
    for (SegmentInfo& s : segments) s.voxelCount = 0;
    for (std::uint16_t l : labels.values())
        if (l) ++segments[l - 1u].voxelCount;
}
}  // namespace

void moveResultToInputGrid(
    SegmentationResult& result, const std::function<LabelVolume(const LabelVolume&)>& labelsOnInput,
    const std::function<std::array<int, 3>(const std::array<int, 3>&)>& voxelOnInput) {
    result.labels = labelsOnInput(result.labels);
    const auto move = [&](std::array<int, 3>& v) { v = voxelOnInput(v); };
    for (ObjectSegmentation& o : result.objects) {
        for (auto& v : o.skeleton) move(v.voxel);
        for (auto& j : o.junctions) move(j.voxel);
        for (auto& c : o.criticalPoints) move(c.voxel);
        for (auto& c : o.cuts) move(c.voxel);
        for (auto& c : o.jointCandidates) move(c.voxel);
        for (auto& loop : o.cutLoops)
            for (auto& v : loop) move(v);
        for (ObjectLevel& level : o.finerLevels)
            for (auto& loop : level.cutLoops)
                for (auto& v : loop) move(v);
        move(o.bboxMin);
        move(o.bboxMax);
    }
    recountSegmentVoxels(result.labels, result.segments);
    for (SegmentationLevel& level : result.finerLevels) {
        level.labels = labelsOnInput(level.labels);
        recountSegmentVoxels(level.labels, level.segments);
    }
}

void cubicResultOnInputGrid(SegmentationResult& result, const CubicGrid& grid,
                            Interrupter& interrupter) {
    moveResultToInputGrid(
        result,
        [&](const LabelVolume& labels) { return labelsOnInputGrid(labels, grid, {}, interrupter); },
        [&](const std::array<int, 3>& v) { return grid.inputVoxelOf(v); });
}

}  // namespace skelseg
