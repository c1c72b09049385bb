// Helpers shared by the kernel unit tests: small hand-made volumes, node
// look-ups on the boundary graph and brute-force references.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <queue>
#include <random>
#include <vector>

#include "kernels/BoundaryGraph.h"
#include "kernels/FeatureTransform.h"
#include "kernels/PathSearch.h"
#include "kernels/SkeletonCandidates.h"
#include "kernels/SkeletonMeasures.h"
#include "kernels/base/Volume.h"
#include "tests/support/Pi.h"

namespace skelseg::test {

/// Unit direction at `azimuth` degrees from the x axis in the xy plane,
/// leaning `elevation` degrees out of it: shapes laid at an angle to the grid.
inline std::array<double, 3> unitDirection(double azimuth, double elevation) {
    const double a = azimuth * kPi / 180.0, e = elevation * kPi / 180.0;
    return {std::cos(a) * std::cos(e), std::sin(a) * std::cos(e), std::sin(e)};
}

/// A voxelised ball: voxel centres within `radius` of `centre`.
inline MaskVolume ballMask(Dims dims, std::array<double, 3> centre, double radius) {
    MaskVolume mask(dims, 0);
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x) {
                const double dx = x - centre[0], dy = y - centre[1], dz = z - centre[2];
                mask(x, y, z) = dx * dx + dy * dy + dz * dz <= radius * radius ? 1 : 0;
            }
    return mask;
}

/// A solid axis-aligned box [lo, hi] (inclusive) set to 1 in `mask`.
inline void fillBox(MaskVolume& mask, std::array<int, 3> lo, std::array<int, 3> hi) {
    for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
            for (int x = lo[0]; x <= hi[0]; ++x) mask(x, y, z) = 1;
}

/// A plate 13 x 13 x 3 voxels (x, y 1 to 13, z 2 to 4 of a 15 x 15 x 7
/// grid) with a square hole of `width` voxels through it from (7, 7):
/// genus 1.
inline MaskVolume plateWithSquareHole(int width) {
    MaskVolume mask(Dims{15, 15, 7}, 0);
    fillBox(mask, {1, 1, 2}, {13, 13, 4});
    for (int y = 7; y < 7 + width; ++y)
        for (int x = 7; x < 7 + width; ++x)
            for (int z = 2; z <= 4; ++z) mask(x, y, z) = 0;
    return mask;
}

/// Empties the outermost layer of `mask`, as a crop's is.
inline void emptyOuterLayer(MaskVolume& mask) {
    const Dims d = mask.dims();
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x)
                if (x == 0 || y == 0 || z == 0 || x + 1 == d.x || y + 1 == d.y || z + 1 == d.z)
                    mask(x, y, z) = 0;
}

/// Uniform random mask with P(object) = density.
inline MaskVolume randomMask(Dims dims, double density, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::bernoulli_distribution coin(density);
    MaskVolume mask(dims, 0);
    for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = coin(rng) ? 1 : 0;
    return mask;
}

/// A random smooth blob: a union of `count` random balls in a cube of side n.
inline MaskVolume randomBlob(int n, int count, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(0.3 * n, 0.7 * n), rad(0.15 * n, 0.3 * n);
    MaskVolume mask(Dims{n, n, n}, 0);
    for (int b = 0; b < count; ++b) {
        const double cx = pos(rng), cy = pos(rng), cz = pos(rng), r = rad(rng);
        for (int z = 0; z < n; ++z)
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) {
                    const double dx = x - cx, dy = y - cy, dz = z - cz;
                    if (dx * dx + dy * dy + dz * dz <= r * r) mask(x, y, z) = 1;
                }
    }
    return mask;
}

