#include "engine/SegmentationStages.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "engine/SegmentationLevels.h"
#include "engine/Stage.h"
#include "kernels/CutLoopOrder.h"
#include "kernels/CutPieceReach.h"
#include "kernels/FeatureTransform.h"
#include "kernels/RimCount.h"
#include "kernels/SkeletonBand.h"
#include "kernels/SurfaceLabelling.h"
#include "kernels/VoxelGenus.h"
#include "kernels/base/ParallelFor.h"

namespace skelseg {

std::array<int, 3> ObjectState::toGrid(std::uint32_t cropVoxel) const {
    const Dims cropDims = crop.dims();
    const std::uint32_t cx = std::uint32_t(cropDims.x), cy = std::uint32_t(cropDims.y);
    return {int(cropVoxel % cx) + origin[0], int((cropVoxel / cx) % cy) + origin[1],
            int(cropVoxel / (cx * cy)) + origin[2]};
}

SkeletonMeasureOptions ObjectState::measureOptions() const {
    SkeletonMeasureOptions options;
    options.landmarks = &landmarks;
    options.tau = out.tauArea;
    options.noiseArea = out.noiseArea;
    options.surfaceHasGenusZero = out.genus == 0 && !parameters.handleFlagOnGenusZero;
    // One measure serves every level (engine/SegmentationLevels.h): sigma
    // down to the finest tau.
    if (!parameters.finerTaus.empty()) options.sigmaTau = finerLevels.front().tauArea;
    options.threaded = parameters.threaded;
    return options;
}

void cropObject(ObjectState& state, const ConnectedObjects& objects) {
    Stage stage(state.timer, state.interrupter, "crop", true);
    const ObjectExtent& extent = state.extent;
    state.origin = {extent.lo[0] - 1, extent.lo[1] - 1, extent.lo[2] - 1};
    const std::array<int, 3> origin = state.origin;
    const Dims cropDims{extent.hi[0] - extent.lo[0] + 3, extent.hi[1] - extent.lo[1] + 3,
                        extent.hi[2] - extent.lo[2] + 3};
    state.crop = MaskVolume(cropDims, 0);
    MaskVolume& crop = state.crop;
    const VoxelRuns& runs = objects.runs;
    // Planes 1 .. cropDims.z - 2 of the crop (the outer ones stay background).
    parallelFor(
        cropDims.z - 2,
        [&](int begin, int end) {
            for (int z = begin + 1; z < end + 1; ++z)
                for (int y = 1; y < cropDims.y - 1; ++y) {
                    const std::size_t row = runs.rowOf(y + origin[1], z + origin[2]);
                    std::uint8_t* out = crop.data() + crop.index(0, y, z);
                    for (std::uint32_t k = runs.rowStart[row]; k < runs.rowStart[row + 1]; ++k)
                        if (objects.objectOfRun[k] == extent.id)
                            std::fill(out + (runs.runs[k].x0 - origin[0]),
                                      out + (runs.runs[k].x1 - origin[0] + 1), 1);
                }
        },
        state.parameters.threaded);
    // Parts are parts of the outer surface (kernels/Cavities.h).
    const bool threaded = state.parameters.threaded;
    state.cavities = fillCavities(crop, {threaded}, state.interrupter);
    // The measures need to know whether a loop can go round a handle here.
    state.out.genus = voxelTopology(crop, {threaded}, state.interrupter).genus;
    if (state.parameters.closeNarrowTunnels && state.out.genus > 0) {
        state.tunnelVoxels = closeNarrowTunnels(crop, state.interrupter);
        if (!state.tunnelVoxels.empty())
            state.out.genus = voxelTopology(crop, {threaded}, state.interrupter).genus;
        if (state.out.genus > 0) {
            const std::vector<std::size_t> plugs =
                plugTunnelsTwoVoxelsWide(crop, state.interrupter);
            state.tunnelVoxels.insert(state.tunnelVoxels.end(), plugs.begin(), plugs.end());
        }
        if (!state.tunnelVoxels.empty()) {
            // Closing the mouth of a pit that narrow seals its bottom.
            state.sealedCavities = fillCavities(crop, {threaded}, state.interrupter);
            state.out.genus = voxelTopology(crop, {threaded}, state.interrupter).genus;
        }
    }
    state.out.cavities = state.cavities.count + state.sealedCavities.count;
    state.out.cavityVoxels = state.cavities.voxels + state.sealedCavities.voxels;
    state.out.tunnelVoxels = state.tunnelVoxels.size();
}

void computeObjectFeatureTransform(ObjectState& state) {
    Stage stage(state.timer, state.interrupter, "feature transform", true);
    const bool threaded = state.parameters.threaded;
    const MaskVolume sites = boundaryVoxels(state.crop, {threaded});
    state.featureTransform = featureTransform(sites, {threaded}, state.interrupter);
}

void buildObjectBoundaryGraph(ObjectState& state) {
    Stage stage(state.timer, state.interrupter, "boundary graph", true);
    const SegmentationParameters& p = state.parameters;
    state.graph = buildBoundaryGraph(state.crop, {p.threaded}, state.interrupter);
    ObjectSegmentation& out = state.out;
    out.boundaryArea = state.graph.nodeCount();
    out.boundaryComponents = state.graph.componentSize.size();
    out.tauArea = p.tau.areaFor(out.boundaryArea);
    out.noiseArea = p.noiseAreaFor(double(out.boundaryArea));
    // The levels below the top, finest first: the joint level (at the
    // finest junction-rule level's tau), the finer junction-rule levels,
    // and with --joints and one tau the junction-rule level itself.
    std::vector<TauSpec> taus;
    if (p.joints) taus.push_back(p.finerTaus.empty() ? p.tau : p.finerTaus.front());
    taus.insert(taus.end(), p.finerTaus.begin(), p.finerTaus.end());
    if (p.joints && p.finerTaus.empty()) taus.push_back(p.tau);
    state.finerLevels.resize(taus.size());
    out.finerLevels.resize(taus.size());
    for (std::size_t k = 0; k < taus.size(); ++k) {
        ObjectLevelWork& level = state.finerLevels[k];
        level.tauArea = taus[k].areaFor(out.boundaryArea);
        level.noiseArea = p.noiseAreaFor(double(out.boundaryArea), taus[k]);
        out.finerLevels[k].tauArea = level.tauArea;
        out.finerLevels[k].noiseArea = level.noiseArea;
    }
}

void selectObjectCandidates(ObjectState& state) {
    Stage stage(state.timer, state.interrupter, "skeleton candidates", true);
    CandidateOptions options;
    options.threaded = state.parameters.threaded;
    state.candidates =
        selectSkeletonCandidates(state.crop, state.featureTransform, state.graph, options,
                                 &state.out.candidateStats, state.interrupter);
}

void computeObjectLandmarks(ObjectState& state) {
    Stage stage(state.timer, state.interrupter, "landmarks", true);
    state.landmarks = computeLandmarks(state.graph, state.parameters.threaded, state.interrupter);
}

void measureObjectSkeleton(ObjectState& state) {
    Stage stage(state.timer, state.interrupter, "path sets, rims, areas, sigma", true);
    if (state.parameters.skeletonSearch == SkeletonSearch::Band) {
        SkeletonBandOptions band;
        band.closureRadius = std::max(1, int(std::ceil(state.parameters.bridgeGap)));
        state.points =
            measureSkeletonInBand(state.graph, state.candidates, state.crop, state.featureTransform,
                                  state.measureOptions(), band, &state.out.bandStats,
                                  &state.out.measureStats, state.interrupter);
    } else {
        state.points = measureSkeleton(state.graph, state.candidates, state.measureOptions(),
                                       &state.out.measureStats, state.interrupter);
        state.out.bandStats.candidatesMeasured = state.candidates.size();
    }
    state.out.curveSkeletonPoints = state.points.size();
}

void buildObjectSkeletonGraph(ObjectState& state) {
    Stage stage(state.timer, state.interrupter, "skeleton graph", false);
    SkeletonGraphOptions options;
    options.tau = state.out.tauArea;
    options.regionRadius = state.parameters.regionRadius;
    options.bridgeGap = state.parameters.bridgeGap;
    options.forkJunctions = state.parameters.forkJunctions;
    options.growRegionsToSplits = state.parameters.growRegionsToSplits;
    options.junctionMergeRadii = state.parameters.junctionMergeRadii;
    options.inside = &state.crop;
    options.threaded = state.parameters.threaded;
    state.skeleton =
        buildSkeletonGraph(state.points, state.crop.dims(), options, state.interrupter);
    throwIfInterrupted(state.interrupter);
}

namespace {

/// The loops Gamma of skeleton graph nodes `nodes` become cuts of `kind`:
/// as path sets for the labelling and as ordered polylines for the outputs.
void appendCutLoops(ObjectState& state, const std::vector<std::uint32_t>& nodes, CutKind kind) {
    const BoundaryGraph& graph = state.graph;
    // Every search of the run shares the landmarks, so the loops follow the
    // same paths the measures saw.
    GeodesicSearch search(graph, &state.landmarks);
    RimCounter rims(graph);
    for (std::uint32_t node : nodes) {
        const SkeletonPoint& sp = state.points[state.skeleton.point[node]];
        std::uint32_t a = 0, b = 0;
        state.cutLoops.push_back(
            pathSet(graph, state.candidates[sp.candidate], search, nullptr, &a, &b));
        std::vector<std::array<int, 3>> polyline;
        for (std::uint32_t n : orderCutLoop(graph, state.cutLoops.back(), a, b, search, rims))
            polyline.push_back(state.toGrid(graph.voxel[n]));
        state.out.cutLoops.push_back(std::move(polyline));
        CutInfo info;
        info.kind = kind;
        info.voxel = state.toGrid(sp.voxel);
        info.sigma = sp.sigma;
        info.rhoS = sp.rhoS;
        state.out.cuts.push_back(info);
    }
}

}  // namespace

void placeObjectCuts(ObjectState& state) {
    Stage stage(state.timer, state.interrupter, "cut placement", false);
    const SegmentationParameters& p = state.parameters;
    const BoundaryGraph& graph = state.graph;
    const CutOptions options = p.cutOptions();
    SkeletonMeasureOptions exactOptions = state.measureOptions();
    exactOptions.exactRhoC = true;
    // The cut loops as the labelling will draw them (the run's landmarks, so
    // the same paths as appendCutLoops). Workspaces made on first use: most
    // objects need neither check.
    std::unique_ptr<GeodesicSearch> search;
    std::unique_ptr<RimCounter> rims;
    std::unique_ptr<PieceReachMeasurer> reach;
    auto searchOnce = [&]() -> GeodesicSearch& {
        if (!search) search = std::make_unique<GeodesicSearch>(graph, &state.landmarks);
        return *search;
    };
    // Whether the loops of a set of cuts separate, judged together as the
    // labelling cuts them.
    std::map<std::uint32_t, std::vector<std::uint32_t>> loopOfPoint;
    const LoopSeparation loopsSeparate = [&](const std::vector<std::uint32_t>& pointIndices) {
        std::vector<std::vector<std::uint32_t>> loops;
        for (std::uint32_t point : pointIndices) {
            auto it = loopOfPoint.find(point);
            if (it == loopOfPoint.end())
                it = loopOfPoint
                         .emplace(point,
                                  pathSet(graph, state.candidates[state.points[point].candidate],
                                          searchOnce()))
                         .first;
            loops.push_back(it->second);
        }
        return separatingLoops(graph, loops, state.out.noiseArea);
    };
    // The corner rule's reach of the piece past a cut, flooded to twice
    // cornerReach so that the answer on either side of the threshold is exact.
    const PieceReach pieceReach = [&](std::uint32_t cutNode, std::uint32_t junction) {
        if (!rims) rims = std::make_unique<RimCounter>(graph);
        const SkeletonPoint& sp = state.points[state.skeleton.point[cutNode]];
        std::uint32_t a = 0, b = 0;
        const std::vector<std::uint32_t> gamma =
            pathSet(graph, state.candidates[sp.candidate], searchOnce(), nullptr, &a, &b);
        const std::vector<std::uint32_t> loop =
            orderCutLoop(graph, gamma, a, b, searchOnce(), *rims);
        const Coord at = state.skeleton.coord[state.skeleton.junctions[junction].representative];
        if (!reach) reach = std::make_unique<PieceReachMeasurer>(graph);
        // Far enough for every reach the rules compare with.
        return reach->measure(
            gamma, loop, {double(at.x), double(at.y), double(at.z)},
            std::max({2.0 * options.cornerReach, options.stubReach, options.endReach}));
    };
    state.plan = placeCuts(
        state.skeleton, state.points, options,
        [&](std::uint32_t pointIndex) {
            SkeletonPoint exact;
            return measurePoint(graph, state.candidates[state.points[pointIndex].candidate],
                                exactOptions, exact)
                       ? exact.rhoC
                       : 0.0;
        },
        loopsSeparate, pieceReach);
    appendCutLoops(state, state.plan.cutNodes, CutKind::Junction);
    throwIfInterrupted(state.interrupter);
}

void placeJointCuts(ObjectState& state, const std::vector<std::uint32_t>& existingCuts) {
    Stage stage(state.timer, state.interrupter, "joint cuts", false);
    JointOptions options = state.parameters.jointOptions;
    options.sigmaMin = state.parameters.sigmaMin;
    const std::vector<JointCandidate> found =
        detectJoints(state.skeleton, state.points, existingCuts, options, state.interrupter);
    std::vector<std::uint32_t> jointNodes;
    for (const JointCandidate& c : found) {
        JointCandidateInfo info;
        info.voxel = state.toGrid(state.points[state.skeleton.point[c.node]].voxel);
        info.kind = c.kind;
        info.status = c.status;
        info.ratio = c.ratio;
        info.angleDegrees = c.angleDegrees;
        info.radius = c.radius;
        info.sigma = c.sigma;
        state.out.jointCandidates.push_back(info);
        if (c.status == JointStatus::Cut) jointNodes.push_back(c.node);
    }
    appendCutLoops(state, jointNodes, CutKind::Joint);
    throwIfInterrupted(state.interrupter);
}

namespace {

/// The skeleton and the cut decisions as the outputs show them.
void recordSkeleton(ObjectState& state) {
    ObjectSegmentation& out = state.out;
    const SkeletonGraph& skeleton = state.skeleton;
    const CutPlan& plan = state.plan;
    const std::vector<SkeletonPoint>& points = state.points;
    out.simplifiedSkeletonPoints = skeleton.nodeCount();
    out.skeletonBridges = skeleton.bridgeCount;
    out.skeletonBridgesAlongObject = skeleton.bridgesAlongObject;
    std::vector<std::uint8_t> critical(skeleton.nodeCount(), 0);
    for (const CutCandidate& c : plan.candidates) critical[c.node] = 1;
    for (std::uint32_t n = 0; n < skeleton.nodeCount(); ++n) {
        const SkeletonPoint& sp = points[skeleton.point[n]];
        SkeletonVertex v;
        v.voxel = state.toGrid(sp.voxel);
        v.rhoS = sp.rhoS;
        v.rhoC = sp.rhoC;
        v.sigma = sp.sigma;
        v.junction = isJunctionPoint(sp);
        v.critical = critical[n] != 0;
        out.junctionVoxels += v.junction;
        out.handlePoints += sp.isHandle;
        out.skeleton.push_back(v);
    }
    out.skeletonEdges = skeleton.edges;
    for (std::uint32_t j = 0; j < skeleton.junctions.size(); ++j) {
        const SkeletonJunction& sj = skeleton.junctions[j];
        JunctionInfo info;
        info.voxel = state.toGrid(points[skeleton.point[sj.representative]].voxel);
        info.branches = plan.junctions[j].branches;
        info.cuts = plan.junctions[j].cuts;
        info.rhoS = sj.rhoS;
        info.coreVoxels = std::uint32_t(sj.core.size());
        info.forkVoxels =
            std::uint32_t(std::count_if(sj.core.begin(), sj.core.end(), [&](std::uint32_t n) {
                return !isJunctionPoint(points[skeleton.point[n]]);
            }));
        out.junctions.push_back(info);
    }
    for (const CutCandidate& c : plan.candidates) {
        const SkeletonPoint& sp = points[skeleton.point[c.node]];
        CriticalPointInfo info;
        info.voxel = state.toGrid(sp.voxel);
        info.junction = c.junction;
        info.sigma = c.sigma;
        info.rhoS = sp.rhoS;
        info.limbRhoS = c.limbRhoS;
        info.rhoC = c.exactRhoC >= 0.0 ? c.exactRhoC : sp.rhoC;
        info.similarity = c.similarity;
        info.isCorner = c.isCorner;
        info.belowSigmaMin = c.belowSigmaMin;
        info.stubLimb = c.stubLimb;
        info.loopSeparates = c.loopSeparates;
        info.movedToSeparate = c.movedToSeparate;
        info.isCut = c.isCut;
        out.criticalPoints.push_back(info);
    }
}

/// The labelling stages need only the crop, the feature transform, the
/// graph and the cut loops: the rest goes before they allocate.
void releaseSkeletonData(ObjectState& state) {
    state.candidates = {};
    state.landmarks = {};
    state.points = {};
    state.skeleton = {};
    state.plan = {};
}

}  // namespace

void labelObjectSurface(ObjectState& state) {
    Stage stage(state.timer, state.interrupter, "labelling", false);
    // Joint cuts part limbs into pieces (a hand, a forearm) that are often
    // smaller than tau, the junction rule's smallest part: on the joint level
    // the smallest segment is a fraction of tau instead (docs/algorithm.md,
    // Joints). The top level is the joint level with --joints and one tau.
    const SegmentationParameters& p = state.parameters;
    const double smallest = p.joints && p.finerTaus.empty()
                                ? p.jointOptions.minSegmentTauFraction * state.out.tauArea
                                : state.out.tauArea;
    state.segments = labelSurface(state.graph, state.cutLoops,
                                  std::max(smallest, state.out.noiseArea), state.out.noiseArea);
    state.out.segmentsBeforeMerge = state.segments.before;
    if (state.out.cuts.size() == state.segments.loopSeparates.size())
        for (std::size_t i = 0; i < state.out.cuts.size(); ++i)
            state.out.cuts[i].separates = state.segments.loopSeparates[i] != 0;
    throwIfInterrupted(state.interrupter);
}

Volume<std::uint16_t> objectInteriorLabels(const ObjectState& state,
                                           const SurfaceSegments& segments) {
    const std::uint32_t segmentCount = segments.segmentCount;
    std::vector<std::uint16_t> localId(segmentCount);
    for (std::uint32_t s = 0; s < segmentCount; ++s)
        localId[s] = std::uint16_t(std::min<std::uint32_t>(s + 1, 65535));
    Volume<std::uint16_t> labels(state.crop.dims(), 0);
    labelInterior(state.crop, state.featureTransform, state.graph, segments, localId, labels,
                  state.parameters.threaded);
    // What was filled was background in the input (a cavity may hold
    // another object).
    clearVoxelRuns(labels, state.cavities.runs);
    clearVoxelRuns(labels, state.sealedCavities.runs);
    for (std::size_t i : state.tunnelVoxels) labels[i] = 0;
    return labels;
}

void labelObjectInterior(ObjectState& state) {
    Stage stage(state.timer, state.interrupter, "interior labels", true);
    state.localLabels = objectInteriorLabels(state, state.segments);
}

void runObjectStages(ObjectState& state, const ConnectedObjects& objects) {
    state.out.voxelCount = state.extent.voxels;
    state.out.bboxMin = state.extent.lo;
    state.out.bboxMax = state.extent.hi;
    cropObject(state, objects);
    computeObjectFeatureTransform(state);
    buildObjectBoundaryGraph(state);
    if (state.extent.voxels >= state.parameters.minObjectVoxels) {
        selectObjectCandidates(state);
        computeObjectLandmarks(state);
        measureObjectSkeleton(state);
        {
            LevelClock clock(state.coarsestSeconds);
            buildObjectSkeletonGraph(state);
            placeObjectCuts(state);
            // With one tau the joint level is the top-level result; with a
            // list it is placed below the finest level (placeFinerLevelCuts).
            if (state.parameters.joints && state.parameters.finerTaus.empty())
                placeJointCuts(state, state.plan.cutNodes);
        }
        recordSkeleton(state);
        if (!state.parameters.finerTaus.empty()) placeFinerLevelCuts(state);
        releaseSkeletonData(state);
    }
    if (state.parameters.joints && state.parameters.finerTaus.empty())
        splitSingleTauJointLevels(state);
    {
        LevelClock clock(state.coarsestSeconds);
        labelObjectSurface(state);
        labelObjectInterior(state);
    }
    if (!state.finerLevels.empty()) labelFinerLevels(state);
}

}  // namespace skelseg
