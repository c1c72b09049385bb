#include "engine/LevelOutputs.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "io/mesh/FaceLabelNesting.h"
#include "io/mesh/FaceLabels.h"

using json = nlohmann::json;

namespace skelseg {

namespace {

/// Per coarser label c (1-based, index c - 1): the fine label with the most
/// voxels among its children (ties: the smaller label), 0 if none.
std::vector<std::uint16_t> largestChildren(const SegmentationLevel& fine,
                                           std::size_t coarserSegments) {
    std::vector<std::uint16_t> child(coarserSegments, 0);
    std::vector<std::uint64_t> best(coarserSegments, 0);
    for (std::size_t l = 0; l < fine.parentLabel.size(); ++l) {
        const std::size_t c = fine.parentLabel[l] - 1u;
        if (!child[c] || fine.segments[l].voxelCount > best[c])
            child[c] = std::uint16_t(l + 1), best[c] = fine.segments[l].voxelCount;
    }
    return child;
}

/// World position to (fractional) voxel index: the inverse of indexToWorld.
struct WorldToVoxel {
    explicit WorldToVoxel(const VolumeGeometry& g) : origin(g.origin) {
        const auto& d = g.directions;  // d[axis][component]: columns of the matrix
        const double m[3][3] = {
            {d[0][0], d[1][0], d[2][0]}, {d[0][1], d[1][1], d[2][1]}, {d[0][2], d[1][2], d[2][2]}};
        const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) {
                // Inverse by cofactors: inv[r][c] = cofactor(c, r) / det.
                const int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
                inverse[r][c] = (m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]) / det;
            }
    }
    std::array<double, 3> operator()(const std::array<double, 3>& w) const {
        std::array<double, 3> index{};
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) index[r] += inverse[r][c] * (w[c] - origin[c]);
        return index;
    }
    std::array<double, 3> origin;
    double inverse[3][3];
};

}  // namespace

void labelLevelFaces(const TriangleMesh& mesh, const SegmentationResult& result,
                     const std::vector<std::uint32_t>& coarsestFaceLabels,
                     const std::vector<std::uint32_t>& coarsestVoxelLabelOfFaceLabel,
                     LevelOutputs& levels, Interrupter& interrupter) {
    const std::size_t count = result.levelCount();
    auto voxelLabelsOf = [](const std::vector<std::uint32_t>& faceLabels,
                            const std::vector<std::uint32_t>& voxelLabelOfFaceLabel) {
        std::vector<std::uint32_t> voxel(faceLabels.size(), 0);
        if (!voxelLabelOfFaceLabel.empty())
            for (std::size_t f = 0; f < faceLabels.size(); ++f)
                voxel[f] = voxelLabelOfFaceLabel[faceLabels[f]];
        return voxel;
    };
    levels.faceVoxelLabels.assign(count, {});
    levels.faceLabels.assign(count, {});
    levels.nestedFaces.assign(count, 0);
    if (result.topIsCoarsestLevel) {
        levels.faceVoxelLabels[count - 1] =
            voxelLabelsOf(coarsestFaceLabels, coarsestVoxelLabelOfFaceLabel);
        levels.faceLabels[count - 1] = coarsestFaceLabels;
    } else {
        // The coarsest level is not the top-level result: its faces are
        // voted on from its own labels, as the top level's are.
        FaceLabelStatistics statistics;
        const std::vector<std::uint32_t> voted =
            labelFaces(mesh, result.levelLabels(count - 1), {}, interrupter, &statistics);
        levels.faceVoxelLabels[count - 1] = voxelLabelsOf(voted, statistics.voxelLabels);
        levels.faceLabels[count - 1] = voted;
    }
    for (std::size_t k = count - 1; k-- > 0;) {
        const SegmentationLevel& level = result.finerLevels[k];
        FaceLabelStatistics statistics;
        const std::vector<std::uint32_t> voted =
            labelFaces(mesh, level.labels, {}, interrupter, &statistics);
        std::vector<std::uint32_t> voxel = voxelLabelsOf(voted, statistics.voxelLabels);
        levels.nestedFaces[k] =
            nestFaceLabels(mesh, voxel, levels.faceVoxelLabels[k + 1], level.parentLabel,
                           largestChildren(level, result.levelSegments(k + 1).size()));
        levels.faceLabels[k] = renumberFaceLabels(voxel);
        levels.faceVoxelLabels[k] = std::move(voxel);
    }
}

