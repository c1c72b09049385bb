#include "kernels/CutPieceReach.h"

#include <algorithm>
#include <cmath>

namespace skelseg {

namespace {

using Vec3 = std::array<double, 3>;

Vec3 coordOf(const BoundaryGraph& g, std::uint32_t n) {
    return {double(g.coord[n].x), double(g.coord[n].y), double(g.coord[n].z)};
}

double dot(const Vec3& a, const Vec3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

}  // namespace

double pieceReachPastLoop(const BoundaryGraph& graph, const std::vector<std::uint32_t>& gamma,
                          const std::vector<std::uint32_t>& loop, const Vec3& junction,
                          double limitRatio) {
    return PieceReachMeasurer(graph).measure(gamma, loop, junction, limitRatio);
}

PieceReachMeasurer::PieceReachMeasurer(const BoundaryGraph& graph)
    : mGraph(graph), mBlocked(graph.nodeCount()), mSeen(graph.nodeCount()) {}

double PieceReachMeasurer::measure(const std::vector<std::uint32_t>& gamma,
                                   const std::vector<std::uint32_t>& loop, const Vec3& junction,
                                   double limitRatio) {
    const BoundaryGraph& g = mGraph;
    if (loop.size() < 3 || gamma.empty()) return limitRatio;
    // The plane: the loop's mean and its vector area (Newell's normal).
    Vec3 centre{0.0, 0.0, 0.0};
    for (std::uint32_t n : loop) {
        const Vec3 p = coordOf(g, n);
        for (int k = 0; k < 3; ++k) centre[k] += p[k];
    }
    for (double& c : centre) c /= double(loop.size());
    Vec3 normal{0.0, 0.0, 0.0};
    for (std::size_t i = 0; i < loop.size(); ++i) {
        const Vec3 p = coordOf(g, loop[i]), q = coordOf(g, loop[(i + 1) % loop.size()]);
        normal[0] += (p[1] - q[1]) * (p[2] + q[2]);
        normal[1] += (p[2] - q[2]) * (p[0] + q[0]);
        normal[2] += (p[0] - q[0]) * (p[1] + q[1]);
    }
    if (dot(normal, normal) <= 0.0) return limitRatio;
    const Vec3 towardsJunction{junction[0] - centre[0], junction[1] - centre[1],
                               junction[2] - centre[2]};
    if (dot(towardsJunction, normal) > 0.0)
        for (double& c : normal) c = -c;
    const auto offset = [&](std::uint32_t n) {
        const Vec3 p = coordOf(g, n);
        return Vec3{p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]};
    };
    double loopSize = 0.0;  // squared, then the distance
    for (std::uint32_t n : gamma) {
        const Vec3 d = offset(n);
        loopSize = std::max(loopSize, dot(d, d));
    }
    loopSize = std::sqrt(loopSize);
    if (loopSize <= 0.0) return limitRatio;
    const double ball = limitRatio * loopSize;

    mBlocked.nextGeneration();
    mBlockedNodes.clear();
    for (std::uint32_t n : gamma) {
        if (mBlocked.insert(n)) mBlockedNodes.push_back(n);
        for (std::uint32_t e = g.offset[n]; e < g.offset[n + 1]; ++e)
            if (mBlocked.insert(g.neighbour[e])) mBlockedNodes.push_back(g.neighbour[e]);
    }
    // Seeds: the nodes next to the dilation, in node order (deterministic).
    std::vector<std::uint32_t>& seeds = mSeeds;
    seeds.clear();
    for (std::uint32_t n : mBlockedNodes)
        for (std::uint32_t e = g.offset[n]; e < g.offset[n + 1]; ++e)
            if (!mBlocked.isMarked(g.neighbour[e])) seeds.push_back(g.neighbour[e]);
    std::sort(seeds.begin(), seeds.end());
    seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());

    mSeen.nextGeneration();
    double farthest = 0.0;
    std::vector<std::uint32_t>& front = mFront;
    for (std::uint32_t seed : seeds) {
        if (!mSeen.insert(seed)) continue;
        // One component within the ball: its farthest node, its mean
        // distance past the plane, and whether it goes on out of the ball.
        front.assign(1, seed);
        double componentFarthest = 0.0, sum = 0.0;
        bool open = false;
        while (!front.empty()) {
            const std::uint32_t n = front.back();
            front.pop_back();
            const Vec3 d = offset(n);
            const double distance = std::sqrt(dot(d, d));
            if (distance >= ball) {
                open = true;
                continue;
            }
            componentFarthest = std::max(componentFarthest, distance);
            sum += dot(d, normal);
            for (std::uint32_t e = g.offset[n]; e < g.offset[n + 1]; ++e) {
                const std::uint32_t m = g.neighbour[e];
                if (!mBlocked.isMarked(m) && mSeen.insert(m)) front.push_back(m);
            }
        }
        // On average behind the plane: the body's side.
        if (sum <= 0.0) continue;
        if (open) return limitRatio;
        farthest = std::max(farthest, componentFarthest);
    }
    return farthest / loopSize;
}

}  // namespace skelseg
