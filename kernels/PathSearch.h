// skelseg: shortest boundary paths (ALGORITHM.md section 3).
//
// GeodesicSearch is a per-thread workspace for A* searches on the boundary
// graph (the Euclidean distance is an admissible, consistent heuristic since
// every edge weighs its Euclidean length). Visit marks are generation-tagged
// so a search costs what it touches, never the graph size. Ties in the heap
// are broken by node id, so the path found for (a, b) is a function of the
// graph alone: any thread finds the same path.
//
// PathCache keeps the paths already found by one thread. Many voxels ask for
// the same feature pair (ALGORITHM.md section 13: only ~20% are distinct), so
// searching each distinct pair once is the largest single saving. Because a
// pair's path does not depend on who computes it, the cache changes cost,
// never results.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "kernels/BoundaryGraph.h"

namespace skelseg {

constexpr float kUnreachable = std::numeric_limits<float>::infinity();

/// Work counters, summed over threads for report.json.
struct SearchCounters {
    std::uint64_t searches = 0;
    std::uint64_t heapPops = 0;
    std::uint64_t nodesSettled = 0;
    SearchCounters& operator+=(const SearchCounters& o) {
        searches += o.searches, heapPops += o.heapPops, nodesSettled += o.nodesSettled;
        return *this;
    }
};

/// Landmark distances for the ALT lower bound (A*, Landmarks, Triangle
/// inequality): for any landmark L, |d(L,t) - d(L,n)| <= d(n,t). On a surface
/// the Euclidean bound is loose for paths that wrap around an edge (the
/// medial surface of a flat part: top-to-bottom paths around the rim), which
/// is where most search work goes; landmarks at the extremes of the shape
/// tighten exactly those bounds.
struct Landmarks {
    std::uint32_t count = 0;
    std::vector<std::uint32_t> node;
    /// distance[n * count + k]: geodesic distance from landmark k to node n
    /// (infinity in other components). Interleaved per node: one cache line.
    std::vector<float> distance;
};

/// Landmarks at the boundary nodes that are extreme along 14 directions (the
/// axes and the diagonals; ties by lowest id), distances by full Dijkstra,
/// one landmark per task. Deterministic for any thread count.
Landmarks computeLandmarks(const BoundaryGraph& graph, bool threaded = true);

class GeodesicSearch {
public:
    explicit GeodesicSearch(const BoundaryGraph& graph, const Landmarks* landmarks = nullptr);

    /// Length of a shortest path from `from` to `to` (A*), or kUnreachable.
    /// If `path` is given it receives the nodes from `from` to `to` inclusive.
    /// With a finite `bound` the search gives up (kUnreachable) once every
    /// remaining path is known to be longer than `bound`; a path it does find
    /// is the same as without the bound (same settle order, earlier stop).
    float shortestPath(std::uint32_t from, std::uint32_t to, std::vector<std::uint32_t>* path = nullptr,
                       float bound = kUnreachable);

    /// Dijkstra restricted to nodes with allowed(node) true (both ends must be
    /// allowed). Used on small node sets (a path set and its dilation).
    template <typename Allowed>
    float shortestPathWithin(std::uint32_t from, std::uint32_t to, const Allowed& allowed,
                             std::vector<std::uint32_t>* path = nullptr);

    /// Plain single-source Dijkstra over the whole graph (reference for tests).
    std::vector<float> distancesFrom(std::uint32_t source) const;

    const BoundaryGraph& graph() const noexcept { return mGraph; }
    SearchCounters counters;

private:
    struct HeapEntry {
        float priority;
        std::uint32_t node;
    };
    template <typename Heuristic, typename Allowed>
    float search(std::uint32_t from, std::uint32_t to, const Heuristic& heuristic, const Allowed& allowed,
                 std::vector<std::uint32_t>* path);
    void nextGeneration();

    const BoundaryGraph& mGraph;
    const Landmarks* mLandmarks;
    float mBound = kUnreachable;
    std::vector<std::uint32_t> mSeen, mSettled;  // generation stamps
    std::vector<float> mDistance;
    std::vector<std::uint32_t> mParent;
    std::uint32_t mGeneration = 0;
    std::vector<HeapEntry> mHeap;
};

/// Per-thread cache of pair paths, bounded in memory.
class PathCache {
public:
    struct Entry {
        float length;
        std::uint32_t begin, count;  // range in the node pool
        float bound = kUnreachable;  // for length == kUnreachable: the bound searched up to
    };
    /// maxNodes: the pool is cleared when it would hold more path nodes.
    explicit PathCache(std::size_t maxNodes = std::size_t(1) << 22) : mMaxNodes(maxNodes) {}

