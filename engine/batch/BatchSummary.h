// skelseg: the record of a batch, OUTROOT/summary.{json,csv}.
//
// One entry per input of the shard, in manifest order: status ("done": made
// by this run; "skipped": done earlier, its marker matched; "failed";
// "pending": not reached, e.g. the run was interrupted), parts, wall and CPU
// seconds, peak memory and the error message. The batch rewrites the files
// (atomically) as inputs finish, so a killed run still leaves an accurate
// record of what it finished. With several shapes in flight, CPU seconds and
// peak memory are the process's over the shape's run (report.json's figures),
// shared with the shapes beside it; wall seconds are the shape's own.
//
// A shard writes summary.shard-I-of-N.{json,csv}; mergeBatchSummaries()
// combines a cluster job's shard files into summary.{json,csv}, taking the
// done markers on disk as the truth, and lists what is missing.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/batch/Manifest.h"

namespace skelseg {

struct BatchEntry {
    std::string name;
    std::filesystem::path input;
    int line = 0;  // the manifest line that listed it (0: a folder given as the manifest)
    std::string status = "pending";  // done | skipped | failed | pending | missing (merge only)
    std::uint64_t parts = 0;
    double wallSeconds = 0.0, cpuSeconds = 0.0;
    std::uint64_t peakMemoryBytes = 0;
    std::uint64_t estimatedMemoryBytes = 0;
    std::string error;       // one line; empty unless failed
    std::string finishedAt;  // UTC; empty while pending
    bool isDone() const { return status == "done" || status == "skipped"; }
};

/// "NAME (line N)", or NAME for an input of a folder given as the manifest:
/// the manifest line tells which line to fix when a path is wrong.
std::string nameAndLine(const BatchEntry& entry);

struct BatchSummary {
    std::string skelsegVersion;
    std::string skelsegBuild;  // engineBuildId(); empty in summaries that predate it
    std::filesystem::path manifest;
    ShardSpec shard;
    std::string options;  // outputAffectingOptions() JSON text
    std::string run;      // host:pid
    std::string startedAt, updatedAt;
    bool complete = false;  // the run reached its end (not killed, not interrupted)
    double wallSeconds = 0.0;
    /// Every output name of the whole manifest, so that a merge knows what to expect.
    std::vector<std::string> manifestNames;
    std::vector<BatchEntry> entries;  // this shard's inputs, manifest order

    std::size_t count(const std::string& status) const;
};

/// Writes OUTROOT/<stem>.json and OUTROOT/<stem>.csv, each atomically.
/// @throw OutputError.
void writeBatchSummary(const std::filesystem::path& outroot, const std::string& stem,
                       const BatchSummary& summary);

/// Reads a summary JSON file. @throw InputError naming the file.
BatchSummary readBatchSummary(const std::filesystem::path& file);

struct MergeResult {
    BatchSummary merged;                     // shard = 0/1; entries for the whole manifest
    std::vector<std::string> shardFiles;     // the files combined
    std::vector<std::string> missingShards;  // "I/N" or a run "I-J/N" with no summary file
    std::vector<std::string> failed;         // names whose last status is failed
    std::vector<std::string> missing;        // names with no done marker (failed ones included)
};

/// Combines OUTROOT/summary.shard-*-of-N.json (N: that of the most recently
/// updated file; files of another N, left from an earlier split, are
/// ignored) and writes OUTROOT/summary.{json,csv}. Without shard files, it
/// checks OUTROOT/summary.json against the markers instead.
/// @throw InputError if OUTROOT holds no summary at all.
MergeResult mergeBatchSummaries(const std::filesystem::path& outroot);

}  // namespace skelseg
