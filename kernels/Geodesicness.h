// skelseg: geodesicness sigma of a skeleton point's loop (docs/algorithm.md §7).
//
// The two feature points a, b that realise rho_S(p) split the loop Gamma(p)
// into two arcs. With c, d the arc-length midpoints of the arcs,
//     sigma = |gamma(c, d)| / (loop length from c over a to d),
// which is 1 when the loop is itself a geodesic and drops where it kinks.
//
// How the arcs are found (a choice of ours, see docs/algorithm.md): the
// dilated path set Gamma' is an annulus; removing small neighbourhoods of a
// and b from it leaves one piece per arc. Each arc's length is the shortest
// path from a to b through Gamma restricted to that piece (plus the two
// neighbourhoods). A loop with no second arc (e.g. inside the "web" at a
// disc's centre) gets sigma = 0, as docs/algorithm.md §7 explains. For a
// junction, whose annulus splits into more than two arcs, sigma is the
// minimum over pairs of arcs.
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

    const BoundaryGraph& mGraph;
    GenerationMarks mBlob;
    GenerationMap<std::uint32_t> mHops, mArcOf;
    std::vector<std::uint32_t> mQueue, mPath;
};

}  // namespace skelseg
