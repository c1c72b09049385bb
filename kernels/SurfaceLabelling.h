// skelseg: from cut loops to labelled segments (docs/algorithm.md §9).
//
// The cut loops, dilated by one step on the boundary graph (a 26-connected
// curve does not separate 26-connected regions; its one-step dilation does),
// are removed from the boundary graph; the connected components of the rest
// are the surface segments. Cut nodes take the label of the segment that
// reaches them first in a breadth-first sweep seeded in node order. Segments
// smaller than `minSegmentArea` merge into their largest neighbour; a segment
// is measured as rho_C measures a part, with the whole band of each cut it
// touches (unless it is smaller than that band: a pocket of a wide loop). Closed
// surfaces without any cut that are not the object's outer surface (inner
// cavities) join the largest segment. Segment ids are 0..K-1 by decreasing
// area, ties by smallest node: stable and deterministic.
//
// Interior voxels take the label of their feature voxel F(p), the nearest
// boundary voxel: the simplest rule consistent with the surface labels.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/BoundaryGraph.h"
#include "kernels/base/Volume.h"

namespace skelseg {

struct SurfaceSegments {
    std::vector<std::uint32_t> nodeLabel;  // per boundary node, 0..segmentCount-1
    std::uint32_t segmentCount = 0;
    std::vector<std::uint64_t> area;  // boundary nodes per segment
};

SurfaceSegments labelSurface(const BoundaryGraph& graph,
                             const std::vector<std::vector<std::uint32_t>>& cutLoops,
                             double minSegmentArea);

/// Labels every object voxel of `mask` by the segment of its feature voxel:
/// out[v] = labelOfSegment[nodeLabel(F(v))] (labelOfSegment: one output label
/// per segment, segmentCount entries); background voxels, and object voxels
/// whose feature voxel is not a boundary node, are left alone.
/// threaded: TBB over blocks of voxels (same output).
void labelInterior(const MaskVolume& mask, const Volume<std::uint32_t>& featureTransform,
                   const BoundaryGraph& graph, const SurfaceSegments& segments,
                   const std::vector<std::uint16_t>& labelOfSegment, Volume<std::uint16_t>& out,
                   bool threaded = true);

}  // namespace skelseg
