#include "kernels/SkeletonGraph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <set>

#include "tests/kernels/SkeletonTestPoints.h"
#include "tests/support/StopAtOnce.h"

namespace skelseg {
namespace {

using test::nodeOf;
using test::SkeletonPointSet;
using test::StopAtOnce;

/// A Y: a centre voxel with three 12-voxel arms in the z = 1 plane.
struct YShape {
    SkeletonPointSet set{Dims{41, 41, 3}};
    std::uint32_t centre;
    std::vector<std::uint32_t> arms[3];
    YShape() {
        centre = set.add({20, 20, 1}, 20.0f, 1000.0, 3);
        arms[0] = set.chain({21, 20, 1}, {1, 0, 0}, 12);
        arms[1] = set.chain({19, 21, 1}, {-1, 1, 0}, 12);
        arms[2] = set.chain({19, 19, 1}, {-1, -1, 0}, 12);
    }
};

TEST(SkeletonGraph, YGivesOneJunctionWithThreeBranches) {
    YShape y;
    const std::vector<SkeletonPoint> points = y.set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, y.set.dims(), {});
    ASSERT_EQ(g.nodeCount(), 37u);
    EXPECT_EQ(g.edges.size(), 36u);  // a tree: the chains and the centre
    EXPECT_EQ(g.bridgeCount, 0u);
    ASSERT_EQ(g.junctions.size(), 1u);
    const SkeletonJunction& j = g.junctions[0];
    const std::uint32_t centre = nodeOf(g, points, y.centre);
    EXPECT_EQ(j.core, std::vector<std::uint32_t>{centre});
    EXPECT_EQ(j.representative, centre);
    EXPECT_EQ(j.rhoS, 20.0f);
    // Region: the centre and the first regionRadius (3) voxels of each arm.
    EXPECT_EQ(j.region.size(), 10u);
    for (const auto& arm : y.arms)
        for (std::size_t i = 0; i < arm.size(); ++i)
            EXPECT_EQ(g.junctionOf[nodeOf(g, points, arm[i])], i < 3 ? 0u : kNoJunction)
                << "arm voxel " << i;
    // Three branch pieces of 9 voxels each, one per arm.
    ASSERT_EQ(g.pieceCount, 3u);
    std::set<std::uint32_t> pieces;
    for (const auto& arm : y.arms) {
        const std::uint32_t piece = g.pieceOf[nodeOf(g, points, arm[5])];
        ASSERT_NE(piece, kNoJunction);
        pieces.insert(piece);
        for (std::size_t i = 3; i < arm.size(); ++i)
            EXPECT_EQ(g.pieceOf[nodeOf(g, points, arm[i])], piece);
    }
    EXPECT_EQ(pieces.size(), 3u);
    // CSR and edge list agree; adjacency is symmetric.
    EXPECT_EQ(g.neighbour.size(), 2 * g.edges.size());
    for (const auto& e : g.edges) {
        EXPECT_LT(e[0], e[1]);
        auto has = [&](std::uint32_t a, std::uint32_t b) {
            return std::find(g.neighbour.begin() + g.offset[a],
                             g.neighbour.begin() + g.offset[a + 1],
                             b) != g.neighbour.begin() + g.offset[a + 1];
        };
        EXPECT_TRUE(has(e[0], e[1]));
        EXPECT_TRUE(has(e[1], e[0]));
    }
}

TEST(SkeletonGraph, WithoutRobustCentreOrForksThereIsNoJunction) {
    YShape y;
    y.set.point(y.centre).robustRims = 2;
    SkeletonGraphOptions options;
    options.forkJunctions = false;
    const SkeletonGraph g = buildSkeletonGraph(y.set.points(), y.set.dims(), options);
    EXPECT_TRUE(g.junctions.empty());
    EXPECT_EQ(g.pieceCount, 1u);
}

/// A Y without any J_tau point, `scale` times the size of YShape: arms of
/// 12 * scale voxels with rho_S 10 * scale, and the stem (arm 0) twice as
/// thick as the other two, as a body with two limbs.
struct ScaledFork {
    SkeletonPointSet set;
    std::uint32_t centre;
    ScaledFork(int scale) : set(Dims{40 * scale + 1, 40 * scale + 1, 3}) {
        const int c = 20 * scale, length = 12 * scale;
        const float rho = 10.0f * float(scale);
        centre = set.add({c, c, 1}, rho, 1000.0, 2);
        set.chain({c + 1, c, 1}, {1, 0, 0}, length, 2.0f * rho);
        set.chain({c - 1, c + 1, 1}, {-1, 1, 0}, length, rho);
        set.chain({c - 1, c - 1, 1}, {-1, -1, 0}, length, rho);
    }
};

TEST(SkeletonGraph, ForkWithoutJunctionPointIsOneJunctionAtEveryScale) {
    // Where no point's path set goes round three parts, the branching of
    // C_tau still is a junction, whatever the resolution.
    for (int scale : {1, 2, 3}) {
        ScaledFork y(scale);
        const std::vector<SkeletonPoint> points = y.set.points();
        const SkeletonGraph g = buildSkeletonGraph(points, y.set.dims(), {});
        ASSERT_EQ(g.junctions.size(), 1u) << "scale " << scale;
        const SkeletonJunction& j = g.junctions[0];
        const std::uint32_t centre = nodeOf(g, points, y.centre);
        EXPECT_NE(std::find(j.core.begin(), j.core.end(), centre), j.core.end());
        EXPECT_EQ(g.pieceCount, 3u) << "scale " << scale;
        // The body's loop (the thick stem's), not a limb's: rho_S 20 * scale.
        EXPECT_EQ(j.rhoS, 20.0f * float(scale)) << "scale " << scale;
    }
}

TEST(SkeletonGraph, ForksAroundAJunctionPointAddNoCore) {
    // With a J_tau point within reach the junction is the paper's alone.
    YShape y;
    const std::vector<SkeletonPoint> points = y.set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, y.set.dims(), {});
    ASSERT_EQ(g.junctions.size(), 1u);
    EXPECT_EQ(g.junctions[0].core, std::vector<std::uint32_t>{nodeOf(g, points, y.centre)});
}

