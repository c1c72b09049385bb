#include "engine/Segmenter.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/NumberText.h"
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
        if (used != number.size() || !isDecimalNumberText(number))
            throw std::invalid_argument("not a decimal number");
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
    // The shortest text that reads back as the same value: "%g" kept six
    // digits, so the levels of --tau 3%,3.0000001% were both named "3%".
    return fmt::format(percent ? "{}%" : "{}", value);
}

const char* skeletonSearchName(SkeletonSearch search) {
    return search == SkeletonSearch::Band ? "band" : "exhaustive";
}

SkeletonSearch skeletonSearchToRun(const SegmentationParameters& parameters) {
    return parameters.finerTaus.empty() ? parameters.skeletonSearch : SkeletonSearch::Exhaustive;
}

std::vector<TauSpec> parseTauList(const std::string& text) {
    std::vector<TauSpec> taus;
    std::size_t start = 0;
    for (;;) {
        const std::size_t comma = text.find(',', start);
        const std::string item =
            text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (item.empty())
            throw UsageError("--tau '" + text +
                             "' has an empty value; give a list such as 1%,3%,9%");
        try {
            taus.push_back(TauSpec::parse(item));
        } catch (const UsageError& e) {
            if (item == text) throw;
            // Name the whole list: "--tau '1%,x': 'x' is not a number ...".
            std::string problem = e.what();
            const std::string prefix = "--tau '" + item + "' ";
            if (problem.rfind(prefix, 0) == 0) problem = problem.substr(prefix.size());
            throw UsageError("--tau '" + text + "': '" + item + "' " + problem);
        }
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    for (const TauSpec& t : taus)
        if (t.percent != taus.front().percent)
            throw UsageError("--tau '" + text +
                             "' mixes percentages and voxel areas; give all of one kind");
    std::sort(taus.begin(), taus.end(),
              [](const TauSpec& a, const TauSpec& b) { return a.value < b.value; });
    for (std::size_t i = 1; i < taus.size(); ++i)
        if (taus[i].value == taus[i - 1].value)
            throw UsageError("--tau '" + text + "' gives " + taus[i].toString() + " twice");
    return taus;
}

std::vector<TauSpec> SegmentationParameters::levelTaus() const {
    std::vector<TauSpec> taus = finerTaus;
    taus.push_back(tau);
    return taus;
}

std::string SegmentationParameters::tauListString() const {
    std::string text;
    for (const TauSpec& t : levelTaus()) text += (text.empty() ? "" : ",") + t.toString();
    return text;
}

CutOptions SegmentationParameters::cutOptions() const {
    CutOptions options = cutRules;
    options.sigmaMin = sigmaMin;
    options.bodyRatio = bodyRatio;
    options.consecutiveLevels = consecutiveLevels;
    options.mode = mode;
    return options;
}

std::uint64_t estimateSegmentationMemory(const Dims& dims, std::uint64_t objectVoxels, int threads,
                                         int levels, std::uint64_t boundaryVoxels) {
    const std::uint64_t voxels = dims.voxelCount();
    // Input mask (1) + labels (2) + object ids (4) per grid voxel; per object
    // crop at most the grid: mask (1) + feature transform (4) + node map (4).
    std::uint64_t bytes = voxels * (1 + 2 + 4) + voxels * (1 + 4 + 4);
    // Boundary graph ~ a sixth of the object voxels at most: ~12 bytes each
    // of CSR and the node's landmark row, plus per-thread workspaces (40
    // bytes per node, and a path cache at its bound whatever the graph);
    // candidates ~ 40 bytes per object voxel.
    const std::uint64_t boundary =
        std::max(std::min<std::uint64_t>(objectVoxels, objectVoxels / 6 + 4096), boundaryVoxels);
    bytes += boundary * (12 + sizeof(float) * Landmarks::kStride) +
             (boundary * 40 + PathCache::maxBytes()) * std::uint64_t(std::max(threads, 1));
    bytes += objectVoxels / 4 * 48;
    bytes += std::uint64_t(std::max(levels, 1) - 1) * voxels * 4;
    return bytes;
}

namespace {

/// Labels 1..65535 of a 16-bit label volume.
constexpr std::size_t kMaxLabelSegments = 65535;

/// One object's segments at one level, before global ids exist.
struct ObjectLabels {
    std::array<int, 3> origin;
    std::vector<std::uint64_t> area;  // boundary area of each local segment
    Volume<std::uint16_t> local;      // local id + 1 in the object's crop, 0 outside
};

/// Gives every segment of every object one global label 1..K by decreasing
/// boundary area (ties: object order, then local id), paints them into
/// `labels` and lists them in `segments`. Returns each object's global
/// label of each local segment.
std::vector<std::vector<std::uint16_t>> assembleLevelLabels(
    const std::vector<ObjectLabels>& objectLabels, LabelVolume& labels,
    std::vector<SegmentInfo>& segments) {
    struct LocalSegment {
        std::uint32_t object, local;
        std::uint64_t area;
    };
    std::vector<LocalSegment> localSegments;
    for (std::size_t o = 0; o < objectLabels.size(); ++o)
        for (std::size_t s = 0; s < objectLabels[o].area.size(); ++s)
            localSegments.push_back({std::uint32_t(o), std::uint32_t(s), objectLabels[o].area[s]});
    // The input's doing: bad input (exit 2). The file is unknown here:
    // segmentMaskStep() names it (an InputError with an empty file).
    if (localSegments.size() > kMaxLabelSegments)
        throw InputError("", "the volume has " + std::to_string(localSegments.size()) +
                                 " segments, more than a 16-bit label volume can hold");
    std::vector<std::size_t> order(localSegments.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return localSegments[a].area > localSegments[b].area;
    });
    std::vector<std::vector<std::uint16_t>> globalOf(objectLabels.size());
    for (std::size_t o = 0; o < objectLabels.size(); ++o)
        globalOf[o].assign(objectLabels[o].area.size(), 0);
    for (std::size_t rank = 0; rank < order.size(); ++rank) {
        const LocalSegment& s = localSegments[order[rank]];
        globalOf[s.object][s.local] = std::uint16_t(rank + 1);
        segments.push_back({std::uint16_t(rank + 1), s.object, 0, s.area});
    }
    for (std::size_t o = 0; o < objectLabels.size(); ++o) {
        const ObjectLabels& ol = objectLabels[o];
        const Dims cd = ol.local.dims();
        for (int z = 1; z < cd.z - 1; ++z)
            for (int y = 1; y < cd.y - 1; ++y)
                for (int x = 1; x < cd.x - 1; ++x) {
                    const std::uint16_t local = ol.local(x, y, z);
                    if (!local) continue;
                    const std::uint16_t label = globalOf[o][local - 1u];
                    labels(x + ol.origin[0], y + ol.origin[1], z + ol.origin[2]) = label;
                    ++segments[label - 1u].voxelCount;
                }
    }
    return globalOf;
}

}  // namespace

