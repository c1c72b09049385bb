#include "kernels/PathSearch.h"

#include <algorithm>
#include <queue>

namespace skelseg {

GeodesicSearch::GeodesicSearch(const BoundaryGraph& graph)
    : mGraph(graph),
      mSeen(graph.nodeCount(), 0),
      mSettled(graph.nodeCount(), 0),
      mDistance(graph.nodeCount(), 0.0f),
      mParent(graph.nodeCount(), kNoNode) {}

void GeodesicSearch::nextGeneration() {
    if (++mGeneration == 0) {
        std::fill(mSeen.begin(), mSeen.end(), 0u);
        std::fill(mSettled.begin(), mSettled.end(), 0u);
        mGeneration = 1;
    }
}

float GeodesicSearch::shortestPath(std::uint32_t from, std::uint32_t to, std::vector<std::uint32_t>* path) {
    const BoundaryGraph& g = mGraph;
    return search(
        from, to, [&](std::uint32_t n) { return g.euclidean(n, to); }, [](std::uint32_t) { return true; },
        path);
}

std::vector<float> GeodesicSearch::distancesFrom(std::uint32_t source) const {
    std::vector<float> dist(mGraph.nodeCount(), kUnreachable);
    using Item = std::pair<float, std::uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    dist[source] = 0.0f;
    heap.push({0.0f, source});
    while (!heap.empty()) {
        const auto [d, n] = heap.top();
        heap.pop();
        if (d > dist[n]) continue;
        for (std::uint32_t e = mGraph.offset[n]; e < mGraph.offset[n + 1]; ++e) {
            const std::uint32_t m = mGraph.neighbour[e];
            const float dm = d + mGraph.weight[e];
            if (dm < dist[m]) {
                dist[m] = dm;
                heap.push({dm, m});
            }
        }
    }
    return dist;
}

const PathCache::Entry& PathCache::path(GeodesicSearch& search, std::uint32_t a, std::uint32_t b) {
    if (a > b) std::swap(a, b);
    const std::uint64_t key = (std::uint64_t(a) << 32) | b;
    auto it = mEntries.find(key);
    if (it != mEntries.end()) {
        ++hits;
        return it->second;
    }
    ++misses;
    const float length = search.shortestPath(a, b, &mScratch);
    if (mPool.size() + mScratch.size() > mMaxNodes) {
        mPool.clear();
        mEntries.clear();
    }
    Entry entry{length, std::uint32_t(mPool.size()), std::uint32_t(mScratch.size())};
    mPool.insert(mPool.end(), mScratch.begin(), mScratch.end());
    return mEntries.emplace(key, entry).first->second;
}

}  // namespace skelseg
