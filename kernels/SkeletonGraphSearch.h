// skelseg: searches on the skeleton graph that its stages share
// (kernels/SkeletonGraph.cpp, kernels/SkeletonForks.cpp): the connected
// pieces of a node subset, distances along the edges up to a reach, and the
// parts of the shell around a node or a region.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "kernels/SkeletonGraph.h"

namespace skelseg {

/// Connected components of the nodes with include(n), following the edges;
/// numbered by smallest node. Returns the count; label kNoJunction elsewhere.
template <typename Include>
std::uint32_t labelComponents(const SkeletonGraph& g, const Include& include,
                              std::vector<std::uint32_t>& label) {
    label.assign(g.nodeCount(), kNoJunction);
    std::uint32_t count = 0;
    std::vector<std::uint32_t> queue;
    for (std::uint32_t seed = 0; seed < g.nodeCount(); ++seed) {
        if (!include(seed) || label[seed] != kNoJunction) continue;
        queue.assign(1, seed);
        label[seed] = count;
        for (std::size_t h = 0; h < queue.size(); ++h)
            for (std::uint32_t e = g.offset[queue[h]]; e < g.offset[queue[h] + 1]; ++e) {
                const std::uint32_t m = g.neighbour[e];
                if (include(m) && label[m] == kNoJunction) label[m] = count, queue.push_back(m);
            }
        ++count;
    }
    return count;
}

/// Distances along the skeleton graph's edges (Euclidean edge lengths,
/// bridges included) from seed nodes, up to `reach`, over the nodes with
/// allowed(n). Kept across calls: reset() clears only what the last search
/// touched.
struct BoundedDistances {
    std::vector<double> distance;
    std::vector<std::uint32_t> touched;  // nodes with a finite distance
    std::vector<std::pair<double, std::uint32_t>> heap;
    explicit BoundedDistances(std::size_t n) : distance(n, HUGE_VAL) {}

    void reset() {
        for (std::uint32_t n : touched) distance[n] = HUGE_VAL;
        touched.clear();
        heap.clear();
    }
    bool reached(std::uint32_t n) const { return distance[n] != HUGE_VAL; }
    /// Offers node m at distance d; false (ignored) beyond reach or when not
    /// shorter. A taken offer is pushed onto the heap's end.
    bool offer(std::uint32_t m, double d, double reach) {
        if (d > reach || d >= distance[m]) return false;
        if (distance[m] == HUGE_VAL) touched.push_back(m);
        distance[m] = d;
        heap.push_back({d, m});
        return true;
    }
    /// Offers m at its edge length from n.
    bool offerFrom(const SkeletonGraph& g, std::uint32_t n, double dn, std::uint32_t m,
                   double reach) {
        const double dx = g.coord[m].x - g.coord[n].x, dy = g.coord[m].y - g.coord[n].y,
                     dz = g.coord[m].z - g.coord[n].z;
        return offer(m, dn + std::sqrt(dx * dx + dy * dy + dz * dz), reach);
    }
    /// Dijkstra from the offered seeds.
    template <class Allowed>
    void run(const SkeletonGraph& g, double reach, const Allowed& allowed) {
        auto later = [](const auto& a, const auto& b) { return a > b; };
        std::make_heap(heap.begin(), heap.end(), later);
        while (!heap.empty()) {
            std::pop_heap(heap.begin(), heap.end(), later);
            const auto [d, n] = heap.back();
            heap.pop_back();
            if (d > distance[n]) continue;
            for (std::uint32_t e = g.offset[n]; e < g.offset[n + 1]; ++e)
                if (const std::uint32_t m = g.neighbour[e];
                    allowed(m) && offerFrom(g, n, d, m, reach))
                    std::push_heap(heap.begin(), heap.end(), later);
        }
    }
};

/// The connected parts of the shell (radius, reach] of a BoundedDistances
/// search, over the nodes with allowed(n). A part counts as a branch when it
/// reaches past 1.5 radius or leaves the ball (a neighbour with allowed(n)
/// and no distance): a branch, not a bump of the thick skeleton. Calls
/// visit(node) for each node of a part, then part(seed, counts) once per
/// part. `mark` holds each shell node's part (its seed) and must be
/// kNoJunction on the touched nodes at the start; the caller clears it.
template <class Allowed, class Visit, class Part>
void forEachShellPart(const SkeletonGraph& g, const BoundedDistances& ball, double radius,
                      std::vector<std::uint32_t>& mark, std::vector<std::uint32_t>& queue,
                      const Allowed& allowed, const Visit& visit, const Part& part) {
    const double reach = 2.0 * radius;
    for (std::uint32_t seed : ball.touched) {
        if (ball.distance[seed] <= radius || mark[seed] != kNoJunction) continue;
        mark[seed] = seed;
        queue.assign(1, seed);
        double farthest = 0.0;
        bool leavesBall = false;
        for (std::size_t h = 0; h < queue.size(); ++h) {
            const std::uint32_t n = queue[h];
            farthest = std::max(farthest, ball.distance[n]);
            visit(n);
            for (std::uint32_t e = g.offset[n]; e < g.offset[n + 1]; ++e) {
                const std::uint32_t m = g.neighbour[e];
                if (!allowed(m)) continue;
                if (!ball.reached(m)) leavesBall = true;
                if (ball.distance[m] > radius && ball.distance[m] <= reach &&
                    mark[m] == kNoJunction)
                    mark[m] = seed, queue.push_back(m);
            }
        }
        part(seed, farthest > 1.5 * radius || leavesBall);
    }
}

}  // namespace skelseg
