// skelseg: the `skelseg score` command.
//
// Reads a mesh, a candidate .seg and one or more human .seg files (plain or
// .gz), checks that every segmentation has one label per mesh face, scores the
// candidate against each human with the Princeton benchmark's convention (Rand
// Index over faces, Hamming distance weighted by face area; see
// engine/SegmentationScore.h) and prints a table or JSON.
#pragma once

#include <filesystem>
#include <ostream>
#include <vector>

namespace skelseg {

/// Runs the command and returns the exit code (0). JSON output:
/// {"mesh": ..., "candidate": ..., "faces": N, "weighting": "benchmark",
///  "humans": [{"file", "rand_index_error", "hamming_distance",
///              "missing_rate", "false_alarm_rate"}, ...],
///  "mean": {"rand_index_error", ...}}
/// @throw InputError naming the file that cannot be read or whose label count
/// differs from the mesh's face count; UsageError without human files.
int runScoreCommand(const std::filesystem::path& mesh, const std::filesystem::path& candidate,
                    const std::vector<std::filesystem::path>& humans, bool json, std::ostream& out);

}  // namespace skelseg
