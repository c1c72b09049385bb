#include "kernels/SkeletonForks.h"

#include <algorithm>
#include <cmath>

namespace skelseg {

std::uint32_t ForkSearch::countBranches(const SkeletonGraph& g,
                                        const std::vector<SkeletonPoint>& points, std::uint32_t s,
                                        double minimumRadius, float& bodyRhoS) {
    const double radius = std::max(minimumRadius, loopRadius(double(points[g.point[s]].rhoS)));
    const double reach = 2.0 * radius;
    for (std::uint32_t n : mBall.touched) mPiece[n] = kNoJunction;
    mBall.reset();
    mBall.offer(s, 0.0, reach);
    const auto anyNode = [](std::uint32_t) { return true; };
    mBall.run(g, reach, anyNode);
    // A junction point within reach already marks this branching.
    for (std::uint32_t n : mBall.touched)
        if (mBall.distance[n] <= radius && isJunctionPoint(points[g.point[n]])) return 0;
    std::uint32_t branches = 0;
    bodyRhoS = 0.0f;
    // Edges from a node to beyond the reach are bridges (no 26-step
    // leaves the ball from inside it). One from the inner ball (a limb's
    // skeleton that broke near its base, bridged here) is a branch.
    for (std::uint32_t n : mBall.touched)
        if (mBall.distance[n] <= radius)
            for (std::uint32_t e = g.offset[n]; e < g.offset[n + 1]; ++e)
                if (const std::uint32_t far = g.neighbour[e]; !mBall.reached(far)) {
                    ++branches;
                    bodyRhoS = std::max(bodyRhoS, points[g.point[far]].rhoS);
                }
    mRho.clear();
    forEachShellPart(
        g, mBall, radius, mPiece, mQueue, anyNode,
        [&](std::uint32_t n) { mRho.push_back(points[g.point[n]].rhoS); },
        [&](std::uint32_t, bool isBranch) {
            if (isBranch) {
                ++branches;
                std::nth_element(mRho.begin(), mRho.begin() + mRho.size() / 2, mRho.end());
                bodyRhoS = std::max(bodyRhoS, mRho[mRho.size() / 2]);
            }
            mRho.clear();
        });
    return branches;
}

void growRegionsToBranchSplits(SkeletonGraph& g, const SkeletonGraphOptions& options) {
    const std::uint32_t n = g.nodeCount();
    BoundedDistances ball(n);
    std::vector<std::uint32_t> mark(n, kNoJunction), component(n, kNoJunction);
    std::vector<std::uint8_t> levelled(n, 0);  // taken by the region, or its next level
    std::vector<std::uint32_t> pieces, counted, queue, taken, front, next, flooded;
    for (std::uint32_t j = 0; j < g.junctions.size(); ++j) {
        const double radius =
            std::max(double(options.regionRadius), loopRadius(double(g.junctions[j].rhoS)));
        const double reach = 2.0 * radius;
        pieces.clear();
        for (std::uint32_t r : g.junctions[j].region)
            for (std::uint32_t e = g.offset[r]; e < g.offset[r + 1]; ++e)
                if (const std::uint32_t p = g.pieceOf[g.neighbour[e]];
                    p != kNoJunction && std::find(pieces.begin(), pieces.end(), p) == pieces.end())
                    pieces.push_back(p);
        std::sort(pieces.begin(), pieces.end());
        bool grownHere = false;
        for (std::uint32_t p : pieces) {
            const auto inPiece = [&](std::uint32_t m) { return g.pieceOf[m] == p; };
            // Labels c's part of the piece's nodes the region has not taken.
            const auto floodRest = [&](std::uint32_t c) {
                component[c] = c;
                flooded.push_back(c);
                queue.assign(1, c);
                for (std::size_t h = 0; h < queue.size(); ++h)
                    for (std::uint32_t e = g.offset[queue[h]]; e < g.offset[queue[h] + 1]; ++e)
                        if (const std::uint32_t m = g.neighbour[e];
                            inPiece(m) && !levelled[m] && component[m] == kNoJunction)
                            component[m] = c, queue.push_back(m), flooded.push_back(m);
            };
            // Distances within the piece from the region, bounded by 2R.
            ball.reset();
            for (std::uint32_t r : g.junctions[j].region)
                for (std::uint32_t e = g.offset[r]; e < g.offset[r + 1]; ++e)
                    if (const std::uint32_t m = g.neighbour[e]; inPiece(m))
                        ball.offerFrom(g, r, 0.0, m, reach);
            ball.run(g, reach, inPiece);
            counted.clear();
            forEachShellPart(
                g, ball, radius, mark, queue, inPiece, [](std::uint32_t) {},
                [&](std::uint32_t seed, bool isBranch) {
                    if (isBranch) counted.push_back(seed);
                });
            taken.clear();  // nodes the region would take
            bool separated = false;
            if (counted.size() >= 2) {
                // Breadth-first levels from the region within the piece.
                front.clear();
                for (std::uint32_t r : g.junctions[j].region)
                    for (std::uint32_t e = g.offset[r]; e < g.offset[r + 1]; ++e)
                        if (const std::uint32_t m = g.neighbour[e]; inPiece(m) && !levelled[m])
                            levelled[m] = 1, front.push_back(m);
                flooded.clear();
                while (!front.empty() && !separated) {
                    if (std::any_of(front.begin(), front.end(),
                                    [&](std::uint32_t m) { return ball.distance[m] > radius; }))
                        break;
                    taken.insert(taken.end(), front.begin(), front.end());
                    // Pieces of what is left; separated when no two counted
                    // parts share one.
                    for (std::uint32_t m : flooded) component[m] = kNoJunction;
                    flooded.clear();
                    std::size_t seeds = 0;
                    for (std::uint32_t c : counted) {
                        if (component[c] != kNoJunction) break;
                        ++seeds;
                        floodRest(c);
                    }
                    separated = seeds == counted.size();
                    next.clear();
                    for (std::uint32_t m0 : front)
                        for (std::uint32_t e = g.offset[m0]; e < g.offset[m0 + 1]; ++e)
                            if (const std::uint32_t m = g.neighbour[e]; inPiece(m) && !levelled[m])
                                levelled[m] = 1, next.push_back(m);
                    front.swap(next);
                }
                if (separated) {
                    // Bits of the ball cut off from every counted part join the
                    // region as well (they are not branches).
                    for (std::uint32_t m : ball.touched)
                        if (!levelled[m] && component[m] == kNoJunction) taken.push_back(m);
                }
                for (std::uint32_t m : ball.touched) levelled[m] = 0;
                for (std::uint32_t m : front) levelled[m] = 0;
                for (std::uint32_t m : flooded) component[m] = kNoJunction;
            }
            for (std::uint32_t m : ball.touched) mark[m] = kNoJunction;
            if (!separated) continue;
            for (std::uint32_t m : taken) {
                g.junctionOf[m] = j;
                g.junctions[j].region.push_back(m);
            }
            grownHere = true;
        }
        if (!grownHere) continue;
        // Later junctions see the pieces as they are now.
        std::sort(g.junctions[j].region.begin(), g.junctions[j].region.end());
        g.pieceCount = labelComponents(
            g, [&](std::uint32_t m) { return g.junctionOf[m] == kNoJunction; }, g.pieceOf);
    }
}

}  // namespace skelseg
