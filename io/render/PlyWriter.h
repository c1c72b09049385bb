// skelseg: PLY files of the results (skeleton.ply, cuts.ply, segments.ply).
//
// All three are binary_little_endian PLY 1.0 with float positions in world
// coordinates (the input's frame), which MeshLab, CloudCompare, ParaView and
// Blender read; the element and property names are listed in docs/outputs.md.
// Binary rather than ascii because a 400^3 run gives ~10^6 faces and ascii
// would be ~5x larger and slower to load; every common viewer reads binary.
//
// Every writer builds the whole file in memory and writes it through
// writeFileAtomically() (temporary name in the same directory + rename), so a
// reader never sees a half-written file. Failures throw OutputError whose
// message starts with the path. Indices that point past the vertex list are
// reported the same way (the file would be unreadable), before anything is
// written.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace skelseg {

/// One curve-skeleton point as written to skeleton.ply.
struct SkeletonPointRecord {
    /// World coordinates.
    std::array<double, 3> position{0.0, 0.0, 0.0};
    /// Surface-distance and centre-distance radii and the sigma measure of the
    /// point, in the units the kernels report them (voxels unless documented
    /// otherwise by the caller).
    float rhoS = 0.0f, rhoC = 0.0f, sigma = 0.0f;
    /// The point is a junction (three or more branches meet) / a critical point
    /// where a cut was made.
    bool junction = false, critical = false;
};

/// Writes the curve skeleton: element `vertex` with properties
/// x y z rho_s rho_c sigma (float) junction critical (uchar 0/1), then element
/// `edge` with vertex1 vertex2 (int, 0-based indices into the vertices).
/// @throw OutputError if an edge index is out of range or the file cannot be
///        written.
void writeSkeletonPly(const std::filesystem::path& file,
                      const std::vector<SkeletonPointRecord>& points,
                      const std::vector<std::array<std::uint32_t, 2>>& edges);

/// Writes cut loops as closed polylines. Loop i (points in order) becomes its
/// vertices, each with vertex property `cut` = i, and its edges: consecutive
/// points plus the closing edge from the last point back to the first, each
/// with edge property `cut` = i. A loop of two points gives one edge, a loop of
/// one point only its vertex, an empty loop nothing (later loops keep their
/// index). Elements: vertex (x y z float, cut int), edge (vertex1 vertex2 int,
/// cut int).
/// @throw OutputError if the file cannot be written.
void writeCutsPly(const std::filesystem::path& file,
                  const std::vector<std::vector<std::array<double, 3>>>& loops);

/// Writes a triangle mesh coloured by segment. `vertices`: V world positions;
/// `triangles`: T triples of 0-based vertex indices; `triangleLabels`: T
/// segment labels in the label-volume convention (1..K; 0 = unlabelled, drawn
/// grey). Elements: vertex (x y z float), face (list uchar int vertex_indices,
/// red green blue uchar = segmentColour(label), segment int = label).
/// @throw OutputError if the sizes disagree, an index is out of range or the
///        file cannot be written.
void writeColouredMeshPly(const std::filesystem::path& file,
                          const std::vector<std::array<double, 3>>& vertices,
                          const std::vector<std::array<std::uint32_t, 3>>& triangles,
                          const std::vector<std::uint32_t>& triangleLabels);

}  // namespace skelseg
