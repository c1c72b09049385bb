// skelseg end-to-end benchmarks: segmentVolume() on the synthetic shapes of
// BenchShapes.h, with default parameters (tau = 3%), serial and threaded.
// The per-stage times of the last run are reported as counters (seconds).

#include <benchmark/benchmark.h>

#include <cctype>

#include "bench/BenchShapes.h"
#include "engine/Segmenter.h"
#include "engine/StageTimer.h"

namespace skelseg::bench {
namespace {

/// "path sets, rims, areas, sigma" -> "stage_path_sets_rims_areas_sigma"
std::string counterName(const std::string& stage) {
    std::string out = "stage_";
    for (char c : stage) {
        if (std::isalnum(static_cast<unsigned char>(c)))
            out += c;
        else if (out.back() != '_')
            out += '_';
    }
    while (out.back() == '_') out.pop_back();
    return out;
}

void segmentVolumeBench(benchmark::State& state, const std::string& shape, bool threaded) {
    const ShapeInput& in = shapeInput(shape, int(state.range(0)));
    SegmentationParameters parameters;
    parameters.threaded = threaded;
    std::size_t segments = 0, skeletonPoints = 0, cuts = 0;
    std::vector<StageTiming> stages;
    for (auto _ : state) {
        StageTimer timer;
        SegmentationResult result = segmentVolume(in.mask, parameters, nullInterrupter(), &timer);
        benchmark::DoNotOptimize(result.labels.data());
        segments = result.segments.size();
        skeletonPoints = cuts = 0;
        for (const ObjectSegmentation& o : result.objects) {
            skeletonPoints += o.simplifiedSkeletonPoints;
            cuts += o.cutLoops.size();
        }
        stages = timer.timings();
    }
    state.counters["segments"] = double(segments);
    state.counters["cuts"] = double(cuts);
    state.counters["skeletonPoints"] = double(skeletonPoints);
    state.counters["objectVoxels"] = double(std::count_if(
        in.mask.values().begin(), in.mask.values().end(), [](std::uint8_t v) { return v != 0; }));
    for (const StageTiming& s : stages) state.counters[counterName(s.name)] = s.wallSeconds;
}

[[maybe_unused]] const bool kRegistered = [] {
    const std::vector<int> sizes = {64, 128};
    registerForShapes("SegmentVolume", sizes,
                      [](benchmark::State& state, const std::string& shape) {
                          segmentVolumeBench(state, shape, false);
                      });
    registerForShapes("SegmentVolumeThreaded", sizes,
                      [](benchmark::State& state, const std::string& shape) {
                          segmentVolumeBench(state, shape, true);
                      });
    return true;
}();

}  // namespace
}  // namespace skelseg::bench