TEST(SkeletonGraph, ForkBesideAJunctionSeparatesItsLimbs) {
    // A limb branching off another 1.3 radii from a junction point (two
    // octopus arms whose skeletons join just before the mouth's junction):
    // the fork is a junction of its own, so the two limbs are different
    // branches. A J_tau point within one radius of a node (not within its
    // whole ball of two radii) is what marks the branching as the
    // junction's own.
    SkeletonPointSet set(Dims{101, 101, 3});
    set.add({50, 50, 1}, 60.0f, 1000.0, 3);
    const std::vector<std::uint32_t> stem = set.chain({51, 50, 1}, {1, 0, 0}, 40, 30.0f);
    set.chain({49, 51, 1}, {-1, 1, 0}, 40, 30.0f);
    set.chain({49, 49, 1}, {-1, -1, 0}, 40, 30.0f);
    const std::vector<std::uint32_t> side = set.chain({62, 51, 1}, {0, 1, 0}, 40, 30.0f);
    const std::vector<SkeletonPoint> points = set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
    const std::uint32_t sidePiece = g.pieceOf[nodeOf(g, points, side[30])];
    const std::uint32_t stemPiece = g.pieceOf[nodeOf(g, points, stem[35])];
    ASSERT_NE(sidePiece, kNoJunction);
    ASSERT_NE(stemPiece, kNoJunction);
    EXPECT_NE(sidePiece, stemPiece);
}

TEST(SkeletonGraph, ForksWhoseRegionsLeaveTwoBranchesAreNoJunction) {
    // A limb branching off 0.6 radii from a junction point: the branching
    // itself lies within one radius of the J_tau point, so it is no fork;
    // the nodes around it see three branches but form two clusters on
    // either side whose regions leave two branches each. A fork is three
    // branches, so neither is a junction: the junction point's is the only
    // one (as on an elephant's head, whose forks' regions swallowed a short
    // branch and cut the trunk in some poses only).
    SkeletonPointSet set(Dims{101, 101, 3});
    const std::uint32_t centre = set.add({50, 50, 1}, 60.0f, 1000.0, 3);
    set.chain({51, 50, 1}, {1, 0, 0}, 40, 30.0f);
    set.chain({49, 51, 1}, {-1, 1, 0}, 40, 30.0f);
    set.chain({49, 49, 1}, {-1, -1, 0}, 40, 30.0f);
    set.chain({56, 51, 1}, {0, 1, 0}, 40, 30.0f);
    const std::vector<SkeletonPoint> points = set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
    ASSERT_EQ(g.junctions.size(), 1u);
    EXPECT_EQ(g.junctions[0].core, std::vector<std::uint32_t>{nodeOf(g, points, centre)});
}

