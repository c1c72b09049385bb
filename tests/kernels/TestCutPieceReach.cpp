#include "kernels/CutPieceReach.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "kernels/CutPlacement.h"
#include "tests/kernels/KernelTestSupport.h"
#include "tests/kernels/SkeletonTestPoints.h"

namespace skelseg {
namespace {

using test::fillBox;

/// The boundary nodes for which `onLoop` holds, ordered by their angle round
/// their mean in the plane spanned by `u` and `v`: a cut loop round a convex
/// cross-section, in order as orderCutLoop gives it.
std::vector<std::uint32_t> loopWhere(const BoundaryGraph& g,
                                     const std::function<bool(const Coord&)>& onLoop,
                                     std::array<double, 3> u, std::array<double, 3> v) {
    std::vector<std::uint32_t> loop;
    double mean[3] = {0.0, 0.0, 0.0};
    for (std::uint32_t n = 0; n < g.nodeCount(); ++n)
        if (onLoop(g.coord[n])) {
            loop.push_back(n);
            mean[0] += g.coord[n].x, mean[1] += g.coord[n].y, mean[2] += g.coord[n].z;
        }
    for (double& m : mean) m /= double(std::max<std::size_t>(loop.size(), 1));
    const auto angle = [&](std::uint32_t n) {
        const double d[3] = {g.coord[n].x - mean[0], g.coord[n].y - mean[1],
                             g.coord[n].z - mean[2]};
        return std::atan2(d[0] * v[0] + d[1] * v[1] + d[2] * v[2],
                          d[0] * u[0] + d[1] * u[1] + d[2] * u[2]);
    };
    std::sort(loop.begin(), loop.end(),
              [&](std::uint32_t a, std::uint32_t b) { return angle(a) < angle(b); });
    return loop;
}

/// A block (a body, side 24 s) with a flat fin 12 s wide and 3 s thick along
/// x, at scale s; the loop goes round the fin `past` voxels before its end.
struct Fin {
    int bodyEnd = 0, finEnd = 0;
    BoundaryGraph graph;
    std::vector<std::uint32_t> loop;
    Fin(int s, int past) {
        const int body = 24 * s, length = 16 * s, width = 12 * s, thickness = 3 * s;
        bodyEnd = 2 + body;
        finEnd = bodyEnd + length;
        MaskVolume mask(Dims{finEnd + 3, body + 4, body + 4}, 0);
        fillBox(mask, {2, 2, 2}, {bodyEnd, body + 1, body + 1});
        const int y0 = 2 + (body - width) / 2, z0 = 2 + (body - thickness) / 2;
        fillBox(mask, {bodyEnd, y0, z0}, {finEnd, y0 + width - 1, z0 + thickness - 1});
        graph = buildBoundaryGraph(mask);
        const int x = finEnd - past;
        loop = loopWhere(graph, [x](const Coord& c) { return c.x == x; }, {0, 1, 0}, {0, 0, 1});
    }
    std::array<double, 3> junction() const { return {double(bodyEnd) / 2.0, 14.0, 14.0}; }
};

/// The fin's reach with its loop `past` voxels before its end, at scale s:
/// the tip's corner against the loop's corner (the loop is the rim of the
/// cross-section, whose mean is the cross-section's centre).
double expectedFinReach(int scale, int past) {
    const double halfWidth = (12.0 * scale - 1.0) / 2.0, halfThickness = (3.0 * scale - 1.0) / 2.0;
    const double loop = std::hypot(halfWidth, halfThickness);
    return std::sqrt(double(past) * double(past) + loop * loop) / loop;
}

/// A block's corner cut off by the loop x + y + z = K, `fromCorner` voxels
/// from the corner along each edge, on a block of side 20 s.
struct BlockCorner {
    BoundaryGraph graph;
    std::vector<std::uint32_t> loop;
    BlockCorner(int scale, int fromCorner) {
        const int hi = 2 + 20 * scale;
        MaskVolume mask(Dims{hi + 3, hi + 3, hi + 3}, 0);
        fillBox(mask, {2, 2, 2}, {hi, hi, hi});
        graph = buildBoundaryGraph(mask);
        const int k = 3 * hi - fromCorner;
        const double s2 = std::sqrt(2.0), s6 = std::sqrt(6.0);
        loop = loopWhere(graph, [k](const Coord& c) { return c.x + c.y + c.z == k; },
                         {1 / s2, -1 / s2, 0}, {1 / s6, 1 / s6, -2 / s6});
    }
};

TEST(CutPieceReach, FinSticksOutOfItsLoopsBallAtTwoScales) {
    // A flat fin's loop is long and thin (12 s by 3 s): the piece 6 s long
    // past it reaches to the tip's corner, the same multiple of the loop's
    // size at any scale.
    for (const int scale : {1, 2}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        const Fin fin(scale, 6 * scale);
        ASSERT_GT(fin.loop.size(), 20u);
        const double reach = pieceReachPastLoop(fin.graph, fin.loop, fin.loop, fin.junction(), 3.0);
        EXPECT_NEAR(reach, expectedFinReach(scale, 6 * scale), 1e-9);
        EXPECT_GT(reach, 1.3);
        EXPECT_DOUBLE_EQ(pieceReachPastLoop(fin.graph, fin.loop, fin.loop, fin.junction(), 1.2),
                         1.2)
            << "the flood stops at the limit";
    }
}

TEST(CutPieceReach, TheBodyIsNotThePiece) {
    // Seen from past the fin's tip, the piece away from the "junction" is
    // the body: it leaves the ball past the plane, so the reach is the limit.
    const Fin fin(1, 6);
    const std::array<double, 3> beyondTip{double(fin.finEnd) + 10.0, 14.0, 14.0};
    EXPECT_DOUBLE_EQ(pieceReachPastLoop(fin.graph, fin.loop, fin.loop, beyondTip, 3.0), 3.0);
}

TEST(CutPieceReach, CornerOfABlockStaysInItsLoopsBallAtTwoScales) {
    // A loop across a block's corner (the plane x + y + z = K, 4 s voxels
    // from the corner along each edge) cuts off a tetrahedron whose farthest
    // node from the loop's centre is no farther than the loop's own nodes.
    for (const int scale : {1, 2}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        const BlockCorner corner(scale, 4 * scale);
        ASSERT_GE(corner.loop.size(), 6u);
        const double reach =
            pieceReachPastLoop(corner.graph, corner.loop, corner.loop, {12.0, 12.0, 12.0}, 3.0);
        EXPECT_GT(reach, 0.0);
        EXPECT_LE(reach, 1.0);
    }
}

TEST(CutPieceReach, OneMeasurerForManyLoopsAnswersAsAFreshCallEachTime) {
    // The cut placement asks one measurer about every cut of an object; the
    // marks of one flood must not leak into the next (a node left "seen"
    // would end a later component early, one left "blocked" would cut it).
    // Loops at every distance from the fin's end, from either side and with
    // limits on both sides of the reach, asked in turn of one measurer.
    const Fin fin(1, 6);
    const std::array<double, 3> beyondTip{double(fin.finEnd) + 10.0, 14.0, 14.0};
    PieceReachMeasurer measurer(fin.graph);
    int answers = 0, distinct = 0;
    double previous = -1.0;
    for (int past = 2; past <= 14; past += 3) {
        const Fin at(1, past);
        ASSERT_EQ(at.graph.nodeCount(), fin.graph.nodeCount());
        for (const auto& junction : {at.junction(), beyondTip})
            for (const double limit : {1.2, 3.0}) {
                SCOPED_TRACE("past " + std::to_string(past) + ", limit " + std::to_string(limit));
                const double fresh =
                    pieceReachPastLoop(fin.graph, at.loop, at.loop, junction, limit);
                EXPECT_EQ(measurer.measure(at.loop, at.loop, junction, limit), fresh);
                ++answers;
                distinct += fresh != previous;
                previous = fresh;
            }
    }
    EXPECT_EQ(answers, 20);
    EXPECT_GT(distinct, 10) << "the loops must give different answers to tell a stale mark";
}

/// A body (rho_S 40 s) and one limb of rho_S 20 s (loop radius 6.4 s) whose
/// skeleton goes on `levelsPastCut` levels past its first level, where it is
/// cut, at scale s (as in TestCutPlacement.cpp); `reach` answers the corner
/// rule's question about the piece past the cut.
CutPlan limbWithPiece(int scale, int levelsPastCut, const PieceReach& reach) {
    const test::SkeletonPointSet set = test::bodyWithOneLimb(scale, 3 + 1 + levelsPastCut);
    const std::vector<SkeletonPoint> points = set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
    return placeCuts(
        g, points, {}, [](std::uint32_t) { return 0.0; }, {}, reach);
}

const CutCandidate* limbCut(const CutPlan& plan) {
    for (const CutCandidate& c : plan.candidates)
        if (c.junction == 0 && !c.onBody) return &c;
    return nullptr;
}

TEST(CutPieceReach, FinEndingPastItsSkeletonIsCutACornerIsNotAtTwoScales) {
    // Both skeletons end 3 s levels past the cut, 0.47 loop radii: under
    // half a radius, so the skeleton's levels take both for corners (PSB
    // 222's dorsal fin at resolution 192, docs/quality.md "sweep17"). The
    // fin's surface goes on 6 s past its loop and sticks out of the loop's
    // ball; the block's corner stays inside it: the piece's reach tells them
    // apart at both scales.
    for (const int scale : {1, 2}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        const Fin fin(scale, 6 * scale);
        const BlockCorner corner(scale, 4 * scale);
        int calls = 0;
        const CutPlan finPlan = limbWithPiece(scale, 3 * scale, [&](std::uint32_t, std::uint32_t) {
            ++calls;
            return pieceReachPastLoop(fin.graph, fin.loop, fin.loop, fin.junction(),
                                      2.0 * CutOptions{}.cornerReach);
        });
        const CutCandidate* c = limbCut(finPlan);
        ASSERT_NE(c, nullptr);
        EXPECT_GT(calls, 0);
        EXPECT_LT(c->similarity, 0.6f);
        EXPECT_FALSE(c->isCorner);
        EXPECT_TRUE(c->isCut);
        EXPECT_EQ(finPlan.cutNodes.size(), 1u);

        const CutPlan cornerPlan =
            limbWithPiece(scale, 3 * scale, [&](std::uint32_t, std::uint32_t) {
                return pieceReachPastLoop(corner.graph, corner.loop, corner.loop,
                                          {12.0, 12.0, 12.0}, 2.0 * CutOptions{}.cornerReach);
            });
        c = limbCut(cornerPlan);
        ASSERT_NE(c, nullptr);
        EXPECT_TRUE(c->isCorner);
        EXPECT_FALSE(c->isCut);
        EXPECT_TRUE(cornerPlan.cutNodes.empty());
    }
}

}  // namespace
}  // namespace skelseg
