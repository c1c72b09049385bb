// skelseg: shortest boundary paths (docs/algorithm.md §3).
//
// GeodesicSearch is a per-thread workspace for A* searches on the boundary
// graph (the Euclidean distance is an admissible, consistent heuristic since
// every edge weighs its Euclidean length). Visit marks are generation-tagged
// so a search costs what it touches, never the graph size. Ties in the heap
// are broken by node id, so the path found for (a, b) is a function of the
// graph alone: any thread finds the same path.
//
// PathCache keeps the paths already found by one thread. Many voxels ask for
// the same feature pair (docs/algorithm.md §3.3: only ~20% are distinct), so
// searching each distinct pair once is the largest single saving. Because a
// pair's path does not depend on who computes it, the cache changes cost,
// never results.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "kernels/BoundaryGraph.h"
#include "kernels/base/UninitialisedStorage.h"

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
    /// Row width: at most this many landmarks (14 extremes, the rest by
    /// farthest-point selection). 48 floats are three cache lines per node;
    /// more landmarks tighten the bound less than a fourth cache line and a
    /// longer selection cost (measurements in docs/performance.md).
    static constexpr std::uint32_t kStride = 48;

    std::uint32_t count = 0;
    std::vector<std::uint32_t> node;

    /// Geodesic distance from landmark k to node n (infinity in other
    /// components).
    float distance(std::uint32_t n, std::uint32_t k) const noexcept { return row(n)[k]; }
    /// All landmark distances of node n: kStride floats (unused slots 0),
    /// 64-byte aligned, so the A* bound is a few SIMD maxima over one row
    /// instead of a loop with branches.
    const float* row(std::uint32_t n) const noexcept {
        return mRows.data() + mRowsOffset + std::size_t(n) * kStride;
    }
    float* row(std::uint32_t n) noexcept {
        return mRows.data() + mRowsOffset + std::size_t(n) * kStride;
    }
    /// Sizes the rows for `nodes` nodes, unwritten: the caller writes all
    /// kStride floats of every row (computeLandmarks() does, in parallel).
    void allocateRows(std::uint32_t nodes);
    bool hasRows() const noexcept { return !mRows.empty(); }

private:
    UninitialisedVector<float> mRows;  // first touched by the parallel fill
    std::size_t mRowsOffset = 0;       // first element on a 64-byte boundary
};

/// Landmarks: the boundary nodes that are extreme along 14 directions (the
/// axes and the diagonals; ties by lowest id), then farthest-point landmarks
/// (the node farthest from all landmarks so far) up to Landmarks::kStride.
/// Distances by full Dijkstra, the landmarks one per task.
/// Deterministic for any thread count. Costs about Landmarks::kStride full
/// searches: polls `interrupter` once per landmark and throws
/// InterruptedError when asked to stop.
Landmarks computeLandmarks(const BoundaryGraph& graph, bool threaded = true,
                           Interrupter& interrupter = nullInterrupter());

class GeodesicSearch {
public:
    explicit GeodesicSearch(const BoundaryGraph& graph, const Landmarks* landmarks = nullptr);

    /// Length of a shortest path from `from` to `to` (A*), or kUnreachable.
    /// If `path` is given it receives the nodes from `from` to `to` inclusive.
    /// With a finite `bound` the answer is the unbounded one if its length is
    /// at most `bound`, else kUnreachable: the search gives up once every
    /// remaining path is known to be longer, and a path it does find is the
    /// same as without the bound (same settle order, earlier stop). The stop
    /// test allows a relative slack of kBoundSlack over `bound` so that float
    /// rounding in the heuristic cannot stop it before a path of length <=
    /// `bound`; a path found in the slack is reported as kUnreachable. So the
    /// answer is a function of (from, to, bound), which PathCache relies on.
    float shortestPath(std::uint32_t from, std::uint32_t to,
                       std::vector<std::uint32_t>* path = nullptr, float bound = kUnreachable);

    /// Dijkstra restricted to nodes with allowed(node) true (both ends must be
    /// allowed). Used on small node sets (a path set and its dilation).
    template <typename Allowed>
    float shortestPathWithin(std::uint32_t from, std::uint32_t to, const Allowed& allowed,
                             std::vector<std::uint32_t>* path = nullptr);

    /// Single-source Dijkstra over the whole graph: the distance from `source`
    /// to every node (kUnreachable in other components). computeLandmarks()
    /// fills the landmark rows with it; tests also use it as the reference.
    std::vector<float> distancesFrom(std::uint32_t source) const;

