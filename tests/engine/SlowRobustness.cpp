// Slow degenerate-shape tests (label slow): a scanned mesh with tunnels.
// The quick ones are in TestRobustnessShapes.cpp.
#include <fstream>

#include "io/MeshIO.h"
#include "tests/engine/RobustnessShapes.h"

namespace fs = std::filesystem;
using namespace skelseg;
using namespace skelseg::test;

namespace {

TEST(SlowDegenerateShapes, FertilityHasTunnels) {
    const fs::path input = sharedDataDir() / "shapes" / "fertility.off";
    if (!fs::exists(input)) GTEST_SKIP() << input << " is absent (shared data not installed)";
    TempDir dir;
    const CliResult result = runSegment(input, dir / "out", {"--resolution", "96"});
    ASSERT_EQ(result.exitCode, 0) << result.describe();
    EXPECT_EQ(warningLines(result).size(), result.errLines().size()) << result.describe();
    const nlohmann::json report = readReport(dir / "out");
    EXPECT_EQ(report["status"], "ok");
    EXPECT_EQ(report["input"]["mesh_closed"], true);
    EXPECT_EQ(report["objects"].size(), 1u);
    EXPECT_GE(report["segment_count"].get<int>(), 2);
    // One label per input face, all of them segments that exist.
    const TriangleMesh mesh = readMesh(input);
    std::ifstream seg(dir / "out" / "segmentation.seg");
    std::size_t lines = 0;
    for (std::string line; std::getline(seg, line);) {
        ++lines;
        EXPECT_LT(std::stoul(line), report["face_segments"].get<std::size_t>());
    }
    EXPECT_EQ(lines, mesh.faceCount);
    EXPECT_EQ(readNrrdLabels(dir / "out" / "labels.nrrd").dims().x, report["grid"]["size"][0].get<int>());
}

}  // namespace
