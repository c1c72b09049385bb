#include "kernels/JointDetection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "kernels/base/Error.h"
#include "tests/kernels/SkeletonTestPoints.h"
#include "tests/support/Pi.h"

namespace skelseg {
namespace {

using test::kPi;
using test::SkeletonPointSet;

/// A straight profile of `length` one-voxel samples along x with rho_S
/// given per sample.
template <class Rho>
BranchProfile straightProfile(int length, Rho rho, double scale = 1.0) {
    BranchProfile p;
    for (int i = 0; i < length; ++i) {
        p.arc.push_back(scale * i);
        p.rhoS.push_back(scale * rho(i));
        p.position.push_back({scale * i, 0.0, 0.0});
    }
    return p;
}

/// rho_S 30 (radius about 9.5 voxels) with a dip to `depth` around `centre`.
double dip(int i, double centre, double depth) {
    const double t = (i - centre) / 6.0;
    return 30.0 - (30.0 - depth) * std::exp(-0.5 * t * t);
}

std::vector<ProfileJoint> passing(const std::vector<ProfileJoint>& joints, JointKind kind) {
    std::vector<ProfileJoint> out;
    for (const auto& j : joints)
        if (j.passes && j.kind == kind) out.push_back(j);
    return out;
}

TEST(JointDetection, ClearNarrowingBetweenWiderStretchesIsFound) {
    const BranchProfile p = straightProfile(140, [](int i) { return dip(i, 70, 16.0); });
    const auto found = passing(findProfileJoints(p, {}), JointKind::Narrowing);
    ASSERT_EQ(found.size(), 1u);
    EXPECT_NEAR(double(found[0].sample), 70.0, 2.0);
    EXPECT_LT(found[0].ratio, 0.7);
    EXPECT_GT(found[0].ratio, 16.0 / 30.0);  // smoothing lifts the minimum a little
    EXPECT_TRUE(passing(findProfileJoints(p, {}), JointKind::Bend).empty());
}

TEST(JointDetection, ShallowNarrowingIsBelowTheRatio) {
    const BranchProfile p = straightProfile(140, [](int i) { return dip(i, 70, 27.0); });
    EXPECT_TRUE(passing(findProfileJoints(p, {}), JointKind::Narrowing).empty());
}

TEST(JointDetection, MildNoiseIsNotAJoint) {
    std::uint64_t state = 12345;
    std::vector<double> noise;
    for (int i = 0; i < 200; ++i) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        noise.push_back(double(state >> 40) / double(1ull << 24) - 0.5);  // [-0.5, 0.5)
    }
    // +-2 voxels of rho_S noise per sample (about +-7%), positions jittered by
    // half a voxel sideways.
    BranchProfile p =
        straightProfile(200, [&](int i) { return 30.0 + 4.0 * noise[std::size_t(i)]; });
    for (std::size_t i = 0; i < p.position.size(); ++i)
        p.position[i][1] = noise[(i * 7) % noise.size()];
    for (const auto& j : findProfileJoints(p, {})) EXPECT_FALSE(j.passes) << j.sample;
}

TEST(JointDetection, EndCapsAreNotJoints) {
    // A capsule's profile: rho_S falls like a hemisphere towards both tips.
    const double radius = 30.0 / kPi, length = 120.0;
    const BranchProfile p = straightProfile(int(length), [&](int i) {
        const double fromEnd = std::min(double(i), length - 1 - i);
        const double h = std::max(radius - fromEnd, 0.0);
        return kPi * std::sqrt(std::max(radius * radius - h * h, 1.0));
    });
    for (const auto& j : findProfileJoints(p, {})) EXPECT_FALSE(j.passes) << j.sample;
}

TEST(JointDetection, NarrowingNextToATipNeedsLengthOnBothSides) {
    // The same clear dip, half a radius from the end of the branch.
    const BranchProfile p = straightProfile(100, [](int i) { return dip(i, 3, 16.0); });
    EXPECT_TRUE(passing(findProfileJoints(p, {}), JointKind::Narrowing).empty());
}

TEST(JointDetection, ThresholdsAreInRadiusUnits) {
    // The profile at twice the resolution: the same joint with the same ratio.
    const auto rho = [](int i) { return dip(i, 70, 16.0); };
    const auto coarse =
        passing(findProfileJoints(straightProfile(140, rho), {}), JointKind::Narrowing);
    const auto fine =
        passing(findProfileJoints(straightProfile(140, rho, 2.0), {}), JointKind::Narrowing);
    ASSERT_EQ(coarse.size(), 1u);
    ASSERT_EQ(fine.size(), 1u);
    EXPECT_NEAR(fine[0].ratio, coarse[0].ratio, 0.03);
    EXPECT_NEAR(fine[0].radius, 2.0 * coarse[0].radius, 0.1 * coarse[0].radius);
}

TEST(JointDetection, AShortBulgeBesideANarrowingLeavesItsRatio) {
    // A limb (rho_S 30) narrowing into a thinner end part (24), with a
    // shallow dip between them; then the same with a short bulge on the thin
    // side, as a flexed neighbouring joint or an unresolved foot makes one.
    // The ratio is taken against the sides' typical thickness (their
    // medians), which three wide samples barely move; against the sides'
    // widest points it would fall by about 0.1 and cross the threshold.
    const auto limb = [](int i) {
        return 27.0 + 3.0 * std::tanh((70.0 - i) / 3.0) -
               6.0 * std::exp(-0.5 * (i - 70) * (i - 70) / 25.0);
    };
    const auto bulged = [&](int i) { return limb(i) + (i >= 84 && i <= 86 ? 12.0 : 0.0); };
    const auto plain = findProfileJoints(straightProfile(160, limb), {});
    const auto bulge = findProfileJoints(straightProfile(160, bulged), {});
    std::vector<ProfileJoint> plainDips, bulgeDips;
    for (const auto& j : plain)
        if (j.kind == JointKind::Narrowing) plainDips.push_back(j);
    for (const auto& j : bulge)
        if (j.kind == JointKind::Narrowing) bulgeDips.push_back(j);
    ASSERT_EQ(plainDips.size(), 1u);
    ASSERT_EQ(bulgeDips.size(), 1u);
    EXPECT_EQ(bulgeDips[0].sample, plainDips[0].sample);
    EXPECT_NEAR(bulgeDips[0].ratio, plainDips[0].ratio, 0.03);
    EXPECT_GT(plainDips[0].ratio, JointOptions{}.narrowingRatio);
    EXPECT_FALSE(bulgeDips[0].passes);
    // The wider stretch on the thin side is still its widest point: the bulge.
    EXPECT_GE(bulgeDips[0].wideAfter, 83u);
    EXPECT_LE(bulgeDips[0].wideAfter, 87u);
}

/// A branch of constant rho_S along two straight legs that meet at
/// `turnDegrees` (0: straight), one sample per voxel of arc length.
BranchProfile turningProfile(double turnDegrees) {
    BranchProfile p;
    const double t = turnDegrees * kPi / 180.0;
    for (int i = 0; i < 160; ++i) {
        p.arc.push_back(i);
        p.rhoS.push_back(30.0);
        if (i <= 80)
            p.position.push_back({double(i), 0.0, 0.0});
        else
            p.position.push_back({80.0 + (i - 80) * std::cos(t), (i - 80) * std::sin(t), 0.0});
    }
    return p;
}

TEST(JointDetection, BendsAreOffByDefault) {
    EXPECT_TRUE(passing(findProfileJoints(turningProfile(90.0), {}), JointKind::Bend).empty());
}

TEST(JointDetection, SharpBendIsFoundAndGentleOnesAreNot) {
    JointOptions options;
    options.bendAngleDegrees = 30.0;
    const auto sharp = passing(findProfileJoints(turningProfile(90.0), options), JointKind::Bend);
    ASSERT_GE(sharp.size(), 1u);
    for (const auto& j : sharp) EXPECT_NEAR(double(j.sample), 80.0, 0.5 * 30.0 / kPi + 2.0);
    EXPECT_GT(sharp[0].angleDegrees, 60.0);
    EXPECT_TRUE(passing(findProfileJoints(turningProfile(0.0), options), JointKind::Bend).empty());
    EXPECT_TRUE(passing(findProfileJoints(turningProfile(25.0), options), JointKind::Bend).empty());
    // No narrowing where rho_S is constant.
    EXPECT_TRUE(
        passing(findProfileJoints(turningProfile(90.0), options), JointKind::Narrowing).empty());
}

/// A one-voxel-thick straight skeleton with a narrowing at x = 70.
struct NarrowedChain {
    SkeletonPointSet set{Dims{144, 3, 3}};
    std::vector<std::uint32_t> voxels;
    explicit NarrowedChain(float sigma) {
        voxels = set.chain({2, 1, 1}, {1, 0, 0}, 140);
        for (std::size_t i = 0; i < voxels.size(); ++i) {
            SkeletonPoint& p = set.point(voxels[i]);
            p.rhoS = float(dip(int(i) + 2, 70, 16.0));
            p.sigma = sigma;
        }
    }
};

TEST(JointDetection, GraphNarrowingBecomesACutAtItsSmoothestNode) {
    NarrowedChain chain(0.9f);
    // The smoothest loop is one voxel off the minimum.
    chain.set.point(chain.set.voxelIndex({71, 1, 1})).sigma = 0.97f;
    const std::vector<SkeletonPoint> points = chain.set.points();
    const SkeletonGraph graph = buildSkeletonGraph(points, chain.set.dims(), {});
    ASSERT_EQ(graph.pieceCount, 1u);
    const auto found = detectJoints(graph, points, {}, {});
    std::vector<JointCandidate> cuts;
    for (const auto& c : found)
        if (c.status == JointStatus::Cut) cuts.push_back(c);
    ASSERT_EQ(cuts.size(), 1u);
    EXPECT_EQ(cuts[0].kind, JointKind::Narrowing);
    EXPECT_EQ(graph.coord[cuts[0].node].x, 71);
    EXPECT_FLOAT_EQ(cuts[0].sigma, 0.97f);
}

TEST(JointDetection, GraphNarrowingWithoutAGeodesicLoopIsNotCut) {
    NarrowedChain chain(0.5f);
    const std::vector<SkeletonPoint> points = chain.set.points();
    const SkeletonGraph graph = buildSkeletonGraph(points, chain.set.dims(), {});
    const auto found = detectJoints(graph, points, {}, {});
    bool lowSigma = false;
    for (const auto& c : found) {
        EXPECT_NE(c.status, JointStatus::Cut);
        lowSigma = lowSigma || c.status == JointStatus::LowSigma;
    }
    EXPECT_TRUE(lowSigma);
}

TEST(JointDetection, GraphNarrowingNextToAnExistingCutIsNotCut) {
    NarrowedChain chain(0.9f);
    const std::vector<SkeletonPoint> points = chain.set.points();
    const SkeletonGraph graph = buildSkeletonGraph(points, chain.set.dims(), {});
    // An existing cut 4 voxels away (less than two radii of about 6 voxels).
    std::uint32_t existing = 0;
    for (std::uint32_t n = 0; n < graph.nodeCount(); ++n)
        if (graph.coord[n].x == 74) existing = n;
    const auto found = detectJoints(graph, points, {existing}, {});
    bool near = false;
    for (const auto& c : found) {
        EXPECT_NE(c.status, JointStatus::Cut);
        near = near || c.status == JointStatus::NearCut;
    }
    EXPECT_TRUE(near);
}

/// The joint candidates of the narrowed chain with one existing cut at x.
std::vector<JointCandidate> narrowedChainWithCutAt(int x) {
    NarrowedChain chain(0.9f);
    const std::vector<SkeletonPoint> points = chain.set.points();
    const SkeletonGraph graph = buildSkeletonGraph(points, chain.set.dims(), {});
    std::uint32_t existing = 0;
    for (std::uint32_t n = 0; n < graph.nodeCount(); ++n)
        if (graph.coord[n].x == x) existing = n;
    return detectJoints(graph, points, {existing}, {});
}

std::size_t cutCount(const std::vector<JointCandidate>& found) {
    std::size_t cuts = 0;
    for (const auto& c : found) cuts += c.status == JointStatus::Cut;
    return cuts;
}

TEST(JointDetection, NarrowingWhoseWiderStretchesACutAlreadyPartsIsNotCut) {
    // The dip (minimum at x = 70, radius about 5 voxels) has its wider
    // stretches at the ends of the 6 r side window, about 30 voxels either
    // side. A cut 16 voxels away passes the distance rule (2 r) but lies
    // between the minimum and a wider stretch: the narrowing adds a sliver.
    const auto between = narrowedChainWithCutAt(86);
    EXPECT_EQ(cutCount(between), 0u);
    bool near = false;
    for (const auto& c : between) near = near || c.status == JointStatus::NearCut;
    EXPECT_TRUE(near);
    // Beyond the wider stretch the cut does not part them: the joint stays.
    EXPECT_EQ(cutCount(narrowedChainWithCutAt(112)), 1u);
    EXPECT_EQ(cutCount(narrowedChainWithCutAt(28)), 1u);
}

TEST(JointDetection, GraphProfileFollowsTheBranchInArcOrder) {
    NarrowedChain chain(0.9f);
    const std::vector<SkeletonPoint> points = chain.set.points();
    const SkeletonGraph graph = buildSkeletonGraph(points, chain.set.dims(), {});
    std::uint32_t branchCount = 0;
    const auto nodeBranch = jointBranches(graph, branchCount);
    ASSERT_EQ(branchCount, 1u);
    std::vector<double> nodeArc;
    const BranchProfile p = branchProfile(graph, points, nodeBranch, 0, &nodeArc);
    ASSERT_EQ(p.arc.size(), 140u);
    for (std::size_t i = 1; i < p.arc.size(); ++i) EXPECT_GT(p.arc[i], p.arc[i - 1]);
    // Either end may come first; the profile runs monotonically along x.
    const double direction = p.position.back()[0] > p.position.front()[0] ? 1.0 : -1.0;
    for (std::size_t i = 1; i < p.position.size(); ++i)
        EXPECT_DOUBLE_EQ(direction * (p.position[i][0] - p.position[i - 1][0]), 1.0);
    for (std::uint32_t n = 0; n < graph.nodeCount(); ++n) EXPECT_GE(nodeArc[n], 0.0);
}

TEST(JointDetection, TwoBranchJunctionsJoinTheirPiecesAndThreeBranchOnesSplit) {
    // A straight chain whose middle voxel claims three robust rims: a
    // junction with two branches, which is one limb.
    SkeletonPointSet line{Dims{64, 3, 3}};
    line.chain({2, 1, 1}, {1, 0, 0}, 60);
    line.add({32, 1, 1}, 10.0f, 1000.0, 3);
    const std::vector<SkeletonPoint> linePoints = line.points();
    const SkeletonGraph lineGraph = buildSkeletonGraph(linePoints, line.dims(), {});
    ASSERT_EQ(lineGraph.junctions.size(), 1u);
    ASSERT_EQ(lineGraph.pieceCount, 2u);
    std::uint32_t count = 0;
    const auto lineBranch = jointBranches(lineGraph, count);
    EXPECT_EQ(count, 1u);
    for (std::uint32_t b : lineBranch) EXPECT_EQ(b, 0u);

    // A Y: three arms from one junction stay three branches.
    SkeletonPointSet y{Dims{45, 45, 4}};
    const std::uint32_t centre = y.add({22, 22, 1}, 20.0f, 5000.0, 3);
    y.chain({23, 22, 1}, {1, 0, 0}, 15);
    y.chain({21, 23, 1}, {-1, 1, 0}, 15);
    y.chain({21, 21, 1}, {-1, -1, 0}, 15);
    const std::vector<SkeletonPoint> yPoints = y.points();
    const SkeletonGraph yGraph = buildSkeletonGraph(yPoints, y.dims(), {});
    const auto yBranch = jointBranches(yGraph, count);
    EXPECT_EQ(count, 3u);
    for (std::uint32_t n = 0; n < yGraph.nodeCount(); ++n)
        if (yPoints[yGraph.point[n]].voxel == centre) EXPECT_EQ(yBranch[n], kNoJunction);
}

TEST(JointDetection, StopsWhenInterrupted) {
    struct StopAtOnce : Interrupter {
        bool wasInterrupted(double) override { return true; }
    } stop;
    NarrowedChain chain(0.9f);
    const std::vector<SkeletonPoint> points = chain.set.points();
    const SkeletonGraph graph = buildSkeletonGraph(points, chain.set.dims(), {});
    EXPECT_THROW(detectJoints(graph, points, {}, {}, stop), InterruptedError);
    EXPECT_NO_THROW(detectJoints(graph, points, {}, {}));
}

}  // namespace
}  // namespace skelseg
