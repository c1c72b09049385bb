// skelseg kernel benchmarks: one benchmark per kernel, on the synthetic
// shapes of BenchShapes.h at 64, 128 (and for the linear-time kernels 192)
// voxels. All kernels run serially (threaded = false): the numbers are work
// per core, comparable across machines with different core counts; the
// end-to-end benchmarks (BenchEndToEnd.cpp) also measure the threaded engine.
//
// Work counters (state.counters) are per iteration, so a change in the
// amount of work shows up separately from a change in speed.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "bench/BenchShapes.h"
#include "kernels/Cavities.h"
#include "kernels/ComponentGrowth.h"
#include "kernels/ConnectedObjects.h"
#include "kernels/Geodesicness.h"
#include "kernels/NarrowTunnels.h"
#include "kernels/RimCount.h"
#include "kernels/SkeletonBand.h"
#include "kernels/SkeletonGraph.h"
#include "kernels/TunnelPlugs.h"
#include "kernels/VoxelGenus.h"

namespace skelseg::bench {
namespace {

const std::vector<int> kLinearSizes = {64, 128, 192};  // kernels linear in the voxels
const std::vector<int> kSizes = {64, 128};             // the search-bound kernels

/// Fixed number of samples so that per-iteration work grows with the shape
/// size only through the kernel itself.
constexpr std::size_t kPairSample = 2000;
constexpr std::size_t kPathSetSample = 400;
constexpr std::size_t kSigmaSample = 200;

/// Path sets of a candidate sample (setup for the rim, growth and sigma
/// benchmarks), with the pair realising rho_S.
struct PathSetSample {
    std::vector<std::vector<std::uint32_t>> sets;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> realising;
};

PathSetSample samplePathSets(const ShapeInput& in,
                             const std::vector<const SkeletonCandidate*>& candidates) {
    PathSetSample sample;
    GeodesicSearch search(in.graph, &in.landmarks);
    for (const SkeletonCandidate* c : candidates) {
        std::uint32_t a = kNoNode, b = kNoNode;
        sample.sets.push_back(pathSet(in.graph, *c, search, nullptr, &a, &b));
        sample.realising.emplace_back(a, b);
    }
    return sample;
}

/// An evenly spaced sample of the points of C (of C_tau if `simplified`)
/// with their path sets: the inputs of component growth and sigma.
struct PointSample {
    std::vector<const SkeletonPoint*> points;
    PathSetSample pathSets;
};

PointSample samplePoints(ShapeInput& in, std::size_t count, bool simplified) {
    std::vector<const SkeletonPoint*> all;
    for (const SkeletonPoint& p : in.skeletonPoints())
        if (!simplified || p.rhoC >= in.tau) all.push_back(&p);
    PointSample sample;
    std::vector<const SkeletonCandidate*> candidates;
    const std::size_t stride = std::max<std::size_t>(1, all.size() / count);
    for (std::size_t i = stride / 2; i < all.size() && sample.points.size() < count; i += stride) {
        sample.points.push_back(all[i]);
        candidates.push_back(&in.candidates[all[i]->candidate]);
    }
    sample.pathSets = samplePathSets(in, candidates);
    return sample;
}

void featureTransformBench(benchmark::State& state, const std::string& shape) {
    const ShapeInput& in = shapeInput(shape, int(state.range(0)));
    for (auto _ : state) {
        Volume<std::uint32_t> ft = featureTransform(in.sites, {false});
        benchmark::DoNotOptimize(ft.data());
    }
    state.counters["voxels"] = double(in.sites.size());
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(in.sites.size()));
}

void boundaryVoxelsBench(benchmark::State& state, const std::string& shape) {
    const ShapeInput& in = shapeInput(shape, int(state.range(0)));
    for (auto _ : state) {
        MaskVolume boundary = boundaryVoxels(in.mask, {false});
        benchmark::DoNotOptimize(boundary.data());
    }
    state.counters["voxels"] = double(in.mask.size());
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(in.mask.size()));
}

