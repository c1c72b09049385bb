// skelseg: the report of one segmentation, as report.json holds it.
//
// One builder for every caller, so the CLI's report.json and the Python
// result's .report cannot drift apart (docs/outputs.md lists the keys):
// status, skelseg_version, input, grid, parameters, counts, work, objects,
// junctions, critical_points, cuts, joint_cuts (and joint_candidates with
// --joints), segments, segment_count, islands,
// face_segments (meshes), stages, timing, memory, warnings. Only "input" is
// the caller's: the CLI describes the file it read, a Python call the array
// or mesh passed in ({"kind": "array", "shape": ..., "dtype": ...}).
// Callers add blocks of their own (the CLI's time_budget) to the result.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "engine/Segmenter.h"
#include "engine/StageTimer.h"

namespace skelseg {

struct ResultReportContext {
    nlohmann::json input;
    SegmentationParameters parameters;
    int threads = 0;
    std::vector<StageTiming> stages;
    double wallSeconds = 0.0;
    double cpuSeconds = 0.0;
    std::uint64_t estimatedMemoryBytes = 0;
    std::uint64_t memoryLimitBytes = 0;
    std::vector<std::string> warnings;
    /// Meshes: the number of distinct face labels.
    std::optional<std::uint32_t> faceSegments;
};

/// The parameters of the method that decide a run's segmentation, keyed as
/// report.json's `parameters` holds them (docs/outputs.md): tau, sigma_min,
/// body_ratio, mode, region_radius, bridge_gap, consecutive_levels and the
/// junction and cut rules (docs/outputs.md lists every key). The batch's
/// done.json records them too, so a run with other rules is not skipped as
/// done.
nlohmann::json methodParameters(const SegmentationParameters& parameters);

/// The report of `result`; peak_resident_bytes is read now (the process's).
nlohmann::json resultReport(const SegmentationResult& result, const ResultReportContext& context);

}  // namespace skelseg
