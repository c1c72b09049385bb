#include "io/render/GltfWriter.h"

#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

#include "io/files/OutputDirectory.h"
#include "io/render/Palette.h"
#include "kernels/base/Error.h"

namespace skelseg {

namespace {

constexpr int kArrayBuffer = 34962;         // bufferView target of vertex data
constexpr int kElementArrayBuffer = 34963;  // bufferView target of indices

/// Appends raw little-endian data to buffer 0 as a bufferView; returns its index.
template <typename T>
int addBufferView(tinygltf::Model& model, const std::vector<T>& data, int target) {
    auto& bytes = model.buffers[0].data;
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = bytes.size();  // every element is 4-byte sized: stays aligned
    view.byteLength = data.size() * sizeof(T);
    view.target = target;
    bytes.resize(bytes.size() + view.byteLength);
    std::memcpy(bytes.data() + view.byteOffset, data.data(), view.byteLength);
    model.bufferViews.push_back(view);
    return int(model.bufferViews.size()) - 1;
}

int addPositions(tinygltf::Model& model, const std::vector<std::array<float, 3>>& positions) {
    tinygltf::Accessor accessor;
    accessor.bufferView = addBufferView(model, positions, kArrayBuffer);
    accessor.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    accessor.type = TINYGLTF_TYPE_VEC3;
    accessor.count = positions.size();
    accessor.minValues.assign(3, std::numeric_limits<double>::infinity());
    accessor.maxValues.assign(3, -std::numeric_limits<double>::infinity());
    for (const auto& p : positions)
        for (int a = 0; a < 3; ++a) {
            accessor.minValues[a] = std::fmin(accessor.minValues[a], double(p[a]));
            accessor.maxValues[a] = std::fmax(accessor.maxValues[a], double(p[a]));
        }
    model.accessors.push_back(accessor);
    return int(model.accessors.size()) - 1;
}

int addIndices(tinygltf::Model& model, const std::vector<std::uint32_t>& indices) {
    tinygltf::Accessor accessor;
    accessor.bufferView = addBufferView(model, indices, kElementArrayBuffer);
    accessor.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    accessor.type = TINYGLTF_TYPE_SCALAR;
    accessor.count = indices.size();
    model.accessors.push_back(accessor);
    return int(model.accessors.size()) - 1;
}

/// glTF colour factors are linear; the palette is sRGB.
double linearFromSrgb(std::uint8_t value) {
    const double c = value / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

int addMaterial(tinygltf::Model& model, const std::string& name,
                const std::array<std::uint8_t, 3>& colour, bool unlit) {
    tinygltf::Material material;
    material.name = name;
    material.pbrMetallicRoughness.baseColorFactor = {
        linearFromSrgb(colour[0]), linearFromSrgb(colour[1]), linearFromSrgb(colour[2]), 1.0};
    material.pbrMetallicRoughness.metallicFactor = 0.0;
    material.pbrMetallicRoughness.roughnessFactor = 0.8;
    material.doubleSided = true;
    if (unlit)
        material.extensions["KHR_materials_unlit"] = tinygltf::Value(tinygltf::Value::Object());
    model.materials.push_back(material);
    return int(model.materials.size()) - 1;
}

void addNode(tinygltf::Model& model, const std::string& name, int positions, int indices,
             int material, int mode) {
    tinygltf::Primitive primitive;
    primitive.attributes["POSITION"] = positions;
    primitive.indices = indices;
    primitive.material = material;
    primitive.mode = mode;
    tinygltf::Mesh mesh;
    mesh.name = name;
    mesh.primitives.push_back(primitive);
    model.meshes.push_back(mesh);
    tinygltf::Node node;
    node.name = name;
    node.mesh = int(model.meshes.size()) - 1;
    model.nodes.push_back(node);
    model.scenes[0].nodes.push_back(int(model.nodes.size()) - 1);
}

std::vector<std::array<float, 3>> toFloat(const std::vector<std::array<double, 3>>& points) {
    std::vector<std::array<float, 3>> out(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
        out[i] = {float(points[i][0]), float(points[i][1]), float(points[i][2])};
    return out;
}

}  // namespace

std::string segmentsGlb(const GltfScene& scene) {
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "skelseg";
    model.buffers.resize(1);
    model.scenes.resize(1);
    model.defaultScene = 0;

    for (const SegmentMesh& segment : scene.segments) {
        if (segment.triangles.empty()) continue;
        std::vector<std::uint32_t> indices;
        indices.reserve(3 * segment.triangles.size());
        for (const auto& t : segment.triangles)
            for (std::uint32_t v : t) {
                if (v >= segment.positions.size())
                    throw UsageError("segments.glb: segment " + std::to_string(segment.label) +
                                     " has a triangle index past its vertices");
                indices.push_back(v);
            }
        const std::string name = "segment " + std::to_string(segment.label);
        const int material = addMaterial(model, name, segmentColour(segment.label), false);
        addNode(model, name, addPositions(model, segment.positions), addIndices(model, indices),
                material, TINYGLTF_MODE_TRIANGLES);
    }

    if (!scene.skeletonEdges.empty()) {
        std::vector<std::uint32_t> indices;
        indices.reserve(2 * scene.skeletonEdges.size());
        for (const auto& e : scene.skeletonEdges)
            for (std::uint32_t v : e) {
                if (v >= scene.skeletonPoints.size())
                    throw UsageError("segments.glb: skeleton edge index " + std::to_string(v) +
                                     " past the " + std::to_string(scene.skeletonPoints.size()) +
                                     " skeleton points");
                indices.push_back(v);
            }
        const int material = addMaterial(model, "skeleton", {40, 40, 40}, true);
        addNode(model, "skeleton", addPositions(model, toFloat(scene.skeletonPoints)),
                addIndices(model, indices), material, TINYGLTF_MODE_LINE);
    }

    std::vector<std::array<double, 3>> cutPoints;
    std::vector<std::uint32_t> cutIndices;
    for (const auto& loop : scene.cutLoops) {
        const auto first = std::uint32_t(cutPoints.size());
        const auto n = std::uint32_t(loop.size());
        cutPoints.insert(cutPoints.end(), loop.begin(), loop.end());
        const std::uint32_t edges = n >= 3 ? n : (n == 2 ? 1 : 0);
        for (std::uint32_t i = 0; i < edges; ++i) {
            cutIndices.push_back(first + i);
            cutIndices.push_back(first + (i + 1) % n);
        }
    }
    if (!cutIndices.empty()) {
        const int material = addMaterial(model, "cuts", {255, 215, 25}, true);
        addNode(model, "cuts", addPositions(model, toFloat(cutPoints)),
                addIndices(model, cutIndices), material, TINYGLTF_MODE_LINE);
    }
    if (!cutIndices.empty() || !scene.skeletonEdges.empty())
        model.extensionsUsed.push_back("KHR_materials_unlit");

    if (model.buffers[0].data.size() > std::numeric_limits<std::uint32_t>::max() - (1u << 24))
        throw OutputError("segments.glb: " + std::to_string(model.buffers[0].data.size()) +
                          " bytes of data, more than a .glb file can hold");
    if (model.buffers[0].data.empty()) model.buffers.clear();  // a buffer may not be empty
    // A scene without nodes is written by tinygltf as `null`, which no
    // glTF schema accepts (an empty volume has no segments, skeleton or
    // cuts): no scene at all is valid.
    if (model.nodes.empty()) {
        model.scenes.clear();
        model.defaultScene = -1;
    }

    std::ostringstream bytes;
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&model, bytes, false, true))
        throw OutputError("segments.glb: the glTF writer failed");
    return bytes.str();
}

void writeSegmentsGlb(const std::filesystem::path& file, const GltfScene& scene) {
    writeFileAtomically(file, segmentsGlb(scene));
}

}  // namespace skelseg