TEST(SkeletonGraph, RegionReachesTheSplitOfTwoLimbsBesideAJunction) {
    // Two limbs whose skeletons join 0.6 radii from a junction point, just
    // outside its region (a hand's ring and little fingers at some
    // resolutions): the fork there is left to the junction, so the
    // junction's region grows along the piece to the split and the two
    // limbs leave it as two branches, at 1x and 2x. The region stops at the
    // split: the limbs' own skeletons stay outside it.
    for (const int scale : {1, 2}) {
        SkeletonPointSet set(Dims{101 * scale, 101 * scale, 3});
        const int c = 50 * scale, length = 40 * scale, split = 6 * scale;
        const float body = 60.0f * float(scale), limb = 30.0f * float(scale);
        const std::uint32_t centre = set.add({c, c, 1}, body, 1000.0, 3);
        const std::vector<std::uint32_t> stem = set.chain({c + 1, c, 1}, {1, 0, 0}, length, limb);
        set.chain({c - 1, c + 1, 1}, {-1, 1, 0}, length, body);
        set.chain({c - 1, c - 1, 1}, {-1, -1, 0}, length, body);
        const std::vector<std::uint32_t> side =
            set.chain({c + split, c + 1, 1}, {0, 1, 0}, length, limb);
        const std::vector<SkeletonPoint> points = set.points();
        const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
        ASSERT_EQ(g.junctions.size(), 1u) << "scale " << scale;
        EXPECT_EQ(g.junctions[0].core, std::vector<std::uint32_t>{nodeOf(g, points, centre)});
        const std::uint32_t sidePiece = g.pieceOf[nodeOf(g, points, side[length / 2])];
        const std::uint32_t stemPiece = g.pieceOf[nodeOf(g, points, stem[length / 2])];
        ASSERT_NE(sidePiece, kNoJunction) << "scale " << scale;
        ASSERT_NE(stemPiece, kNoJunction) << "scale " << scale;
        EXPECT_NE(sidePiece, stemPiece) << "scale " << scale;
        EXPECT_EQ(g.pieceCount, 4u) << "scale " << scale;
        EXPECT_EQ(g.junctionOf[nodeOf(g, points, stem[std::size_t(split) + 1])], kNoJunction)
            << "scale " << scale;
        EXPECT_EQ(g.junctionOf[nodeOf(g, points, side[1])], kNoJunction) << "scale " << scale;
        SkeletonGraphOptions without;
        without.growRegionsToSplits = false;
        const SkeletonGraph h = buildSkeletonGraph(points, set.dims(), without);
        EXPECT_EQ(h.pieceCount, 3u) << "scale " << scale;
    }
}

TEST(SkeletonGraph, RegionDoesNotGrowAlongALoopOfTheSkeleton) {
    // A piece whose two strands part beside a junction and join again (a
    // handle, a hole in the thick skeleton) carries one branch: the region
    // keeps its size.
    SkeletonPointSet set(Dims{101, 101, 3});
    set.add({50, 50, 1}, 60.0f, 1000.0, 3);
    set.chain({51, 50, 1}, {1, 0, 0}, 40, 30.0f);
    set.chain({49, 51, 1}, {-1, 1, 0}, 40, 60.0f);
    set.chain({49, 49, 1}, {-1, -1, 0}, 40, 60.0f);
    set.chain({56, 51, 1}, {0, 1, 0}, 30, 30.0f);
    set.chain({56, 81, 1}, {1, 0, 0}, 30, 30.0f);
    set.chain({86, 51, 1}, {0, 1, 0}, 30, 30.0f);
    const std::vector<SkeletonPoint> points = set.points();
    SkeletonGraphOptions without;
    without.growRegionsToSplits = false;
    const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
    const SkeletonGraph h = buildSkeletonGraph(points, set.dims(), without);
    ASSERT_EQ(g.junctions.size(), 1u);
    EXPECT_EQ(g.junctions[0].region, h.junctions[0].region);
    EXPECT_EQ(g.pieceCount, h.pieceCount);
}