void countBoundaryVoxelsBench(benchmark::State& state, const std::string& shape) {
    const ShapeInput& in = shapeInput(shape, int(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(countBoundaryVoxels(in.mask, {false}));
    state.counters["voxels"] = double(in.mask.size());
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(in.mask.size()));
}

void boundaryGraphBench(benchmark::State& state, const std::string& shape) {
    const ShapeInput& in = shapeInput(shape, int(state.range(0)));
    for (auto _ : state) {
        BoundaryGraph graph = buildBoundaryGraph(in.mask, {false});
        benchmark::DoNotOptimize(graph.neighbour.data());
    }
    state.counters["nodes"] = double(in.graph.nodeCount());
    state.counters["edges"] = double(in.graph.edgeCount());
}

void connectedObjectsBench(benchmark::State& state, const std::string& shape) {
    const ShapeInput& in = shapeInput(shape, int(state.range(0)));
    std::size_t runs = 0;
    for (auto _ : state) {
        ConnectedObjects objects = findConnectedObjects(in.mask, {false});
        runs = objects.runs.runs.size();
        benchmark::DoNotOptimize(objects.objectOfRun.data());
    }
    state.counters["voxels"] = double(in.mask.size());
    state.counters["runs"] = double(runs);
}

void voxelGenusBench(benchmark::State& state, const std::string& shape) {
    const ShapeInput& in = shapeInput(shape, int(state.range(0)));
    VoxelTopologyOptions options;
    options.threaded = false;
    std::int64_t genus = 0;
    for (auto _ : state) {
        genus = voxelTopology(in.mask, options).genus;
        benchmark::DoNotOptimize(genus);
    }
    state.counters["voxels"] = double(in.mask.size());
    state.counters["genus"] = double(genus);
}

/// The shape with stray voxels: a voxel in 97 of those whose 5^3
/// neighbourhood is all object removed (pores: cavities), and, with
/// `surfaceNoise`, about 4% of the voxels within two of the surface flipped
/// (tunnels), both chosen by a fixed hash of the position.
MaskVolume strayVoxels(const MaskVolume& shape, bool surfaceNoise) {
    const Dims d = shape.dims();
    MaskVolume out = shape;
    for (int z = 2; z < d.z - 2; ++z)
        for (int y = 2; y < d.y - 2; ++y)
            for (int x = 2; x < d.x - 2; ++x) {
                bool allObject = true, nearSurface = false;
                for (int dz = -2; dz <= 2; ++dz)
                    for (int dy = -2; dy <= 2; ++dy)
                        for (int dx = -2; dx <= 2; ++dx) {
                            const bool object = shape(x + dx, y + dy, z + dz) != 0;
                            allObject = allObject && object;
                            nearSurface = nearSurface || object != (shape(x, y, z) != 0);
                        }
                const std::uint32_t hash =
                    (std::uint32_t(x) * 73856093u ^ std::uint32_t(y) * 19349663u ^
                     std::uint32_t(z) * 83492791u) *
                    2654435761u;
                if (allObject && (x * 7 + y * 13 + z * 29) % 97 == 0) out(x, y, z) = 0;
                if (surfaceNoise && nearSurface && hash >> 24 < 10) out(x, y, z) = !shape(x, y, z);
            }
    return out;
}

void fillCavitiesBench(benchmark::State& state, const std::string& shape) {
    const ShapeInput& in = shapeInput(shape, int(state.range(0)));
    const MaskVolume porous = strayVoxels(in.mask, false);
    FilledCavities filled;
    for (auto _ : state) {
        state.PauseTiming();
        MaskVolume mask = porous;
        state.ResumeTiming();
        filled = fillCavities(mask, {false});
        benchmark::DoNotOptimize(mask.data());
    }
    state.counters["voxels"] = double(in.mask.size());
    state.counters["cavities"] = double(filled.count);
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(in.mask.size()));
}

