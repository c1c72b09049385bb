// Slow: every pose sequence of ../shared/data/poses keeps its part count in
// all its frames (issue 12), segmented as a new user would
// (`skelseg segment MESH -o OUT --resolution 192`, defaults otherwise).
// Skipped where the data is absent. bench/invariance.py measures the same and
// more (Rand Index error between frames, resolution sweeps).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "tests/support/PoseSequences.h"
#include "tests/support/TempDir.h"
#include "tests/support/TestPaths.h"

namespace skelseg {
namespace {

namespace fs = std::filesystem;

/// Distinct labels of a .seg file (one label per line).
std::size_t partCount(const fs::path& seg) {
    std::ifstream in(seg);
    std::set<long> labels;
    long label = 0;
    while (in >> label) labels.insert(label);
    return labels.size();
}

TEST(Invariance, EveryPoseSequenceKeepsItsPartCount) {
    const fs::path poses = test::sharedDataDir() / "poses";
    if (!fs::is_directory(poses)) GTEST_SKIP() << "no pose data at " << poses << ": skipped";
    if (test::poseSequences(poses).empty()) GTEST_SKIP() << "no pose sequence in " << poses;
    test::TempDir dir;
    for (const auto& [name, outputs] : test::segmentPoseFrames(poses, dir.path())) {
        std::vector<std::size_t> parts;
        for (const fs::path& out : outputs) parts.push_back(partCount(out / "segmentation.seg"));
        EXPECT_EQ(std::set<std::size_t>(parts.begin(), parts.end()).size(), 1u)
            << name << ": parts per frame " << test::countList(parts);
    }
}

}  // namespace
}  // namespace skelseg