    const BoundaryGraph& graph() const noexcept { return mGraph; }
    SearchCounters counters;

    /// Relative slack of the bounded stop test (see shortestPath).
    static constexpr float kBoundSlack = 1.0f / 4096;

private:
    /// All per-node search state in one 16-byte record: a relaxation touches
    /// one cache line instead of four arrays. stamp = generation << 1 for a
    /// node reached in this search, | 1 once it is settled.
    struct NodeState {
        std::uint32_t stamp;
        float distance;
        float heuristic;  // computed once per search, when first reached
        std::uint32_t parent;
    };
    /// Heap keys: the priority's bits (non-negative floats order like their
    /// bit patterns) above the node id, so one integer comparison orders by
    /// priority and breaks ties by node id: the settle order, and so the path
    /// found, is a function of the graph alone.
    using HeapKey = std::uint64_t;
    template <typename Heuristic, typename Allowed>
    float search(std::uint32_t from, std::uint32_t to, const Heuristic& heuristic,
                 const Allowed& allowed, std::vector<std::uint32_t>* path);
    void nextGeneration();
    void heapPush(HeapKey key);
    HeapKey heapPop();

    const BoundaryGraph& mGraph;
    const Landmarks* mLandmarks;
    float mBound = kUnreachable;
    std::vector<NodeState> mState;
    std::uint32_t mGeneration = 0;  // < 2^31
    std::vector<HeapKey> mHeap;
};

/// Per-thread cache of pair paths, bounded in memory: its pool of path
/// nodes and its table are both emptied when either would outgrow its bound,
/// so what a cache holds is at most maxBytes(), whatever the graph. The
/// memory estimate of a run (estimateSegmentationMemory) counts that bound
/// per thread.
class PathCache {
public:
    struct Entry {
        float length;
        std::uint32_t begin, count;  // range in the node pool
        float bound = kUnreachable;  // for length == kUnreachable: the bound searched up to
    };
    /// 2^20 nodes (4 MB): a fixed bound, so that the memory estimate can
    /// count it before the graph exists. What a larger pool would save on
    /// large graphs, and what it would cost every estimate, is in
    /// docs/performance.md, "The path caches and the preview in the memory
    /// estimate".
    static constexpr std::size_t kDefaultMaxNodes = std::size_t(1) << 20;

    /// maxNodes: the pool is cleared when it would hold more path nodes (one
    /// path longer than that is still held, alone); the table is cleared
    /// with it when it holds maxNodes / 8 pairs (pairs searched in vain hold
    /// no nodes, so the pool alone would not bound it).
    explicit PathCache(std::size_t maxNodes = kDefaultMaxNodes)
        : mMaxNodes(std::max<std::size_t>(maxNodes, 1)),
          mMaxEntries(std::max<std::size_t>(mMaxNodes / 8, 1)) {}

    /// The most a cache of `maxNodes` holds in its pool and table, bytes,
    /// the old table while the table doubles included (paths no longer than
    /// maxNodes; a longer one adds its own length).
    static std::size_t maxBytes(std::size_t maxNodes = kDefaultMaxNodes) noexcept;
    /// What this cache holds in its pool and table now, bytes (capacities).
    std::size_t bytesHeld() const noexcept {
        return mPool.capacity() * sizeof(std::uint32_t) + mTable.capacity() * sizeof(Slot);
    }

    /// Shortest path between a and b (searched from min(a,b) so that the
    /// result does not depend on the order of the arguments). The returned
    /// entry's nodes are valid until the next call.
    /// `bound`: see GeodesicSearch::shortestPath; the answer is the same as an
    /// uncached search with the same bound, whatever was asked before. A pair
    /// cached as "longer than B" is searched again when asked with a larger
    /// bound; a pair cached with its path (found under a larger bound) reads
    /// as kUnreachable when asked with a bound below its length.
    const Entry& path(GeodesicSearch& search, std::uint32_t a, std::uint32_t b,
                      float bound = kUnreachable);
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
    /// Empties pool and table (every entry) when `nodes` more path nodes or
    /// `pairs` more pairs would pass a bound.
    void makeRoomFor(std::size_t nodes, std::size_t pairs);
    /// Appends to the pool, growing it by doubling but never past mMaxNodes
    /// (unless one path alone is longer).
    void appendToPool(const std::uint32_t* nodes, std::size_t count);

