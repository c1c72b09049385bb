// skelseg: `skelseg batch MANIFEST -o OUTROOT [segment options]`.
//
// Segments every input of a manifest (engine/batch/Manifest.h) into
// OUTROOT/<name>/, each exactly as `skelseg segment INPUT -o OUTROOT/<name>`
// with the same options would, plus a done marker written last
// (engine/batch/DoneMarker.h). Inputs already done with the same input,
// options and skelseg are skipped; --force redoes all.
//
// Throughput: several shapes are in flight in one process, on a oneTBB flow
// graph: a feeder thread admits shapes by memory (MemoryBudget: the estimates
// in flight within --max-memory, at most `shapesInFlight` at once) and puts
// them into a function_node of unlimited concurrency that runs the segment
// command for each (isolated, so a worker waiting inside one shape's graph
// only helps that shape); a serial node records each finished shape (marker,
// summary, progress) while the others go on. One shape's serial stages
// (reading, voxelising, writing) thus overlap another's parallel ones.
//
// Failures are recorded and the batch goes on; the caller maps the outcome
// to the exit code (0 all done, 5 some failed, 3 interrupted).
#pragma once

#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "engine/SegmentCommand.h"
#include "engine/batch/BatchProgress.h"
#include "engine/batch/Manifest.h"

namespace skelseg {

/// Exit code of a batch (or a merge) in which some inputs failed or are missing.
inline constexpr int kExitSomeInputsFailed = 5;

struct BatchCommandOptions {
    std::filesystem::path manifest;  // file or directory
    std::filesystem::path outroot;
    /// The segment options for every input (input and outdir are set per
    /// input; force means: redo inputs that are done; maxMemoryBytes bounds
    /// the whole batch; timeLimitSeconds applies per input;
    /// budgetFromProcessStart charges the process start to the first input
    /// started only).
    SegmentCommandOptions segment;
    ShardSpec shard;         // 0/1: the whole manifest
    int shapesInFlight = 0;  // 0: threads + 1
    BatchProgress::Display display = BatchProgress::Display::Auto;
};

struct BatchOutcome {
    std::size_t inputs = 0, done = 0, skipped = 0, failed = 0, pending = 0;
    /// With their errors, "name: message", control characters escaped (one
    /// line each, as printed).
    std::vector<std::string> failedNames;
    bool interrupted = false;  // Ctrl-C / SIGTERM: the rest was not started
    std::size_t peakShapesInFlight = 0;
    std::filesystem::path summaryJson;
};

/// Runs the batch (see above). Throws UsageError/InputError for a bad
/// manifest or command line and OutputError if OUTROOT cannot be written;
/// per-input failures are in the outcome, not thrown.
BatchOutcome runBatchCommand(const BatchCommandOptions& options, std::FILE* stream = stderr);

/// `skelseg batch --merge OUTROOT`: combines the shard summaries, prints
/// what is missing to `stream` and returns the exit code (0: every input
/// done; kExitSomeInputsFailed otherwise).
int runBatchMerge(const std::filesystem::path& outroot, std::FILE* stream = stderr);

}  // namespace skelseg
