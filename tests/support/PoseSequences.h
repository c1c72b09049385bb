// The shared pose sequences (../shared/data/poses/NAME_FRAME.obj): frames of
// one animated mesh with identical faces, for the invariance tests.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace skelseg::test {

/// Pose files grouped by the name before the last '_', frames in numeric order.
std::map<std::string, std::vector<std::filesystem::path>> poseSequences(
    const std::filesystem::path& poses);

}  // namespace skelseg::test
