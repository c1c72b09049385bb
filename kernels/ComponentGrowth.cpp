#include "kernels/ComponentGrowth.h"

#include <algorithm>

namespace skelseg {

ComponentGrower::ComponentGrower(const BoundaryGraph& graph)
    : mGraph(graph), mOwner(graph.nodeCount(), kNoNode) {}

std::uint32_t ComponentGrower::findRoot(std::uint32_t piece) {
    while (mParent[piece] != piece) piece = mParent[piece] = mParent[mParent[piece]];
    return piece;
}

const ComponentAreas& ComponentGrower::grow(const RimCounter& rims, std::uint64_t cap) {
    const RimPieces& pieces = rims.result();
    const std::uint32_t k = pieces.pieceCount;
    ComponentAreas& out = mResult;
    out.componentOfPiece.assign(k, 0);
    out.area.clear();
    out.exact.clear();
    out.componentCount = 0;
    out.growthSteps = 0;
    out.rhoC = 0;
    out.rhoCExact = true;
    out.surfaceArea =
        pieces.dilated.empty() ? 0 : mGraph.componentSize[mGraph.component[pieces.dilated.front()]];
    if (k == 0) return out;

    mOwner.clear();
    // Gamma' is marked in the owner map itself, so the growth reads one slot
    // per neighbour to learn whether it is blocked, free or whose it is,
    // instead of the rim marks and then the owner (two cache lines).
    for (std::uint32_t node : pieces.dilated) mOwner.set(node, kBlocked);
    mParent.resize(k);
    mHead.assign(k, 0);
    mSize.assign(k, 0);
    if (mQueue.size() < k) mQueue.resize(k);
    for (std::uint32_t i = 0; i < k; ++i) {
        mParent[i] = i;
        mQueue[i].clear();
    }
    for (std::size_t i = 0; i < pieces.rimNodes.size(); ++i) {
        const std::uint32_t piece = pieces.pieceOfRimNode[i];
        mOwner.set(pieces.rimNodes[i], piece);
        mQueue[piece].push_back(pieces.rimNodes[i]);
        ++mSize[piece];
    }
    mActive.clear();
    for (std::uint32_t i = 0; i < k; ++i) mActive.push_back(i);

    const auto& offset = mGraph.offset;
    const auto& neighbour = mGraph.neighbour;
    auto allAtCap = [&]() {
        for (std::uint32_t r : mActive)
            if (mSize[r] < cap) return false;
        return true;
    };
    // Round-robin: every active root expands one node per round, so when all
    // but one are exhausted the survivor is at least as large as any other.
    while (mActive.size() > 1 && !allAtCap()) {
        for (std::size_t a = 0; a < mActive.size(); ++a) {
            std::uint32_t root = mActive[a];
            if (mParent[root] != root) continue;  // merged away this round
            auto& queue = mQueue[root];
            if (mHead[root] == queue.size()) continue;
            // The queue says which nodes this front expands next: request
            // their offsets, edges and the neighbours' marks, each stage a few
            // rounds before it is read, since a round expands only one node
            // per front (hints only: the growth is the same).
            const std::size_t head = mHead[root];
            if (head + 8 < queue.size()) __builtin_prefetch(&offset[queue[head + 8]]);
            if (head + 5 < queue.size())
                __builtin_prefetch(neighbour.data() + offset[queue[head + 5]]);
            if (head + 2 < queue.size()) {
                const std::uint32_t next = queue[head + 2];
                for (std::uint32_t e = offset[next]; e < offset[next + 1]; ++e)
                    mOwner.prefetch(neighbour[e]);
            }
            const std::uint32_t n = queue[mHead[root]++];
            for (std::uint32_t e = offset[n]; e < offset[n + 1]; ++e) {
                const std::uint32_t m = neighbour[e];
                const std::uint32_t owner = mOwner.get(m);
                if (owner == kBlocked) continue;
                if (owner == kNoNode) {
                    mOwner.set(m, root);
                    mQueue[root].push_back(m);
                    ++mSize[root];
                    ++out.growthSteps;
                    continue;
                }
                const std::uint32_t other = findRoot(owner);
                if (other == root) continue;
                // Fronts met: one component. Keep the lower id as root so the
                // result does not depend on which front arrived first.
                const std::uint32_t keep = std::min(root, other), drop = std::max(root, other);
                mParent[drop] = keep;
                mSize[keep] += mSize[drop];
                auto& dq = mQueue[drop];
                mQueue[keep].insert(mQueue[keep].end(), dq.begin() + std::ptrdiff_t(mHead[drop]),
                                    dq.end());
                dq.clear();
                mHead[drop] = 0;
                root = keep;
            }
        }
        // Drop merged and exhausted roots.
        mActive.clear();
        for (std::uint32_t r = 0; r < k; ++r)
            if (mParent[r] == r && mHead[r] < mQueue[r].size()) mActive.push_back(r);
    }

    // Number components by first piece, collect areas.
    std::vector<std::uint32_t> roots(k);
    for (std::uint32_t i = 0; i < k; ++i) roots[i] = findRoot(i);
    std::vector<std::uint32_t> index(k, kNoNode);
    std::uint64_t exhaustedSum = 0;
    for (std::uint32_t i = 0; i < k; ++i) {
        const std::uint32_t r = roots[i];
        if (index[r] == kNoNode) {
            index[r] = out.componentCount++;
            out.area.push_back(mSize[r]);
            const bool active = std::find(mActive.begin(), mActive.end(), r) != mActive.end();
            out.exact.push_back(active ? 0 : 1);
            if (!active) exhaustedSum += mSize[r];
        }
        out.componentOfPiece[i] = index[r];
    }
    const std::uint64_t blocked = pieces.dilated.size();
    const std::uint64_t rest =
        out.surfaceArea > blocked + exhaustedSum ? out.surfaceArea - blocked - exhaustedSum : 0;
    if (mActive.size() == 1) {
        // The survivor is everything not yet accounted for.
        for (std::uint32_t c = 0; c < out.componentCount; ++c)
            if (!out.exact[c]) out.area[c] = rest, out.exact[c] = 1;
    }
    std::uint64_t largest = 0;
    std::uint32_t largestIndex = 0;
    for (std::uint32_t c = 0; c < out.componentCount; ++c)
        if (out.area[c] > largest) largest = out.area[c], largestIndex = c;
    if (mActive.size() <= 1) {
        out.rhoC = out.surfaceArea - largest;
    } else {
        // Lower bound: everything but the largest growing component counted
        // at its current size, which is at least cap.
        out.rhoCExact = false;
        std::uint64_t sum = blocked;
        for (std::uint32_t c = 0; c < out.componentCount; ++c)
            if (c != largestIndex) sum += out.area[c];
        out.rhoC = sum;
    }
    return out;
}

}  // namespace skelseg
