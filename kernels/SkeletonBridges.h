// skelseg: bridges between the pieces of a broken skeleton (docs/algorithm.md
// §6, "Bridging gaps").
//
// Noise breaks a limb's skeleton near its base, and a thin limb's skeleton
// can miss voxels; the walks of §8.1 must still reach every limb from its
// junction, so pieces of C_tau close to each other are joined by one edge.
#pragma once

#include <vector>

#include "kernels/SkeletonGraph.h"

namespace skelseg {

/// Adds bridge edges to g.edges and counts them in g.bridgeCount: between
/// connected parts of g within `bridgeGap` voxels of each other, or within the
/// radius of the parts around both ends (loopRadius of rho_S) where that is
/// larger, shortest first and one per pair of parts (a spanning forest); then,
/// if `options.inside` is given, parts still apart are joined through the
/// object. g's adjacency must be built and is not updated: returns whether an
/// edge was added, so the caller rebuilds it.
bool bridgeSkeletonParts(SkeletonGraph& g, const std::vector<SkeletonPoint>& points,
                         const SkeletonGraphOptions& options);

}  // namespace skelseg
