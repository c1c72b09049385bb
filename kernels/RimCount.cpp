#include "kernels/RimCount.h"

#include <algorithm>

namespace skelseg {

RimCounter::RimCounter(const BoundaryGraph& graph)
    : mGraph(graph), mState(graph.nodeCount(), 0), mPiece(graph.nodeCount(), 0) {}

const RimPieces& RimCounter::countRims(const std::vector<std::uint32_t>& pathSet) {
    if (++mGeneration >=
        (1u << (32 - kFlagBits))) {  // stamps are 28 bits: really clear once in a while
        std::fill(mState.begin(), mState.end(), 0u);
        mGeneration = 1;
    }
    RimPieces& r = mResult;
    r.dilated.clear();
    r.rimNodes.clear();
    r.pieceOfRimNode.clear();
    r.pieceCount = 0;
    const auto& offset = mGraph.offset;
    const auto& neighbour = mGraph.neighbour;

    for (std::uint32_t n : pathSet)
        if (setFlag(n, kPathSet) && setFlag(n, kDilated)) r.dilated.push_back(n);
    const std::size_t coreCount = r.dilated.size();
    for (std::size_t i = 0; i < coreCount; ++i) {
        const std::uint32_t n = r.dilated[i];
        for (std::uint32_t e = offset[n]; e < offset[n + 1]; ++e)
            if (setFlag(neighbour[e], kDilated)) r.dilated.push_back(neighbour[e]);
    }
    // Rim: neighbours of Gamma' outside it. Only the dilation layer can have
    // such neighbours (every neighbour of a Gamma node is in Gamma').
    for (std::size_t i = coreCount; i < r.dilated.size(); ++i) {
        const std::uint32_t n = r.dilated[i];
        for (std::uint32_t e = offset[n]; e < offset[n + 1]; ++e) {
            const std::uint32_t m = neighbour[e];
            if (!(flags(m) & kDilated) && setFlag(m, kRim)) r.rimNodes.push_back(m);
        }
    }
    // Pieces: BFS over rim nodes along graph edges (26-adjacency).
    for (std::uint32_t seed : r.rimNodes) {
        if (!setFlag(seed, kPieced)) continue;
        const std::uint32_t piece = r.pieceCount++;
        mQueue.clear();
        mQueue.push_back(seed);
        mPiece[seed] = piece;
        for (std::size_t head = 0; head < mQueue.size(); ++head) {
            const std::uint32_t n = mQueue[head];
            for (std::uint32_t e = offset[n]; e < offset[n + 1]; ++e) {
                const std::uint32_t m = neighbour[e];
                if ((flags(m) & (kRim | kPieced)) == kRim) {
                    setFlag(m, kPieced);
                    mPiece[m] = piece;
                    mQueue.push_back(m);
                }
            }
        }
    }
    r.pieceOfRimNode.resize(r.rimNodes.size());
    for (std::size_t i = 0; i < r.rimNodes.size(); ++i) r.pieceOfRimNode[i] = mPiece[r.rimNodes[i]];
    return r;
}

std::uint32_t rimCount(const BoundaryGraph& graph, const std::vector<std::uint32_t>& pathSet) {
    RimCounter counter(graph);
    return counter.countRims(pathSet).pieceCount;
}

}  // namespace skelseg