std::vector<std::vector<std::vector<std::array<double, 3>>>> levelCutLoops(
    const SegmentationResult& result) {
    const std::size_t count = result.levelCount();
    std::vector<std::vector<std::vector<std::array<double, 3>>>> loops(count);
    const VolumeGeometry& g = result.labels.geometry;
    for (std::size_t k = 0; k < count; ++k)
        for (const ObjectSegmentation& object : result.objects) {
            for (const auto& loop : object.levelCutLoops(k)) {
                std::vector<std::array<double, 3>> points;
                for (const auto& v : loop) points.push_back(g.indexToWorld(v[0], v[1], v[2]));
                loops[k].push_back(std::move(points));
            }
        }
    return loops;
}

std::vector<std::vector<std::uint32_t>> levelTriangleLabels(
    const SegmentationResult& result, const std::vector<std::array<double, 3>>& vertices,
    const std::vector<std::array<std::uint32_t, 3>>& triangles,
    const std::vector<std::uint32_t>& triangleLabels) {
    const std::size_t count = result.levelCount();
    std::vector<std::vector<std::uint32_t>> out(count);
    out[count - 1] = triangleLabels;
    if (count == 1) return out;
    // The surface's labels: the top-level result's, the coarsest level's
    // unless --joints with one tau made the top the joint level.
    const LabelVolume& coarse = result.labels;
    const LabelVolume& finest = result.finerLevels[0].labels;
    // Fallback for a triangle with no voxel of its segment nearby: the
    // largest finest segment under its top-level segment.
    std::vector<std::uint16_t> fallback(result.segments.size() + 1, 0);
    std::vector<std::uint64_t> fallbackSize(result.segments.size() + 1, 0);
    if (result.topIsCoarsestLevel) {
        for (std::size_t l = 1; l <= result.finerLevels[0].segments.size(); ++l) {
            std::uint32_t ancestor = std::uint32_t(l);
            for (std::size_t k = 0; k + 1 < count; ++k)
                ancestor = result.finerLevels[k].parentLabel[ancestor - 1u];
            const std::uint64_t size = result.finerLevels[0].segments[l - 1].voxelCount;
            if (!fallback[ancestor] || size > fallbackSize[ancestor])
                fallback[ancestor] = std::uint16_t(l), fallbackSize[ancestor] = size;
        }
    } else {
        // The top level is not in the chain of parents: count the overlaps.
        std::unordered_map<std::uint32_t, std::uint64_t> overlap;
        const std::vector<std::uint16_t>& top = coarse.values();
        const std::vector<std::uint16_t>& fine = finest.values();
        for (std::size_t i = 0; i < top.size(); ++i)
            if (top[i] && fine[i]) ++overlap[(std::uint32_t(top[i]) << 16) | fine[i]];
        for (const auto& [key, size] : overlap) {
            const std::uint32_t topLabel = key >> 16, fineLabel = key & 0xffffu;
            if (topLabel < fallback.size() &&
                (size > fallbackSize[topLabel] ||
                 (size == fallbackSize[topLabel] && fineLabel < fallback[topLabel])))
                fallback[topLabel] = std::uint16_t(fineLabel), fallbackSize[topLabel] = size;
        }
    }
    const WorldToVoxel toVoxel(coarse.geometry);
    constexpr int kRadius = 2;
    for (auto& labels : out) labels.resize(triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        std::array<double, 3> centroid{};
        for (std::uint32_t v : triangles[t])
            for (int c = 0; c < 3; ++c) centroid[c] += vertices[v][c] / 3.0;
        const std::array<double, 3> index = toVoxel(centroid);
        const std::uint32_t label = triangleLabels[t];
        const int cx = int(std::floor(index[0] + 0.5)), cy = int(std::floor(index[1] + 0.5)),
                  cz = int(std::floor(index[2] + 0.5));
        double bestDistance = 1e300;
        std::uint32_t fine = label < fallback.size() ? fallback[label] : 0;
        for (int z = cz - kRadius; z <= cz + kRadius; ++z)
            for (int y = cy - kRadius; y <= cy + kRadius; ++y)
                for (int x = cx - kRadius; x <= cx + kRadius; ++x) {
                    if (!coarse.contains(x, y, z) || coarse(x, y, z) != label) continue;
                    const double d = (x - index[0]) * (x - index[0]) +
                                     (y - index[1]) * (y - index[1]) +
                                     (z - index[2]) * (z - index[2]);
                    if (d < bestDistance) bestDistance = d, fine = finest(x, y, z);
                }
        out[0][t] = fine;
        const std::size_t chained = result.topIsCoarsestLevel ? count - 1 : count;
        for (std::size_t k = 1; k < chained; ++k)
            out[k][t] =
                out[k - 1][t] ? result.finerLevels[k - 1].parentLabel[out[k - 1][t] - 1u] : 0;
    }
    return out;
}