void closeNarrowTunnelsBench(benchmark::State& state, const std::string& shape) {
    const ShapeInput& in = shapeInput(shape, int(state.range(0)));
    const MaskVolume noisy = strayVoxels(in.mask, true);
    std::size_t closed = 0;
    for (auto _ : state) {
        state.PauseTiming();
        MaskVolume mask = noisy;
        state.ResumeTiming();
        closed = closeNarrowTunnels(mask).size();
        benchmark::DoNotOptimize(mask.data());
    }
    state.counters["voxels"] = double(in.mask.size());
    state.counters["closed"] = double(closed);
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(in.mask.size()));
}

void plugTunnelsBench(benchmark::State& state, const std::string& shape) {
    const ShapeInput& in = shapeInput(shape, int(state.range(0)));
    // As the engine calls it: after the tunnels one voxel wide are closed.
    MaskVolume noisy = strayVoxels(in.mask, true);
    closeNarrowTunnels(noisy);
    std::size_t plugged = 0;
    for (auto _ : state) {
        state.PauseTiming();
        MaskVolume mask = noisy;
        state.ResumeTiming();
        plugged = plugTunnelsTwoVoxelsWide(mask).size();
        benchmark::DoNotOptimize(mask.data());
    }
    state.counters["voxels"] = double(in.mask.size());
    state.counters["plugged"] = double(plugged);
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(in.mask.size()));
}

void skeletonCandidatesBench(benchmark::State& state, const std::string& shape) {
    const ShapeInput& in = shapeInput(shape, int(state.range(0)));
    CandidateOptions options;
    options.threaded = false;
    CandidateStats stats;
    for (auto _ : state) {
        std::vector<SkeletonCandidate> candidates =
            selectSkeletonCandidates(in.mask, in.featureTransform, in.graph, options, &stats);
        benchmark::DoNotOptimize(candidates.data());
    }
    state.counters["objectVoxels"] = double(stats.objectVoxels);
    state.counters["withThreeFeatures"] = double(stats.withThreeFeatures);
    state.counters["candidates"] = double(stats.candidates);
}

void landmarksBench(benchmark::State& state, const std::string& shape) {
    const ShapeInput& in = shapeInput(shape, int(state.range(0)));
    for (auto _ : state) {
        Landmarks landmarks = computeLandmarks(in.graph, false);
        benchmark::DoNotOptimize(landmarks.row(0));
    }
    state.counters["landmarks"] = double(in.landmarks.count);
    state.counters["nodes"] = double(in.graph.nodeCount());
    // How often a sweep sharing one frontier among the 16 sources of a row
    // line would have to expand each node: its 16 distances become final in
    // as many distinct unit buckets (16 = no sharing at all).
    const Landmarks& lm = in.landmarks;
    double expansions = 0.0;
    std::uint64_t lines = 0;
    for (std::uint32_t first = 0; first + 16 <= lm.count; first += 16, ++lines)
        for (std::uint32_t n = 0; n < in.graph.nodeCount(); ++n) {
            std::uint32_t bucket[16];
            for (std::uint32_t k = 0; k < 16; ++k)
                bucket[k] = std::uint32_t(std::min(lm.distance(n, first + k), 1e9f));
            std::sort(bucket, bucket + 16);
            expansions += double(std::unique(bucket, bucket + 16) - bucket);
        }
    state.counters["sharedFrontierExpansionsPer16"] =
        lines ? expansions / double(lines * in.graph.nodeCount()) : 0.0;
}

/// A* on a fixed list of distinct feature pairs; `useLandmarks` as the engine
/// (true) or with the Euclidean bound alone (false).
void geodesicSearchBench(benchmark::State& state, const std::string& shape, bool useLandmarks) {
    const ShapeInput& in = shapeInput(shape, int(state.range(0)));
    // A fixed list of distinct feature pairs spread over the whole shape: the
    // two farthest-apart features (first and last by node id) of each
    // candidate of an evenly spaced sample.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    {
        std::set<std::pair<std::uint32_t, std::uint32_t>> seen;
        for (const SkeletonCandidate* c : in.candidateSample(kPairSample)) {
            const std::pair<std::uint32_t, std::uint32_t> pair{c->feature[0],
                                                               c->feature[c->featureCount - 1u]};
            if (seen.insert(pair).second) pairs.push_back(pair);
        }
    }
    GeodesicSearch search(in.graph, useLandmarks ? &in.landmarks : nullptr);
    double total = 0.0;
    for (auto _ : state) {
        for (const auto& [a, b] : pairs) total += double(search.shortestPath(a, b));
        benchmark::DoNotOptimize(total);
    }
    state.counters["pairs"] = double(pairs.size());
    state.counters["searches"] = perIteration(double(search.counters.searches));
    state.counters["heapPops"] = perIteration(double(search.counters.heapPops));
    state.counters["nodesSettled"] = perIteration(double(search.counters.nodesSettled));
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(pairs.size()));
}