TEST(SkeletonGraph, LimbBridgedToTheMiddleOfABranchMakesAFork) {
    // A limb whose skeleton stops 10 voxels short of a body's branch (the
    // octopus's arms, bridged to a neighbour's skeleton, at 256), at 1x and
    // 2x: the bridge leaves the body node's ball of two radii, and still it
    // is a third branch there.
    for (const int scale : {1, 2}) {
        const Dims dims{41 * scale, 31 * scale, 3};
        SkeletonPointSet set(dims);
        const float rho = 12.0f * float(scale);
        const std::vector<std::uint32_t> body =
            set.chain({0, 5 * scale, 1}, {1, 0, 0}, 41 * scale, rho);
        const std::vector<std::uint32_t> limb =
            set.chain({20 * scale, 15 * scale, 1}, {0, 1, 0}, 15 * scale, rho);
        MaskVolume object(dims, 1);
        SkeletonGraphOptions options;
        options.inside = &object;
        const std::vector<SkeletonPoint> points = set.points();
        const SkeletonGraph g = buildSkeletonGraph(points, dims, options);
        ASSERT_EQ(g.bridgeCount, 1u) << "scale " << scale;
        ASSERT_EQ(g.junctions.size(), 1u) << "scale " << scale;
        EXPECT_EQ(g.pieceCount, 3u) << "scale " << scale;
        EXPECT_NE(g.pieceOf[nodeOf(g, points, limb.back())],
                  g.pieceOf[nodeOf(g, points, body.front())])
            << "scale " << scale;
    }
}

TEST(SkeletonGraph, ShortSpurIsNoFork) {
    // A bump of the thick skeleton shorter than the part's radius is no
    // branch: a straight chain with a 2-voxel spur stays one piece.
    SkeletonPointSet set(Dims{41, 11, 3});
    set.chain({0, 5, 1}, {1, 0, 0}, 41);
    set.chain({20, 6, 1}, {0, 1, 0}, 2);
    const SkeletonGraph g = buildSkeletonGraph(set.points(), set.dims(), {});
    EXPECT_TRUE(g.junctions.empty());
    EXPECT_EQ(g.pieceCount, 1u);
}

TEST(SkeletonGraph, JunctionClusterIsOneJunctionWithMedianRhoS) {
    YShape y;
    // Two more junction voxels next to the centre: one cluster of three.
    y.set.point(y.arms[0][0]).robustRims = 3;
    y.set.point(y.arms[0][0]).rhoS = 26.0f;
    y.set.add({20, 21, 1}, 14.0f, 1000.0, 4);  // touches the centre and arm 1
    const std::vector<SkeletonPoint> points = y.set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, y.set.dims(), {});
    ASSERT_EQ(g.junctions.size(), 1u);
    EXPECT_EQ(g.junctions[0].core.size(), 3u);
    EXPECT_EQ(g.junctions[0].rhoS, 20.0f);  // median of 14, 20, 26
    EXPECT_EQ(g.junctions[0].representative, nodeOf(g, points, y.centre));
    EXPECT_EQ(g.pieceCount, 3u);

    // Even count: the mean of the two middle values.
    y.set.point(y.set.voxelIndex({20, 21, 1})).robustRims = 2;
    const SkeletonGraph g2 = buildSkeletonGraph(y.set.points(), y.set.dims(), {});
    ASSERT_EQ(g2.junctions.size(), 1u);
    EXPECT_EQ(g2.junctions[0].core.size(), 2u);
    EXPECT_EQ(g2.junctions[0].rhoS, 23.0f);
}

/// A chain along x with two junction voxels (rho_S `rhoS`) `distance` apart.
SkeletonPointSet twoJunctionsOnAChain(int distance, float rhoS) {
    SkeletonPointSet set(Dims{40, 5, 3});
    const auto chain = set.chain({5, 2, 1}, {1, 0, 0}, 25);
    for (const std::uint32_t v : {chain[5], chain[5 + std::size_t(distance)]}) {
        set.point(v).robustRims = 3;
        set.point(v).rhoS = rhoS;
    }
    return set;
}

