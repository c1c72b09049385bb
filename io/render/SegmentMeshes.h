// skelseg: one triangle mesh per segment, cut out of a labelled surface.
//
// segments.glb and viewer.html hand each segment to the viewer as a mesh of
// its own (a glTF mesh with its own material; a group the web viewer can
// colour and pick). The labelled surfaces of a run come in two shapes: the
// input mesh with one label per face (vertices shared across segment
// borders) or the per-label surfaces of a label volume (a soup whose labels
// never share a vertex). Splitting gives both the same form: a vertex used by
// several segments is copied into each, unused vertices are dropped, and the
// triangles keep their order and orientation.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace skelseg {

/// The triangles of one segment, with their own compact vertex list.
struct SegmentMesh {
    /// Segment label (label-volume convention: 1..K, 0 = unlabelled).
    std::uint32_t label = 0;
    /// V positions (world), float as every mesh format stores them.
    std::vector<std::array<float, 3>> positions;
    /// T triples of 0-based indices into `positions`.
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

/// Splits a labelled surface by label. `vertices`: V world positions;
/// `triangles`: T index triples; `triangleLabels`: T labels. Returns one
/// SegmentMesh per label present, in increasing label order; each keeps the
/// input order of its triangles, and its vertices are numbered in order of
/// first use.
/// @throw UsageError if the sizes disagree or an index is out of range.
std::vector<SegmentMesh> splitSegmentMeshes(
    const std::vector<std::array<double, 3>>& vertices,
    const std::vector<std::array<std::uint32_t, 3>>& triangles,
    const std::vector<std::uint32_t>& triangleLabels);

/// Total triangle count of `meshes`.
std::size_t triangleCount(const std::vector<SegmentMesh>& meshes) noexcept;

}  // namespace skelseg
