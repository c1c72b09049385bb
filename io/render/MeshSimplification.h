// skelseg: fewer triangles for display (viewer.html).
//
// A 400^3 run gives about a million surface triangles: 20 MB of positions
// and indices before base64, too much for a page that should open at once.
// The viewer needs the shape and the segment borders, not every voxel step,
// so each segment is simplified on its own by meshoptimizer's edge-collapse
// simplifier (Debian's libmeshoptimizer-dev), which keeps the topology and
// the border of the segment's mesh (so neighbouring segments still meet
// where they did). Each segment gets a share of the budget in proportion to
// its triangles, and at least kMinTrianglesPerSegment, so small segments
// stay visible. A segment with a vertex shared by a large share of its
// triangles (a cone's apex) goes to meshoptimizer's topology-ignoring
// ("sloppy") simplifier instead, whose time does not grow with such a fan.
#pragma once

#include <cstddef>
#include <vector>

#include "io/render/SegmentMeshes.h"

namespace skelseg {

constexpr std::size_t kMinTrianglesPerSegment = 200;

/// Simplifies `meshes` in place to about `maxTriangles` triangles in all
/// (nothing changes if they have no more). The simplifier may stop above its
/// target where the error would exceed 5% of a segment's extent; then the
/// topology-ignoring ("sloppy") simplifier of meshoptimizer finishes the
/// job, so the budget holds. Unused vertices are dropped; triangles keep
/// their orientation. Deterministic.
void simplifyForDisplay(std::vector<SegmentMesh>& meshes, std::size_t maxTriangles);

}  // namespace skelseg