TEST(SkeletonGraph, JunctionRegionsThatTouchMerge) {
    // Junction voxels on one chain `distance` apart, in a part of radius 15.9
    // (rho_S 50): with regionRadius 3 the regions touch (and merge) up to
    // distance 7, not at 8.
    for (int distance : {7, 8}) {
        const SkeletonPointSet set = twoJunctionsOnAChain(distance, 50.0f);
        const SkeletonGraph g = buildSkeletonGraph(set.points(), set.dims(), {});
        EXPECT_EQ(g.junctions.size(), distance == 7 ? 1u : 2u) << "distance " << distance;
        // Pieces: the two ends, plus the voxel between two separate regions.
        EXPECT_EQ(g.pieceCount, distance == 7 ? 2u : 3u) << "distance " << distance;
        EXPECT_TRUE(g.junctionContacts.empty());
    }
}

TEST(SkeletonGraph, TouchingRegionsOfJunctionsARadiusApartStayTwo) {
    // The same chain in a part of radius 6.4 (rho_S 20): cores 7 voxels apart
    // are 1.1 radii apart, two junctions whether their regions touch (as at
    // a low resolution) or not; the touching regions are a contact.
    const SkeletonPointSet set = twoJunctionsOnAChain(7, 20.0f);
    const std::vector<SkeletonPoint> points = set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
    ASSERT_EQ(g.junctions.size(), 2u);
    EXPECT_EQ(g.pieceCount, 2u) << "the two ends; nothing between the regions";
    ASSERT_EQ(g.junctionContacts.size(), 1u);
    const JunctionContact& contact = g.junctionContacts[0];
    EXPECT_EQ(contact.junction, 0u);
    EXPECT_EQ(contact.other, 1u);
    EXPECT_EQ(g.junctionOf[contact.node], 0u);
    EXPECT_EQ(g.junctionOf[contact.otherNode], 1u);
    EXPECT_EQ(std::abs(g.coord[contact.node].x - g.coord[contact.otherNode].x), 1);

    SkeletonGraphOptions merging;
    merging.junctionMergeRadii = 0.0;
    const SkeletonGraph merged = buildSkeletonGraph(points, set.dims(), merging);
    EXPECT_EQ(merged.junctions.size(), 1u) << "0: every touching pair is one junction";
    EXPECT_TRUE(merged.junctionContacts.empty());
}

/// Two chains along x at y = 5, the second starting `gap` empty voxels after
/// the first ends.
SkeletonPointSet twoChains(int gap, std::uint32_t& endA, std::uint32_t& startB) {
    SkeletonPointSet set(Dims{40, 11, 3});
    endA = set.chain({2, 5, 1}, {1, 0, 0}, 10).back();  // x = 2..11
    startB = set.chain({12 + gap, 5, 1}, {1, 0, 0}, 10).front();
    return set;
}

TEST(SkeletonGraph, SmallGapIsBridged) {
    std::uint32_t endA = 0, startB = 0;
    const SkeletonPointSet set = twoChains(3, endA, startB);
    const std::vector<SkeletonPoint> points = set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
    EXPECT_EQ(g.bridgeCount, 1u);
    EXPECT_EQ(g.edges.size(), 9u + 9u + 1u);
    // The bridge joins the closest pair: the facing chain ends.
    const std::uint32_t a = nodeOf(g, points, endA), b = nodeOf(g, points, startB);
    EXPECT_NE(std::find(g.edges.begin(), g.edges.end(),
                        std::array<std::uint32_t, 2>{std::min(a, b), std::max(a, b)}),
              g.edges.end());
    EXPECT_EQ(g.pieceCount, 1u);  // walks follow the bridge
}