    std::size_t mMaxNodes;
    std::size_t mMaxEntries;
    std::vector<Slot> mTable;
    std::size_t mUsed = 0;
    Entry mSelf{};
    Entry mBeyondBound{};  // the answer for a cached path longer than the bound asked
    std::vector<std::uint32_t> mPool;
    std::vector<std::uint32_t> mScratch;
};

// ---------------------------------------------------------------------------
// Implementation of the template members.

inline void GeodesicSearch::heapPush(HeapKey key) {
    // 4-ary min-heap, hole-based sift-up (no swaps). Four children share a
    // cache line and the heap is half as deep as a binary one: fewer levels
    // on every pop, which is where a search spends its heap time.
    std::size_t i = mHeap.size();
    mHeap.push_back(key);
    HeapKey* h = mHeap.data();
    while (i > 0) {
        const std::size_t parent = (i - 1) >> 2;
        if (h[parent] <= key) break;
        h[i] = h[parent];
        i = parent;
    }
    h[i] = key;
}

inline GeodesicSearch::HeapKey GeodesicSearch::heapPop() {
    HeapKey* h = mHeap.data();
    const HeapKey top = h[0];
    const HeapKey last = h[mHeap.size() - 1];
    mHeap.pop_back();
    const std::size_t n = mHeap.size();
    if (n == 0) return top;
    std::size_t i = 0;
    for (;;) {
        const std::size_t first = 4 * i + 1;
        if (first >= n) break;
        std::size_t child = first;
        const std::size_t end = std::min(first + 4, n);
        for (std::size_t c = first + 1; c < end; ++c)
            if (h[c] < h[child]) child = c;
        if (last <= h[child]) break;
        h[i] = h[child];
        i = child;
    }
    h[i] = last;
    return top;
}

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
    const std::uint32_t reached = mGeneration << 1, settled = reached | 1u;
    auto key = [](float priority, std::uint32_t node) {
        std::uint32_t bits;
        std::memcpy(&bits, &priority, sizeof bits);
        return (HeapKey(bits) << 32) | node;
    };
    NodeState* state = mState.data();
    const std::uint32_t* offset = mGraph.offset.data();
    const std::uint32_t* neighbour = mGraph.neighbour.data();
    const float* weight = mGraph.weight.data();
    mHeap.clear();
    state[from] = NodeState{reached, 0.0f, heuristic(from), kNoNode};
    heapPush(key(state[from].heuristic, from));
    float result = kUnreachable;
    while (!mHeap.empty()) {
        const HeapKey top = heapPop();
        ++counters.heapPops;
        const std::uint32_t n = std::uint32_t(top);
        const std::uint32_t priorityBits = std::uint32_t(top >> 32);
        float priority;
        std::memcpy(&priority, &priorityBits, sizeof priority);
        if (priority > mBound) break;  // admissible heuristic: nothing within the bound is left
        NodeState& sn = state[n];
        if (sn.stamp == settled) continue;
        sn.stamp = settled;
        ++counters.nodesSettled;
        if (n == to) {
            result = sn.distance;
            break;
        }
        const float dn = sn.distance;
        for (std::uint32_t e = offset[n], end = offset[n + 1]; e < end; ++e) {
            const std::uint32_t m = neighbour[e];
            NodeState& sm = state[m];
            if (sm.stamp == settled || !allowed(m)) continue;
            const float dm = dn + weight[e];
            if (sm.stamp != reached) {
                sm.stamp = reached;
                sm.heuristic = heuristic(m);
            } else if (!(dm < sm.distance)) {
                continue;
            }
            sm.distance = dm;
            sm.parent = n;
            heapPush(key(dm + sm.heuristic, m));
        }
    }
    if (path && result != kUnreachable) {
        for (std::uint32_t n = to; n != kNoNode; n = state[n].parent) path->push_back(n);
        std::reverse(path->begin(), path->end());
    }
    return result;
}

template <typename Allowed>
float GeodesicSearch::shortestPathWithin(std::uint32_t from, std::uint32_t to,
                                         const Allowed& allowed, std::vector<std::uint32_t>* path) {
    if (!allowed(from) || !allowed(to)) {
        if (path) path->clear();
        return kUnreachable;
    }
    const BoundaryGraph& g = mGraph;
    return search(
        from, to, [&](std::uint32_t n) { return g.euclidean(n, to); }, allowed, path);
}

}  // namespace skelseg
