#include "kernels/PathSearch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <mutex>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "tests/kernels/KernelTestSupport.h"
#include "tests/support/DirtyAllocations.h"

namespace skelseg {
namespace {

/// Lengths agree when they differ by float rounding only (A* and Dijkstra
/// may sum equally long paths in a different order).
void expectSameLength(double expected, double actual, const char* what) {
    EXPECT_NEAR(actual, expected, 1e-5 * std::max(1.0, expected)) << what;
}

/// The path is a chain of graph edges from `from` to `to` whose weights sum
/// to `length`.
void expectValidPath(const BoundaryGraph& graph, const std::vector<std::uint32_t>& path,
                     std::uint32_t from, std::uint32_t to, float length) {
    ASSERT_FALSE(path.empty());
    EXPECT_EQ(path.front(), from);
    EXPECT_EQ(path.back(), to);
    float sum = 0.0f;
    for (std::size_t i = 1; i < path.size(); ++i) {
        float w = -1.0f;
        for (std::uint32_t e = graph.offset[path[i - 1]]; e < graph.offset[path[i - 1] + 1]; ++e)
            if (graph.neighbour[e] == path[i]) w = graph.weight[e];
        ASSERT_GE(w, 0.0f) << "step " << i << " of the path is not an edge";
        sum += w;
    }
    EXPECT_FLOAT_EQ(sum, length);
}

class PathSearchOnBlob : public ::testing::Test {
protected:
    void SetUp() override {
        mask = test::randomBlob(14, 3, 5);
        graph = buildBoundaryGraph(mask, {false});
    }
    MaskVolume mask;
    BoundaryGraph graph;
};

TEST_F(PathSearchOnBlob, AStarEqualsDijkstraForAllPairs) {
    ASSERT_GT(graph.nodeCount(), 200u);
    ASSERT_EQ(graph.componentSize.size(), 1u);
    GeodesicSearch search(graph);
    std::vector<std::uint32_t> path;
    std::size_t checked = 0;
    for (std::uint32_t a = 0; a < graph.nodeCount(); ++a) {
        const std::vector<float> reference = search.distancesFrom(a);
        for (std::uint32_t b = a; b < graph.nodeCount(); ++b) {
            const float length = search.shortestPath(a, b, &path);
            if (std::fabs(double(length) - double(reference[b])) >
                1e-5 * std::max(1.0, double(reference[b]))) {
                FAIL() << "A* " << length << " != Dijkstra " << reference[b] << " for " << a
                       << " -> " << b;
            }
            // Every 7th pair: also the path and the symmetric length.
            if ((a + b) % 7 == 0) {
                expectValidPath(graph, path, a, b, length);
                const float back = search.shortestPath(b, a);
                expectSameLength(length, back, "d(a,b) != d(b,a)");
            }
            ++checked;
        }
    }
    EXPECT_EQ(checked, std::size_t(graph.nodeCount()) * (graph.nodeCount() + 1) / 2);
}

TEST_F(PathSearchOnBlob, DijkstraReferenceIsSane) {
    // The reference itself: 0 at the source, symmetric, triangle inequality
    // along edges, and at least the Euclidean distance.
    GeodesicSearch search(graph);
    const std::vector<float> d0 = search.distancesFrom(0);
    EXPECT_EQ(d0[0], 0.0f);
    for (std::uint32_t n = 0; n < graph.nodeCount(); ++n) {
        EXPECT_GE(d0[n] + 1e-4f, graph.euclidean(0, n));
        for (std::uint32_t e = graph.offset[n]; e < graph.offset[n + 1]; ++e)
            EXPECT_LE(d0[graph.neighbour[e]], d0[n] + graph.weight[e] + 1e-4f);
    }
    const std::uint32_t far = std::uint32_t(std::max_element(d0.begin(), d0.end()) - d0.begin());
    expectSameLength(d0[far], search.distancesFrom(far)[0], "Dijkstra not symmetric");
}

TEST_F(PathSearchOnBlob, SamePathForSameQueryAndCounters) {
    GeodesicSearch search(graph);
    std::vector<std::uint32_t> first, second;
    const std::uint32_t a = 3, b = graph.nodeCount() - 5;
    const float l1 = search.shortestPath(a, b, &first);
    search.shortestPath(b, a);  // other searches in between must not matter
    const float l2 = search.shortestPath(a, b, &second);
    EXPECT_EQ(l1, l2);
    EXPECT_EQ(first, second);
    EXPECT_EQ(search.counters.searches, 3u);
    EXPECT_GE(search.counters.heapPops, search.counters.nodesSettled);
    EXPECT_GE(search.counters.nodesSettled, 3u * std::uint64_t(first.size()) - 3u);
    // A second workspace finds the identical path (a function of the graph).
    GeodesicSearch other(graph);
    std::vector<std::uint32_t> third;
    other.shortestPath(a, b, &third);
    EXPECT_EQ(first, third);
}

TEST_F(PathSearchOnBlob, TrivialQuery) {
    GeodesicSearch search(graph);
    std::vector<std::uint32_t> path = {1, 2, 3};
    EXPECT_EQ(search.shortestPath(7, 7, &path), 0.0f);
    EXPECT_EQ(path, std::vector<std::uint32_t>{7});
    // A neighbour: one edge, whatever its length (no path is shorter than
    // the Euclidean distance, which the edge weight is).
    const std::uint32_t m = graph.neighbour[graph.offset[7]];
    EXPECT_FLOAT_EQ(search.shortestPath(7, m, &path), graph.weight[graph.offset[7]]);
    EXPECT_EQ(path, (std::vector<std::uint32_t>{7, m}));
}

TEST(PathSearch, UnreachableAcrossComponents) {
    MaskVolume mask(Dims{20, 8, 8}, 0);
    test::fillBox(mask, {1, 1, 1}, {5, 6, 6});
    test::fillBox(mask, {10, 1, 1}, {15, 6, 6});
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    ASSERT_EQ(graph.componentSize.size(), 2u);
    GeodesicSearch search(graph);
    const std::uint32_t a = graph.nodeOfVoxel[mask.index(1, 1, 1)],
                        b = graph.nodeOfVoxel[mask.index(15, 6, 6)];
    std::vector<std::uint32_t> path = {42};
    EXPECT_EQ(search.shortestPath(a, b, &path), kUnreachable);
    EXPECT_TRUE(path.empty());
    EXPECT_EQ(search.distancesFrom(a)[b], kUnreachable);
    // The search is still usable afterwards.
    const std::uint32_t c = graph.nodeOfVoxel[mask.index(5, 6, 6)];
    EXPECT_GT(search.shortestPath(a, c), 0.0f);
}

TEST(PathSearch, KnownLengthOnABoxFace) {
    // Straight along an edge of a box: 7 unit steps; diagonal across a face:
    // 6 sqrt2 steps (no path is shorter than the Euclidean distance).
    MaskVolume mask(Dims{14, 14, 14}, 0);
    test::fillBox(mask, {2, 2, 2}, {11, 11, 11});
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    GeodesicSearch search(graph);
    auto node = [&](int x, int y, int z) { return graph.nodeOfVoxel[mask.index(x, y, z)]; };
    EXPECT_FLOAT_EQ(search.shortestPath(node(3, 2, 5), node(10, 2, 5)), 7.0f);
    EXPECT_NEAR(search.shortestPath(node(3, 3, 2), node(9, 9, 2)), 6.0 * std::sqrt(2.0), 1e-5);
    // Around an edge of the box, from the z=2 face to the x=2 face: longer
    // than the Euclidean distance; check against Dijkstra.
    const std::uint32_t a = node(6, 6, 2), b = node(2, 6, 6);
    const float around = search.shortestPath(a, b);
    expectSameLength(search.distancesFrom(a)[b], around, "around an edge");
    EXPECT_GT(around, graph.euclidean(a, b) + 0.5f);
}

TEST_F(PathSearchOnBlob, ShortestPathWithinRespectsAllowedSet) {
    GeodesicSearch search(graph);
    // Allowed: a band of slabs. Also a checker-like restriction that forces
    // detours. Compare with a restricted Dijkstra.
    const std::vector<std::function<bool(std::uint32_t)>> restrictions = {
        [&](std::uint32_t n) { return graph.coord[n].z <= 8; },
        [&](std::uint32_t n) { return graph.coord[n].x + graph.coord[n].y != 13; },
        [&](std::uint32_t n) { return (n % 5) != 0; },
    };
    std::mt19937 rng(9);
    std::uniform_int_distribution<std::uint32_t> pick(0, graph.nodeCount() - 1);
    std::vector<std::uint32_t> path;
    for (const auto& allowed : restrictions) {
        int finite = 0, longer = 0;
        for (int trial = 0; trial < 40; ++trial) {
            const std::uint32_t a = pick(rng), b = pick(rng);
            const std::vector<double> reference = test::restrictedDistances(graph, a, allowed);
            const float length = search.shortestPathWithin(a, b, allowed, &path);
            if (!allowed(a) || !allowed(b) ||
                reference[b] == std::numeric_limits<double>::infinity()) {
                EXPECT_EQ(length, kUnreachable);
                EXPECT_TRUE(path.empty());
                continue;
            }
            ++finite;
            expectSameLength(reference[b], length, "restricted A* != restricted Dijkstra");
            expectValidPath(graph, path, a, b, length);
            for (std::uint32_t n : path) EXPECT_TRUE(allowed(n)) << "path leaves the allowed set";
            longer += length > search.shortestPath(a, b) + 1e-3f;
        }
        EXPECT_GT(finite, 10);
        (void)longer;
    }
}

TEST(PathSearch, ShortestPathWithinTakesTheDetour) {
    // On a box, forbid a wall across the top face: the path must go around.
    MaskVolume mask(Dims{16, 16, 8}, 0);
    test::fillBox(mask, {1, 1, 1}, {14, 14, 6});
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    GeodesicSearch search(graph);
    auto node = [&](int x, int y, int z) { return graph.nodeOfVoxel[mask.index(x, y, z)]; };
    const std::uint32_t a = node(4, 7, 6), b = node(11, 7, 6);
    auto allowed = [&](std::uint32_t n) {
        const Coord c = graph.coord[n];
        return !(c.x == 7 && c.y >= 2 && c.y <= 13) && c.z == 6;  // top face only, wall at x = 7
    };
    std::vector<std::uint32_t> path;
    const float free = search.shortestPath(a, b);
    const float within = search.shortestPathWithin(a, b, allowed, &path);
    EXPECT_FLOAT_EQ(free, 7.0f);
    EXPECT_GT(within, free + 4.0f);
    const std::vector<double> reference = test::restrictedDistances(graph, a, allowed);
    expectSameLength(reference[b], within, "detour length");
    for (std::uint32_t n : path) EXPECT_TRUE(allowed(n));
    // An end outside the allowed set gives no path.
    EXPECT_EQ(search.shortestPathWithin(node(4, 7, 1), b, allowed, &path), kUnreachable);
}

TEST_F(PathSearchOnBlob, LandmarkDistancesAreDijkstra) {
    const Landmarks serial = computeLandmarks(graph, false);
    ASSERT_GE(serial.count, 2u);
    ASSERT_LE(serial.count, Landmarks::kStride);
    ASSERT_EQ(serial.node.size(), serial.count);
    EXPECT_EQ(std::set<std::uint32_t>(serial.node.begin(), serial.node.end()).size(), serial.count);
    GeodesicSearch search(graph);
    for (std::uint32_t k = 0; k < serial.count; ++k) {
        const std::vector<float> d = search.distancesFrom(serial.node[k]);
        for (std::uint32_t n = 0; n < graph.nodeCount(); ++n)
            ASSERT_EQ(serial.distance(n, k), d[n]);
    }
    // The extreme node along +x is a landmark.
    std::uint32_t maxX = 0;
    for (std::uint32_t n = 0; n < graph.nodeCount(); ++n)
        if (graph.coord[n].x > graph.coord[maxX].x) maxX = n;
    EXPECT_NE(std::find(serial.node.begin(), serial.node.end(), maxX), serial.node.end());
    // The row is filled with farthest-point landmarks: the last one is a node
    // farthest from all the landmarks before it.
    ASSERT_EQ(serial.count, std::min<std::uint32_t>(Landmarks::kStride, graph.nodeCount()));
    auto nearestBefore = [&](std::uint32_t n, std::uint32_t k) {
        float d = kUnreachable;
        for (std::uint32_t j = 0; j < k; ++j) d = std::min(d, serial.distance(n, j));
        return d;
    };
    const std::uint32_t last = serial.count - 1;
    const float lastNearest = nearestBefore(serial.node[last], last);
    EXPECT_GT(lastNearest, 0.0f);
    for (std::uint32_t n = 0; n < graph.nodeCount(); ++n)
        ASSERT_LE(nearestBefore(n, last), lastNearest);
    const Landmarks parallel = computeLandmarks(graph, true);
    EXPECT_EQ(parallel.node, serial.node);
    for (std::uint32_t n = 0; n < graph.nodeCount(); ++n)
        for (std::uint32_t k = 0; k < serial.count; ++k)
            ASSERT_EQ(parallel.distance(n, k), serial.distance(n, k));
}

TEST(PathSearch, LandmarkRowsAreWrittenEverywhereWhenMemoryComesDirty) {
    // The rows are allocated unwritten: every distance and, past the
    // landmark count, every unused slot (which the A* bound reads) must be
    // written, whatever the allocator handed out (0xA5... here).
    const test::DirtyAllocations dirty;
    MaskVolume small(Dims{5, 5, 5}, 0);
    test::fillBox(small, {1, 1, 1}, {3, 3, 3});  // 26 boundary voxels: fewer than a row
    const MaskVolume blob = test::randomBlob(22, 4, 7);
    for (const MaskVolume* mask : std::vector<const MaskVolume*>{&small, &blob})
        for (bool threaded : {false, true}) {
            SCOPED_TRACE(std::string(threaded ? "parallel" : "serial") + ", dirty " +
                         (dirty.active() ? "yes" : "no"));
            const BoundaryGraph graph = buildBoundaryGraph(*mask, {false});
            const Landmarks landmarks = computeLandmarks(graph, threaded);
            ASSERT_EQ(landmarks.count,
                      std::min<std::uint32_t>(Landmarks::kStride, graph.nodeCount()));
            GeodesicSearch search(graph);
            for (std::uint32_t k = 0; k < landmarks.count; ++k) {
                const std::vector<float> d = search.distancesFrom(landmarks.node[k]);
                for (std::uint32_t n = 0; n < graph.nodeCount(); ++n)
                    ASSERT_EQ(landmarks.distance(n, k), d[n]) << "node " << n << ", landmark " << k;
            }
            for (std::uint32_t n = 0; n < graph.nodeCount(); ++n)
                for (std::uint32_t k = landmarks.count; k < Landmarks::kStride; ++k)
                    ASSERT_EQ(landmarks.row(n)[k], 0.0f) << "node " << n << ", unused slot " << k;
        }
}

TEST_F(PathSearchOnBlob, AStarWithLandmarksEqualsDijkstra) {
    const Landmarks landmarks = computeLandmarks(graph, false);
    GeodesicSearch alt(graph, &landmarks), plain(graph);
    std::vector<std::uint32_t> path;
    for (std::uint32_t a = 0; a < graph.nodeCount(); a += 3) {
        const std::vector<float> reference = alt.distancesFrom(a);
        for (std::uint32_t b = 0; b < graph.nodeCount(); ++b) {
            const float length = alt.shortestPath(a, b, &path);
            if (std::fabs(double(length) - double(reference[b])) >
                1e-5 * std::max(1.0, double(reference[b])))
                FAIL() << "A* with landmarks " << length << " != Dijkstra " << reference[b]
                       << " for " << a << " -> " << b;
            if ((a + b) % 11 == 0) expectValidPath(graph, path, a, b, length);
            plain.shortestPath(a, b);
        }
    }
    // The landmark bound is at least the Euclidean one, so the search settles
    // no more nodes than plain A* (up to ties).
    EXPECT_LE(double(alt.counters.nodesSettled), 1.02 * double(plain.counters.nodesSettled));
}

TEST(PathSearch, LandmarksOnTwoComponents) {
    MaskVolume mask(Dims{24, 10, 10}, 0);
    test::fillBox(mask, {1, 1, 1}, {8, 8, 8});
    test::fillBox(mask, {12, 2, 2}, {21, 7, 7});
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    ASSERT_EQ(graph.componentSize.size(), 2u);
    const Landmarks landmarks = computeLandmarks(graph, false);
    GeodesicSearch alt(graph, &landmarks);
    auto node = [&](int x, int y, int z) { return graph.nodeOfVoxel[mask.index(x, y, z)]; };
    // Within each component: exact; across: unreachable.
    for (const auto& [a, b] :
         std::vector<std::pair<std::uint32_t, std::uint32_t>>{{node(1, 1, 1), node(8, 8, 8)},
                                                              {node(12, 2, 2), node(21, 7, 7)},
                                                              {node(4, 1, 4), node(4, 8, 4)},
                                                              {node(12, 4, 2), node(21, 4, 7)}}) {
        EXPECT_NEAR(alt.shortestPath(a, b), alt.distancesFrom(a)[b], 1e-4);
    }
    EXPECT_EQ(alt.shortestPath(node(1, 1, 1), node(21, 7, 7)), kUnreachable);
    // An empty graph has no landmarks.
    const BoundaryGraph empty = buildBoundaryGraph(MaskVolume(Dims{3, 3, 3}, 0));
    EXPECT_EQ(computeLandmarks(empty, false).count, 0u);
}

/// A random undirected graph with `nodes` nodes and about `degree` edges per
/// node, random coordinates, weights drawn from `weights` (all in [1, 2), as
/// on a boundary graph). A few nodes are left without edges (components of
/// their own).
BoundaryGraph randomGraph(std::uint32_t nodes, std::uint32_t degree,
                          const std::vector<float>& weights, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::uint32_t> pick(0, nodes - 1);
    std::uniform_int_distribution<std::size_t> kind(0, weights.size() - 1);
    std::uniform_int_distribution<int> position(0, 99);
    std::vector<std::vector<std::pair<std::uint32_t, float>>> adjacent(nodes);
    for (std::uint32_t i = 0; i < nodes * degree / 2; ++i) {
        // Mostly near neighbours (long paths), some long jumps.
        const std::uint32_t a = pick(rng);
        const std::uint32_t b = i % 8 ? (a + 1 + pick(rng) % 16) % nodes : pick(rng);
        if (a == b || a % 97 == 5 || b % 97 == 5) continue;
        const float w = weights[kind(rng)];
        adjacent[a].push_back({b, w});
        adjacent[b].push_back({a, w});
    }
    BoundaryGraph graph;
    graph.voxel.resize(nodes);
    graph.coord.resize(nodes);
    graph.offset.assign(1, 0);
    for (std::uint32_t n = 0; n < nodes; ++n) {
        graph.coord[n] = Coord{position(rng), position(rng), position(rng)};
        for (const auto& [m, w] : adjacent[n]) {
            graph.neighbour.push_back(m);
            graph.weight.push_back(w);
        }
        graph.offset.push_back(std::uint32_t(graph.neighbour.size()));
    }
    return graph;
}

/// Every landmark field, serial and parallel, equals a single-source sweep
/// from a fresh array bit for bit (the fields reuse their buffers from one
/// group of landmarks to the next).
void expectFieldsAreSingleSourceSweeps(const BoundaryGraph& graph, const char* what) {
    const Landmarks serial = computeLandmarks(graph, false);
    const Landmarks parallel = computeLandmarks(graph, true);
    ASSERT_GT(serial.count, 1u) << what;
    ASSERT_EQ(parallel.node, serial.node) << what;
    GeodesicSearch reference(graph);
    for (std::uint32_t k = 0; k < serial.count; ++k) {
        const std::vector<float> d = reference.distancesFrom(serial.node[k]);
        for (std::uint32_t n = 0; n < graph.nodeCount(); ++n) {
            const float s = serial.distance(n, k), p = parallel.distance(n, k);
            ASSERT_EQ(std::memcmp(&s, &d[n], sizeof s), 0)
                << what << ": landmark " << k << " node " << n << " " << s << " != " << d[n];
            ASSERT_EQ(std::memcmp(&p, &d[n], sizeof p), 0)
                << what << " (parallel): landmark " << k << " node " << n;
        }
    }
}

TEST(PathSearch, LandmarkFieldsAreSingleSourceSweepsOnRandomGraphs) {
    // The voxel steps, and many weights (sums that round differently in
    // every order).
    const std::vector<float> steps = {1.0f, std::sqrt(2.0f), std::sqrt(3.0f)};
    std::vector<float> many;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(1.0f, 2.0f);
    for (int i = 0; i < 64; ++i) many.push_back(std::min(unit(rng), 1.9999999f));
    for (std::uint32_t seed = 1; seed <= 3; ++seed) {
        expectFieldsAreSingleSourceSweeps(randomGraph(3000, 6, steps, seed), "steps");
        expectFieldsAreSingleSourceSweeps(randomGraph(2000, 8, many, seed), "many weights");
    }
}

TEST(PathSearch, LandmarkFieldsAreSingleSourceSweepsOnABoundaryGraph) {
    // Two blobs side by side: two components, landmarks in both.
    MaskVolume mask(Dims{72, 40, 40}, 0);
    const MaskVolume blob = test::randomBlob(36, 4, 11);
    for (int z = 0; z < 36; ++z)
        for (int y = 0; y < 36; ++y)
            for (int x = 0; x < 36; ++x) {
                mask(x + 1, y + 2, z + 2) = blob(x, y, z);
                if (x < 34) mask(x + 37, y + 2, z + 2) = blob(35 - x, y, z);
            }
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    ASSERT_EQ(graph.componentSize.size(), 2u);
    ASSERT_GT(graph.nodeCount(), 3000u);
    expectFieldsAreSingleSourceSweeps(graph, "boundary graph");
}

TEST_F(PathSearchOnBlob, PathCacheMatchesUncachedAndHitsOnRepeats) {
    GeodesicSearch search(graph), plain(graph);
    PathCache cache;
    std::mt19937 rng(3);
    std::uniform_int_distribution<std::uint32_t> pick(0, graph.nodeCount() - 1);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    for (int i = 0; i < 60; ++i) pairs.emplace_back(pick(rng), pick(rng));
    std::vector<std::uint32_t> path;
    for (const auto& [a, b] : pairs) {
        const PathCache::Entry& e = cache.path(search, a, b);
        const float reference = plain.shortestPath(std::min(a, b), std::max(a, b), &path);
        EXPECT_EQ(e.length, reference);
        ASSERT_EQ(e.count, path.size());
        EXPECT_TRUE(std::equal(path.begin(), path.end(), cache.nodes(e)));
    }
    const std::uint64_t misses = cache.misses, searches = search.counters.searches;
    EXPECT_EQ(cache.hits + cache.misses, pairs.size());
    // Repeats, in either argument order: all hits, no new search.
    for (const auto& [a, b] : pairs) {
        const PathCache::Entry& e1 = cache.path(search, a, b);
        const float l1 = e1.length;
        const PathCache::Entry& e2 = cache.path(search, b, a);
        EXPECT_EQ(l1, e2.length);
        expectSameLength(search.distancesFrom(a)[b], l1, "cached length");
    }
    EXPECT_EQ(cache.misses, misses);
    EXPECT_EQ(search.counters.searches, searches);
    EXPECT_GE(cache.hits, 2 * pairs.size());
}

TEST_F(PathSearchOnBlob, PathCacheStaysCorrectWhenItOverflows) {
    // A tiny pool forces clears; results must not change.
    GeodesicSearch search(graph), plain(graph);
    PathCache cache(16);
    std::vector<std::uint32_t> path;
    for (std::uint32_t i = 0; i < 50; ++i) {
        const std::uint32_t a = (i * 37) % graph.nodeCount(),
                            b = (i * 101 + 13) % graph.nodeCount();
        const PathCache::Entry& e = cache.path(search, a, b);
        const float reference = plain.shortestPath(std::min(a, b), std::max(a, b), &path);
        EXPECT_EQ(e.length, reference);
        ASSERT_EQ(e.count, path.size());
        EXPECT_TRUE(std::equal(path.begin(), path.end(), cache.nodes(e)));
    }
}

TEST_F(PathSearchOnBlob, PathCacheHoldsNoMoreThanItsBound) {
    // Three kinds of request grow a cache: paths (pool and table), pairs
    // searched in vain under a small bound (table only) and point pairs (pool
    // only). Each kind alone, and all mixed, must stay within maxBytes(),
    // and the answers must stay those of an uncached search.
    const std::size_t maxNodes = 64;
    ASSERT_LT(PathCache::maxBytes(maxNodes), PathCache::maxBytes());
    GeodesicSearch search(graph), plain(graph);
    std::vector<std::uint32_t> path;
    const std::uint32_t n = graph.nodeCount();
    for (int kind = 0; kind < 4; ++kind) {
        PathCache cache(maxNodes);
        std::size_t largest = 0;
        // More distinct pairs than the table's first size holds at half load.
        std::mt19937 rng(std::uint32_t(11 + kind));
        std::uniform_int_distribution<std::uint32_t> pick(0, n - 1);
        for (std::uint32_t i = 0; i < 5000; ++i) {
            const std::uint32_t a = pick(rng);
            const std::uint32_t b = kind == 2 || (kind == 3 && i % 3 == 2) ? a : pick(rng);
            const float bound = kind == 1 || (kind == 3 && i % 3 == 1) ? 0.5f : kUnreachable;
            if (a != b && plain.shortestPath(std::min(a, b), std::max(a, b)) > float(maxNodes - 2))
                continue;  // a path longer than the pool is held alone, beyond the bound
            const PathCache::Entry& e = cache.path(search, a, b, bound);
            const float reference =
                plain.shortestPath(std::min(a, b), std::max(a, b), &path, bound);
            ASSERT_EQ(e.length, reference) << "kind " << kind << " pair " << a << "-" << b;
            if (reference != kUnreachable) {
                ASSERT_EQ(e.count, path.size());
                ASSERT_TRUE(std::equal(path.begin(), path.end(), cache.nodes(e)));
            }
            largest = std::max(largest, cache.bytesHeld());
        }
        EXPECT_LE(largest, PathCache::maxBytes(maxNodes)) << "kind " << kind;
        EXPECT_GT(largest, 0u) << "kind " << kind;
    }
    // A cache at the default bound on a graph whose pairs would fill it many
    // times over (every pair of a 2,000-node sample).
    PathCache cache;
    std::size_t largest = 0;
    for (std::uint32_t i = 0; i < 2000 && i < n; ++i)
        for (std::uint32_t j = i + 1; j < 2000 && j < n; j += 7) {
            cache.path(search, i, j);
            largest = std::max(largest, cache.bytesHeld());
        }
    EXPECT_LE(largest, PathCache::maxBytes());
}

TEST_F(PathSearchOnBlob, PathCacheAnswerDoesNotDependOnEarlierBounds) {
    // Each pair is asked with a bound below, at and above its length, in an
    // order that first caches the path (large bound) and then asks below it:
    // the cache must answer as an uncached search with the same bound, or
    // which candidates count would depend on a thread's earlier requests.
    Landmarks landmarks = computeLandmarks(graph, false);
    GeodesicSearch search(graph, &landmarks), plain(graph, &landmarks);
    PathCache cache;
    std::vector<std::uint32_t> path;
    int belowLength = 0;
    for (std::uint32_t i = 0; i < 40; ++i) {
        const std::uint32_t a = (i * 53) % graph.nodeCount(), b = (i * 211 + 7) % graph.nodeCount();
        const float length = plain.shortestPath(std::min(a, b), std::max(a, b));
        if (length == kUnreachable || length < 2.0f) continue;
        for (float bound : {kUnreachable, 2.0f * length, length, 0.5f * length, length,
                            0.9f * length, kUnreachable}) {
            const float reference =
                plain.shortestPath(std::min(a, b), std::max(a, b), &path, bound);
            const PathCache::Entry& e = cache.path(search, a, b, bound);
            EXPECT_EQ(e.length, reference) << "pair " << a << "-" << b << " bound " << bound;
            if (bound < length) {
                ++belowLength;
                EXPECT_EQ(reference, kUnreachable);
            } else {
                EXPECT_EQ(reference, length);
                ASSERT_EQ(e.count, path.size());
                EXPECT_TRUE(std::equal(path.begin(), path.end(), cache.nodes(e)));
            }
        }
    }
    EXPECT_GT(belowLength, 20);
}

TEST_F(PathSearchOnBlob, BoundedSearchFindsPathsUpToTheBoundExactly) {
    // At a bound equal to the length the path is found; just below it, not.
    GeodesicSearch search(graph);
    std::vector<std::uint32_t> unbounded, bounded;
    for (std::uint32_t i = 0; i < 30; ++i) {
        const std::uint32_t a = (i * 29) % graph.nodeCount(), b = (i * 97 + 3) % graph.nodeCount();
        const float length = search.shortestPath(std::min(a, b), std::max(a, b), &unbounded);
        if (length == kUnreachable || length == 0.0f) continue;
        EXPECT_EQ(search.shortestPath(std::min(a, b), std::max(a, b), &bounded, length), length);
        EXPECT_EQ(bounded, unbounded);
        EXPECT_EQ(search.shortestPath(std::min(a, b), std::max(a, b), &bounded,
                                      std::nextafter(length, 0.0f)),
                  kUnreachable);
        EXPECT_TRUE(bounded.empty());
    }
}

/// Says stop after `allowed` polls; records the stage and the fractions.
class StopAfter final : public Interrupter {
public:
    explicit StopAfter(int allowed) : mAllowed(allowed) {}
    void start(const char* name) override { stage = name; }
    bool wasInterrupted(double fraction) override {
        std::lock_guard<std::mutex> lock(mMutex);
        fractions.push_back(fraction);
        return ++mPolls > mAllowed;
    }
    std::string stage;
    std::vector<double> fractions;

private:
    std::mutex mMutex;
    int mAllowed, mPolls = 0;
};

TEST_F(PathSearchOnBlob, LandmarksPollTheInterrupterAndStopWhenAsked) {
    for (bool threaded : {false, true}) {
        StopAfter never(1 << 30);
        const Landmarks landmarks = computeLandmarks(graph, threaded, never);
        EXPECT_EQ(never.stage, "landmarks");
        // One poll per farthest-point landmark and one per distance field.
        EXPECT_GE(never.fractions.size(), std::size_t(landmarks.count));
        for (double f : never.fractions) {
            EXPECT_GE(f, 0.0);
            EXPECT_LE(f, 1.0);
        }
        StopAfter soon(3);
        EXPECT_THROW(computeLandmarks(graph, threaded, soon), InterruptedError);
    }
}

}  // namespace
}  // namespace skelseg
