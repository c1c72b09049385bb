// segments.glb and viewer.html of a real run agree with its report.json: the
// built `skelseg` segments a generated figure; the glTF file is read back
// with tinygltf and the viewer's data block with nlohmann-json.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include "tests/engine/RobustnessHelpers.h"
#include "tests/support/TempDir.h"

namespace skelseg {
namespace {

using json = nlohmann::json;
using test::fileBytes;
using test::runSkelseg;

TEST(SegmentViews, GlbAndViewerDescribeTheSegmentsOfTheRun) {
    test::TempDir dir;
    ASSERT_EQ(
        runSkelseg({"generate", "figure", "-o", (dir / "figure.nrrd").string(), "--size", "96"})
            .exitCode,
        0);
    const auto run = runSkelseg({"segment", (dir / "figure.nrrd").string(), "-o",
                                 (dir / "out").string(), "-q", "--no-preview"});
    ASSERT_EQ(run.exitCode, 0) << run.describe();
    const json report = test::readReport(dir / "out");
    const std::size_t parts = report["segment_count"];
    ASSERT_GE(parts, 3u);

    // segments.glb: "segment 1".."segment K", then the skeleton and the cuts.
    const std::string glb = fileBytes(dir / "out" / "segments.glb");
    tinygltf::TinyGLTF reader;
    tinygltf::Model model;
    std::string error, warning;
    ASSERT_TRUE(reader.LoadBinaryFromMemory(&model, &error, &warning,
                                            reinterpret_cast<const unsigned char*>(glb.data()),
                                            unsigned(glb.size())))
        << error;
    ASSERT_EQ(model.meshes.size(), parts + 2);
    std::size_t glbTriangles = 0;
    for (std::size_t s = 0; s < parts; ++s) {
        EXPECT_EQ(model.meshes[s].name, "segment " + std::to_string(s + 1));
        glbTriangles +=
            model.accessors[std::size_t(model.meshes[s].primitives[0].indices)].count / 3;
    }
    EXPECT_EQ(model.meshes[parts].name, "skeleton");
    EXPECT_EQ(model.meshes[parts + 1].name, "cuts");

    // viewer.html: the same segments with the report's sizes, the same surface.
    const std::string html = fileBytes(dir / "out" / "viewer.html");
    const std::string start = "<script type=\"application/json\" id=\"skelseg-data\">";
    const std::size_t begin = html.find(start) + start.size();
    const json data = json::parse(html.substr(begin, html.find("</script>", begin) - begin));
    EXPECT_EQ(data["title"], "figure.nrrd");
    ASSERT_EQ(data["levels"].size(), 1u);
    const json& segments = data["levels"][0]["segments"];
    ASSERT_EQ(segments.size(), parts);
    for (std::size_t s = 0; s < parts; ++s) {
        EXPECT_EQ(segments[s]["id"], report["segments"][s]["id"]);
        EXPECT_EQ(segments[s]["voxels"], report["segments"][s]["voxels"]);
        EXPECT_TRUE(segments[s]["parent"].is_null());
    }
    EXPECT_EQ(data["surface"]["fullTriangles"].get<std::size_t>(), glbTriangles);
    std::size_t cuts = 0;
    for (const auto& object : report["objects"]) cuts += object["cuts"].get<std::size_t>();
    EXPECT_GT(cuts, 0u);
    EXPECT_EQ(data["levels"][0]["cuts"]["loopStarts"].size(), cuts);
}

}  // namespace
}  // namespace skelseg