void rimCountBench(benchmark::State& state, const std::string& shape) {
    const ShapeInput& in = shapeInput(shape, int(state.range(0)));
    const PathSetSample sample = samplePathSets(in, in.candidateSample(kPathSetSample));
    RimCounter rims(in.graph);
    std::uint64_t pieces = 0, pathNodes = 0;
    for (const auto& set : sample.sets) pathNodes += set.size();
    for (auto _ : state) {
        for (const auto& set : sample.sets) pieces += rims.countRims(set).pieceCount;
        benchmark::DoNotOptimize(pieces);
    }
    state.counters["pathSets"] = double(sample.sets.size());
    state.counters["pathNodes"] = double(pathNodes);
    state.counters["rimPieces"] = perIteration(double(pieces));
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(sample.sets.size()));
}

/// Rim test + component growth on a sample of the points of C (path sets
/// that hold a loop), with the engine's cap (max(noise area, tau)); the rim
/// test alone is BM_RimCount.
void componentGrowthBench(benchmark::State& state, const std::string& shape) {
    ShapeInput& in = shapeInput(shape, int(state.range(0)));
    const PointSample sample = samplePoints(in, kPathSetSample, false);
    std::vector<const std::vector<std::uint32_t>*> loops;
    for (const auto& set : sample.pathSets.sets) loops.push_back(&set);
    RimCounter rims(in.graph);
    ComponentGrower grower(in.graph);
    const std::uint64_t cap = std::uint64_t(std::ceil(std::max(in.noiseArea, in.tau)));
    std::uint64_t steps = 0, rhoC = 0;
    for (auto _ : state) {
        for (const auto* set : loops) {
            rims.countRims(*set);
            const ComponentAreas& areas = grower.grow(rims, cap);
            steps += areas.growthSteps;
            rhoC += areas.rhoC;
        }
        benchmark::DoNotOptimize(rhoC);
    }
    state.counters["loops"] = double(loops.size());
    state.counters["growthSteps"] = perIteration(double(steps));
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(loops.size()));
}

/// Rim test + sigma on a sample of the simplified skeleton's points.
void geodesicnessBench(benchmark::State& state, const std::string& shape) {
    ShapeInput& in = shapeInput(shape, int(state.range(0)));
    const PointSample points = samplePoints(in, kSigmaSample, true);
    const PathSetSample& sample = points.pathSets;
    const std::vector<const SkeletonPoint*>& sampled = points.points;
    RimCounter rims(in.graph);
    GeodesicnessEvaluator evaluator(in.graph);
    GeodesicSearch search(in.graph, &in.landmarks);
    double sigmaSum = 0.0;
    for (auto _ : state) {
        for (std::size_t i = 0; i < sampled.size(); ++i) {
            rims.countRims(sample.sets[i]);
            sigmaSum += double(
                evaluator.evaluate(rims, sampled[i]->featureA, sampled[i]->featureB, search).sigma);
        }
        benchmark::DoNotOptimize(sigmaSum);
    }
    state.counters["points"] = double(sampled.size());
    state.counters["searches"] = perIteration(double(search.counters.searches));
    state.counters["heapPops"] = perIteration(double(search.counters.heapPops));
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(sampled.size()));
}