/// The boundary node nearest (Euclidean) to a point given in voxel units.
inline std::uint32_t nearestNode(const BoundaryGraph& graph, std::array<double, 3> p) {
    std::uint32_t best = kNoNode;
    double bestD = 1e300;
    for (std::uint32_t n = 0; n < graph.nodeCount(); ++n) {
        const Coord c = graph.coord[n];
        const double dx = c.x - p[0], dy = c.y - p[1], dz = c.z - p[2];
        const double d = dx * dx + dy * dy + dz * dz;
        if (d < bestD) bestD = d, best = n;
    }
    return best;
}

/// The boundary node nearest to centre + radius * (unit vector at latitude,
/// longitude given in degrees; latitude measured from the xy plane).
inline std::uint32_t nodeOnSphere(const BoundaryGraph& graph, std::array<double, 3> centre,
                                  double radius, double latitudeDeg, double longitudeDeg) {
    const double lat = latitudeDeg * kPi / 180.0, lon = longitudeDeg * kPi / 180.0;
    return nearestNode(graph, {centre[0] + radius * std::cos(lat) * std::cos(lon),
                               centre[1] + radius * std::cos(lat) * std::sin(lon),
                               centre[2] + radius * std::sin(lat)});
}

/// Union (in order of first appearance, no duplicates) of shortest paths
/// between consecutive entries of `waypoints` (closed: last -> first too).
inline std::vector<std::uint32_t> pathThrough(GeodesicSearch& search,
                                              const std::vector<std::uint32_t>& waypoints,
                                              bool closed) {
    std::vector<std::uint32_t> set, path;
    const std::size_t legs = closed ? waypoints.size() : waypoints.size() - 1;
    for (std::size_t i = 0; i < legs; ++i) {
        const float length =
            search.shortestPath(waypoints[i], waypoints[(i + 1) % waypoints.size()], &path);
        EXPECT_NE(length, kUnreachable);
        for (std::uint32_t n : path)
            if (std::find(set.begin(), set.end(), n) == set.end()) set.push_back(n);
    }
    return set;
}

/// Connected components of the graph nodes with allowed(n), by BFS; label
/// kNoNode elsewhere. Returns the component sizes.
inline std::vector<std::uint64_t> floodFill(const BoundaryGraph& graph,
                                            const std::function<bool(std::uint32_t)>& allowed,
                                            std::vector<std::uint32_t>& label) {
    label.assign(graph.nodeCount(), kNoNode);
    std::vector<std::uint64_t> sizes;
    std::vector<std::uint32_t> queue;
    for (std::uint32_t seed = 0; seed < graph.nodeCount(); ++seed) {
        if (!allowed(seed) || label[seed] != kNoNode) continue;
        const std::uint32_t id = std::uint32_t(sizes.size());
        queue.assign(1, seed);
        label[seed] = id;
        for (std::size_t h = 0; h < queue.size(); ++h)
            for (std::uint32_t e = graph.offset[queue[h]]; e < graph.offset[queue[h] + 1]; ++e) {
                const std::uint32_t m = graph.neighbour[e];
                if (allowed(m) && label[m] == kNoNode) label[m] = id, queue.push_back(m);
            }
        sizes.push_back(queue.size());
    }
    return sizes;
}

/// Dijkstra on the subgraph of nodes with allowed(n) (reference for tests).
inline std::vector<double> restrictedDistances(const BoundaryGraph& graph, std::uint32_t source,
                                               const std::function<bool(std::uint32_t)>& allowed) {
    std::vector<double> dist(graph.nodeCount(), std::numeric_limits<double>::infinity());
    if (!allowed(source)) return dist;
    using Item = std::pair<double, std::uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    dist[source] = 0.0;
    heap.push({0.0, source});
    while (!heap.empty()) {
        const auto [d, n] = heap.top();
        heap.pop();
        if (d > dist[n]) continue;
        for (std::uint32_t e = graph.offset[n]; e < graph.offset[n + 1]; ++e) {
            const std::uint32_t m = graph.neighbour[e];
            if (!allowed(m)) continue;
            const double dm = d + double(graph.weight[e]);
            if (dm < dist[m]) dist[m] = dm, heap.push({dm, m});
        }
    }
    return dist;
}

