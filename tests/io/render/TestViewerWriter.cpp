#include "io/render/ViewerWriter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

#include "io/render/Palette.h"
#include "kernels/base/Error.h"
#include "tests/support/TempDir.h"

namespace skelseg {
namespace {

using json = nlohmann::json;

const std::string kDataStart = "<script type=\"application/json\" id=\"skelseg-data\">";

/// The JSON block of a page, parsed (JSON's \u escapes give the text back).
json pageData(const std::string& html) {
    const std::size_t start = html.find(kDataStart);
    EXPECT_NE(start, std::string::npos);
    const std::size_t begin = start + kDataStart.size();
    const std::size_t end = html.find("</script>", begin);
    EXPECT_NE(end, std::string::npos);
    return json::parse(html.substr(begin, end - begin));
}

std::vector<unsigned char> fromBase64(const std::string& text) {
    static const std::string alphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::vector<unsigned char> out;
    std::uint32_t bits = 0;
    int count = 0;
    for (char c : text) {
        if (c == '=') break;
        bits = (bits << 6) | std::uint32_t(alphabet.find(c));
        count += 6;
        if (count >= 8) {
            count -= 8;
            out.push_back(static_cast<unsigned char>((bits >> count) & 0xFF));
        }
    }
    return out;
}

template <typename T>
std::vector<T> decode(const json& value) {
    const auto bytes = fromBase64(value.get<std::string>());
    EXPECT_EQ(bytes.size() % sizeof(T), 0u);
    std::vector<T> out(bytes.size() / sizeof(T));
    std::memcpy(out.data(), bytes.data(), bytes.size());
    return out;
}

/// Two unit squares side by side (labels 1 and 2 at level 0, both 1 at level 1).
ViewerScene twoSquares(const std::string& title) {
    ViewerScene scene;
    scene.title = title;
    scene.facts = {"2 parts", "grid 4 x 2 x 1"};
    scene.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}};
    scene.triangles = {{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 2}};
    SkeletonPointRecord a, b;
    a.position = {0.5, 0.5, 0};
    a.sigma = 0.9f;
    a.rhoC = 10;
    b.position = {1.5, 0.5, 0};
    b.sigma = 0.2f;
    b.rhoC = 1000;
    scene.skeletonPoints = {a, b};
    scene.skeletonEdges = {{0, 1}};
    ViewerLevel fine;
    fine.tau = "1%";
    fine.triangleLabels = {1, 1, 2, 2};
    fine.segments = {{1, 100, 1}, {2, 60, 1}};
    fine.cutLoops = {{{1, 0, 0}, {1, 1, 0}}};
    ViewerLevel coarse;
    coarse.tau = "9%";
    coarse.triangleLabels = {1, 1, 1, 1};
    coarse.segments = {{1, 160, 0}};
    scene.levels = {fine, coarse};
    return scene;
}

TEST(ViewerWriter, Base64MatchesRfc4648) {
    const auto encode = [](const std::string& s) { return base64(s.data(), s.size()); };
    EXPECT_EQ(encode(""), "");
    EXPECT_EQ(encode("f"), "Zg==");
    EXPECT_EQ(encode("fo"), "Zm8=");
    EXPECT_EQ(encode("foo"), "Zm9v");
    EXPECT_EQ(encode("foob"), "Zm9vYg==");
    EXPECT_EQ(encode("fooba"), "Zm9vYmE=");
    EXPECT_EQ(encode("foobar"), "Zm9vYmFy");
    const unsigned char high[] = {0xFF, 0xFE, 0x00};
    EXPECT_EQ(base64(high, 3), "//4A");
}

TEST(ViewerWriter, ScriptElementEscapes) {
    EXPECT_EQ(jsonForScriptElement("\"</script><b>&amp;\""),
              "\"\\u003c/script\\u003e\\u003cb\\u003e\\u0026amp;\"");
    EXPECT_EQ(json::parse(jsonForScriptElement(json("a</script>&b").dump())), "a</script>&b");
}

