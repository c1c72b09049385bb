// A real benchmark model, segmented through the CLI and scored against its
// human segmentations, must beat the trivial one-segment baseline (issue 3).
// Skipped where ../shared/data is absent.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "engine/SegmentationScore.h"
#include "io/mesh/MeshIO.h"
#include "io/mesh/SegFile.h"
#include "tests/support/TempDir.h"
#include "tests/support/TestPaths.h"

namespace skelseg::test {
namespace {

TEST(PsbScore, HumanModelBeatsTheOneSegmentBaseline) {
    const auto psb = sharedDataDir() / "psb";
    const auto mesh = psb / "off" / "1.off";
    if (!std::filesystem::exists(mesh)) GTEST_SKIP() << "no shared data at " << psb << ": skipped";
    TempDir dir;
    const std::string command = skelsegBinary() + " segment " + mesh.string() + " -o " +
                                (dir / "out").string() +
                                " --resolution 160 -q --no-preview > /dev/null 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    const std::vector<std::int64_t> candidate = readSeg(dir / "out" / "segmentation.seg");
    const TriangleMesh triangles = readMesh(mesh);
    ASSERT_EQ(candidate.size(), triangles.faceCount);
    std::vector<std::vector<std::int64_t>> humans;
    for (const auto& entry : std::filesystem::directory_iterator(psb / "seg" / "1"))
        humans.push_back(readSeg(entry.path()));
    ASSERT_FALSE(humans.empty());
    const std::vector<double> areas = faceAreas(triangles);
    const ScoreSummary ours = scoreAgainstHumans(candidate, humans, &areas);
    const ScoreSummary oneSegment =
        scoreAgainstHumans(std::vector<std::int64_t>(candidate.size(), 0), humans, &areas);
    EXPECT_LT(ours.mean.randIndexError, oneSegment.mean.randIndexError);
    EXPECT_LT(ours.mean.hammingDistance, oneSegment.mean.hammingDistance);
    // Several parts were found (a human figure: head, torso, limbs).
    std::int64_t parts = 0;
    for (std::int64_t l : candidate) parts = std::max(parts, l + 1);
    EXPECT_GE(parts, 4);
}

}  // namespace
}  // namespace skelseg::test
