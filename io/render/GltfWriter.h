// skelseg: segments.glb, the result as one binary glTF 2.0 file.
//
// glTF is what Blender, MeshLab, three.js and most web viewers open without
// a plug-in, and its binary container (.glb) keeps JSON and data in one file.
// The file holds one mesh per segment (its own node, material and name,
// "segment L", coloured by segmentColour(L)), the curve skeleton as lines
// (primitive mode 1, node "skeleton") and the cut loops as lines (node
// "cuts"). Positions are float32 in the world frame of the input, like the
// PLY outputs; glTF's convention of +y up is not imposed (the input decides
// which axis is up). Materials are double-sided (input meshes may be open);
// the lines use KHR_materials_unlit, because lines have no normals to shade.
//
// The container is written by tinygltf (Debian's libtinygltf-dev): the JSON
// chunk padded with spaces and the BIN chunk with zeros to 4 bytes, every
// POSITION accessor with its min and max, as the specification requires.
// The bytes go through writeFileAtomically(), so a reader never sees half a
// file.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "io/render/SegmentMeshes.h"

namespace skelseg {

/// What segments.glb holds; any part may be empty (an empty scene is still a
/// valid file with an empty scene list of nodes).
struct GltfScene {
    /// One mesh per segment (splitSegmentMeshes()); meshes without triangles
    /// are left out.
    std::vector<SegmentMesh> segments;
    /// Curve skeleton: points (world) and edges (0-based indices into them).
    std::vector<std::array<double, 3>> skeletonPoints;
    std::vector<std::array<std::uint32_t, 2>> skeletonEdges;
    /// Cut loops: closed polylines (world); the last point joins the first,
    /// as in cuts.ply (a loop of two points is one edge).
    std::vector<std::vector<std::array<double, 3>>> cutLoops;
};

/// The bytes of the .glb file of `scene`.
/// @throw UsageError if a skeleton edge points past the skeleton points or a
///        triangle past its segment's positions; OutputError if the data
///        exceeds the 4 GiB a .glb can hold.
std::string segmentsGlb(const GltfScene& scene);

/// segmentsGlb() written atomically to `file`.
/// @throw OutputError naming `file` if it cannot be written; as above.
void writeSegmentsGlb(const std::filesystem::path& file, const GltfScene& scene);

}  // namespace skelseg