SegmentationResult segmentVolume(const MaskVolume& mask, const SegmentationParameters& requested,
                                 Interrupter& interrupter, StageTimer* timerIn) {
    SegmentationParameters p = requested;
    p.skeletonSearch = skeletonSearchToRun(p);
    StageTimer localTimer;
    StageTimer& timer = timerIn ? *timerIn : localTimer;
    SegmentationResult result;
    const Dims dims = mask.dims();
    result.labels = LabelVolume(dims, 0);
    result.labels.geometry = mask.geometry;
    result.tau = p.tau;
    // --joints with one tau: the top-level result is the joint level as a
    // run without levels gives it; the hierarchy is the nested joint level
    // and the junction-rule level (engine/SegmentationLevels.h).
    result.topIsCoarsestLevel = !(p.joints && p.finerTaus.empty());

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
            // The finest level's tau: a fragment is no part at any level.
            const TauSpec finestTau = p.levelTaus().front();
            const Fragments fragments =
                p.objectSources.empty()
                    ? Fragments{}
                    : findFragments(
                          found, areas, p.objectSources, islands.isIsland,
                          [&](double area) { return finestTau.areaFor(std::uint64_t(area)); });
            result.islands.fragments = fragments.count;
            result.islands.fragmentVoxels = fragments.voxels;
            found.objects.erase(
                std::remove_if(found.objects.begin(), found.objects.end(),
                               [&](const ObjectExtent& o) {
                                   return islands.isIsland[o.id] != 0 ||
                                          (fragments.count && fragments.isFragment[o.id] != 0);
                               }),
                found.objects.end());
        }
    }
    if (found.objects.empty())
        result.warnings.push_back("the volume holds no object voxels: no segments");
    // Every object is at least one segment: refused before any is segmented
    // (assembleLevelLabels checks the count of segments itself).
    if (found.objects.size() > kMaxLabelSegments)
        throw InputError("", "the volume has " + std::to_string(found.objects.size()) +
                                 " objects, so at least " + std::to_string(found.objects.size()) +
                                 " segments, more than a 16-bit label volume can hold");

    std::vector<ObjectLabels> objectLabels;
    // Per level below the top (finest first), per object: the same for that
    // level. With --joints the joint level comes first, at the finest tau.
    std::vector<TauSpec> finerTaus;
    if (p.joints) finerTaus.push_back(p.finerTaus.empty() ? p.tau : p.finerTaus.front());
    finerTaus.insert(finerTaus.end(), p.finerTaus.begin(), p.finerTaus.end());
    if (!result.topIsCoarsestLevel) finerTaus.push_back(p.tau);
    const std::size_t finerCount = finerTaus.size();
    std::vector<std::vector<ObjectLabels>> finerLabels(finerCount);
    std::vector<std::vector<std::vector<std::uint32_t>>> finerParents(finerCount);
    std::vector<std::uint64_t> movedNodes(finerCount, 0);
    std::vector<LevelSeconds> finerSeconds(finerCount);

    for (const ObjectExtent& extent : found.objects) {
        ObjectState state(p, interrupter, timer, extent);
        runObjectStages(state, found);
        objectLabels.push_back({state.origin, state.segments.area, std::move(state.localLabels)});
        for (std::size_t k = 0; k < finerCount; ++k) {
            ObjectLevelWork& level = state.finerLevels[k];
            finerLabels[k].push_back(
                {state.origin, level.segments.area, std::move(level.localLabels)});
            finerParents[k].push_back(std::move(level.parent));
            movedNodes[k] += level.movedNodes;
            finerSeconds[k].wall += level.seconds.wall;
            finerSeconds[k].cpu += level.seconds.cpu;
        }
        result.coarsestLevelSeconds.wall += state.coarsestSeconds.wall;
        result.coarsestLevelSeconds.cpu += state.coarsestSeconds.cpu;
        result.objects.push_back(std::move(state.out));
        throwIfInterrupted(interrupter);
    }

    std::vector<std::vector<std::uint16_t>> globalOf;
    {
        Stage stage(timer, interrupter, "label volume", false);
        globalOf = assembleLevelLabels(objectLabels, result.labels, result.segments);
        for (std::size_t o = 0; o < objectLabels.size(); ++o)
            for (std::uint16_t label : globalOf[o]) result.objects[o].labels.push_back(label);
    }
    // Finer levels from the coarsest down: each level's parents are labels
    // of the one above it (none for a coarsest level that is not the top).
    result.finerLevels.resize(finerCount);
    for (std::size_t k = finerCount; k-- > 0;) {
        Stage stage(timer, interrupter, "label volume", false);
        SegmentationLevel& level = result.finerLevels[k];
        level.tau = finerTaus[k];
        level.joints = p.joints && k == 0;
        const bool coarsest = !result.topIsCoarsestLevel && k + 1 == finerCount;
        level.labels = LabelVolume(dims, 0);
        level.labels.geometry = mask.geometry;
        level.seconds = finerSeconds[k];
        level.nestingMovedNodes = movedNodes[k];
        const std::vector<std::vector<std::uint16_t>> levelGlobalOf =
            assembleLevelLabels(finerLabels[k], level.labels, level.segments);
        if (!coarsest) level.parentLabel.assign(level.segments.size(), 0);
        for (std::size_t o = 0; o < levelGlobalOf.size(); ++o) {
            if (!coarsest)
                for (std::size_t s = 0; s < levelGlobalOf[o].size(); ++s)
                    level.parentLabel[levelGlobalOf[o][s] - 1u] =
                        globalOf[o][finerParents[k][o][s]];
            result.objects[o].finerLevels[k].labels = levelGlobalOf[o];
        }
        globalOf = levelGlobalOf;
    }
    return result;
}

}  // namespace skelseg
