// skelseg: bridges between the pieces of a broken skeleton (docs/algorithm.md
// §6, "Bridging gaps").
//
// Noise breaks a limb's skeleton near its base, and a thin limb's skeleton
// can miss voxels; the walks of §8.1 must still reach every limb from its
// junction, so pieces of C_tau close to each other are joined by one edge.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "kernels/SkeletonGraph.h"
#include "kernels/base/Interrupter.h"

namespace skelseg {

/// Adds bridge edges to g.edges and counts them in g.bridgeCount: between
/// connected parts of g within `bridgeGap` voxels of each other, or within the
/// radius of the parts around both ends (loopRadius of rho_S) where that is
/// larger, shortest first and one per pair of parts (a spanning forest); then,
/// if `options.inside` is given, parts still apart are joined through the
/// object by straight segments, and those still apart after that along the
/// object (joinGroupsAlongObject). g's adjacency must be built and is not
/// updated: returns whether an edge was added, so the caller rebuilds it.
/// @throw InterruptedError when asked to stop (polled by the flood of
/// joinGroupsAlongObject).
bool bridgeSkeletonParts(SkeletonGraph& g, const std::vector<SkeletonPoint>& points,
                         const SkeletonGraphOptions& options,
                         Interrupter& interrupter = nullInterrupter());

/// The join through the object of bridgeSkeletonParts: nodes at `coord`,
/// each in one of `groups` groups (`group`, ids below `groups`). For every
/// node and every other group, the group's node nearest to it (ties to the
/// lower index) is a candidate pair; candidates are taken shortest first
/// (then by the lower group's node, then the other), and one is a bridge
/// when its groups are still apart and the straight segment between its
/// nodes, sampled every half voxel, stays in `inside`. Returns the bridges
/// (i < j) in the order taken.
std::vector<std::array<std::uint32_t, 2>> joinGroupsThroughObject(
    const std::vector<Coord>& coord, const std::vector<std::uint32_t>& group, std::uint32_t groups,
    const MaskVolume& inside);

/// The last join of bridgeSkeletonParts, for groups that no straight segment
/// inside the object joins (a folded limb's skeleton, broken at the bend,
/// sees its body only across the gap the voxeliser kept): a breadth-first
/// flood through the 6-connected voxels of `inside` from every node at once,
/// in node order, gives each voxel it reaches the node it came from; where
/// voxels of two groups' floods touch, the pair of nodes is a candidate of
/// length (steps from one node) + (steps from the other) + 1. Candidates are
/// taken shortest first (then by the lower group's node, then the other),
/// one per pair of groups still apart (a spanning forest). Nodes outside
/// `inside` seed nothing. Returns the bridges (i < j) in the order taken.
/// @throw InterruptedError when asked to stop (polled every 65,536 voxels).
std::vector<std::array<std::uint32_t, 2>> joinGroupsAlongObject(
    const std::vector<Coord>& coord, const std::vector<std::uint32_t>& group, std::uint32_t groups,
    const MaskVolume& inside, Interrupter& interrupter = nullInterrupter());

}  // namespace skelseg
