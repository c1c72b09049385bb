#include "engine/Segmenter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "engine/SegmentationStages.h"
#include "engine/Stage.h"
#include "kernels/ConnectedObjects.h"
#include "kernels/Islands.h"
#include "kernels/PathSearch.h"

namespace skelseg {

TauSpec TauSpec::parse(const std::string& text) {
    TauSpec spec;
    std::string number = text;
    spec.percent = !number.empty() && number.back() == '%';
    if (spec.percent) number.pop_back();
    try {
        std::size_t used = 0;
        spec.value = std::stod(number, &used);
        if (used != number.size()) throw std::invalid_argument("trailing characters");
    } catch (const std::exception&) {
        throw UsageError("--tau '" + text +
                         "' is not a number of voxels or a percentage such as 3%");
    }
    if (!(spec.value >= 0.0) || !std::isfinite(spec.value) || (spec.percent && spec.value > 100.0))
        throw UsageError("--tau '" + text +
                         "' is out of range (0 to 100% or a non-negative voxel area)");
    return spec;
}

std::string TauSpec::toString() const {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, percent ? "%g%%" : "%g", value);
    return buffer;
}

const char* skeletonSearchName(SkeletonSearch search) {
    return search == SkeletonSearch::Band ? "band" : "exhaustive";
}

std::uint64_t estimateSegmentationMemory(const Dims& dims, std::uint64_t objectVoxels,
                                         int threads) {
    const std::uint64_t voxels = dims.voxelCount();
    // Input mask (1) + labels (2) + object ids (4) per grid voxel; per object
    // crop at most the grid: mask (1) + feature transform (4) + node map (4).
    std::uint64_t bytes = voxels * (1 + 2 + 4) + voxels * (1 + 4 + 4);
    // Boundary graph ~ a sixth of the object voxels at most: ~12 bytes each
    // of CSR and the node's landmark row, plus per-thread workspaces;
    // candidates ~ 40 bytes per object voxel.
    const std::uint64_t boundary = std::min<std::uint64_t>(objectVoxels, objectVoxels / 6 + 4096);
    bytes += boundary * (12 + sizeof(float) * Landmarks::kStride) +
             boundary * 40 * std::uint64_t(std::max(threads, 1));
    bytes += objectVoxels / 4 * 48;
    return bytes;
}

SegmentationResult segmentVolume(const MaskVolume& mask, const SegmentationParameters& p,
                                 Interrupter& interrupter, StageTimer* timerIn) {
    StageTimer localTimer;
    StageTimer& timer = timerIn ? *timerIn : localTimer;
    SegmentationResult result;
    const Dims dims = mask.dims();
    result.labels = LabelVolume(dims, 0);
    result.labels.geometry = mask.geometry;

    ConnectedObjects found;
    {
        Stage stage(timer, interrupter, "objects", true);
        found = findConnectedObjects(mask, {p.threaded}, interrupter);
        // Islands: objects whose boundary area is below the largest object's
        // noise area are no parts (kernels/Islands.h).
        const std::vector<std::uint64_t> areas = objectBoundaryAreas(mask, found, {p.threaded});
        if (!areas.empty()) {
            const double largestArea = double(areas[largestObject(areas)]);
            result.islands.noiseArea = p.noiseAreaFor(largestArea);
            const Islands islands = findIslands(found.objects, areas, result.islands.noiseArea);
            result.islands.count = islands.count;
            result.islands.voxels = islands.voxels;
            found.objects.erase(
                std::remove_if(found.objects.begin(), found.objects.end(),
                               [&](const ObjectExtent& o) { return islands.isIsland[o.id] != 0; }),
                found.objects.end());
        }
    }
    if (found.objects.empty())
        result.warnings.push_back("the volume holds no object voxels: no segments");

    struct LocalSegment {
        std::uint32_t object, local;
        std::uint64_t area, voxels;
    };
    std::vector<LocalSegment> localSegments;
    // Per object: local segment label of each voxel in the crop, kept until
    // global ids are known.
    struct ObjectLabels {
        std::array<int, 3> origin;
        Volume<std::uint16_t> local;  // local id + 1
    };
    std::vector<ObjectLabels> objectLabels;

    for (const ObjectExtent& extent : found.objects) {
        ObjectState state(p, interrupter, timer, extent);
        runObjectStages(state, mask, found.component);
        for (std::uint32_t s = 0; s < state.segments.segmentCount; ++s)
            localSegments.push_back(
                {std::uint32_t(result.objects.size()), s, state.segments.area[s], 0});
        objectLabels.push_back({state.origin, std::move(state.localLabels)});
        result.objects.push_back(std::move(state.out));
        throwIfInterrupted(interrupter);
    }

    // Global ids by decreasing boundary area; ties by object, then local id.
    if (localSegments.size() > 65535)
        throw Error("the volume has " + std::to_string(localSegments.size()) +
                    " segments, more than a 16-bit label volume can hold");
    std::vector<std::size_t> order(localSegments.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return localSegments[a].area > localSegments[b].area;
    });
    std::vector<std::vector<std::uint16_t>> globalOf(result.objects.size());
    for (std::size_t rank = 0; rank < order.size(); ++rank) {
        const LocalSegment& s = localSegments[order[rank]];
        auto& map = globalOf[s.object];
        if (map.size() <= s.local) map.resize(s.local + 1, 0);
        map[s.local] = std::uint16_t(rank + 1);
        result.segments.push_back({std::uint16_t(rank + 1), s.object, 0, s.area});
    }
    {
        Stage stage(timer, interrupter, "label volume", false);
        for (std::size_t o = 0; o < objectLabels.size(); ++o) {
            const ObjectLabels& ol = objectLabels[o];
            const Dims cd = ol.local.dims();
            for (int z = 1; z < cd.z - 1; ++z)
                for (int y = 1; y < cd.y - 1; ++y)
                    for (int x = 1; x < cd.x - 1; ++x) {
                        const std::uint16_t local = ol.local(x, y, z);
                        if (!local) continue;
                        const std::uint16_t label = globalOf[o][local - 1u];
                        result.labels(x + ol.origin[0], y + ol.origin[1], z + ol.origin[2]) = label;
                        ++result.segments[label - 1u].voxelCount;
                    }
            for (std::uint16_t label : globalOf[o]) result.objects[o].labels.push_back(label);
        }
    }
    return result;
}

}  // namespace skelseg