TEST(SkeletonGraph, LargeGapIsNotBridged) {
    for (int gap : {5, 6}) {
        std::uint32_t endA = 0, startB = 0;
        const SkeletonPointSet set = twoChains(gap, endA, startB);
        const SkeletonGraph g = buildSkeletonGraph(set.points(), set.dims(), {});
        EXPECT_EQ(g.bridgeCount, 0u) << "gap " << gap;
        EXPECT_EQ(g.edges.size(), 18u);
        EXPECT_EQ(g.pieceCount, 2u);
    }
    // bridgeGap below 1 turns bridging off.
    std::uint32_t endA = 0, startB = 0;
    const SkeletonPointSet set = twoChains(3, endA, startB);
    SkeletonGraphOptions options;
    options.bridgeGap = 0.0;
    EXPECT_EQ(buildSkeletonGraph(set.points(), set.dims(), options).bridgeCount, 0u);
}

TEST(SkeletonGraph, GapWithinThePartsRadiusIsBridgedAtAnyResolution) {
    // The same break of a limb's skeleton, drawn at 1x and 2x the
    // resolution: 3 and 6 empty voxels between chains whose loops have
    // rho_S 15 and 30 (radius 4.8 and 9.5 voxels). Both are bridged.
    for (const int scale : {1, 2}) {
        SkeletonPointSet set(Dims{60, 11, 3});
        const float rhoS = 15.0f * float(scale);
        const std::uint32_t endA = set.chain({2, 5, 1}, {1, 0, 0}, 10 * scale, rhoS).back();
        const std::uint32_t startB =
            set.chain({2 + 10 * scale + 3 * scale, 5, 1}, {1, 0, 0}, 10, rhoS).front();
        const std::vector<SkeletonPoint> points = set.points();
        const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
        EXPECT_EQ(g.bridgeCount, 1u) << "scale " << scale;
        const std::uint32_t a = nodeOf(g, points, endA), b = nodeOf(g, points, startB);
        EXPECT_NE(std::find(g.edges.begin(), g.edges.end(),
                            std::array<std::uint32_t, 2>{std::min(a, b), std::max(a, b)}),
                  g.edges.end())
            << "scale " << scale;
        EXPECT_EQ(g.pieceCount, 1u) << "scale " << scale;
    }
    // The reach of both ends counts: a thin piece (rho_S 10, radius 3.2,
    // so the bridgeGap of 4) 6 voxels from a thick one stays apart.
    SkeletonPointSet set(Dims{40, 11, 3});
    set.chain({2, 5, 1}, {1, 0, 0}, 10, 30.0f);
    set.chain({18, 5, 1}, {1, 0, 0}, 10, 10.0f);
    EXPECT_EQ(buildSkeletonGraph(set.points(), set.dims(), {}).bridgeCount, 0u);
}

TEST(SkeletonGraph, PieceLeftFloatingIsJoinedThroughTheObject) {
    // A limb's skeleton (rho_S 15, radius 4.8) that stops 14 voxels short of
    // the body's (rho_S 30), as the horse's hind leg at 128, drawn at 1x and
    // 2x: beyond every reach, but the segment between them lies inside the
    // object, so it is joined; without the object's voxels it is not.
    for (const int scale : {1, 2}) {
        const Dims dims{20 + 40 * scale, 11, 3};
        SkeletonPointSet set(dims);
        const std::uint32_t endA = set.chain({2, 5, 1}, {1, 0, 0}, 10, 30.0f).back();
        const std::uint32_t startB =
            set.chain({11 + 15 * scale, 5, 1}, {1, 0, 0}, 10 * scale, 15.0f * float(scale)).front();
        MaskVolume object(dims, 0);
        for (int x = 1; x < dims.x - 1; ++x)
            for (int y = 1; y < dims.y - 1; ++y) object(x, y, 1) = 1;
        const std::vector<SkeletonPoint> points = set.points();
        EXPECT_EQ(buildSkeletonGraph(points, dims, {}).pieceCount, 2u) << "scale " << scale;
        SkeletonGraphOptions options;
        options.inside = &object;
        const SkeletonGraph g = buildSkeletonGraph(points, dims, options);
        EXPECT_EQ(g.bridgeCount, 1u) << "scale " << scale;
        EXPECT_EQ(g.bridgesAlongObject, 0u) << "scale " << scale;
        EXPECT_EQ(g.pieceCount, 1u) << "scale " << scale;
        const std::uint32_t a = nodeOf(g, points, endA), b = nodeOf(g, points, startB);
        EXPECT_NE(std::find(g.edges.begin(), g.edges.end(),
                            std::array<std::uint32_t, 2>{std::min(a, b), std::max(a, b)}),
                  g.edges.end())
            << "scale " << scale;
        // Where the segment leaves the object (a gap of background across
        // it), the pieces stay apart.
        for (int y = 0; y < dims.y; ++y) object(18, y, 1) = 0;
        EXPECT_EQ(buildSkeletonGraph(points, dims, options).pieceCount, 2u) << "scale " << scale;
    }
}

