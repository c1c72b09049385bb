// skelseg benchmarks: synthetic inputs and the per-kernel setup, built once
// per (shape, size) and kept for the whole run so that no benchmark times
// its own setup.
//
// Every benchmark is registered for each shape in kBenchShapes as
//   BM_<Kernel>/<shape>/<size>
// so that `--benchmark_filter='/64$'` selects the smallest size of every
// benchmark (see bench/README.md).
#pragma once

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "io/shapes/SyntheticShapes.h"
#include "kernels/BoundaryGraph.h"
#include "kernels/FeatureTransform.h"
#include "kernels/PathSearch.h"
#include "kernels/SkeletonCandidates.h"
#include "kernels/SkeletonMeasures.h"
#include "kernels/base/Volume.h"

namespace skelseg::bench {

/// Shapes every benchmark runs on: a sphere-bodied figure with thin limbs and
/// a box body with tubes (the two cost profiles of docs/algorithm.md §13).
inline const std::vector<std::string>& benchShapes() {
    static const std::vector<std::string> shapes = {"figure", "box-tubes"};
    return shapes;
}

/// tau and the noise area the engine would use (3% of the boundary area).
inline double tauFor(std::uint64_t boundaryArea) {
    return 0.03 * double(boundaryArea);
}
inline double noiseAreaFor(std::uint64_t boundaryArea) {
    return std::min(std::max(10.0, 0.002 * double(boundaryArea)),
                    std::max(tauFor(boundaryArea), 1.0));
}

/// The inputs of one shape at one size. Stages are computed on first use.
struct ShapeInput {
    std::string shape;
    int size = 0;
    MaskVolume mask;
    MaskVolume sites;  // boundary voxels
    Volume<std::uint32_t> featureTransform;
    BoundaryGraph graph;
    std::vector<SkeletonCandidate> candidates;
    Landmarks landmarks;  // A* lower bounds, as the engine computes them
    double tau = 0.0, noiseArea = 0.0;

    /// Options the engine would pass to measureSkeleton (serial).
    SkeletonMeasureOptions measureOptions() const {
        SkeletonMeasureOptions o;
        o.tau = tau;
        o.noiseArea = noiseArea;
        o.threaded = false;
        o.landmarks = &landmarks;
        return o;
    }

    /// An evenly spaced, deterministic sample of at most `count` candidates.
    std::vector<const SkeletonCandidate*> candidateSample(std::size_t count) const {
        std::vector<const SkeletonCandidate*> out;
        if (candidates.empty()) return out;
        const std::size_t stride = std::max<std::size_t>(1, candidates.size() / count);
        for (std::size_t i = stride / 2; i < candidates.size() && out.size() < count; i += stride)
            out.push_back(&candidates[i]);
        return out;
    }

    /// The points of C (measured once, serially, like the engine does).
    const std::vector<SkeletonPoint>& skeletonPoints() {
        if (!mPointsReady) {
            mPoints = measureSkeleton(graph, candidates, measureOptions());
            mPointsReady = true;
        }
        return mPoints;
    }

private:
    std::vector<SkeletonPoint> mPoints;
    bool mPointsReady = false;
};

/// The cached input for (shape, size); built on first request.
inline ShapeInput& shapeInput(const std::string& shape, int size) {
    static std::map<std::pair<std::string, int>, std::unique_ptr<ShapeInput>> cache;
    auto& slot = cache[{shape, size}];
    if (!slot) {
        slot = std::make_unique<ShapeInput>();
        ShapeInput& in = *slot;
        in.shape = shape;
        in.size = size;
        in.mask = rasterise(makeShape(shape), {size, 3});
        in.sites = boundaryVoxels(in.mask, {false});
        in.featureTransform = featureTransform(in.sites, {false});
        in.graph = buildBoundaryGraph(in.mask, {false});
        CandidateOptions options;
        options.threaded = false;
        in.candidates = selectSkeletonCandidates(in.mask, in.featureTransform, in.graph, options);
        in.landmarks = computeLandmarks(in.graph, false);
        in.tau = tauFor(in.graph.nodeCount());
        in.noiseArea = noiseAreaFor(in.graph.nodeCount());
    }
    return *slot;
}

/// Registers `body` as BM_<kernel>/<shape>/<size> for every bench shape and
/// size. body(state, shape, size) does its setup through shapeInput() before
/// the timed loop.
inline void registerForShapes(const std::string& kernel, const std::vector<int>& sizes,
                              std::function<void(benchmark::State&, const std::string&)> body) {
    for (const std::string& shape : benchShapes()) {
        auto* b = benchmark::RegisterBenchmark(
            ("BM_" + kernel + "/" + shape).c_str(),
            [body, shape](benchmark::State& state) { body(state, shape); });
        for (int size : sizes) b->Arg(size);
        b->Unit(benchmark::kMillisecond);
    }
}

/// A counter averaged over the iterations (work per run of the kernel).
inline benchmark::Counter perIteration(double total) {
    return benchmark::Counter(total, benchmark::Counter::kAvgIterations);
}

}  // namespace skelseg::bench
