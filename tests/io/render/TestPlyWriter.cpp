#include "io/render/PlyWriter.h"

#include <gtest/gtest.h>

#include <set>

#include "io/render/Palette.h"
#include "kernels/base/Error.h"
#include "tests/io/render/PlyTestReader.h"
#include "tests/support/TempDir.h"

namespace skelseg {
namespace {

using test::readPly;
using test::TempDir;

std::vector<std::string> propertyNames(const test::PlyElement& element) {
    std::vector<std::string> names;
    for (const auto& p : element.properties)
        names.push_back(p.name + ":" + (p.isList ? "list " : "") + p.type);
    return names;
}

TEST(Palette, LabelsGetDistinctDeterministicColours) {
    EXPECT_EQ(segmentColour(0), (std::array<std::uint8_t, 3>{128, 128, 128}));
    EXPECT_EQ(segmentColour(1), segmentColour(1));
    std::set<std::array<std::uint8_t, 3>> seen;
    for (std::uint32_t label = 1; label <= 200; ++label) {
        const auto colour = segmentColour(label);
        EXPECT_TRUE(seen.insert(colour).second) << "label " << label << " repeats a colour";
        // Never as pale as the background nor as dark as the skeleton lines.
        const int sum = colour[0] + colour[1] + colour[2];
        EXPECT_GT(sum, 120) << "label " << label;
        EXPECT_LT(sum, 3 * 240) << "label " << label;
    }
    // Consecutive labels are well apart (squared RGB distance).
    for (std::uint32_t label = 1; label < 200; ++label) {
        const auto a = segmentColour(label), b = segmentColour(label + 1);
        int distance = 0;
        for (int c = 0; c < 3; ++c) distance += (a[c] - b[c]) * (a[c] - b[c]);
        EXPECT_GT(distance, 40 * 40) << "labels " << label << " and " << label + 1;
    }
}

TEST(PlyWriter, SkeletonRoundTrips) {
    TempDir dir;
    std::vector<SkeletonPointRecord> points(3);
    points[0] = {{1.5, -2.0, 3.25}, 4.0f, 5.0f, 0.5f, true, false};
    points[1] = {{10.0, 20.0, 30.0}, 1.0f, 2.0f, 0.25f, false, true};
    points[2] = {{-7.0, 0.0, 1e4}, 0.0f, 0.0f, 0.0f, false, false};
    const std::vector<std::array<std::uint32_t, 2>> edges = {{0, 1}, {1, 2}};
    writeSkeletonPly(dir / "skeleton.ply", points, edges);

    const auto ply = readPly(dir / "skeleton.ply");
    EXPECT_EQ(ply.format, "binary_little_endian");
    const auto& vertex = ply.element("vertex");
    ASSERT_EQ(vertex.count, 3u);
    EXPECT_EQ(
        propertyNames(vertex),
        (std::vector<std::string>{"x:float", "y:float", "z:float", "rho_s:float", "rho_c:float",
                                  "sigma:float", "junction:uchar", "critical:uchar"}));
    EXPECT_DOUBLE_EQ(vertex.value(0, "x"), 1.5);
    EXPECT_DOUBLE_EQ(vertex.value(0, "y"), -2.0);
    EXPECT_DOUBLE_EQ(vertex.value(0, "z"), 3.25);
    EXPECT_DOUBLE_EQ(vertex.value(2, "z"), 1e4);
    EXPECT_DOUBLE_EQ(vertex.value(0, "rho_s"), 4.0);
    EXPECT_DOUBLE_EQ(vertex.value(0, "rho_c"), 5.0);
    EXPECT_DOUBLE_EQ(vertex.value(1, "sigma"), 0.25);
    EXPECT_EQ(vertex.value(0, "junction"), 1.0);
    EXPECT_EQ(vertex.value(0, "critical"), 0.0);
    EXPECT_EQ(vertex.value(1, "junction"), 0.0);
    EXPECT_EQ(vertex.value(1, "critical"), 1.0);
    const auto& edge = ply.element("edge");
    ASSERT_EQ(edge.count, 2u);
    EXPECT_EQ(propertyNames(edge), (std::vector<std::string>{"vertex1:int", "vertex2:int"}));
    EXPECT_EQ(edge.value(1, "vertex1"), 1.0);
    EXPECT_EQ(edge.value(1, "vertex2"), 2.0);
}

TEST(PlyWriter, EmptySkeletonIsAValidFile) {
    TempDir dir;
    writeSkeletonPly(dir / "skeleton.ply", {}, {});
    const auto ply = readPly(dir / "skeleton.ply");
    EXPECT_EQ(ply.element("vertex").count, 0u);
    EXPECT_EQ(ply.element("edge").count, 0u);
}

TEST(PlyWriter, SkeletonEdgeOutOfRangeThrowsAndWritesNothing) {
    TempDir dir;
    std::vector<SkeletonPointRecord> points(2);
    try {
        writeSkeletonPly(dir / "skeleton.ply", points, {{0, 2}});
        FAIL() << "expected OutputError";
    } catch (const OutputError& error) {
        EXPECT_NE(std::string(error.what()).find("skeleton.ply"), std::string::npos)
            << error.what();
    }
    EXPECT_FALSE(std::filesystem::exists(dir / "skeleton.ply"));
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));  // no temporary left behind
}

