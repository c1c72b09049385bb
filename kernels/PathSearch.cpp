#include "kernels/PathSearch.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace skelseg {

GeodesicSearch::GeodesicSearch(const BoundaryGraph& graph, const Landmarks* landmarks)
    : mGraph(graph),
      mLandmarks(landmarks && landmarks->count ? landmarks : nullptr),
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

float GeodesicSearch::shortestPath(std::uint32_t from, std::uint32_t to, std::vector<std::uint32_t>* path,
                                   float bound) {
    struct BoundScope {  // the bound applies to this call only
        float& slot;
        BoundScope(float& s, float b) : slot(s) { slot = b; }
        ~BoundScope() { slot = kUnreachable; }
    } scope(mBound, bound);
    const BoundaryGraph& g = mGraph;
    auto all = [](std::uint32_t) { return true; };
    if (!mLandmarks) return search(from, to, [&](std::uint32_t n) { return g.euclidean(n, to); }, all, path);
    constexpr std::uint32_t kMax = 16;
    const std::uint32_t k = std::min(mLandmarks->count, kMax);
    float target[kMax];
    const float* dist = mLandmarks->distance.data();
    for (std::uint32_t i = 0; i < k; ++i) target[i] = dist[std::size_t(to) * mLandmarks->count + i];
    auto heuristic = [&](std::uint32_t n) {
        float h = g.euclidean(n, to);
        const float* dn = dist + std::size_t(n) * mLandmarks->count;
        for (std::uint32_t i = 0; i < k; ++i) {
            const float landmarkBound = std::fabs(dn[i] - target[i]);
            // Nodes in another component than a landmark see infinity; the
            // difference is then meaningless (inf - inf) or unbounded.
            if (landmarkBound > h && landmarkBound != kUnreachable && dn[i] != kUnreachable) h = landmarkBound;
        }
        return h;
    };
    return search(from, to, heuristic, all, path);
}

Landmarks computeLandmarks(const BoundaryGraph& graph, bool threaded) {
    Landmarks result;
    const std::uint32_t n = graph.nodeCount();
    if (n == 0) return result;
    static const int directions[14][3] = {{1, 0, 0},  {-1, 0, 0},  {0, 1, 0},  {0, -1, 0},  {0, 0, 1},
                                          {0, 0, -1}, {1, 1, 1},   {1, 1, -1}, {1, -1, 1},  {1, -1, -1},
                                          {-1, 1, 1}, {-1, 1, -1}, {-1, -1, 1}, {-1, -1, -1}};
    for (const auto& d : directions) {
        std::uint32_t best = 0;
        long bestDot = std::numeric_limits<long>::min();
        for (std::uint32_t v = 0; v < n; ++v) {
            const Coord c = graph.coord[v];
            const long dot = long(c.x) * d[0] + long(c.y) * d[1] + long(c.z) * d[2];
            if (dot > bestDot) bestDot = dot, best = v;
        }
        if (std::find(result.node.begin(), result.node.end(), best) == result.node.end()) result.node.push_back(best);
    }
    result.count = std::uint32_t(result.node.size());
    result.distance.assign(std::size_t(n) * result.count, kUnreachable);
    GeodesicSearch plain(graph);
    auto one = [&](std::uint32_t k) {
        const std::vector<float> d = plain.distancesFrom(result.node[k]);
        for (std::uint32_t v = 0; v < n; ++v) result.distance[std::size_t(v) * result.count + k] = d[v];
    };
    if (threaded)
        tbb::parallel_for(std::uint32_t(0), result.count, one);
    else
        for (std::uint32_t k = 0; k < result.count; ++k) one(k);
    return result;
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

void PathCache::clearTable() {
    if (mTable.empty()) mTable.resize(1u << 12);
    for (Slot& slot : mTable) slot.key = 0;
    mUsed = 0;
}

void PathCache::growTable() {
    std::vector<Slot> old(mTable.size() * 2, Slot{0, Entry{}});
    old.swap(mTable);
    const std::size_t mask = mTable.size() - 1;
    for (const Slot& slot : old) {
        if (!slot.key) continue;
        std::size_t i = std::size_t((slot.key * 0x9E3779B97F4A7C15ull) >> 20) & mask;
        while (mTable[i].key) i = (i + 1) & mask;
        mTable[i] = slot;
    }
}

const PathCache::Entry& PathCache::path(GeodesicSearch& search, std::uint32_t a, std::uint32_t b, float bound) {
    if (a > b) std::swap(a, b);
    if (a == b) {  // key 0 marks empty slots; a point pair needs no search anyway
        ++hits;
        mScratch.assign(1, a);
        mPool.push_back(a);
        mSelf = Entry{0.0f, std::uint32_t(mPool.size() - 1), 1, kUnreachable};
        return mSelf;
    }
    const std::uint64_t key = (std::uint64_t(a) << 32) | b;
    if (mTable.empty()) clearTable();
    std::size_t mask = mTable.size() - 1;
    std::size_t i = std::size_t((key * 0x9E3779B97F4A7C15ull) >> 20) & mask;
    while (mTable[i].key) {
        if (mTable[i].key == key) {
            Entry& e = mTable[i].entry;
            if (e.length != kUnreachable || e.bound >= bound) {
                ++hits;
                return e;
            }
            // Known only to be longer than a smaller bound: search further.
            ++misses;
            const float length = search.shortestPath(a, b, &mScratch, bound);
            if (length == kUnreachable) {
                e.bound = bound;
                return e;
            }
            if (mPool.size() + mScratch.size() > mMaxNodes) {
                mPool.clear();
                clearTable();
                return path(search, a, b, bound);
            }
            e = Entry{length, std::uint32_t(mPool.size()), std::uint32_t(mScratch.size()), kUnreachable};
            mPool.insert(mPool.end(), mScratch.begin(), mScratch.end());
            return e;
        }
        i = (i + 1) & mask;
    }
    ++misses;
    const float length = search.shortestPath(a, b, &mScratch, bound);
    if (mPool.size() + mScratch.size() > mMaxNodes) {
        mPool.clear();
        clearTable();
    }
    if (2 * (mUsed + 1) > mTable.size()) growTable();
    mask = mTable.size() - 1;
    i = std::size_t((key * 0x9E3779B97F4A7C15ull) >> 20) & mask;
    while (mTable[i].key) i = (i + 1) & mask;
    mTable[i] = Slot{key, Entry{length, std::uint32_t(mPool.size()), std::uint32_t(mScratch.size()), bound}};
    ++mUsed;
    mPool.insert(mPool.end(), mScratch.begin(), mScratch.end());
    return mTable[i].entry;
}

}  // namespace skelseg