/// Path sets, rims, rho_C and sigma for every candidate (the dominant stage).
/// The band search (kernels/SkeletonBand.h) on the same inputs as
/// BM_MeasureSkeleton: compare the two rows and their work counters.
void measureSkeletonInBandBench(benchmark::State& state, const std::string& shape) {
    const ShapeInput& in = shapeInput(shape, int(state.range(0)));
    const SkeletonMeasureOptions options = in.measureOptions();
    SkeletonMeasureStats total;
    SkeletonBandStats band;
    std::uint64_t measured = 0;
    for (auto _ : state) {
        SkeletonMeasureStats stats;
        std::vector<SkeletonPoint> result = measureSkeletonInBand(
            in.graph, in.candidates, in.mask, in.featureTransform, options, {}, &band, &stats);
        benchmark::DoNotOptimize(result.data());
        total.search += stats.search;
        measured += band.candidatesMeasured;
    }
    state.counters["candidates"] = double(in.candidates.size());
    state.counters["candidatesMeasured"] = perIteration(double(measured));
    state.counters["coarseCandidates"] = double(band.coarseCandidates);
    state.counters["coarseMeasured"] = double(band.coarseMeasured);
    state.counters["thinWallSeeds"] = double(band.thinWallSeeds);
    state.counters["heapPops"] = perIteration(double(total.search.heapPops));
}

void measureSkeletonBench(benchmark::State& state, const std::string& shape) {
    const ShapeInput& in = shapeInput(shape, int(state.range(0)));
    const SkeletonMeasureOptions options = in.measureOptions();
    SkeletonMeasureStats total;
    std::uint64_t hits = 0, misses = 0, rimTests = 0, growth = 0, sigmas = 0, points = 0;
    for (auto _ : state) {
        SkeletonMeasureStats stats;
        std::vector<SkeletonPoint> result =
            measureSkeleton(in.graph, in.candidates, options, &stats);
        benchmark::DoNotOptimize(result.data());
        total.search += stats.search;
        total.sigmaSearch += stats.sigmaSearch;
        hits += stats.pathCacheHits, misses += stats.pathCacheMisses, rimTests += stats.rimTests;
        growth += stats.componentGrowthSteps, sigmas += stats.sigmaEvaluations,
            points += stats.skeletonPoints;
    }
    state.counters["candidates"] = double(in.candidates.size());
    state.counters["pairSearches"] = perIteration(double(total.search.searches));
    state.counters["heapPops"] = perIteration(double(total.search.heapPops));
    state.counters["cacheHits"] = perIteration(double(hits));
    state.counters["cacheMisses"] = perIteration(double(misses));
    state.counters["rimTests"] = perIteration(double(rimTests));
    state.counters["growthSteps"] = perIteration(double(growth));
    state.counters["sigmaEvaluations"] = perIteration(double(sigmas));
    state.counters["sigmaHeapPops"] = perIteration(double(total.sigmaSearch.heapPops));
    state.counters["skeletonPoints"] = perIteration(double(points));
}

/// The graph of C_tau from the measured skeleton (junctions, forks, bridges,
/// joins through the object), as the engine builds it but serially. Its cost
/// is the fork tests, which grow with the square of a sheet's size where C_tau
/// thickens into one (docs/performance.md, "The fork tests in parallel and
/// stoppable"); the counters tell a larger graph from a slower build.
void skeletonGraphBench(benchmark::State& state, const std::string& shape) {
    ShapeInput& in = shapeInput(shape, int(state.range(0)));
    const std::vector<SkeletonPoint>& points = in.skeletonPoints();
    SkeletonGraphOptions options;
    options.tau = in.tau;
    options.inside = &in.mask;
    options.threaded = false;
    SkeletonGraph graph;
    for (auto _ : state) {
        graph = buildSkeletonGraph(points, in.mask.dims(), options);
        benchmark::DoNotOptimize(graph.point.data());
    }
    state.counters["points"] = double(points.size());
    state.counters["nodes"] = double(graph.nodeCount());
    state.counters["junctions"] = double(graph.junctions.size());
    state.counters["pieces"] = double(graph.pieceCount);
    state.counters["bridges"] = double(graph.bridgeCount);
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(graph.nodeCount()));
}

