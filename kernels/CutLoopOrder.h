// skelseg: a cut loop as an ordered polyline.
//
// A cut is the path set Gamma(q) of a critical point q: an unordered set of
// boundary nodes around the shape. cuts.ply and the preview draw it as a
// polyline, so its nodes need an order. orderCutLoop() walks it as two arcs
// between the feature pair (a, b) of q: a shortest arc a -> b inside Gamma,
// then the way back b -> a inside Gamma that avoids the first arc (nodes
// within 2.5 voxels of a or b stay usable so the two arcs can meet at their
// ends). Where no way back exists inside Gamma it searches the dilated set
// Gamma' (RimCount.h), and where that fails too it returns the open arc.
// Every consecutive pair of the result is a boundary-graph edge; the loop is
// closed (last back to first) when the second arc was found.
//
// The searches use the same GeodesicSearch (and so the same landmarks) as the
// path sets: equally short paths are broken the same way, so a run's cuts
// do not depend on which workspace ordered them.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/BoundaryGraph.h"
#include "kernels/PathSearch.h"
#include "kernels/RimCount.h"

namespace skelseg {

/// Orders `gamma` (the path set of a critical point, any order) into a
/// polyline that starts at `a` and passes `b`, using the caller's workspaces.
/// Returns `gamma` itself when b cannot be reached from a inside it.
std::vector<std::uint32_t> orderCutLoop(const BoundaryGraph& graph,
                                        const std::vector<std::uint32_t>& gamma, std::uint32_t a,
                                        std::uint32_t b, GeodesicSearch& search, RimCounter& rims);

/// The same with workspaces of its own; `landmarks` as given to the path sets.
std::vector<std::uint32_t> orderCutLoop(const BoundaryGraph& graph,
                                        const std::vector<std::uint32_t>& gamma, std::uint32_t a,
                                        std::uint32_t b, const Landmarks* landmarks = nullptr);

}  // namespace skelseg