/// True if a and b are joined by an edge of the graph.
inline bool hasEdge(const BoundaryGraph& graph, std::uint32_t a, std::uint32_t b) {
    for (std::uint32_t e = graph.offset[a]; e < graph.offset[a + 1]; ++e)
        if (graph.neighbour[e] == b) return true;
    return false;
}

/// Field-by-field equality of two skeleton points.
inline void expectSamePoint(const SkeletonPoint& a, const SkeletonPoint& b) {
    EXPECT_EQ(a.voxel, b.voxel);
    EXPECT_EQ(a.candidate, b.candidate);
    EXPECT_EQ(a.rhoS, b.rhoS);
    EXPECT_EQ(a.rhoC, b.rhoC);
    EXPECT_EQ(a.rhoCExact, b.rhoCExact);
    EXPECT_EQ(a.isHandle, b.isHandle);
    EXPECT_EQ(a.rims, b.rims);
    EXPECT_EQ(a.robustRims, b.robustRims);
    EXPECT_EQ(a.sigma, b.sigma);
    EXPECT_EQ(a.featureA, b.featureA);
    EXPECT_EQ(a.featureB, b.featureB);
}

/// A voxelised ball (radius kBallRadius in a 31^3 grid) and its boundary
/// graph, built once per test suite; boundary nodes are picked by latitude
/// and longitude, path sets are made of geodesics between them.
class BallBoundaryFixture : public ::testing::Test {
protected:
    static constexpr std::array<double, 3> kBallCentre{15.0, 15.0, 15.0};
    static constexpr double kBallRadius = 12.5;

    static void SetUpTestSuite() {
        mask = new MaskVolume(ballMask(Dims{31, 31, 31}, kBallCentre, kBallRadius));
        graph = new BoundaryGraph(buildBoundaryGraph(*mask, {false}));
    }
    static void TearDownTestSuite() {
        delete graph;
        delete mask;
        graph = nullptr, mask = nullptr;
    }
    std::uint32_t at(double latitude, double longitude) const {
        return nodeOnSphere(*graph, kBallCentre, kBallRadius, latitude, longitude);
    }
    /// A closed loop of four geodesic arcs through the points at `latitude`
    /// and longitudes 0, 90, 180, 270: for latitude > 0 it cuts off a
    /// northern cap smaller than the rest.
    std::vector<std::uint32_t> loopAt(double latitude, GeodesicSearch& search) const {
        return pathThrough(
            search, {at(latitude, 0), at(latitude, 90), at(latitude, 180), at(latitude, 270)},
            true);
    }

    static inline MaskVolume* mask = nullptr;
    static inline BoundaryGraph* graph = nullptr;
};

/// A mask's skeleton points as the engine measures them, serially: tau 1%
/// of the boundary area and the engine's noise area (the tube tests read
/// the middle of long tubes, where 3% would simplify too little away).
struct OnePercentSkeleton {
    BoundaryGraph graph;
    std::vector<SkeletonPoint> points;
};

inline OnePercentSkeleton measureSkeletonAtOnePercent(const MaskVolume& mask) {
    OnePercentSkeleton out;
    const Volume<std::uint32_t> ft = featureTransform(boundaryVoxels(mask, {false}), {false});
    out.graph = buildBoundaryGraph(mask, {false});
    CandidateOptions candidateOptions;
    candidateOptions.threaded = false;
    const auto candidates = selectSkeletonCandidates(mask, ft, out.graph, candidateOptions);
    const Landmarks landmarks = computeLandmarks(out.graph, false);
    SkeletonMeasureOptions options;
    options.tau = 0.01 * out.graph.nodeCount();
    options.noiseArea = std::min(std::max(10.0, 0.002 * out.graph.nodeCount()), options.tau);
    options.landmarks = &landmarks;
    options.threaded = false;
    out.points = measureSkeleton(out.graph, candidates, options);
    return out;
}

}  // namespace skelseg::test
