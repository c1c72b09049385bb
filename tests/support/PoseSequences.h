// The shared pose sequences (../shared/data/poses/NAME_FRAME.obj): frames of
// one animated mesh with identical faces, for the invariance tests.
#pragma once

#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace skelseg::test {

/// Pose files grouped by the name before the last '_', frames in numeric order.
std::map<std::string, std::vector<std::filesystem::path>> poseSequences(
    const std::filesystem::path& poses);

/// Segments every frame of every sequence in `poses` with
/// `skelseg segment FRAME -o OUTROOT/STEM --resolution 192 -q --no-preview`
/// plus `extraArguments`, as a user would; a frame that fails adds a test
/// failure and no folder. Returns, per sequence, the output folders in frame
/// order.
std::map<std::string, std::vector<std::filesystem::path>> segmentPoseFrames(
    const std::filesystem::path& poses, const std::filesystem::path& outRoot,
    const std::vector<std::string>& extraArguments = {});

/// "a, b, c": per-frame counts for a failure message.
std::string countList(const std::vector<std::size_t>& counts);

}  // namespace skelseg::test
