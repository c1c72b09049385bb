// skelseg: the Jordan-curve test (docs/algorithm.md §4).
//
// Given a path set Gamma(p) (boundary nodes), dilate it by one step on the
// boundary graph (Gamma') and split the rim (nodes adjacent to Gamma' but not
// in it) into 26-connected pieces. An open path gives one rim piece, a closed
// loop two, a junction of n branches n. One dilation step and 26-adjacency
// are the choices measured as right (docs/algorithm.md §4: without the
// dilation rims leak through diagonal steps; 6-adjacency breaks every rim).
// Cost is proportional to |Gamma(p)|, not to the surface.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/BoundaryGraph.h"
#include "kernels/GenerationMarks.h"

namespace skelseg {

struct RimPieces {
    /// Gamma'(p): the path set dilated by one step.
    std::vector<std::uint32_t> dilated;
    /// Rim nodes and the piece (0..pieceCount-1) each belongs to.
    std::vector<std::uint32_t> rimNodes;
    std::vector<std::uint32_t> pieceOfRimNode;
    std::uint32_t pieceCount = 0;
};

/// Per-thread workspace for the rim test.
class RimCounter {
public:
    explicit RimCounter(const BoundaryGraph& graph);
    /// Computes Gamma' and the rim pieces of `pathSet` (duplicates allowed).
    const RimPieces& countRims(const std::vector<std::uint32_t>& pathSet);
    /// True if node is in Gamma' of the last countRims() call.
    bool isInDilated(std::uint32_t node) const noexcept { return flags(node) & kDilated; }
    /// True if node is in Gamma of the last countRims() call.
    bool isInPathSet(std::uint32_t node) const noexcept { return flags(node) & kPathSet; }
    const RimPieces& result() const noexcept { return mResult; }
    const BoundaryGraph& graph() const noexcept { return mGraph; }

private:
    // One generation-stamped word per node holds all four memberships
    // (stamp << 4 | flags): one memory access per neighbour instead of four.
    // kPieced marks a rim node whose entry in mPiece is valid.
    enum : std::uint32_t { kPathSet = 1, kDilated = 2, kRim = 4, kPieced = 8 };
    static constexpr std::uint32_t kFlagBits = 4;
    std::uint32_t flags(std::uint32_t node) const noexcept {
        const std::uint32_t s = mState[node];
        return (s >> kFlagBits) == mGeneration ? (s & 15u) : 0u;
    }
    /// Sets flag f; returns true if it was not set before.
    bool setFlag(std::uint32_t node, std::uint32_t f) noexcept {
        std::uint32_t s = mState[node];
        if ((s >> kFlagBits) != mGeneration) s = mGeneration << kFlagBits;
        if (s & f) return false;
        mState[node] = s | f;
        return true;
    }

    const BoundaryGraph& mGraph;
    std::vector<std::uint32_t> mState;
    std::uint32_t mGeneration = 0;
    std::vector<std::uint32_t> mPiece;  // valid where kPieced is set
    RimPieces mResult;
    std::vector<std::uint32_t> mQueue;
};

/// Number of rim pieces of `pathSet` (convenience wrapper).
std::uint32_t rimCount(const BoundaryGraph& graph, const std::vector<std::uint32_t>& pathSet);

}  // namespace skelseg