/// C_tau as a flat square sheet of `side` x `side` points one voxel thick,
/// rho_S 30 to 40 voxels: what a wall's medial surface gives when its path
/// sets close into loops (the cup PSB 34 at 160). Every node's fork test
/// then searches a ball holding most of the sheet, so the stage grows with
/// the square of the sheet's size; the synthetic shapes never show that.
std::vector<SkeletonPoint> skeletonSheet(int side, Dims& dims) {
    dims = Dims{side + 4, side + 4, 3};
    std::vector<SkeletonPoint> points;
    for (int y = 2; y < side + 2; ++y)
        for (int x = 2; x < side + 2; ++x) {
            SkeletonPoint p;
            p.voxel = std::uint32_t(x + dims.x * (y + dims.y * 1));
            p.candidate = std::uint32_t(points.size());
            p.rhoS = 30.0f + float((x * 7 + y * 3) % 11);
            p.rhoC = 1000.0;
            p.rims = p.robustRims = 2;
            p.sigma = 0.5f;
            points.push_back(p);
        }
    return points;
}

void skeletonGraphSheetBench(benchmark::State& state) {
    Dims dims;
    const std::vector<SkeletonPoint> points = skeletonSheet(int(state.range(0)), dims);
    SkeletonGraphOptions options;
    options.tau = 1.0;
    options.threaded = false;
    SkeletonGraph graph;
    for (auto _ : state) {
        graph = buildSkeletonGraph(points, dims, options);
        benchmark::DoNotOptimize(graph.point.data());
    }
    state.counters["nodes"] = double(graph.nodeCount());
    state.counters["junctions"] = double(graph.junctions.size());
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(graph.nodeCount()));
}

[[maybe_unused]] const bool kRegistered = [] {
    registerForShapes("FeatureTransform", kLinearSizes, featureTransformBench);
    registerForShapes("BoundaryVoxels", kLinearSizes, boundaryVoxelsBench);
    registerForShapes("CountBoundaryVoxels", kLinearSizes, countBoundaryVoxelsBench);
    registerForShapes("BoundaryGraph", kLinearSizes, boundaryGraphBench);
    registerForShapes("SkeletonCandidates", kLinearSizes, skeletonCandidatesBench);
    registerForShapes("ConnectedObjects", kLinearSizes, connectedObjectsBench);
    registerForShapes("VoxelGenus", kLinearSizes, voxelGenusBench);
    registerForShapes("FillCavities", kLinearSizes, fillCavitiesBench);
    registerForShapes("CloseNarrowTunnels", kLinearSizes, closeNarrowTunnelsBench);
    registerForShapes("PlugTunnels", kLinearSizes, plugTunnelsBench);
    registerForShapes("Landmarks", kLinearSizes, landmarksBench);
    registerForShapes("GeodesicSearch", kSizes,
                      [](benchmark::State& state, const std::string& shape) {
                          geodesicSearchBench(state, shape, true);
                      });
    registerForShapes("GeodesicSearchEuclidean", kSizes,
                      [](benchmark::State& state, const std::string& shape) {
                          geodesicSearchBench(state, shape, false);
                      });
    registerForShapes("RimCount", kSizes, rimCountBench);
    registerForShapes("ComponentGrowth", kSizes, componentGrowthBench);
    registerForShapes("Geodesicness", kSizes, geodesicnessBench);
    registerForShapes("MeasureSkeleton", kSizes, measureSkeletonBench);
    registerForShapes("MeasureSkeletonInBand", kSizes, measureSkeletonInBandBench);
    registerForShapes("SkeletonGraph", kSizes, skeletonGraphBench);
    benchmark::RegisterBenchmark("BM_SkeletonGraph/sheet", skeletonGraphSheetBench)
        ->Arg(32)
        ->Arg(64)
        ->Unit(benchmark::kMillisecond);
    return true;
}();

}  // namespace
}  // namespace skelseg::bench

BENCHMARK_MAIN();
