#include "kernels/PathSearch.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>

#include "kernels/base/ParallelFor.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace skelseg {

GeodesicSearch::GeodesicSearch(const BoundaryGraph& graph, const Landmarks* landmarks)
    : mGraph(graph),
      mLandmarks(landmarks && landmarks->count && landmarks->hasRows() ? landmarks : nullptr),
      mState(graph.nodeCount(), NodeState{0, 0.0f, 0.0f, kNoNode}) {}

void GeodesicSearch::nextGeneration() {
    if (++mGeneration >= (1u << 31)) {  // stamps hold generation << 1
        for (NodeState& s : mState) s.stamp = 0;
        mGeneration = 1;
    }
}

namespace {

/// max(h, |row[i] - target[i]|) over the kStride slots. A NaN difference
/// (inf - inf: a landmark in another component than both nodes) is skipped,
/// which is what _mm_max_ps(difference, h) does: it returns its second
/// operand when either is NaN. The search only reaches nodes in the target's
/// component, so a finite/infinite mix cannot occur.
inline float landmarkBound(const float* row, const float* target, float h) {
#if defined(__SSE2__)
    const __m128 signMask = _mm_set1_ps(-0.0f);
    __m128 best = _mm_set1_ps(h);
    for (std::uint32_t i = 0; i < Landmarks::kStride; i += 4) {
        const __m128 difference =
            _mm_andnot_ps(signMask, _mm_sub_ps(_mm_loadu_ps(row + i), _mm_loadu_ps(target + i)));
        best = _mm_max_ps(difference, best);
    }
    best = _mm_max_ps(best, _mm_shuffle_ps(best, best, _MM_SHUFFLE(1, 0, 3, 2)));
    best = _mm_max_ps(best, _mm_shuffle_ps(best, best, _MM_SHUFFLE(2, 3, 0, 1)));
    return _mm_cvtss_f32(best);
#else
    for (std::uint32_t i = 0; i < Landmarks::kStride; ++i) {
        const float difference = std::fabs(row[i] - target[i]);
        if (difference > h) h = difference;  // false for NaN
    }
    return h;
#endif
}

/// Single-source shortest paths from `source` that lower dist[] wherever
/// they find a shorter distance and stop expanding where they do not: on an
/// all-infinite array a full single-source search, on the distance to the
/// nearest of several sources the new source's Voronoi cell.
///
/// A bucket queue (Dial's algorithm) instead of a heap: every edge weighs at
/// least 1, so with buckets of width 1 a node can only lower nodes in later
/// buckets, and every node of the current bucket already holds its final
/// distance when the bucket is reached. Distances are the same floats as
/// Dijkstra's (each is the minimum of the same sums), at a fraction of the
/// cost. Weights are below 2, so three buckets in a ring suffice.
///
/// The sweep waits on memory: the nodes of a bucket lie along a wave front,
/// so each node's offsets, edges and distance are cache misses. The bucket
/// says which nodes come next, so their lines are requested ahead (offsets
/// twice as far ahead, since the edges' address needs them). Hints only: the
/// sweep itself is unchanged.
using Buckets = std::array<std::vector<std::uint32_t>, 3>;
void lowerDistancesFrom(const BoundaryGraph& graph, std::uint32_t source, float* dist,
                        Buckets& buckets) {
    constexpr std::size_t kAhead = 8;
    const std::uint32_t* offset = graph.offset.data();
    const std::uint32_t* neighbour = graph.neighbour.data();
    const float* weight = graph.weight.data();
    for (auto& b : buckets) b.clear();
    dist[source] = 0.0f;
    buckets[0].push_back(source);
    std::size_t pending = 1;
    for (std::uint32_t k = 0; pending > 0; ++k) {
        std::vector<std::uint32_t>& bucket = buckets[k % 3];
        for (std::size_t i = 0; i < bucket.size(); ++i) {
            if (i + 2 * kAhead < bucket.size()) __builtin_prefetch(offset + bucket[i + 2 * kAhead]);
            if (i + kAhead < bucket.size()) {
                const std::uint32_t ahead = bucket[i + kAhead];
                __builtin_prefetch(neighbour + offset[ahead]);
                __builtin_prefetch(weight + offset[ahead]);
                __builtin_prefetch(dist + ahead);
            }
            const std::uint32_t n = bucket[i];
            const float d = dist[n];
            if (std::uint32_t(d) != k) continue;  // lowered into an earlier bucket since
            for (std::uint32_t e = offset[n], end = offset[n + 1]; e < end; ++e) {
                const std::uint32_t m = neighbour[e];
                const float dm = d + weight[e];
                const float old = dist[m];
                if (dm < old) {
                    dist[m] = dm;
                    // Already queued in the same bucket: no second entry.
                    if (old == kUnreachable || std::uint32_t(old) != std::uint32_t(dm)) {
                        buckets[std::uint32_t(dm) % 3].push_back(m);
                        ++pending;
                    }
                }
            }
        }
        pending -= bucket.size();
        bucket.clear();
    }
}

}  // namespace