TEST(SkeletonGraph, PieceOfAFoldedLimbIsJoinedAlongTheObjectAndALonePointIsNot) {
    // A comb of three bars joined at x >= 40, background between the bars:
    // the body's skeleton (rho_S 30) in the first, a folded limb's piece
    // (rho_S 6, radius 1.9, 12 voxels long) in the second, a lone point of
    // C_tau (a hoof's tip) in the third. No straight segment inside the
    // object joins any two; paths along it through the base do. The limb's
    // piece is joined; the lone point spans less than its part's width and
    // is left apart.
    const Dims dims{48, 21, 3};
    MaskVolume object(dims, 0);
    for (int y = 1; y < 20; ++y)
        for (int x = 1; x < dims.x - 1; ++x)
            if (y <= 4 || (y >= 8 && y <= 11) || y >= 15 || x >= 40) object(x, y, 1) = 1;
    SkeletonPointSet set(dims);
    const std::vector<std::uint32_t> body = set.chain({2, 2, 1}, {1, 0, 0}, 36, 30.0f);
    const std::vector<std::uint32_t> limb = set.chain({4, 10, 1}, {1, 0, 0}, 12, 6.0f);
    const std::uint32_t lone = set.add({30, 17, 1}, 6.0f);
    const std::vector<SkeletonPoint> points = set.points();
    SkeletonGraphOptions options;
    options.inside = &object;
    const SkeletonGraph g = buildSkeletonGraph(points, dims, options);
    EXPECT_EQ(g.bridgeCount, 1u);
    EXPECT_EQ(g.bridgesAlongObject, 1u);
    EXPECT_EQ(g.pieceCount, 2u);  // body and limb joined; the lone point apart
    // The bridge joins the two ends nearest the comb's base.
    const std::uint32_t a = nodeOf(g, points, body.back()), b = nodeOf(g, points, limb.back());
    EXPECT_NE(std::find(g.edges.begin(), g.edges.end(),
                        std::array<std::uint32_t, 2>{std::min(a, b), std::max(a, b)}),
              g.edges.end());
    const std::uint32_t l = nodeOf(g, points, lone);
    EXPECT_EQ(g.offset[l + 1], g.offset[l]);
    // Without the base, nothing joins them.
    for (int y = 0; y < dims.y; ++y)
        for (int x = 40; x < dims.x; ++x) object(x, y, 1) = 0;
    EXPECT_EQ(buildSkeletonGraph(points, dims, options).bridgeCount, 0u);
}

TEST(SkeletonGraph, OneBridgePerPairOfParts) {
    // Two parallel chains 3 voxels apart: many pairs within reach, one bridge.
    SkeletonPointSet set(Dims{30, 12, 3});
    set.chain({2, 3, 1}, {1, 0, 0}, 20);
    set.chain({2, 7, 1}, {1, 0, 0}, 20);
    // A third part within reach of both: joined once (spanning forest).
    set.chain({24, 5, 1}, {1, 0, 0}, 4);
    const SkeletonGraph g = buildSkeletonGraph(set.points(), set.dims(), {});
    EXPECT_EQ(g.bridgeCount, 2u);
    EXPECT_EQ(g.pieceCount, 1u);
}

