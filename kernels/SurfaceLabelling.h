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

/// One surface piece before the small-segment merge, as the merge measured it.
struct SegmentMeasure {
    std::uint64_t core = 0;      // nodes outside every cut's band
    std::uint64_t area = 0;      // ... with the band nodes the sweep gave it
    std::uint64_t measured = 0;  // area plus the rest of each band it touches (§9.2)
    bool merged = false;         // merged into a neighbour as too small
};

struct SurfaceSegments {
    std::vector<std::uint32_t> nodeLabel;  // per boundary node, 0..segmentCount-1
    std::uint32_t segmentCount = 0;
    std::vector<std::uint64_t> area;  // boundary nodes per segment
    /// Per cut loop: separatingLoops, before the small-segment merge
    /// (docs/algorithm.md §8.10).
    std::vector<std::uint8_t> loopSeparates;
    /// Every piece the cuts leave, before the merge, in node order of its
    /// first node (cavities that joined the largest piece included).
    std::vector<SegmentMeasure> before;
};

/// Per cut loop: 1 when, with every loop's dilated band removed from the
/// surface, the nodes next to its band lie in two or more pieces of at least
/// `noiseArea` nodes (a smaller piece is a pocket between the paths of a wide
/// loop, docs/algorithm.md §5.3); 0 when the loop separates nothing (a loop
/// round a handle with no other cut on it). The same test as
/// SurfaceSegments::loopSeparates, without the labelling.
std::vector<std::uint8_t> separatingLoops(const BoundaryGraph& graph,
                                          const std::vector<std::vector<std::uint32_t>>& cutLoops,
                                          double noiseArea);

/// noiseArea: only for SurfaceSegments::loopSeparates (separatingLoops).
SurfaceSegments labelSurface(const BoundaryGraph& graph,
                             const std::vector<std::vector<std::uint32_t>>& cutLoops,
                             double minSegmentArea, double noiseArea = 0.0);

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
