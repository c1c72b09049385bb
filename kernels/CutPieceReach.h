// skelseg: how far the piece a cut loop cuts off reaches, against the loop's
// own size (docs/algorithm.md §8.6, "Corners of flat ends are not limbs").
//
// The corner rule needs a length of the piece past a cut that does not come
// in whole skeleton levels. The piece's surface is flooded on the boundary
// graph up to the loop, and its farthest node from the loop's centre is
// compared with the loop's own farthest node from that centre: a corner of a
// flat end or of a block is a cap that stays within the ball its loop spans
// (the ratio is at most about 1), while a limb, a fin or a head sticks out of
// it. Both distances are measured on the same voxels, so the ratio is free
// of scale and of the loop's shape (a fin's flat loop spans its width).
//
// The piece is every component of the surface without the loop's one-step
// dilation (the set that separates the surface, as in the labelling,
// SurfaceLabelling.h) that touches the dilation and lies on average past the
// loop's plane, on the side away from the junction the cut was found from.
// The plane goes through the loop's mean; its normal is the ordered loop's
// vector area (Newell), well defined for a fin's long thin loop too. The
// flood stays within the ball of `limitRatio` times the loop's size: a
// component past the plane (on average over its nodes in the ball, so the
// answer does not depend on the flood's order) that goes on out of the ball
// is a piece reaching at least that far; one behind the plane is the body.
// The cost is the surface within that ball. The corner rule asks it for
// many cuts of one object, serially, so the class keeps the per-node marks of
// the flood between calls (cleared in O(1)); the free function makes them
// for one call.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "kernels/BoundaryGraph.h"
#include "kernels/GenerationMarks.h"

namespace skelseg {

/// The largest distance of the surface piece cut off by the path set `gamma`
/// from the centre of its ordered loop `loop` (boundary nodes in order round
/// the loop), over the largest distance of a node of `gamma` from that
/// centre; the piece lies on the side of the loop's plane away from
/// `junction` (voxel coordinates). Returns `limitRatio` when a component past
/// the plane reaches that far or when the loop has no plane (fewer than three
/// nodes, no area); 0 when no component lies past the plane.
double pieceReachPastLoop(const BoundaryGraph& graph, const std::vector<std::uint32_t>& gamma,
                          const std::vector<std::uint32_t>& loop,
                          const std::array<double, 3>& junction, double limitRatio);

/// pieceReachPastLoop with its marks kept between calls: for many loops on
/// one graph. Not thread-safe; one per thread.
class PieceReachMeasurer {
public:
    explicit PieceReachMeasurer(const BoundaryGraph& graph);
    /// The same as pieceReachPastLoop(graph, ...) for the graph given above.
    double measure(const std::vector<std::uint32_t>& gamma, const std::vector<std::uint32_t>& loop,
                   const std::array<double, 3>& junction, double limitRatio);

private:
    const BoundaryGraph& mGraph;
    GenerationMarks mBlocked, mSeen;
    std::vector<std::uint32_t> mBlockedNodes, mSeeds, mFront;
};

}  // namespace skelseg