float GeodesicSearch::shortestPath(std::uint32_t from, std::uint32_t to,
                                   std::vector<std::uint32_t>* path, float bound) {
    struct BoundScope {  // the bound applies to this call only
        float& slot;
        BoundScope(float& s, float b) : slot(s) { slot = b; }
        ~BoundScope() { slot = kUnreachable; }
    };
    // The stop test runs at the slackened bound, the answer is filtered at
    // the exact one (see the header).
    const float stopBound = bound == kUnreachable ? kUnreachable : bound * (1.0f + kBoundSlack);
    BoundScope scope(mBound, stopBound);
    const BoundaryGraph& g = mGraph;
    auto all = [](std::uint32_t) { return true; };
    float length;
    if (!mLandmarks) {
        length = search(
            from, to, [&](std::uint32_t n) { return g.euclidean(n, to); }, all, path);
    } else {
        alignas(64) float target[Landmarks::kStride];
        std::memcpy(target, mLandmarks->row(to), sizeof target);
        const Landmarks& lm = *mLandmarks;
        auto heuristic = [&](std::uint32_t n) {
            return landmarkBound(lm.row(n), target, g.euclidean(n, to));
        };
        length = search(from, to, heuristic, all, path);
    }
    if (length != kUnreachable && length > bound) {
        if (path) path->clear();
        return kUnreachable;
    }
    return length;
}

void Landmarks::allocateRows(std::uint32_t nodes) {
    resizeUnwrittenWithHugePages(mRows, std::size_t(nodes) * kStride + 16);
    // Offset so that row 0 starts on a 64-byte boundary (vector data is only
    // 16-byte aligned); moving the vector keeps its buffer, so the offset stays
    // valid (a copy may lose the line alignment, hence unaligned loads).
    const auto address = reinterpret_cast<std::uintptr_t>(mRows.data());
    mRowsOffset = ((64 - address % 64) % 64) / sizeof(float);
    // The floats before row 0 and after the last row are never read; written
    // so that a copy of the rows copies no indeterminate values.
    std::fill(mRows.begin(), mRows.begin() + std::ptrdiff_t(mRowsOffset), 0.0f);
    std::fill(mRows.begin() + std::ptrdiff_t(mRowsOffset + std::size_t(nodes) * kStride),
              mRows.end(), 0.0f);
}

Landmarks computeLandmarks(const BoundaryGraph& graph, bool threaded, Interrupter& interrupter) {
    Landmarks result;
    const std::uint32_t n = graph.nodeCount();
    if (n == 0) return result;
    InterrupterScope scope(interrupter, "landmarks");
    static const int directions[14][3] = {
        {1, 0, 0},  {-1, 0, 0}, {0, 1, 0},   {0, -1, 0}, {0, 0, 1},   {0, 0, -1},  {1, 1, 1},
        {1, 1, -1}, {1, -1, 1}, {1, -1, -1}, {-1, 1, 1}, {-1, 1, -1}, {-1, -1, 1}, {-1, -1, -1}};
    for (const auto& d : directions) {
        std::uint32_t best = 0;
        long bestDot = std::numeric_limits<long>::min();
        for (std::uint32_t v = 0; v < n; ++v) {
            const Coord c = graph.coord[v];
            const long dot = long(c.x) * d[0] + long(c.y) * d[1] + long(c.z) * d[2];
            if (dot > bestDot) bestDot = dot, best = v;
        }
        if (std::find(result.node.begin(), result.node.end(), best) == result.node.end())
            result.node.push_back(best);
    }
    // Farthest-point landmarks fill the row up to Landmarks::kStride: each is
    // the node farthest from every landmark so far. Extremes sit on the tips
    // of a shape; the farthest points land in the middle of broad faces (a
    // palm, a torso), which bound the long searches around a flat part.
    // Choosing them needs only the
    // distance to the nearest landmark, which a new landmark changes only in
    // its own Voronoi cell: a Dijkstra pruned to that cell is exact (the
    // nearest-landmark distance is 1-Lipschitz, so the cell is closed under
    // shortest paths from its landmark), and all the cells together cost
    // about one full Dijkstra. Selection is serial; every full distance field
    // is computed in parallel afterwards.
    std::vector<float> nearest(n, kUnreachable);
    Buckets buckets;
    auto claimCell = [&](std::uint32_t source) {
        lowerDistancesFrom(graph, source, nearest.data(), buckets);
    };
    for (std::uint32_t landmark : result.node) claimCell(landmark);
    // Progress: selection and the distance fields each count as half.
    while (result.node.size() < Landmarks::kStride) {
        throwIfInterrupted(interrupter, 0.5 * double(result.node.size()) / Landmarks::kStride);
        std::uint32_t best = 0;
        for (std::uint32_t v = 1; v < n; ++v)
            if (nearest[v] > nearest[best]) best = v;
        if (nearest[best] <= 0.0f) break;  // every node is a landmark
        result.node.push_back(best);
        claimCell(best);
    }
    result.count = std::uint32_t(result.node.size());
    result.allocateRows(n);
    // The fields are computed a row cache line (16 landmarks) at a time and
    // then written into the rows by node ranges: a thread writing one
    // landmark's column into every row would share each row's cache lines
    // with the threads writing the neighbouring columns.
    std::atomic<std::uint32_t> fieldsDone{0};
    constexpr std::uint32_t kGroup = 16;
    // One field buffer and bucket ring per slot of a group, reused by every
    // group: no fresh pages to fault in and zero for each field.
    std::vector<std::vector<float>> fields(kGroup);
    std::vector<Buckets> fieldBuckets(kGroup);
    for (std::uint32_t first = 0; first < result.count; first += kGroup) {
        const std::uint32_t group = std::min(kGroup, result.count - first);
        parallelForEach(
            group,
            [&](std::uint32_t k) {
                throwIfInterrupted(interrupter,
                                   0.5 + 0.5 * double(fieldsDone.load()) / result.count);
                fields[k].assign(n, kUnreachable);
                lowerDistancesFrom(graph, result.node[first + k], fields[k].data(),
                                   fieldBuckets[k]);
                ++fieldsDone;
            },
            threaded);
        parallelFor(
            n,
            [&](std::uint32_t begin, std::uint32_t end) {
                for (std::uint32_t v = begin; v < end; ++v) {
                    float* row = result.row(v);
                    for (std::uint32_t k = 0; k < group; ++k) row[first + k] = fields[k][v];
                    // The rows were allocated unwritten: the last group also
                    // writes the unused slots, which the A* bound reads as 0.
                    if (first + group == result.count)
                        std::fill(row + result.count, row + Landmarks::kStride, 0.0f);
                }
            },
            threaded, 4096);
    }
    return result;
}

