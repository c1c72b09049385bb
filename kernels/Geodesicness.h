// skelseg: geodesicness sigma of a skeleton point's loop (docs/algorithm.md §7).
//
// The two feature points a, b that realise rho_S(p) split the loop Gamma(p)
// into two arcs. With c, d the arc-length midpoints of the arcs,
//     sigma = |gamma(c, d)| / (loop length from c over a to d),
// which is 1 when the loop is itself a geodesic and drops where it kinks.
//
// How the arcs are found (choices of ours, docs/algorithm.md §7): a simple
// loop (two rim pieces) is split directly: a shortest a-b path in Gamma, and
// the way back that keeps one step away from it. Any other annulus (a
// junction's several loops) is cut at a and b by removing small
// neighbourhoods of them from Gamma', which leaves one piece per arc; sigma
// is then the minimum over pairs of arcs. A loop with no second arc (e.g.
// inside the "web" at a disc's centre) gets sigma = 0.
//
// How lengths are measured (§7.1): along chords over three graph steps, so
// that the one-voxel pips and the 1/sqrt2/sqrt3 staircase of a digital
// surface do not decide the value; d is moved by up to two nodes to split
// the loop evenly, and the two halves and the direct path are all c-d paths
// measured alike. Straight tubes then read 0.92 to 1 from radius 2 voxels
// up, at any angle to the grid.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/GenerationMarks.h"
#include "kernels/PathSearch.h"
#include "kernels/RimCount.h"

namespace skelseg {

struct GeodesicnessResult {
    float sigma = 0.0f;
    std::uint32_t arcCount = 0;
    /// Arc-length midpoints of the two arcs used (kNoNode if none).
    std::uint32_t midpointC = kNoNode, midpointD = kNoNode;
    float loopLength = 0.0f;
};

/// Length of the node path nodes[0..count) measured along chords that join
/// every `stride`-th node (and the last node): see docs/algorithm.md,
/// "Geodesicness on digital surfaces".
float chordLength(const BoundaryGraph& graph, const std::uint32_t* nodes, std::size_t count,
                  std::size_t stride);

/// Per-thread workspace.
class GeodesicnessEvaluator {
public:
    explicit GeodesicnessEvaluator(const BoundaryGraph& graph);
    /// sigma of the loop held by the last rims.countRims(pathSet) call, with
    /// a, b the feature pair that realises rho_S.
    GeodesicnessResult evaluate(const RimCounter& rims, std::uint32_t a, std::uint32_t b,
                                GeodesicSearch& search);

private:
    /// Nodes of Gamma' within `radius` hops of `seed` (inside Gamma').
    void markBlob(const RimCounter& rims, std::uint32_t seed, int radius);

    /// The two arcs of a simple loop: mFirstArc = a shortest a-b path in
    /// Gamma, mSecondArc = a shortest b-a path that keeps one step away from
    /// it except next to a and b. False when there is no such second path
    /// (an open path set).
    bool splitLoop(const RimCounter& rims, std::uint32_t a, std::uint32_t b,
                   GeodesicSearch& search);
    /// The arcs of any annulus: removing growing neighbourhoods of a and b
    /// from Gamma' leaves one piece per arc. Adds up to four arcs to mArcs;
    /// returns the number of pieces found.
    std::uint32_t splitAnnulus(const RimCounter& rims, std::uint32_t a, std::uint32_t b,
                               GeodesicSearch& search);
    /// Appends an arc (its nodes from a to b; `reversed`: path runs from b
    /// to a) to mArcs.
    void addArc(const std::vector<std::uint32_t>& path, bool reversed);

    struct ArcNodes {
        std::size_t begin, count;  // range in mArcPool, from a to b
        std::size_t midpoint;      // position of the chord-length midpoint
    };

    const BoundaryGraph& mGraph;
    GenerationMarks mBlob;
    GenerationMap<std::uint32_t> mHops, mArcOf;
    std::vector<std::uint32_t> mQueue, mPath, mFirstArc, mSecondArc;
    std::vector<ArcNodes> mArcs;
    std::vector<std::uint32_t> mArcPool, mHalf;
};

}  // namespace skelseg
