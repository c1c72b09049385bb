// skelseg: making a finer surface segmentation nest in a coarser one
// (levels of a hierarchy run, docs/algorithm.md "Levels").
//
// The finer level is labelled with a superset of the coarser level's cut
// loops, so its segments nearly always refine the coarser ones; they may not
// where labelSurface's small-segment merge or its sweep over cut nodes went
// another way at the other tau. The repair, on the boundary graph:
//  1. Each fine segment's parent is the coarse segment it overlaps most
//     (boundary nodes; ties to the smaller coarse id).
//  2. Nodes whose coarse segment is not their fine segment's parent lose
//     their fine label; a breadth-first sweep seeded in node order from the
//     consistent nodes gives each of them the fine label that reaches it first
//     through nodes of the same coarse segment.
//  3. Nodes no consistent node reaches (a coarse segment without a child)
//     become new fine segments, one per connected piece.
//  4. Ids are renumbered by decreasing area, ties by smallest node, as
//     labelSurface numbers them.
// Afterwards every fine segment lies inside exactly one coarse segment, node
// by node; interior voxels follow their feature voxel's node at every level,
// so the label volumes nest voxel by voxel as well.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/BoundaryGraph.h"
#include "kernels/SurfaceLabelling.h"

namespace skelseg {

struct NestedSegments {
    SurfaceSegments segments;           // the repaired finer level
    std::vector<std::uint32_t> parent;  // per segment: its coarse segment
    std::uint64_t movedNodes = 0;       // nodes whose fine segment changed (step 2 and 3)
};

/// The repaired `fine` segmentation of `graph` and each segment's parent in
/// `coarse` (both from labelSurface on the same graph).
/// @throw UsageError if the node labels do not cover the graph.
NestedSegments nestSegments(const BoundaryGraph& graph, const SurfaceSegments& coarse,
                            const SurfaceSegments& fine);

}  // namespace skelseg