TEST(PlyWriter, UnwritablePathThrowsOutputErrorNamingIt) {
    TempDir dir;
    const auto file = dir / "missing-folder" / "cuts.ply";
    try {
        writeCutsPly(file, {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}});
        FAIL() << "expected OutputError";
    } catch (const OutputError& error) {
        EXPECT_NE(std::string(error.what()).find(file.string()), std::string::npos) << error.what();
    }
}

TEST(PlyWriter, CutLoopsAreClosedPolylinesTaggedByLoop) {
    TempDir dir;
    const std::vector<std::vector<std::array<double, 3>>> loops = {
        {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}},  // square: 4 edges incl. closing one
        {},                                            // empty: nothing, index kept
        {{5, 5, 5}, {6, 5, 5}},                        // two points: one edge
        {{9, 9, 9}, {9, 8, 9}, {8, 8, 9}},             // triangle: 3 edges
    };
    writeCutsPly(dir / "cuts.ply", loops);
    const auto ply = readPly(dir / "cuts.ply");
    const auto& vertex = ply.element("vertex");
    const auto& edge = ply.element("edge");
    ASSERT_EQ(vertex.count, 9u);
    ASSERT_EQ(edge.count, 8u);
    EXPECT_EQ(propertyNames(vertex),
              (std::vector<std::string>{"x:float", "y:float", "z:float", "cut:int"}));
    EXPECT_EQ(propertyNames(edge),
              (std::vector<std::string>{"vertex1:int", "vertex2:int", "cut:int"}));
    EXPECT_EQ(vertex.value(3, "cut"), 0.0);
    EXPECT_EQ(vertex.value(4, "cut"), 2.0);
    EXPECT_EQ(vertex.value(8, "cut"), 3.0);
    EXPECT_DOUBLE_EQ(vertex.value(5, "x"), 6.0);
    // Closing edge of the square.
    EXPECT_EQ(edge.value(3, "vertex1"), 3.0);
    EXPECT_EQ(edge.value(3, "vertex2"), 0.0);
    EXPECT_EQ(edge.value(3, "cut"), 0.0);
    EXPECT_EQ(edge.value(4, "vertex1"), 4.0);
    EXPECT_EQ(edge.value(4, "vertex2"), 5.0);
    EXPECT_EQ(edge.value(4, "cut"), 2.0);
    EXPECT_EQ(edge.value(7, "vertex1"), 8.0);
    EXPECT_EQ(edge.value(7, "vertex2"), 6.0);
    EXPECT_EQ(edge.value(7, "cut"), 3.0);
    // Every vertex of a closed loop (3+ points) has exactly two edges of its loop.
    std::vector<int> degree(vertex.count, 0);
    for (std::size_t e = 0; e < edge.count; ++e) {
        const auto a = std::size_t(edge.value(e, "vertex1")),
                   b = std::size_t(edge.value(e, "vertex2"));
        EXPECT_EQ(vertex.value(a, "cut"), edge.value(e, "cut"));
        EXPECT_EQ(vertex.value(b, "cut"), edge.value(e, "cut"));
        ++degree[a], ++degree[b];
    }
    for (std::size_t v : {0, 1, 2, 3, 6, 7, 8}) EXPECT_EQ(degree[v], 2) << "vertex " << v;
}

TEST(PlyWriter, ColouredMeshHasFaceColoursAndSegments) {
    TempDir dir;
    const std::vector<std::array<double, 3>> vertices = {
        {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const std::vector<std::array<std::uint32_t, 3>> triangles = {
        {0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    const std::vector<std::uint32_t> labels = {1, 2, 2, 25};
    writeColouredMeshPly(dir / "segments.ply", vertices, triangles, labels);

    const auto ply = readPly(dir / "segments.ply");
    ASSERT_EQ(ply.element("vertex").count, 4u);
    const auto& face = ply.element("face");
    ASSERT_EQ(face.count, 4u);
    EXPECT_EQ(propertyNames(face),
              (std::vector<std::string>{"vertex_indices:list int", "red:uchar", "green:uchar",
                                        "blue:uchar", "segment:int"}));
    EXPECT_EQ(face.properties[0].countType, "uchar");
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const auto& corners = face.list(t, "vertex_indices");
        ASSERT_EQ(corners.size(), 3u);
        for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(corners[k], double(triangles[t][k]));
        const auto colour = segmentColour(labels[t]);
        EXPECT_EQ(face.value(t, "red"), colour[0]);
        EXPECT_EQ(face.value(t, "green"), colour[1]);
        EXPECT_EQ(face.value(t, "blue"), colour[2]);
        EXPECT_EQ(face.value(t, "segment"), double(labels[t]));
    }
    EXPECT_DOUBLE_EQ(ply.element("vertex").value(3, "z"), 1.0);
}

TEST(PlyWriter, ColouredMeshRejectsBadInput) {
    TempDir dir;
    const std::vector<std::array<double, 3>> vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    EXPECT_THROW(writeColouredMeshPly(dir / "a.ply", vertices, {{0, 1, 3}}, {1}), OutputError);
    EXPECT_THROW(writeColouredMeshPly(dir / "b.ply", vertices, {{0, 1, 2}}, {}), OutputError);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(PlyWriter, ReplacesAnExistingFile) {
    TempDir dir;
    writeCutsPly(dir / "cuts.ply", {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}});
    writeCutsPly(dir / "cuts.ply", {});
    EXPECT_EQ(readPly(dir / "cuts.ply").element("vertex").count, 0u);
}

}  // namespace
}  // namespace skelseg
