// skelseg: component areas behind the rims (docs/algorithm.md §5).
//
// Removing Gamma'(p) splits the surface into components; rho_C(p) is all the
// surface area except the largest component. Instead of a flood fill of the
// whole surface per point, all components grow at once from their rim pieces,
// one node per component per round. When all but one are exhausted the
// areas are exact (the last one is the rest of the surface); the cost then
// follows rho_C(p), not the surface size. With a finite `cap` the growth also
// stops once every component still growing has reached `cap` nodes: then
// each of those is known to be >= cap, which decides every comparison with
// tau, and rho_C is reported as a lower bound (exact = false).
//
// Rim pieces whose growth fronts meet belong to one component (union-find):
// on a surface with a handle, the two rims of a loop around the handle bound
// the same component.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "kernels/BoundaryGraph.h"
#include "kernels/GenerationMarks.h"
#include "kernels/RimCount.h"

namespace skelseg {

struct ComponentAreas {
    /// Component (0..componentCount-1) bounded by each rim piece.
    std::vector<std::uint32_t> componentOfPiece;
    /// Node count of each component: exact where componentExact, else a lower bound.
    std::vector<std::uint64_t> area;
    std::vector<std::uint8_t> exact;
    std::uint32_t componentCount = 0;
    /// Area of the connected surface that holds Gamma(p).
    std::uint64_t surfaceArea = 0;
    /// rho_C = surfaceArea - largest component (lower bound unless rhoCExact).
    std::uint64_t rhoC = 0;
    bool rhoCExact = true;
    /// Nodes taken by the growth (work counter).
    std::uint64_t growthSteps = 0;
};

/// Per-thread workspace.
class ComponentGrower {
public:
    explicit ComponentGrower(const BoundaryGraph& graph);
    /// Grows the components behind the rims of the last rims.countRims() call.
    /// cap: stop rule described above (use kExactArea for exact areas).
    const ComponentAreas& grow(const RimCounter& rims, std::uint64_t cap);

    static constexpr std::uint64_t kExactArea = std::numeric_limits<std::uint64_t>::max();

private:
    std::uint32_t findRoot(std::uint32_t piece);
    /// mOwner's value for the nodes of Gamma': no front may take them.
    static constexpr std::uint32_t kBlocked = kNoNode - 1;

    const BoundaryGraph& mGraph;
    GenerationMap<std::uint32_t> mOwner;  // node -> piece that took it, or kBlocked
    std::vector<std::uint32_t> mParent;   // union-find over pieces
    std::vector<std::vector<std::uint32_t>> mQueue;
    std::vector<std::size_t> mHead;
    std::vector<std::uint64_t> mSize;
    std::vector<std::uint32_t> mActive;
    ComponentAreas mResult;
};

}  // namespace skelseg