    /// Shortest path between a and b (searched from min(a,b) so that the
    /// result does not depend on the order of the arguments). The returned
    /// entry's nodes are valid until the next call.
    /// `bound`: see GeodesicSearch::shortestPath. A pair cached as "longer than
    /// B" is searched again when asked with a larger bound, so the answer never
    /// depends on which request came first.
    const Entry& path(GeodesicSearch& search, std::uint32_t a, std::uint32_t b, float bound = kUnreachable);
    const std::uint32_t* nodes(const Entry& e) const noexcept { return mPool.data() + e.begin; }

    std::uint64_t hits = 0, misses = 0;

private:
    /// Open addressing with linear probing: the std::unordered_map it
    /// replaced cost a cache miss per node walk and an allocation per entry.
    struct Slot {
        std::uint64_t key;  // 0 = empty (a pair key always has b > a >= 0, so key > 0)
        Entry entry;
    };
    void clearTable();
    void growTable();

    std::size_t mMaxNodes;
    std::vector<Slot> mTable;
    std::size_t mUsed = 0;
    Entry mSelf{};
    std::vector<std::uint32_t> mPool;
    std::vector<std::uint32_t> mScratch;
};

// ---------------------------------------------------------------------------
// Implementation of the template members.

template <typename Heuristic, typename Allowed>
float GeodesicSearch::search(std::uint32_t from, std::uint32_t to, const Heuristic& heuristic,
                             const Allowed& allowed, std::vector<std::uint32_t>* path) {
    ++counters.searches;
    if (path) path->clear();
    if (from == to) {
        if (path) path->push_back(from);
        return 0.0f;
    }
    nextGeneration();
    const std::uint32_t gen = mGeneration;
    auto later = [](const HeapEntry& a, const HeapEntry& b) {
        return a.priority > b.priority || (a.priority == b.priority && a.node > b.node);
    };
    mHeap.clear();
    mSeen[from] = gen;
    mDistance[from] = 0.0f;
    mParent[from] = kNoNode;
    mHeap.push_back({heuristic(from), from});
    float result = kUnreachable;
    while (!mHeap.empty()) {
        std::pop_heap(mHeap.begin(), mHeap.end(), later);
        const HeapEntry top = mHeap.back();
        mHeap.pop_back();
        ++counters.heapPops;
        const std::uint32_t n = top.node;
        if (top.priority > mBound) break;  // admissible heuristic: nothing within the bound is left
        if (mSettled[n] == gen) continue;
        mSettled[n] = gen;
        ++counters.nodesSettled;
        if (n == to) {
            result = mDistance[n];
            break;
        }
        const float dn = mDistance[n];
        for (std::uint32_t e = mGraph.offset[n], end = mGraph.offset[n + 1]; e < end; ++e) {
            const std::uint32_t m = mGraph.neighbour[e];
            if (mSettled[m] == gen || !allowed(m)) continue;
            const float dm = dn + mGraph.weight[e];
            if (mSeen[m] != gen || dm < mDistance[m]) {
                mSeen[m] = gen;
                mDistance[m] = dm;
                mParent[m] = n;
                mHeap.push_back({dm + heuristic(m), m});
                std::push_heap(mHeap.begin(), mHeap.end(), later);
            }
        }
    }
    if (path && result != kUnreachable) {
        for (std::uint32_t n = to; n != kNoNode; n = mParent[n]) path->push_back(n);
        std::reverse(path->begin(), path->end());
    }
    return result;
}

template <typename Allowed>
float GeodesicSearch::shortestPathWithin(std::uint32_t from, std::uint32_t to, const Allowed& allowed,
                                         std::vector<std::uint32_t>* path) {
    if (!allowed(from) || !allowed(to)) {
        if (path) path->clear();
        return kUnreachable;
    }
    const BoundaryGraph& g = mGraph;
    return search(
        from, to, [&](std::uint32_t n) { return g.euclidean(n, to); }, allowed, path);
}

}  // namespace skelseg
