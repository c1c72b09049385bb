// The surfaces and the preview as the segment command writes them.
// segments.ply: its `segment` property and colours use the labels of
// labels.nrrd (1..K), for volumes and for meshes (face label + 1), as
// docs/outputs.md says. It held label - 1 before, so the largest segment read
// as "unlabelled" (0) and was drawn grey. A run leaves no earlier run's
// preview.png or segmentation.seg that it does not write itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <vector>

#include "engine/SegmentCommand.h"
#include "io/mesh/MeshIO.h"
#include "io/render/Palette.h"
#include "io/shapes/SyntheticShapes.h"
#include "io/volume/NrrdIO.h"
#include "tests/io/render/PlyTestReader.h"
#include "tests/support/ShapeMeshes.h"
#include "tests/support/TempDir.h"

using namespace skelseg;
namespace fs = std::filesystem;

namespace {

void segment(const fs::path& input, const fs::path& outdir, int resolution = 0,
             bool writePreview = false) {
    SegmentCommandOptions options;
    options.input = input;
    options.outdir = outdir;
    options.threads = 2;
    options.writePreview = writePreview;
    options.force = true;
    if (resolution > 0) options.resolution = resolution;
    ProgressReporter progress(ProgressReporter::Display::Quiet);
    runSegmentCommand(options, progress);
}

/// The `segment` value of every face of segments.ply, after checking that
/// each face's colour is segmentColour(segment).
std::vector<int> segmentsPlyLabels(const fs::path& file) {
    const test::PlyFile ply = test::readPly(file);
    const test::PlyElement& faces = ply.element("face");
    std::vector<int> labels(faces.count);
    for (std::size_t f = 0; f < faces.count; ++f) {
        labels[f] = int(faces.value(f, "segment"));
        const auto colour = segmentColour(std::uint32_t(labels[f]));
        EXPECT_EQ(faces.value(f, "red"), colour[0]) << "face " << f;
        EXPECT_EQ(faces.value(f, "green"), colour[1]) << "face " << f;
        EXPECT_EQ(faces.value(f, "blue"), colour[2]) << "face " << f;
        if (testing::Test::HasFailure()) break;
    }
    return labels;
}

}  // namespace

TEST(SegmentOutput, VolumeSegmentsPlyHoldsTheLabelsOfLabelsNrrd) {
    const test::TempDir dir;
    const fs::path input = dir / "y-arms.nrrd";
    writeNrrdMask(input, rasterise(makeShape("y-arms"), {48, 2}));
    segment(input, dir / "out");

    const LabelVolume labels = readNrrdLabels(dir / "out" / "labels.nrrd");
    std::set<int> volumeLabels;
    for (std::size_t i = 0; i < labels.size(); ++i)
        if (labels.data()[i] != 0) volumeLabels.insert(labels.data()[i]);
    ASSERT_GE(volumeLabels.size(), 2u) << "the y-arms shape must give several segments";

    const std::vector<int> plyLabels = segmentsPlyLabels(dir / "out" / "segments.ply");
    const std::set<int> surfaceLabels(plyLabels.begin(), plyLabels.end());
    EXPECT_EQ(surfaceLabels, volumeLabels);  // 1..K, no 0 (unlabelled)
}

TEST(SegmentOutput, MeshSegmentsPlyHoldsFaceLabelPlusOne) {
    const test::TempDir dir;
    // A ball with three limbs, meshed on voxel faces: several segments from a
    // mesh a tenth of the generated figure's size.
    Shape star;
    star.sphere({0, 0, 0}, 18);
    for (const std::array<double, 3>& end :
         {std::array<double, 3>{44, 0, 0}, {-22, 38, 0}, {-22, -38, 0}})
        star.capsule({0, 0, 0}, end, 8);
    const fs::path input = dir / "star.off";
    writeOff(input, test::meshOfShape(star, {-54, -50, -20}, {54, 50, 20}));
    segment(input, dir / "out", 48);

    std::vector<int> faceLabels;
    std::ifstream seg(dir / "out" / "segmentation.seg");
    for (int label = 0; seg >> label;) faceLabels.push_back(label);
    ASSERT_GE(*std::max_element(faceLabels.begin(), faceLabels.end()), 1)
        << "the figure must give several segments";

    const std::vector<int> plyLabels = segmentsPlyLabels(dir / "out" / "segments.ply");
    ASSERT_EQ(plyLabels.size(), faceLabels.size());  // a triangle mesh: one face each
    for (std::size_t f = 0; f < faceLabels.size(); ++f)
        ASSERT_EQ(plyLabels[f], faceLabels[f] + 1) << "face " << f;
}

TEST(SegmentOutput, ARunWithoutPreviewRemovesAnEarlierRunsPreview) {
    const test::TempDir dir;
    const fs::path input = dir / "y-arms.nrrd";
    writeNrrdMask(input, rasterise(makeShape("y-arms"), {48, 2}));
    segment(input, dir / "out", 0, /*writePreview=*/true);
    ASSERT_TRUE(fs::exists(dir / "out" / "preview.png"));
    segment(input, dir / "out", 0, /*writePreview=*/false);  // --force --no-preview
    EXPECT_TRUE(fs::exists(dir / "out" / "labels.nrrd"));
    EXPECT_FALSE(fs::exists(dir / "out" / "preview.png"));
}

TEST(SegmentOutput, AVolumeRunRemovesAnEarlierMeshRunsSegmentation) {
    const test::TempDir dir;
    TriangleMesh cube;
    cube.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                     {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    cube.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                      {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
    cube.triangleFace = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
    cube.faceCount = 12;
    writeOff(dir / "cube.off", cube);
    segment(dir / "cube.off", dir / "out", 16);
    ASSERT_TRUE(fs::exists(dir / "out" / "segmentation.seg"));
    const fs::path volume = dir / "y-arms.nrrd";
    writeNrrdMask(volume, rasterise(makeShape("y-arms"), {48, 2}));
    segment(volume, dir / "out");  // --force, a volume
    EXPECT_TRUE(fs::exists(dir / "out" / "labels.nrrd"));
    EXPECT_FALSE(fs::exists(dir / "out" / "segmentation.seg"));
}
