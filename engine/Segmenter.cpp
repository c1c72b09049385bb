#include "engine/Segmenter.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "kernels/BoundaryGraph.h"
#include "kernels/ConnectedObjects.h"
#include "kernels/FeatureTransform.h"
#include "kernels/Islands.h"
#include "kernels/PathSearch.h"
#include "kernels/RimCount.h"
#include "kernels/SkeletonGraph.h"
#include "kernels/SurfaceLabelling.h"

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

namespace {

/// Orders a cut loop Gamma(q) into a polyline: a shortest arc a -> b inside
/// Gamma, then the way back b -> a avoiding the first arc (falls back to the
/// dilated set, then to the open arc).
std::vector<std::uint32_t> orderLoop(const BoundaryGraph& graph,
                                     const std::vector<std::uint32_t>& gamma, std::uint32_t a,
                                     std::uint32_t b, GeodesicSearch& search, RimCounter& rims) {
    rims.countRims(gamma);
    std::vector<std::uint32_t> arc1, arc2;
    if (search.shortestPathWithin(
            a, b, [&](std::uint32_t n) { return rims.isInPathSet(n); }, &arc1) == kUnreachable)
        return gamma;
    std::vector<std::uint8_t> blockedLocal;
    std::vector<std::uint32_t> blocked;
    const float keepRadius = 2.5f;
    for (std::size_t i = 1; i + 1 < arc1.size(); ++i) {
        const std::uint32_t n = arc1[i];
        if (graph.euclidean(n, a) < keepRadius || graph.euclidean(n, b) < keepRadius) continue;
        blocked.push_back(n);
        for (std::uint32_t e = graph.offset[n]; e < graph.offset[n + 1]; ++e) {
            const std::uint32_t m = graph.neighbour[e];
            if (graph.euclidean(m, a) >= keepRadius && graph.euclidean(m, b) >= keepRadius)
                blocked.push_back(m);
        }
    }
    std::sort(blocked.begin(), blocked.end());
    auto isBlocked = [&](std::uint32_t n) {
        return std::binary_search(blocked.begin(), blocked.end(), n);
    };
    float back = search.shortestPathWithin(
        b, a, [&](std::uint32_t n) { return rims.isInPathSet(n) && !isBlocked(n); }, &arc2);
    if (back == kUnreachable)
        back = search.shortestPathWithin(
            b, a, [&](std::uint32_t n) { return rims.isInDilated(n) && !isBlocked(n); }, &arc2);
    if (back == kUnreachable) return arc1;
    arc1.insert(arc1.end(), arc2.begin() + 1, arc2.end() - 1);
    return arc1;
}

/// Components below this area never make a rim count in an object of
/// boundary area `boundaryArea` (SegmentationParameters::noiseAreaMin).
double noiseAreaFor(const SegmentationParameters& p, double boundaryArea) {
    return std::min(std::max(p.noiseAreaMin, p.noiseAreaFraction * boundaryArea),
                    std::max(p.tau.areaFor(std::uint64_t(boundaryArea)), 1.0));
}

}  // namespace

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

    std::vector<std::uint32_t> component;
    std::vector<ObjectExtent> objects;
    {
        auto t = timer.stage("objects", true);
        InterrupterScope scope(interrupter, "objects");
        ConnectedObjects found = findConnectedObjects(mask, {p.threaded}, interrupter);
        // Islands: objects whose boundary area is below the largest object's
        // noise area are no parts (kernels/Islands.h).
        const std::vector<std::uint64_t> areas = objectBoundaryAreas(mask, found, {p.threaded});
        if (!areas.empty()) {
            const double largestArea = double(areas[largestObject(areas)]);
            result.islands.noiseArea = noiseAreaFor(p, largestArea);
            const Islands islands = findIslands(found.objects, areas, result.islands.noiseArea);
            result.islands.count = islands.count;
            result.islands.voxels = islands.voxels;
            found.objects.erase(
                std::remove_if(found.objects.begin(), found.objects.end(),
                               [&](const ObjectExtent& o) { return islands.isIsland[o.id] != 0; }),
                found.objects.end());
        }
        objects = std::move(found.objects);
        component = std::move(found.component);
    }
    if (objects.empty())
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

    for (const ObjectExtent& extent : objects) {
        ObjectSegmentation out;
        out.voxelCount = extent.voxels;
        out.bboxMin = extent.lo;
        out.bboxMax = extent.hi;
        // Crop with one voxel of background padding on every side.
        const std::array<int, 3> origin = {extent.lo[0] - 1, extent.lo[1] - 1, extent.lo[2] - 1};
        const Dims cropDims{extent.hi[0] - extent.lo[0] + 3, extent.hi[1] - extent.lo[1] + 3,
                            extent.hi[2] - extent.lo[2] + 3};
        MaskVolume crop(cropDims, 0);
        {
            auto t = timer.stage("objects", true);
            auto cropPlanes = [&](int z0, int z1) {
                for (int z = z0; z < z1; ++z)
                    for (int y = 1; y < cropDims.y - 1; ++y) {
                        // Row start at the first object column (x = 1 in the crop): origin[0]
                        // itself may be -1, and forming a pointer before the array is undefined.
                        const std::uint32_t* in =
                            component.data() +
                            mask.index(origin[0] + 1, y + origin[1], z + origin[2]);
                        for (int x = 1; x < cropDims.x - 1; ++x)
                            crop(x, y, z) = in[x - 1] == extent.id + 1 ? 1 : 0;
                    }
            };
            if (p.threaded)
                tbb::parallel_for(
                    tbb::blocked_range<int>(1, cropDims.z - 1),
                    [&](const tbb::blocked_range<int>& r) { cropPlanes(r.begin(), r.end()); });
            else
                cropPlanes(1, cropDims.z - 1);
        }
        auto toGrid = [&](std::uint32_t cropVoxel) -> std::array<int, 3> {
            const std::uint32_t cx = std::uint32_t(cropDims.x), cy = std::uint32_t(cropDims.y);
            return {int(cropVoxel % cx) + origin[0], int((cropVoxel / cx) % cy) + origin[1],
                    int(cropVoxel / (cx * cy)) + origin[2]};
        };

        Volume<std::uint32_t> ft;
        {
            auto t = timer.stage("feature transform", true);
            const MaskVolume sites = boundaryVoxels(crop, {p.threaded});
            ft = featureTransform(sites, {p.threaded}, interrupter);
        }
        BoundaryGraph graph;
        {
            auto t = timer.stage("boundary graph", true);
            graph = buildBoundaryGraph(crop, {p.threaded}, interrupter);
        }
        out.boundaryArea = graph.nodeCount();
        out.boundaryComponents = graph.componentSize.size();
        out.tauArea = p.tau.areaFor(out.boundaryArea);
        out.noiseArea = noiseAreaFor(p, double(out.boundaryArea));

        std::vector<std::vector<std::uint32_t>> cutLoops;
        if (extent.voxels >= p.minObjectVoxels) {
            std::vector<SkeletonCandidate> candidates;
            {
                auto t = timer.stage("skeleton candidates", true);
                CandidateOptions options;
                options.threaded = p.threaded;
                candidates = selectSkeletonCandidates(crop, ft, graph, options, &out.candidateStats,
                                                      interrupter);
            }
            std::vector<SkeletonPoint> points;
            Landmarks landmarks;
            {
                auto t = timer.stage("landmarks", true);
                landmarks = computeLandmarks(graph, p.threaded);
            }
            SkeletonMeasureOptions measureOptions;
            measureOptions.landmarks = &landmarks;
            measureOptions.tau = out.tauArea;
            measureOptions.noiseArea = out.noiseArea;
            measureOptions.threaded = p.threaded;
            {
                auto t = timer.stage("path sets, rims, areas, sigma", true);
                points = measureSkeleton(graph, candidates, measureOptions, &out.measureStats,
                                         interrupter);
            }
            out.curveSkeletonPoints = points.size();
            SkeletonGraph skeleton;
            CutPlan plan;
            {
                auto t = timer.stage("skeleton graph", false);
                InterrupterScope scope(interrupter, "skeleton graph");
                SkeletonGraphOptions options;
                options.tau = out.tauArea;
                options.regionRadius = p.regionRadius;
                options.bridgeGap = p.bridgeGap;
                skeleton = buildSkeletonGraph(points, cropDims, options);
                throwIfInterrupted(interrupter);
            }
            {
                auto t = timer.stage("cut placement", false);
                InterrupterScope scope(interrupter, "cut placement");
                CutOptions options;
                options.sigmaMin = p.sigmaMin;
                options.bodyRatio = p.bodyRatio;
                options.consecutiveLevels = p.consecutiveLevels;
                options.mode = p.mode;
                plan = placeCuts(skeleton, points, options, [&](std::uint32_t pointIndex) {
                    SkeletonPoint exact;
                    SkeletonMeasureOptions o = measureOptions;
                    o.exactRhoC = true;
                    return measurePoint(graph, candidates[points[pointIndex].candidate], o, exact)
                               ? exact.rhoC
                               : 0.0;
                });
                GeodesicSearch search(graph, &landmarks);
                RimCounter rims(graph);
                for (std::uint32_t node : plan.cutNodes) {
                    const SkeletonPoint& sp = points[skeleton.point[node]];
                    std::uint32_t a = 0, b = 0;
                    cutLoops.push_back(
                        pathSet(graph, candidates[sp.candidate], search, nullptr, &a, &b));
                    std::vector<std::array<int, 3>> polyline;
                    for (std::uint32_t n : orderLoop(graph, cutLoops.back(), a, b, search, rims))
                        polyline.push_back(toGrid(graph.voxel[n]));
                    out.cutLoops.push_back(std::move(polyline));
                }
                throwIfInterrupted(interrupter);
            }
            // Skeleton and decisions for the outputs.
            out.simplifiedSkeletonPoints = skeleton.nodeCount();
            out.skeletonBridges = skeleton.bridgeCount;
            std::vector<std::uint8_t> critical(skeleton.nodeCount(), 0);
            for (const CutCandidate& c : plan.candidates) critical[c.node] = 1;
            for (std::uint32_t n = 0; n < skeleton.nodeCount(); ++n) {
                const SkeletonPoint& sp = points[skeleton.point[n]];
                SkeletonVertex v;
                v.voxel = toGrid(sp.voxel);
                v.rhoS = sp.rhoS;
                v.rhoC = sp.rhoC;
                v.sigma = sp.sigma;
                v.junction = sp.robustRims >= 3;
                v.critical = critical[n] != 0;
                out.junctionVoxels += v.junction;
                out.handlePoints += sp.isHandle;
                out.skeleton.push_back(v);
            }
            out.skeletonEdges = skeleton.edges;
            for (std::uint32_t j = 0; j < skeleton.junctions.size(); ++j) {
                const SkeletonJunction& sj = skeleton.junctions[j];
                JunctionInfo info;
                info.voxel = toGrid(points[skeleton.point[sj.representative]].voxel);
                info.branches = plan.junctions[j].branches;
                info.cuts = plan.junctions[j].cuts;
                info.rhoS = sj.rhoS;
                info.coreVoxels = std::uint32_t(sj.core.size());
                out.junctions.push_back(info);
            }
            for (const CutCandidate& c : plan.candidates) {
                const SkeletonPoint& sp = points[skeleton.point[c.node]];
                CriticalPointInfo info;
                info.voxel = toGrid(sp.voxel);
                info.junction = c.junction;
                info.sigma = c.sigma;
                info.rhoS = sp.rhoS;
                info.rhoC = c.exactRhoC >= 0.0 ? c.exactRhoC : sp.rhoC;
                info.similarity = c.similarity;
                info.isCut = c.isCut;
                out.criticalPoints.push_back(info);
            }
        }

        SurfaceSegments segments;
        {
            auto t = timer.stage("labelling", false);
            InterrupterScope scope(interrupter, "labelling");
            segments = labelSurface(graph, cutLoops, std::max(out.tauArea, out.noiseArea));
            throwIfInterrupted(interrupter);
        }
        ObjectLabels labels{origin, Volume<std::uint16_t>(cropDims, 0)};
        {
            auto t = timer.stage("interior labels", true);
            std::vector<std::uint16_t> localId(segments.segmentCount);
            for (std::uint32_t s = 0; s < segments.segmentCount; ++s)
                localId[s] = std::uint16_t(std::min<std::uint32_t>(s + 1, 65535));
            labelInterior(crop, ft, graph, segments, localId, labels.local, p.threaded);
        }
        for (std::uint32_t s = 0; s < segments.segmentCount; ++s)
            localSegments.push_back({std::uint32_t(result.objects.size()), s, segments.area[s], 0});
        objectLabels.push_back(std::move(labels));
        result.objects.push_back(std::move(out));
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
        auto t = timer.stage("label volume", false);
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