TEST(ViewerWriter, InputTextCannotBreakOutOfTheDataBlock) {
    const std::string hostile =
        "<img src=x onerror=alert(1)>.off</script><script>alert(2)</script>\xE2\x80\xA8@SKELSEG_"
        "VIEWER_SCRIPT@";
    ViewerScene scene = twoSquares(hostile);
    scene.facts.push_back("grid name " + hostile);
    const std::string html = viewerHtml(scene);
    EXPECT_EQ(html.find("<img"), std::string::npos);
    EXPECT_EQ(html.find("alert(2)</script>"), std::string::npos);
    EXPECT_EQ(html.find("\xE2\x80\xA8"), std::string::npos);  // U+2028 ends a JS line
    // Exactly the page's own two script elements.
    std::size_t scripts = 0;
    for (std::size_t at = html.find("</script"); at != std::string::npos;
         at = html.find("</script", at + 1))
        ++scripts;
    EXPECT_EQ(scripts, 2u);
    // The text survives, unchanged, as data.
    const json data = pageData(html);
    EXPECT_EQ(data["title"], hostile);
    EXPECT_EQ(data["facts"].back(), "grid name " + hostile);
    // And the script shows it only as text.
    EXPECT_NE(html.find("byId('title').textContent = data.title"), std::string::npos);
    EXPECT_EQ(html.find("innerHTML"), std::string::npos);
}

TEST(ViewerWriter, FileNamesThatAreNotUtf8StillGiveAPage) {
    // Linux file names are bytes: an invalid sequence shows as U+FFFD.
    const json data = pageData(viewerHtml(twoSquares("bad\xFFname.off")));
    EXPECT_EQ(data["title"], "bad\xEF\xBF\xBDname.off");
}

TEST(ViewerWriter, PageIsSelfContained) {
    const std::string html = viewerHtml(twoSquares("shape.off"));
    EXPECT_EQ(html.find("http://"), std::string::npos);
    EXPECT_EQ(html.find("https://"), std::string::npos);
    EXPECT_EQ(html.find(" src="), std::string::npos);  // no external script or image
    EXPECT_NE(html.find("default-src 'none'"), std::string::npos);
    EXPECT_EQ(html.find("@SKELSEG_VIEWER"), std::string::npos);  // placeholders filled
}

TEST(ViewerWriter, DataDescribesLevelsSurfaceAndSkeleton) {
    const json data = pageData(viewerHtml(twoSquares("shape.off")));
    const auto positions = decode<float>(data["surface"]["positions"]);
    const auto indices = decode<std::uint32_t>(data["surface"]["indices"]);
    // Split by level-0 segment: 4 + 4 vertices (the shared edge is copied).
    EXPECT_EQ(positions.size(), 8u * 3);
    EXPECT_EQ(data["surface"]["vertexStarts"], json({0, 4}));
    EXPECT_EQ(indices.size(), 4u * 3);
    for (std::uint32_t i : indices) EXPECT_LT(i, 8u);
    EXPECT_EQ(data["surface"]["fullTriangles"], 4);

    ASSERT_EQ(data["levels"].size(), 2u);
    EXPECT_EQ(decode<std::uint32_t>(data["levels"][0]["baseLabel"]),
              (std::vector<std::uint32_t>{1, 2}));
    EXPECT_EQ(decode<std::uint32_t>(data["levels"][1]["baseLabel"]),
              (std::vector<std::uint32_t>{1, 1}));
    const json& fine = data["levels"][0]["segments"];
    EXPECT_EQ(fine[1]["id"], 2);
    EXPECT_EQ(fine[1]["voxels"], 60);
    EXPECT_EQ(fine[1]["parent"], 1);
    const auto colour = segmentColour(2);
    EXPECT_EQ(fine[1]["colour"], json({colour[0], colour[1], colour[2]}));
    EXPECT_TRUE(data["levels"][1]["segments"][0]["parent"].is_null());
    EXPECT_EQ(data["levels"][0]["tau"], "1%");
    EXPECT_EQ(decode<float>(data["levels"][0]["cuts"]["positions"]).size(), 6u);
    EXPECT_EQ(data["levels"][1]["cuts"]["loopStarts"].size(), 0u);

    EXPECT_EQ(decode<float>(data["skeleton"]["sigma"]), (std::vector<float>{0.9f, 0.2f}));
    EXPECT_EQ(decode<float>(data["skeleton"]["rhoC"]), (std::vector<float>{10.f, 1000.f}));
    EXPECT_EQ(decode<std::uint32_t>(data["skeleton"]["edges"]), (std::vector<std::uint32_t>{0, 1}));
}

