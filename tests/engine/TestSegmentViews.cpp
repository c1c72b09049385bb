// segments.glb and viewer.html of a real run agree with its report.json: the
// built `skelseg` segments a generated figure; the glTF file is read back
// with tinygltf and the viewer's data block with nlohmann-json.
#include <gtest/gtest.h>
#include <tiny_gltf.h>
#include <cstring>

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

/// Decodes the viewer's base64 arrays of 32-bit labels.
std::vector<std::uint32_t> decodeLabels(const std::string& text) {
    static const std::string alphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string bytes;
    std::uint32_t buffer = 0;
    int bits = 0;
    for (char c : text) {
        if (c == '=') break;
        buffer = (buffer << 6) | std::uint32_t(alphabet.find(c));
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            bytes.push_back(char((buffer >> bits) & 0xFF));
        }
    }
    std::vector<std::uint32_t> labels(bytes.size() / 4);
    std::memcpy(labels.data(), bytes.data(), labels.size() * 4);
    return labels;
}

TEST(SegmentViews, ViewerHoldsEveryLevelOfAHierarchyRun) {
    test::TempDir dir;
    ASSERT_EQ(
        runSkelseg({"generate", "figure", "-o", (dir / "figure.nrrd").string(), "--size", "96"})
            .exitCode,
        0);
    const auto run =
        runSkelseg({"segment", (dir / "figure.nrrd").string(), "-o", (dir / "out").string(), "-q",
                    "--no-preview", "--tau", "20%,1%,3%"});
    ASSERT_EQ(run.exitCode, 0) << run.describe();
    const json hierarchy = json::parse(fileBytes(dir / "out" / "hierarchy.json"));
    const std::string html = fileBytes(dir / "out" / "viewer.html");
    const std::string start = "<script type=\"application/json\" id=\"skelseg-data\">";
    const std::size_t begin = html.find(start) + start.size();
    const json data = json::parse(html.substr(begin, html.find("</script>", begin) - begin));
    ASSERT_EQ(data["levels"].size(), 3u);
    ASSERT_EQ(hierarchy["levels"].size(), 3u);
    std::vector<std::vector<std::uint32_t>> baseLabels;
    for (std::size_t k = 0; k < 3; ++k) {
        const json &shown = data["levels"][k], &written = hierarchy["levels"][k];
        EXPECT_EQ(shown["tau"], written["tau"]);
        ASSERT_EQ(shown["segments"].size(), written["segments"].size());
        for (std::size_t s = 0; s < shown["segments"].size(); ++s) {
            EXPECT_EQ(shown["segments"][s]["id"], written["segments"][s]["id"]);
            EXPECT_EQ(shown["segments"][s]["voxels"], written["segments"][s]["voxels"]);
            EXPECT_EQ(shown["segments"][s]["parent"], written["segments"][s]["parent"]);
        }
        baseLabels.push_back(decodeLabels(shown["baseLabel"].get<std::string>()));
        EXPECT_EQ(baseLabels[k].size(), data["surface"]["vertexStarts"].size());
    }
    EXPECT_GT(data["levels"][0]["segments"].size(), data["levels"][2]["segments"].size());
    // Every base segment's label at a level maps to its label at the next
    // coarser level through the parents.
    for (std::size_t k = 0; k + 1 < 3; ++k)
        for (std::size_t b = 0; b < baseLabels[k].size(); ++b) {
            const std::uint32_t label = baseLabels[k][b];
            ASSERT_GE(label, 1u);
            EXPECT_EQ(hierarchy["levels"][k]["segments"][label - 1]["parent"].get<std::uint32_t>(),
                      baseLabels[k + 1][b]);
        }
    // The cut loops grow towards the finer levels (every coarser cut is kept).
    EXPECT_GE(data["levels"][0]["cuts"]["loopStarts"].size(),
              data["levels"][2]["cuts"]["loopStarts"].size());
}

}  // namespace
}  // namespace skelseg