json reportLevelsJson(const SegmentationResult& result,
                      const std::vector<std::size_t>& nestedFaces) {
    json levels = json::array();
    for (std::size_t k = 0; k < result.levelCount(); ++k) {
        const LevelSeconds& seconds = result.levelSeconds(k);
        json level = {{"level", k},
                      {"tau", result.levelTau(k).toString()},
                      {"joints", result.levelIsJoints(k)},
                      {"segments", result.levelSegments(k).size()},
                      {"wall_seconds", seconds.wall},
                      {"cpu_seconds", seconds.cpu}};
        if (!result.isCoarsestLevel(k)) {
            level["nesting_moved_boundary_voxels"] = result.finerLevels[k].nestingMovedNodes;
            if (k < nestedFaces.size()) level["nesting_moved_faces"] = nestedFaces[k];
        }
        levels.push_back(level);
    }
    return levels;
}

std::string hierarchyJson(const SegmentationResult& result, const LevelOutputs& levels,
                          bool isMesh) {
    const std::size_t count = result.levelCount();
    json out;
    out["levels"] = json::array();
    for (std::size_t k = 0; k < count; ++k) {
        const bool coarsest = k + 1 == count;
        const std::vector<SegmentInfo>& segments = result.levelSegments(k);
        json level;
        level["level"] = k;
        level["tau"] = result.levelTau(k).toString();
        // Written only with --joints, so files of runs without it keep their bytes.
        if (result.levelIsJoints(k)) level["joints"] = true;
        json areas = json::array();
        for (const ObjectSegmentation& object : result.objects)
            areas.push_back(object.levelTauArea(k));
        level["tau_areas"] = areas;
        level["segment_count"] = segments.size();
        std::vector<std::uint64_t> faces(segments.size() + 1, 0);
        if (isMesh)
            for (std::uint32_t label : levels.faceVoxelLabels[k])
                if (label && label <= segments.size()) ++faces[label];
        std::uint32_t nextSegLabel = 0;  // segmentation.seg numbers the labels with faces in order
        json list = json::array();
        for (const SegmentInfo& s : segments) {
            json entry = {{"id", s.label}, {"voxels", s.voxelCount}};
            if (isMesh) {
                entry["faces"] = faces[s.label];
                entry["seg_label"] = faces[s.label] ? json(nextSegLabel++) : json(nullptr);
            }
            entry["parent"] = coarsest ? json(nullptr) : json(result.parentLabel(k, s.label));
            list.push_back(entry);
        }
        level["segments"] = list;
        out["levels"].push_back(level);
    }
    return out.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace skelseg
