#include "io/render/GltfWriter.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "io/render/Palette.h"
#include "kernels/base/Error.h"
#include "tests/support/TempDir.h"

namespace skelseg {
namespace {

using json = nlohmann::json;

std::uint32_t readU32(const std::string& bytes, std::size_t at) {
    std::uint32_t value = 0;
    std::memcpy(&value, bytes.data() + at, 4);
    return value;
}

/// A .glb taken apart by hand (the layout of the glTF 2.0 binary container),
/// independent of the writer.
struct GlbParts {
    json document;
    std::string bin;
};

GlbParts parseGlb(const std::string& bytes) {
    GlbParts parts;
    EXPECT_GE(bytes.size(), 20u);
    EXPECT_EQ(bytes.substr(0, 4), "glTF");
    EXPECT_EQ(readU32(bytes, 4), 2u);
    EXPECT_EQ(readU32(bytes, 8), bytes.size());
    const std::uint32_t jsonLength = readU32(bytes, 12);
    EXPECT_EQ(readU32(bytes, 16), 0x4E4F534Au);  // "JSON"
    EXPECT_EQ(jsonLength % 4, 0u);
    EXPECT_LE(20 + std::size_t(jsonLength), bytes.size());
    parts.document = json::parse(bytes.substr(20, jsonLength));
    const std::size_t binAt = 20 + jsonLength;
    if (binAt < bytes.size()) {
        const std::uint32_t binLength = readU32(bytes, binAt);
        EXPECT_EQ(readU32(bytes, binAt + 4), 0x004E4942u);  // "BIN\0"
        EXPECT_EQ(binLength % 4, 0u);
        EXPECT_EQ(binAt + 8 + binLength, bytes.size());
        parts.bin = bytes.substr(binAt + 8, binLength);
    }
    return parts;
}

/// A unit cube of two segments that share the vertices of their border, a
/// skeleton of three points, one square cut loop and one loop of two points.
GltfScene cubeScene() {
    const std::vector<std::array<double, 3>> vertices = {
        {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    const std::vector<std::array<std::uint32_t, 3>> triangles = {
        {0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
        {2, 3, 7}, {2, 7, 6}, {1, 2, 6}, {1, 6, 5}, {0, 4, 7}, {0, 7, 3}};
    const std::vector<std::uint32_t> labels = {1, 1, 2, 2, 1, 2, 1, 2, 1, 2, 1, 2};
    GltfScene scene;
    scene.segments = splitSegmentMeshes(vertices, triangles, labels);
    scene.skeletonPoints = {{0.5, 0.5, 0.1}, {0.5, 0.5, 0.5}, {0.5, 0.5, 0.9}};
    scene.skeletonEdges = {{0, 1}, {1, 2}};
    scene.cutLoops = {{{0, 0, 0.5}, {1, 0, 0.5}, {1, 1, 0.5}, {0, 1, 0.5}},
                      {{0, 0, 0.25}, {1, 1, 0.25}}};
    return scene;
}

std::size_t componentCount(const std::string& type) {
    return type == "VEC3" ? 3 : type == "VEC2" ? 2 : type == "VEC4" ? 4 : 1;
}

TEST(GltfWriter, ContainerChunksAndAccessorsAreConsistent) {
    const GltfScene scene = cubeScene();
    const std::string bytes = segmentsGlb(scene);
    const GlbParts parts = parseGlb(bytes);
    const json& doc = parts.document;
    ASSERT_FALSE(parts.bin.empty());
    EXPECT_EQ(doc["asset"]["version"], "2.0");

    // One buffer, held by the BIN chunk (no uri), fitting in it.
    ASSERT_EQ(doc["buffers"].size(), 1u);
    EXPECT_FALSE(doc["buffers"][0].contains("uri"));
    const std::size_t bufferLength = doc["buffers"][0]["byteLength"];
    EXPECT_LE(bufferLength, parts.bin.size());
    EXPECT_GT(bufferLength + 4, parts.bin.size());  // padding below 4 bytes

    for (const auto& view : doc["bufferViews"]) {
        const std::size_t offset = view.value("byteOffset", 0), length = view["byteLength"];
        EXPECT_EQ(offset % 4, 0u);
        EXPECT_LE(offset + length, bufferLength);
    }
    for (const auto& accessor : doc["accessors"]) {
        const auto& view = doc["bufferViews"][accessor["bufferView"].get<std::size_t>()];
        const std::size_t bytesPer = componentCount(accessor["type"]) * 4;  // float and uint32 only
        EXPECT_TRUE(accessor["componentType"] == 5126 || accessor["componentType"] == 5125);
        EXPECT_LE(accessor.value("byteOffset", 0) + accessor["count"].get<std::size_t>() * bytesPer,
                  view["byteLength"].get<std::size_t>());
        EXPECT_GT(accessor["count"].get<std::size_t>(), 0u);
    }

    // Meshes: "segment 1", "segment 2", then the skeleton and the cuts.
    ASSERT_EQ(doc["meshes"].size(), 4u);
    ASSERT_EQ(doc["nodes"].size(), 4u);
    EXPECT_EQ(doc["scenes"][0]["nodes"].size(), 4u);
    const std::vector<std::string> names = {"segment 1", "segment 2", "skeleton", "cuts"};
    const std::vector<int> modes = {4, 4, 1, 1};
    const std::vector<std::size_t> indexCounts = {6 * 3, 6 * 3, 2 * 2, (4 + 1) * 2};
    for (std::size_t m = 0; m < 4; ++m) {
        const json& mesh = doc["meshes"][m];
        EXPECT_EQ(mesh["name"], names[m]);
        ASSERT_EQ(mesh["primitives"].size(), 1u);
        const json& primitive = mesh["primitives"][0];
        EXPECT_EQ(primitive.value("mode", 4), modes[m]) << names[m];
        const json& position = doc["accessors"][primitive["attributes"]["POSITION"].get<int>()];
        const json& index = doc["accessors"][primitive["indices"].get<int>()];
        EXPECT_EQ(position["type"], "VEC3");
        EXPECT_EQ(index["count"], indexCounts[m]) << names[m];

        // min/max present and equal to the extent of the stored positions.
        ASSERT_TRUE(position.contains("min") && position.contains("max")) << names[m];
        const auto& view = doc["bufferViews"][position["bufferView"].get<int>()];
        const std::size_t count = position["count"];
        std::vector<float> values(3 * count);
        std::memcpy(values.data(), parts.bin.data() + view.value("byteOffset", 0),
                    values.size() * 4);
        for (int a = 0; a < 3; ++a) {
            float low = INFINITY, high = -INFINITY;
            for (std::size_t i = 0; i < count; ++i) {
                low = std::fmin(low, values[3 * i + a]);
                high = std::fmax(high, values[3 * i + a]);
            }
            EXPECT_FLOAT_EQ(position["min"][a].get<float>(), low);
            EXPECT_FLOAT_EQ(position["max"][a].get<float>(), high);
        }
        // Every index points at a stored position.
        const auto& indexView = doc["bufferViews"][index["bufferView"].get<int>()];
        std::vector<std::uint32_t> indices(index["count"].get<std::size_t>());
        std::memcpy(indices.data(), parts.bin.data() + indexView.value("byteOffset", 0),
                    indices.size() * 4);
        for (std::uint32_t i : indices) EXPECT_LT(i, count) << names[m];
    }
    // The lines keep their points: 3 skeleton points, 4 + 2 loop points.
    const auto pointCount = [&](std::size_t mesh) {
        return doc["accessors"][doc["meshes"][mesh]["primitives"][0]["attributes"]["POSITION"]
                                    .get<int>()]["count"]
            .get<int>();
    };
    EXPECT_EQ(pointCount(2), 3);
    EXPECT_EQ(pointCount(3), 6);

    // Material colours: the palette, converted to linear.
    for (std::uint32_t label = 1; label <= 2; ++label) {
        const json& primitive = doc["meshes"][label - 1]["primitives"][0];
        const json& material = doc["materials"][primitive["material"].get<int>()];
        const auto srgb = segmentColour(label);
        for (int c = 0; c < 3; ++c) {
            const double s = srgb[c] / 255.0;
            const double linear = s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
            EXPECT_NEAR(material["pbrMetallicRoughness"]["baseColorFactor"][c].get<double>(),
                        linear, 1e-9);
        }
    }
}

TEST(GltfWriter, TinygltfReadsTheFileBack) {
    const std::string bytes = segmentsGlb(cubeScene());
    tinygltf::TinyGLTF reader;
    tinygltf::Model model;
    std::string error, warning;
    ASSERT_TRUE(reader.LoadBinaryFromMemory(&model, &error, &warning,
                                            reinterpret_cast<const unsigned char*>(bytes.data()),
                                            unsigned(bytes.size())))
        << error;
    EXPECT_EQ(model.meshes.size(), 4u);
    EXPECT_EQ(model.meshes[0].name, "segment 1");
    // The split keeps every triangle: 12 in the cube, 6 per segment.
    EXPECT_EQ(model.accessors[std::size_t(model.meshes[0].primitives[0].indices)].count +
                  model.accessors[std::size_t(model.meshes[1].primitives[0].indices)].count,
              36u);
}

TEST(GltfWriter, EmptySceneIsAValidFileWithoutBinChunk) {
    const std::string bytes = segmentsGlb(GltfScene{});
    const GlbParts parts = parseGlb(bytes);
    EXPECT_TRUE(parts.bin.empty());
    EXPECT_EQ(parts.document["asset"]["version"], "2.0");
    EXPECT_FALSE(parts.document.contains("meshes"));
    // Every scene is an object (tinygltf wrote a scene without nodes as
    // null), and the default scene is one of them.
    for (const auto& scene : parts.document.value("scenes", json::array()))
        EXPECT_TRUE(scene.is_object()) << parts.document.dump();
    if (parts.document.contains("scene"))
        EXPECT_LT(parts.document["scene"].get<std::size_t>(),
                  parts.document.value("scenes", json::array()).size());
}

TEST(GltfWriter, BadSkeletonIndexIsRefused) {
    GltfScene scene = cubeScene();
    scene.skeletonEdges.push_back({0, 3});
    EXPECT_THROW(segmentsGlb(scene), UsageError);
}

TEST(GltfWriter, WritesTheFileAtomically) {
    test::TempDir dir;
    const auto file = dir.path() / "segments.glb";
    writeSegmentsGlb(file, cubeScene());
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(bytes, segmentsGlb(cubeScene()));
    EXPECT_THROW(writeSegmentsGlb(dir.path() / "missing" / "segments.glb", cubeScene()),
                 OutputError);
}

}  // namespace
}  // namespace skelseg