TEST(SkeletonGraph, PointsBelowTauAreLeftOut) {
    SkeletonPointSet set(Dims{20, 5, 3});
    set.chain({2, 2, 1}, {1, 0, 0}, 5, 10.0f, 100.0);
    set.chain({7, 2, 1}, {1, 0, 0}, 5, 10.0f, 40.0);                      // below tau
    set.add({12, 2, 1}, 10.0f, std::numeric_limits<double>::infinity());  // handle loop: kept
    SkeletonGraphOptions options;
    options.tau = 50.0;
    options.bridgeGap = 0.0;
    const SkeletonGraph g = buildSkeletonGraph(set.points(), set.dims(), options);
    EXPECT_EQ(g.nodeCount(), 6u);
    EXPECT_EQ(g.pieceCount, 2u);
    for (std::uint32_t n = 0; n < g.nodeCount(); ++n)
        EXPECT_GE(set.points()[g.point[n]].rhoC, 50.0);
}

/// Six chains from a centre with no J_tau point (a fork of six branches) and,
/// apart from it, a square sheet of C_tau: a fork test per node, whose ball
/// on the sheet holds most of the sheet.
SkeletonPointSet starAndSheet() {
    SkeletonPointSet set(Dims{90, 50, 3});
    set.add({20, 20, 1}, 20.0f);
    const std::array<std::array<int, 3>, 6> steps{
        {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {1, 1, 0}, {-1, -1, 0}}};
    for (const auto& step : steps)
        set.chain({20 + step[0], 20 + step[1], 1}, step, 15, 6.0f + float(step[0] + 2 * step[1]));
    for (int y = 5; y < 45; ++y)
        for (int x = 50; x < 88; ++x) set.add({x, y, 1}, 30.0f + float((x * 7 + y * 3) % 11));
    return set;
}

TEST(SkeletonGraph, SerialAndParallelForkTestsGiveTheSameGraph) {
    const SkeletonPointSet set = starAndSheet();
    const std::vector<SkeletonPoint> points = set.points();
    SkeletonGraphOptions serial;
    serial.threaded = false;
    const SkeletonGraph a = buildSkeletonGraph(points, set.dims(), serial);
    const SkeletonGraph b = buildSkeletonGraph(points, set.dims(), {});
    ASSERT_FALSE(a.junctions.empty()) << "the star's centre must be a fork";
    EXPECT_EQ(a.point, b.point);
    EXPECT_EQ(a.edges, b.edges);
    EXPECT_EQ(a.junctionOf, b.junctionOf);
    EXPECT_EQ(a.pieceOf, b.pieceOf);
    EXPECT_EQ(a.pieceCount, b.pieceCount);
    ASSERT_EQ(a.junctions.size(), b.junctions.size());
    for (std::size_t j = 0; j < a.junctions.size(); ++j) {
        EXPECT_EQ(a.junctions[j].core, b.junctions[j].core);
        EXPECT_EQ(a.junctions[j].region, b.junctions[j].region);
        EXPECT_EQ(a.junctions[j].rhoS, b.junctions[j].rhoS);
        EXPECT_EQ(a.junctions[j].representative, b.junctions[j].representative);
    }
}

TEST(SkeletonGraph, ForkTestsStopWhenAsked) {
    const SkeletonPointSet set = starAndSheet();
    const std::vector<SkeletonPoint> points = set.points();
    for (bool threaded : {false, true}) {
        SkeletonGraphOptions options;
        options.threaded = threaded;
        StopAtOnce stop;
        EXPECT_THROW(buildSkeletonGraph(points, set.dims(), options, stop), InterruptedError);
    }
}

TEST(SkeletonGraph, EmptyInput) {
    const SkeletonGraph g = buildSkeletonGraph({}, Dims{4, 4, 4}, {});
    EXPECT_EQ(g.nodeCount(), 0u);
    EXPECT_TRUE(g.junctions.empty());
    EXPECT_EQ(g.pieceCount, 0u);
}

TEST(SkeletonGraph, AStopAnsweredOnceAtAnyPollOfTheForkTestsThrows) {
    const test::SkeletonPointSet set = test::bodyWithOneLimb(1, 40);
    const std::vector<SkeletonPoint> points = set.points();
    for (const bool threaded : {false, true}) {
        SCOPED_TRACE(threaded ? "threaded" : "serial");
        SkeletonGraphOptions options;
        options.threaded = threaded;
        EXPECT_GT(test::expectAStopAtAnyPollThrows([&](Interrupter& interrupter) {
                      buildSkeletonGraph(points, set.dims(), options, interrupter);
                  }),
                  0);
    }
}

}  // namespace
}  // namespace skelseg
