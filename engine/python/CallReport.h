// skelseg: the report of a Python call, with report.json's content.
//
// The same keys and values the CLI writes to report.json (docs/outputs.md),
// built from the engine's result: status, skelseg_version, input, grid,
// parameters, counts, work, objects, junctions, critical_points, segments,
// segment_count, islands, face_segments (meshes), stages, timing, memory, warnings.
// Only "input" differs: a Python call has no file, so it describes the array
// or the mesh passed in ({"kind": "array", "shape": ..., "dtype": ...} or
// {"kind": "mesh", "faces": ..., ...}).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "engine/Segmenter.h"
#include "engine/StageTimer.h"

namespace skelseg {

struct CallReportContext {
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

nlohmann::json callReport(const SegmentationResult& result, const CallReportContext& context);

}  // namespace skelseg