std::vector<float> GeodesicSearch::distancesFrom(std::uint32_t source) const {
    std::vector<float> dist(mGraph.nodeCount(), kUnreachable);
    Buckets buckets;
    lowerDistancesFrom(mGraph, source, dist.data(), buckets);
    return dist;
}

namespace {

/// The table's first size, slots.
constexpr std::size_t kInitialTableSlots = std::size_t(1) << 12;

}  // namespace

std::size_t PathCache::maxBytes(std::size_t maxNodes) noexcept {
    const std::size_t entries = std::max<std::size_t>(std::max<std::size_t>(maxNodes, 1) / 8, 1);
    // The table doubles while 2 * entries > slots: its last size is the
    // smallest power of two of at least 2 * entries (kInitialTableSlots at
    // least), and while it doubles the old table (half of it) is held too.
    std::size_t slots = kInitialTableSlots;
    while (slots < 2 * entries) slots *= 2;
    return std::max<std::size_t>(maxNodes, 1) * sizeof(std::uint32_t) +
           (slots + slots / 2) * sizeof(Slot);
}

void PathCache::clearTable() {
    if (mTable.empty()) mTable.resize(kInitialTableSlots);
    for (Slot& slot : mTable) slot.key = 0;
    mUsed = 0;
}

void PathCache::makeRoomFor(std::size_t nodes, std::size_t pairs) {
    if (mPool.size() + nodes > mMaxNodes || mUsed + pairs > mMaxEntries) {
        mPool.clear();
        clearTable();
    }
}

void PathCache::appendToPool(const std::uint32_t* nodes, std::size_t count) {
    const std::size_t needed = mPool.size() + count;
    if (needed > mPool.capacity())
        mPool.reserve(std::max(needed, std::min(2 * mPool.capacity(), mMaxNodes)));
    mPool.insert(mPool.end(), nodes, nodes + count);
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

const PathCache::Entry& PathCache::path(GeodesicSearch& search, std::uint32_t a, std::uint32_t b,
                                        float bound) {
    if (a > b) std::swap(a, b);
    if (a == b) {  // key 0 marks empty slots; a point pair needs no search anyway
        ++hits;
        mScratch.assign(1, a);
        makeRoomFor(1, 0);  // a point pair takes no slot of the table
        appendToPool(&a, 1);
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
            if (e.length != kUnreachable) {
                ++hits;
                if (e.length <= bound) return e;
                // Found under a larger bound: an uncached search with this
                // bound gives up, and so does the cache.
                mBeyondBound = Entry{kUnreachable, 0, 0, bound};
                return mBeyondBound;
            }
            if (e.bound >= bound) {
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
            e = Entry{length, std::uint32_t(mPool.size()), std::uint32_t(mScratch.size()),
                      kUnreachable};
            appendToPool(mScratch.data(), mScratch.size());
            return e;
        }
        i = (i + 1) & mask;
    }
    ++misses;
    const float length = search.shortestPath(a, b, &mScratch, bound);
    makeRoomFor(mScratch.size(), 1);
    if (2 * (mUsed + 1) > mTable.size()) growTable();
    mask = mTable.size() - 1;
    i = std::size_t((key * 0x9E3779B97F4A7C15ull) >> 20) & mask;
    while (mTable[i].key) i = (i + 1) & mask;
    mTable[i] = Slot{
        key, Entry{length, std::uint32_t(mPool.size()), std::uint32_t(mScratch.size()), bound}};
    ++mUsed;
    appendToPool(mScratch.data(), mScratch.size());
    return mTable[i].entry;
}

}  // namespace skelseg