TEST(ViewerWriter, OpensAtTheCoarsestLevelUnlessToldOtherwise) {
    ViewerScene scene = twoSquares("x");
    EXPECT_FALSE(pageData(viewerHtml(scene)).contains("openLevel"));
    scene.openLevel = 1;  // the coarsest, said explicitly: the same page
    EXPECT_EQ(viewerHtml(scene), viewerHtml(twoSquares("x")));
    scene.openLevel = 0;  // --joints with one tau: the joint level
    EXPECT_EQ(pageData(viewerHtml(scene))["openLevel"], 0);
}

TEST(ViewerWriter, RefusesLevelsThatDoNotNest) {
    ViewerScene scene = twoSquares("x");
    scene.levels[1].triangleLabels = {1, 2, 1, 1};  // segment 1 of level 0 in two parents
    EXPECT_THROW(viewerHtml(scene), UsageError);
    scene.levels[1].triangleLabels = {1, 1};
    EXPECT_THROW(viewerHtml(scene), UsageError);
    scene.levels.clear();
    EXPECT_THROW(viewerHtml(scene), UsageError);
}

TEST(ViewerWriter, LargeSurfacesAreSimplifiedToTheBudget) {
    // A 600 x 600 grid of quads (720k triangles) in four segments.
    ViewerScene scene = twoSquares("big");
    scene.vertices.clear();
    scene.triangles.clear();
    const int n = 600;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x)
            scene.vertices.push_back(
                {double(x), double(y), 3.0 * std::sin(x * 0.05) * std::cos(y * 0.05)});
    std::vector<std::uint32_t> labels;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const auto at = [&](int xx, int yy) { return std::uint32_t(yy * (n + 1) + xx); };
            scene.triangles.push_back({at(x, y), at(x + 1, y), at(x + 1, y + 1)});
            scene.triangles.push_back({at(x, y), at(x + 1, y + 1), at(x, y + 1)});
            const std::uint32_t label = 1 + (x >= n / 2) + 2 * (y >= n / 2);
            labels.insert(labels.end(), 2, label);
        }
    scene.levels.resize(1);
    scene.levels[0].triangleLabels = labels;
    scene.levels[0].segments = {{1, 1, 0}, {2, 1, 0}, {3, 1, 0}, {4, 1, 0}};
    ViewerOptions options;
    options.maxTriangles = 50000;
    const std::string html = viewerHtml(scene, options);
    const json data = pageData(html);
    EXPECT_EQ(data["surface"]["fullTriangles"], 2 * n * n);
    EXPECT_LE(data["surface"]["shownTriangles"].get<std::size_t>(), 50000u * 3 / 2);
    EXPECT_GT(data["surface"]["shownTriangles"].get<std::size_t>(), 1000u);
    // About 50 bytes of base64 per shown triangle and the script: well under 4 MB.
    EXPECT_LT(html.size(), std::size_t(4) << 20);
    // Every segment is still there, with vertices of its own, and the
    // triangles stay inside the vertex list.
    const json& starts = data["surface"]["vertexStarts"];
    const std::size_t vertexCount = decode<float>(data["surface"]["positions"]).size() / 3;
    ASSERT_EQ(starts.size(), 4u);
    for (std::size_t s = 0; s < 4; ++s) {
        const std::size_t end = s + 1 < 4 ? starts[s + 1].get<std::size_t>() : vertexCount;
        EXPECT_LT(starts[s].get<std::size_t>(), end) << "segment " << s + 1 << " lost";
    }
    for (std::uint32_t i : decode<std::uint32_t>(data["surface"]["indices"]))
        EXPECT_LT(i, vertexCount);
}

TEST(ViewerWriter, WritesTheFile) {
    test::TempDir dir;
    writeViewerHtml(dir.path() / "viewer.html", twoSquares("a.off"));
    EXPECT_TRUE(std::filesystem::is_regular_file(dir.path() / "viewer.html"));
    EXPECT_THROW(writeViewerHtml(dir.path() / "no" / "viewer.html", twoSquares("a.off")),
                 OutputError);
}

}  // namespace
}  // namespace skelseg
