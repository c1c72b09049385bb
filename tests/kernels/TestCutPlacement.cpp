#include "kernels/CutPlacement.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <string>

#include "tests/kernels/SkeletonTestPoints.h"

namespace skelseg {
namespace {

using test::SkeletonPointSet;

/// A Y junction: centre (rho_S 20) and three 15-voxel arms. With
/// regionRadius 3 the first three voxels of each arm are in the junction
/// region, so BFS level L of an arm is its voxel L + 2 (0-based).
struct Junction {
    SkeletonPointSet set{Dims{45, 45, 4}};
    std::uint32_t centre;
    std::vector<std::uint32_t> arms[3];
    Junction() {
        centre = set.add({22, 22, 1}, 20.0f, 5000.0, 3);
        arms[0] = set.chain({23, 22, 1}, {1, 0, 0}, 15);
        arms[1] = set.chain({21, 23, 1}, {-1, 1, 0}, 15);
        arms[2] = set.chain({21, 21, 1}, {-1, -1, 0}, 15);
    }
    /// sigma per BFS level (levels[0] is level 1, at most 12 levels); the
    /// region's voxels and levels past the list get sigma 0.
    void setSigma(int arm, const std::vector<float>& levels) {
        for (std::size_t i = 0; i < arms[arm].size(); ++i) set.point(arms[arm][i]).sigma = 0.0f;
        for (std::size_t l = 0; l < levels.size(); ++l)
            set.point(arms[arm][l + 3]).sigma = levels[l];
    }
    void setRhoS(int arm, float rhoS) {
        for (std::uint32_t v : arms[arm]) set.point(v).rhoS = rhoS;
    }
    /// rho_S per BFS level, as setSigma.
    void setRhoSPerLevel(int arm, const std::vector<float>& levels) {
        for (std::size_t l = 0; l < levels.size(); ++l)
            set.point(arms[arm][l + 3]).rhoS = levels[l];
    }
    std::uint32_t armVoxelAtLevel(int arm, std::uint32_t level) const {
        return arms[arm][level + 2];
    }
};

struct Result {
    std::vector<SkeletonPoint> points;
    SkeletonGraph graph;
    CutPlan plan;
    std::map<std::uint32_t, const CutCandidate*> byVoxel;  // candidate per voxel
    std::vector<std::uint32_t> cutVoxels;
    int callbackCalls = 0;
};

/// Runs graph building and cut placement; `rhoCOfVoxel` answers the exact
/// rho_C callback.
std::unique_ptr<Result> place(const Junction& junction, const CutOptions& options = {},
                              const std::map<std::uint32_t, double>& rhoCOfVoxel = {}) {
    auto r = std::make_unique<Result>();
    r->points = junction.set.points();
    r->graph = buildSkeletonGraph(r->points, junction.set.dims(), {});
    Result* raw = r.get();
    r->plan =
        placeCuts(r->graph, r->points, options, [raw, &rhoCOfVoxel](std::uint32_t pointIndex) {
            ++raw->callbackCalls;
            auto it = rhoCOfVoxel.find(raw->points[pointIndex].voxel);
            return it == rhoCOfVoxel.end() ? 0.0 : it->second;
        });
    for (const CutCandidate& c : r->plan.candidates)
        r->byVoxel[r->points[r->graph.point[c.node]].voxel] = &c;
    for (std::uint32_t n : r->plan.cutNodes)
        r->cutVoxels.push_back(r->points[r->graph.point[n]].voxel);
    std::sort(r->cutVoxels.begin(), r->cutVoxels.end());
    return r;
}

TEST(CutPlacement, CandidateIsTheFirstLevelOfAThreeLevelRun) {
    Junction j;
    // Arm 0: isolated highs, then a run of three starting at level 4, which
    // starts exactly at sigmaMin.
    j.setSigma(0, {0.3f, 0.9f, 0.5f, 0.8f, 0.85f, 0.95f, 0.9f, 0.9f});
    // Arm 1: never three consecutive levels >= 0.8 (nor >= 0.75, §8.7).
    j.setSigma(1, {0.95f, 0.2f, 0.9f, 0.9f, 0.1f, 0.85f, 0.7f, 0.99f, 0.5f, 0.9f, 0.9f, 0.2f});
    // Arm 2: high right from level 1.
    j.setSigma(2, {0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f});
    for (int arm = 0; arm < 3; ++arm) j.setRhoS(arm, 5.0f);  // all limbs (similarity 0.25)
    const auto r = place(j);
    ASSERT_EQ(r->graph.junctions.size(), 1u);
    ASSERT_EQ(r->plan.junctions.size(), 1u);
    EXPECT_EQ(r->plan.junctions[0].branches, 3u);
    ASSERT_EQ(r->plan.candidates.size(), 2u);

    const std::uint32_t q0 = j.armVoxelAtLevel(0, 4), q2 = j.armVoxelAtLevel(2, 1);
    ASSERT_TRUE(r->byVoxel.count(q0)) << "arm 0: candidate not at level 4";
    ASSERT_TRUE(r->byVoxel.count(q2)) << "arm 2: candidate not at level 1";
    EXPECT_EQ(r->byVoxel.at(q0)->level, 4u);
    EXPECT_FLOAT_EQ(r->byVoxel.at(q0)->sigma, 0.8f);
    EXPECT_EQ(r->byVoxel.at(q2)->level, 1u);
    for (const auto& [voxel, c] : r->byVoxel) {
        EXPECT_EQ(c->junction, 0u);
        EXPECT_NEAR(c->similarity, 0.25f, 1e-6f);
        EXPECT_FALSE(c->onBody);
        EXPECT_TRUE(c->isCut);
    }
    EXPECT_EQ(r->cutVoxels, (std::vector<std::uint32_t>{std::min(q0, q2), std::max(q0, q2)}));
    EXPECT_EQ(r->plan.junctions[0].cuts, 2u);
    EXPECT_EQ(r->callbackCalls, 0);
}

TEST(CutPlacement, SingleHighLevelDoesNotCount) {
    Junction j;
    for (int arm = 0; arm < 3; ++arm)
        j.setSigma(arm, {0.1f, 0.95f, 0.1f, 0.2f, 0.99f, 0.3f, 0.9f, 0.9f, 0.4f});
    const auto r = place(j);
    EXPECT_TRUE(r->plan.candidates.empty());
    EXPECT_TRUE(r->plan.cutNodes.empty());
    EXPECT_EQ(r->plan.junctions[0].branches, 3u);

    // With consecutiveLevels = 1 a single level is enough: level 2.
    CutOptions one;
    one.consecutiveLevels = 1;
    j.setRhoS(0, 5.0f);
    const auto r1 = place(j, one);
    ASSERT_TRUE(r1->byVoxel.count(j.armVoxelAtLevel(0, 2)));
    EXPECT_EQ(r1->byVoxel.at(j.armVoxelAtLevel(0, 2))->level, 2u);
}

TEST(CutPlacement, ShortBranchYieldsNoCandidate) {
    // Only two levels outside the region: a run of three cannot fit.
    SkeletonPointSet set(Dims{30, 30, 3});
    set.add({10, 10, 1}, 20.0f, 5000.0, 3);
    auto longArm = set.chain({11, 10, 1}, {1, 0, 0}, 12, 5.0f);
    auto shortArm = set.chain({9, 11, 1}, {-1, 1, 0}, 5, 5.0f);
    auto otherArm = set.chain({9, 9, 1}, {-1, -1, 0}, 8, 5.0f);
    for (auto* arm : {&longArm, &shortArm, &otherArm})
        for (std::uint32_t v : *arm) set.point(v).sigma = 0.95f;
    const std::vector<SkeletonPoint> points = set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
    const CutPlan plan = placeCuts(g, points, {}, [](std::uint32_t) { return 0.0; });
    ASSERT_EQ(plan.junctions.size(), 1u);
    EXPECT_EQ(plan.junctions[0].branches, 3u);
    EXPECT_EQ(plan.candidates.size(), 2u);
    for (const CutCandidate& c : plan.candidates)
        EXPECT_NE(points[g.point[c.node]].voxel, shortArm[3]);
}

TEST(CutPlacement, BestSigmaPerLevelOnAThickBranch) {
    Junction j;
    for (int arm = 0; arm < 3; ++arm) j.setSigma(arm, {0.1f});
    // Arm 0 gets a parallel twin one voxel above: both voxels of a level are
    // one "point"; the twin carries the high sigma from level 2 on.
    std::vector<std::uint32_t> twin = j.set.chain({23, 22, 2}, {1, 0, 0}, 15, 10.0f, 1000.0);
    for (std::size_t i = 0; i < twin.size(); ++i)
        j.set.point(twin[i]).sigma = i >= 4 ? 0.92f : 0.1f;
    for (std::uint32_t v : j.arms[0]) j.set.point(v).sigma = 0.5f;
    j.setRhoS(0, 4.0f);
    for (std::uint32_t v : twin) j.set.point(v).rhoS = 4.0f;
    const auto r = place(j);
    ASSERT_EQ(r->plan.candidates.size(), 1u);
    const CutCandidate& c = r->plan.candidates[0];
    EXPECT_EQ(c.level, 2u);
    EXPECT_EQ(r->points[r->graph.point[c.node]].voxel, twin[4]);
    EXPECT_FLOAT_EQ(c.sigma, 0.92f);
}

TEST(CutPlacement, BodyCandidatesAreDropped) {
    Junction j;
    for (int arm = 0; arm < 3; ++arm) j.setSigma(arm, {0.9f, 0.9f, 0.9f, 0.9f});
    // Arms 0 and 1 continue the body (similarity 0.95 and 0.65 >= bodyRatio),
    // arm 2 is a limb (similarity 0.4).
    j.setRhoS(0, 19.0f);
    j.setRhoS(1, 13.0f);
    j.setRhoS(2, 8.0f);
    const auto r = place(j);
    ASSERT_EQ(r->plan.candidates.size(), 3u);
    const CutCandidate* c0 = r->byVoxel.at(j.armVoxelAtLevel(0, 1));
    const CutCandidate* c1 = r->byVoxel.at(j.armVoxelAtLevel(1, 1));
    const CutCandidate* c2 = r->byVoxel.at(j.armVoxelAtLevel(2, 1));
    EXPECT_NEAR(c0->similarity, 0.95f, 1e-5f);
    EXPECT_NEAR(c1->similarity, 0.65f, 1e-5f);
    EXPECT_NEAR(c2->similarity, 0.4f, 1e-5f);
    EXPECT_TRUE(c0->onBody);
    EXPECT_TRUE(c1->onBody);
    EXPECT_FALSE(c2->onBody);
    EXPECT_EQ(r->cutVoxels, std::vector<std::uint32_t>{j.armVoxelAtLevel(2, 1)});
    EXPECT_EQ(r->plan.junctions[0].cuts, 1u);
    EXPECT_EQ(r->callbackCalls, 0) << "two body candidates need no tie rule";
}

TEST(CutPlacement, MoreThanTwoSimilarDropsOnlyTheLargestRhoC) {
    Junction j;
    for (int arm = 0; arm < 3; ++arm) {
        j.setSigma(arm, {0.9f, 0.9f, 0.9f, 0.9f});
        j.setRhoS(arm, 20.0f + float(arm));
    }
    const std::uint32_t q[3] = {j.armVoxelAtLevel(0, 1), j.armVoxelAtLevel(1, 1),
                                j.armVoxelAtLevel(2, 1)};
    const auto r = place(j, {}, {{q[0], 300.0}, {q[1], 900.0}, {q[2], 600.0}});
    ASSERT_EQ(r->plan.candidates.size(), 3u);
    EXPECT_EQ(r->callbackCalls, 3);
    EXPECT_EQ(r->byVoxel.at(q[1])->exactRhoC, 900.0);
    EXPECT_EQ(r->byVoxel.at(q[0])->exactRhoC, 300.0);
    EXPECT_TRUE(r->byVoxel.at(q[1])->onBody);
    EXPECT_FALSE(r->byVoxel.at(q[0])->onBody);
    EXPECT_FALSE(r->byVoxel.at(q[2])->onBody);
    EXPECT_EQ(r->cutVoxels,
              (std::vector<std::uint32_t>{std::min(q[0], q[2]), std::max(q[0], q[2])}));
    EXPECT_EQ(r->plan.junctions[0].cuts, 2u);
}

TEST(CutPlacement, EqualRhoCTieKeepsLowestVoxelOnBody) {
    Junction j;
    for (int arm = 0; arm < 3; ++arm) {
        j.setSigma(arm, {0.9f, 0.9f, 0.9f});
        j.setRhoS(arm, 18.0f);  // all three on the body
    }
    const std::uint32_t q[3] = {j.armVoxelAtLevel(0, 1), j.armVoxelAtLevel(1, 1),
                                j.armVoxelAtLevel(2, 1)};
    const auto r = place(j, {}, {{q[0], 500.0}, {q[1], 500.0}, {q[2], 500.0}});
    const std::uint32_t lowest = *std::min_element(q, q + 3);
    ASSERT_EQ(r->plan.candidates.size(), 3u);
    for (std::uint32_t v : q) EXPECT_EQ(r->byVoxel.at(v)->onBody, v == lowest) << "voxel " << v;
    EXPECT_EQ(r->cutVoxels.size(), 2u);
    EXPECT_EQ(r->callbackCalls, 3);
}

TEST(CutPlacement, LimbCircumferenceIsMeasuredOneBodyRadiusOut) {
    // The junction's rho_S is 20: one body radius is ceil(20 / pi) = 7
    // levels. Arm 2 is tight from level 1, but its first levels still wrap
    // the limb's base (rho_S 18, similarity 0.9); further out it is 7 thick.
    Junction j;
    EXPECT_EQ(limbCircumferenceLevels(20.0f, 3), 7u);
    EXPECT_EQ(limbCircumferenceLevels(3.0f, 3), 3u) << "at least the run";
    j.setSigma(0, {0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f});
    j.setRhoS(0, 19.0f);  // the body
    j.setSigma(1, {0.1f});
    j.setSigma(2, {0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.3f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f});
    // Level 6 is not tight (its rho_S 2 does not count), level 9 is past the
    // window (its rho_S 3 does not count either).
    j.setRhoSPerLevel(2, {18.0f, 18.0f, 16.0f, 12.0f, 9.0f, 2.0f, 8.0f, 7.0f, 3.0f, 7.0f});
    const auto r = place(j);
    ASSERT_EQ(r->plan.candidates.size(), 2u);
    // The cut moves to the first tight level whose loop is closer to the
    // limb's girth (7) than to the body's (20): level 4 (rho_S 12 <= 13.5).
    const CutCandidate* limb = r->byVoxel.at(j.armVoxelAtLevel(2, 4));
    EXPECT_EQ(limb->level, 4u);
    EXPECT_FLOAT_EQ(limb->baseRhoS, 18.0f) << "where sigma first holds";
    EXPECT_FLOAT_EQ(limb->limbRhoS, 7.0f);
    EXPECT_FLOAT_EQ(limb->bodyRhoS, 20.0f);
    EXPECT_NEAR(limb->similarity, 0.35f, 1e-5f);
    EXPECT_TRUE(limb->isCut);
    const CutCandidate* body = r->byVoxel.at(j.armVoxelAtLevel(0, 1));
    EXPECT_FLOAT_EQ(body->limbRhoS, 19.0f);
    EXPECT_TRUE(body->onBody);
    EXPECT_EQ(body->level, 1u) << "a body candidate does not move";
    EXPECT_EQ(r->cutVoxels, std::vector<std::uint32_t>{j.armVoxelAtLevel(2, 4)});
}

/// A Y junction (body 20 around) whose arm 0 is a head 11 around (tight on
/// levels 1 to 5) with a single tight level 1 around at level 7, inside the
/// body test's window (7 levels): a loop round a thin protrusion at the
/// head's end (PSB 281's ear, docs/algorithm.md §8.13, "loops17").
std::unique_ptr<Result> headWithAStrayTightLevel(bool tightLevelsInRuns) {
    Junction y;
    y.setRhoS(0, 11.0f);
    y.setSigma(0, {0.95f, 0.95f, 0.95f, 0.95f, 0.95f, 0.0f, 0.85f});
    y.setRhoSPerLevel(0, {11.0f, 11.0f, 11.0f, 11.0f, 11.0f, 11.0f, 1.0f});
    for (int arm : {1, 2}) y.setSigma(arm, std::vector<float>(12, 0.95f)), y.setRhoS(arm, 20.0f);
    CutOptions options;
    options.tightLevelsInRuns = tightLevelsInRuns;
    return place(y, options);
}

TEST(CutPlacement, SingleTightLevelAtABranchEndIsNotTheLimbsGirth) {
    // Read on runs of three tight levels only, the head is 11 around
    // (similarity 0.55) and its cut stays at its base; read on every tight
    // level, the stray loop makes it 1 around, the border (20 + 1) / 2 lies
    // under every loop of the head, and the cut goes to the protrusion.
    Junction y;
    const auto runs = headWithAStrayTightLevel(true);
    ASSERT_EQ(runs->cutVoxels.size(), 1u);
    EXPECT_EQ(runs->cutVoxels[0], y.armVoxelAtLevel(0, 1));
    const CutCandidate* head = runs->byVoxel.at(y.armVoxelAtLevel(0, 1));
    EXPECT_FLOAT_EQ(head->limbRhoS, 11.0f);
    EXPECT_NEAR(head->similarity, 0.55f, 1e-5f);
    EXPECT_TRUE(head->isCut);

    const auto every = headWithAStrayTightLevel(false);
    ASSERT_EQ(every->cutVoxels.size(), 1u);
    EXPECT_EQ(every->cutVoxels[0], y.armVoxelAtLevel(0, 7)) << "the rule this test guards";
    EXPECT_FLOAT_EQ(every->byVoxel.at(y.armVoxelAtLevel(0, 7))->limbRhoS, 1.0f);
}

TEST(CutPlacement, LimbWindowIsOneRadiusOfTheBodyNotOfAThinJunctionMedian) {
    // The junction's median fell on thin core voxels (rho_S 3: a window of
    // the run's three levels), while the body through it is 20 thick (one
    // body radius: ceil(20 / pi) = 7 levels). Arm 2 is a trunk whose first
    // four levels still wrap its base (14) and which is 7 thick further out:
    // over three levels it reads 14 (similarity 0.7, body); over the body's
    // radius it reads its girth, 7 (0.35, a limb).
    Junction j;
    j.set.point(j.centre).rhoS = 3.0f;
    j.setSigma(0, {0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f});
    j.setRhoS(0, 20.0f);  // the body
    j.setSigma(1, {0.1f});
    j.setSigma(2, {0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f});
    j.setRhoSPerLevel(2,
                      {14.0f, 14.0f, 14.0f, 14.0f, 7.0f, 7.0f, 7.0f, 7.0f, 7.0f, 7.0f, 7.0f, 7.0f});
    const auto r = place(j);
    ASSERT_EQ(r->plan.candidates.size(), 2u);
    // Cut where the loop is closer to the trunk's girth than to the body's
    // (level 5, rho_S 7 <= 13.5).
    const CutCandidate* trunk = r->byVoxel.at(j.armVoxelAtLevel(2, 5));
    EXPECT_FLOAT_EQ(trunk->bodyRhoS, 20.0f);
    EXPECT_FLOAT_EQ(trunk->limbRhoS, 7.0f);
    EXPECT_NEAR(trunk->similarity, 0.35f, 1e-5f);
    EXPECT_TRUE(trunk->isCut);
    EXPECT_EQ(r->plan.cutNodes.size(), 1u);

    // Without the rule the window is the junction median's: the trunk is body.
    CutOptions without;
    without.windowFromBodyReference = false;
    const auto before = place(j, without);
    const CutCandidate* base = before->byVoxel.at(j.armVoxelAtLevel(2, 1));
    EXPECT_FLOAT_EQ(base->limbRhoS, 14.0f);
    EXPECT_FALSE(base->isCut);
    EXPECT_TRUE(before->plan.cutNodes.empty());
}

TEST(CutPlacement, CutStaysWhereSigmaHoldsWhenThatLoopIsAlreadyLimbSized) {
    // Arm 2 is 7 thick from its first tight level: nothing to move.
    Junction j;
    j.setSigma(0, {0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f});
    j.setRhoS(0, 19.0f);
    j.setSigma(1, {0.1f});
    j.setSigma(2, {0.2f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f});
    j.setRhoS(2, 7.0f);
    const auto r = place(j);
    EXPECT_EQ(r->cutVoxels, std::vector<std::uint32_t>{j.armVoxelAtLevel(2, 2)});
}

TEST(CutPlacement, TightLoopLongerThanTheJunctionSetsTheBodyReference) {
    // The junction's median (20) fell on thin core voxels: the body's first
    // tight loop is 30 long (further out 24). Against 24, arm 1 (16) would
    // be body (similarity 0.67); against the body's 30 it is a limb (0.53).
    Junction j;
    for (int arm = 0; arm < 3; ++arm)
        j.setSigma(arm, {0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f});
    j.setRhoS(0, 24.0f);
    j.setRhoSPerLevel(0, {30.0f});
    j.setRhoS(1, 16.0f);
    j.setRhoS(2, 5.0f);
    const auto r = place(j);
    ASSERT_EQ(r->plan.candidates.size(), 3u);
    const CutCandidate* body = r->byVoxel.at(j.armVoxelAtLevel(0, 1));
    EXPECT_FLOAT_EQ(body->baseRhoS, 30.0f);
    EXPECT_FLOAT_EQ(body->limbRhoS, 24.0f);
    EXPECT_TRUE(body->onBody);
    const CutCandidate* arm1 = r->byVoxel.at(j.armVoxelAtLevel(1, 1));
    EXPECT_FLOAT_EQ(arm1->bodyRhoS, 30.0f);
    EXPECT_NEAR(arm1->similarity, 1.0f - 14.0f / 30.0f, 1e-5f);
    EXPECT_TRUE(arm1->isCut);
    EXPECT_TRUE(r->byVoxel.at(j.armVoxelAtLevel(2, 1))->isCut);
}

TEST(CutPlacement, BodyThickerThanTheJunctionIsStillBody) {
    // A junction whose median rho_S fell on thin core voxels (10) against a
    // body 40 thick: the body, not the junction, is the reference.
    Junction j;
    j.set.point(j.centre).rhoS = 10.0f;
    for (int arm = 0; arm < 3; ++arm) j.setSigma(arm, {0.9f, 0.9f, 0.9f, 0.9f});
    j.setRhoS(0, 40.0f);
    j.setRhoS(1, 36.0f);
    j.setRhoS(2, 14.0f);
    const auto r = place(j);
    ASSERT_EQ(r->plan.candidates.size(), 3u);
    EXPECT_NEAR(r->byVoxel.at(j.armVoxelAtLevel(0, 1))->similarity, 1.0f, 1e-6f);
    EXPECT_NEAR(r->byVoxel.at(j.armVoxelAtLevel(1, 1))->similarity, 0.9f, 1e-6f);
    EXPECT_NEAR(r->byVoxel.at(j.armVoxelAtLevel(2, 1))->similarity, 0.35f, 1e-6f);
    EXPECT_EQ(r->cutVoxels, std::vector<std::uint32_t>{j.armVoxelAtLevel(2, 1)});
}

TEST(CutPlacement, SiblingsAlikeInThicknessGetTheSameAnswer) {
    // Two legs 12.2 and 11.8 thick at a hip of 20: the threshold (12) falls
    // between them. Both join the body candidates, so the "more than two"
    // rule keeps only the torso (largest area) on the body.
    Junction j;
    for (int arm = 0; arm < 3; ++arm) j.setSigma(arm, {0.9f, 0.9f, 0.9f, 0.9f});
    j.setRhoS(0, 18.0f);
    j.setRhoS(1, 12.2f);
    j.setRhoS(2, 11.8f);
    const std::uint32_t q[3] = {j.armVoxelAtLevel(0, 1), j.armVoxelAtLevel(1, 1),
                                j.armVoxelAtLevel(2, 1)};
    const std::map<std::uint32_t, double> areas{{q[0], 900.0}, {q[1], 300.0}, {q[2], 310.0}};
    const auto r = place(j, {}, areas);
    EXPECT_TRUE(r->byVoxel.at(q[0])->onBody);
    EXPECT_TRUE(r->byVoxel.at(q[1])->isCut);
    EXPECT_TRUE(r->byVoxel.at(q[2])->isCut);
    EXPECT_EQ(r->plan.junctions[0].cuts, 2u);

    // Without the tolerance the threshold splits the two legs.
    CutOptions strict;
    strict.siblingTolerance = 0.0;
    const auto s = place(j, strict, areas);
    EXPECT_TRUE(s->byVoxel.at(q[1])->onBody);
    EXPECT_TRUE(s->byVoxel.at(q[2])->isCut);
    EXPECT_EQ(s->plan.junctions[0].cuts, 1u);

    // A clearly thinner third arm is not pulled in.
    j.setRhoS(2, 7.0f);
    const auto t = place(j, {}, areas);
    EXPECT_TRUE(t->byVoxel.at(q[1])->onBody);
    EXPECT_TRUE(t->byVoxel.at(q[2])->isCut);
    EXPECT_EQ(t->callbackCalls, 0);
}

/// Two legs at a hip, modelled on PSB model 3 (figures in docs/algorithm.md
/// §8.6): the thicker leg sits on body_ratio and the two legs differ by
/// more than one leg's measure moves between resolutions. Both legs are
/// limbs whichever side of the threshold the thicker one falls, at two
/// scales of the junction.
TEST(CutPlacement, LegsOnEitherSideOfTheThresholdAreBothLimbsAtTwoScales) {
    for (const float scale : {1.0f, 2.0f}) {
        for (const float thickerLeg : {0.59f, 0.61f}) {
            SCOPED_TRACE("scale " + std::to_string(scale) + ", thicker leg " +
                         std::to_string(thickerLeg));
            Junction j;
            for (int arm = 0; arm < 3; ++arm) j.setSigma(arm, {0.9f, 0.9f, 0.9f, 0.9f});
            j.setRhoS(0, 15.4f * scale);               // torso, similarity 0.77
            j.setRhoS(1, 20.0f * thickerLeg * scale);  // the thicker leg
            j.setRhoS(2, 20.0f * 0.5f * scale);        // the thinner leg, 0.82 of it
            for (std::uint32_t v : j.arms[0]) j.set.point(v).rhoS = 15.4f * scale;
            j.set.point(j.centre).rhoS = 20.0f * scale;
            const std::uint32_t q[3] = {j.armVoxelAtLevel(0, 1), j.armVoxelAtLevel(1, 1),
                                        j.armVoxelAtLevel(2, 1)};
            const std::map<std::uint32_t, double> areas{
                {q[0], 900.0}, {q[1], 300.0}, {q[2], 310.0}};
            const auto r = place(j, {}, areas);
            EXPECT_TRUE(r->byVoxel.at(q[0])->onBody);
            EXPECT_TRUE(r->byVoxel.at(q[1])->isCut);
            EXPECT_TRUE(r->byVoxel.at(q[2])->isCut);
            EXPECT_EQ(r->plan.junctions[0].cuts, 2u);

            // The former tolerance (10 %) split them when the thicker leg
            // read 0.61: that is the flip the wider tolerance removes.
            CutOptions narrow;
            narrow.siblingTolerance = 0.1;
            const auto n = place(j, narrow, areas);
            EXPECT_EQ(n->plan.junctions[0].cuts, thickerLeg < 0.6f ? 2u : 1u);
        }
    }
}

/// A junction the body passes through (two candidates alike) with a thinner
/// branch at seven tenths of them, modelled on elephant.obj's head junction
/// (docs/algorithm.md §8.6): the branch stays a limb, so rule 3 does not cut
/// the body. This bounds the tolerance from above.
TEST(CutPlacement, BranchAtSevenTenthsOfTheBodyIsNotPulledInAtTwoScales) {
    for (const float scale : {1.0f, 2.0f}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        Junction j;
        for (int arm = 0; arm < 3; ++arm) j.setSigma(arm, {0.9f, 0.9f, 0.9f, 0.9f});
        j.set.point(j.centre).rhoS = 20.0f * scale;
        j.setRhoS(0, 12.8f * scale);          // body, similarity 0.64
        j.setRhoS(1, 12.8f * scale);          // body, the other side
        j.setRhoS(2, 0.71f * 12.8f * scale);  // 0.71 of the body's loops
        const std::uint32_t q[3] = {j.armVoxelAtLevel(0, 1), j.armVoxelAtLevel(1, 1),
                                    j.armVoxelAtLevel(2, 1)};
        const auto r = place(j, {}, {{q[0], 4100.0}, {q[1], 4300.0}, {q[2], 2400.0}});
        EXPECT_TRUE(r->byVoxel.at(q[0])->onBody);
        EXPECT_TRUE(r->byVoxel.at(q[1])->onBody);
        EXPECT_TRUE(r->byVoxel.at(q[2])->isCut);
        EXPECT_EQ(r->plan.junctions[0].cuts, 1u);
        EXPECT_EQ(r->callbackCalls, 0) << "two body candidates need no tie rule";

        // At 30 % it joined the body candidates and rule 3 cut the body.
        CutOptions wide;
        wide.siblingTolerance = 0.3;
        const auto w = place(j, wide, {{q[0], 4100.0}, {q[1], 4300.0}, {q[2], 2400.0}});
        EXPECT_EQ(w->plan.junctions[0].cuts, 2u);
        EXPECT_TRUE(w->byVoxel.at(q[0])->isCut);
    }
}

/// A body (rho_S 40) and one long limb meeting at a junction, all tight.
/// Levels are numbered as in Junction: level L of an arm is its voxel L + 2.
struct LongLimb {
    static constexpr int kLength = 60;
    SkeletonPointSet set{Dims{2 * kLength + 5, 5, 3}};
    std::vector<std::uint32_t> body, limb;
    LongLimb() {
        set.add({kLength + 2, 2, 1}, 40.0f, 5000.0, 3);
        body = set.chain({kLength + 1, 2, 1}, {-1, 0, 0}, kLength, 40.0f);
        limb = set.chain({kLength + 3, 2, 1}, {1, 0, 0}, kLength);
        for (std::uint32_t v : body) set.point(v).sigma = 0.9f;
        for (std::uint32_t v : limb) set.point(v).sigma = 0.9f;
    }
    /// The limb's rho_S at level L (1-based) is rhoOfLevel(L).
    template <class F>
    void setLimbProfile(F rhoOfLevel) {
        for (std::size_t i = 3; i < limb.size(); ++i)
            set.point(limb[i]).rhoS = float(rhoOfLevel(int(i) - 2));
    }
    /// Level of the cut on the limb (0: none).
    std::uint32_t cutLevel(const CutOptions& options = {}) const {
        const std::vector<SkeletonPoint> points = set.points();
        const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
        const CutPlan plan = placeCuts(g, points, options, [](std::uint32_t) { return 0.0; });
        for (const CutCandidate& c : plan.candidates)
            if (c.isCut) return c.level;
        return 0;
    }
};

TEST(CutPlacement, SleeveLyingOnALimbDoesNotMoveItsBorder) {
    // The limb is 12 thick (radius about 4 levels). Bare, its loop drops
    // from the body's to the limb's within two levels: the cut is at level
    // 3. With a sleeve lying on it (a skirt on a thigh) the loop shrinks by
    // 2 per level from 38 and reaches the limb's own 12 at level 14 only;
    // the midpoint rule alone would cut at level 7, inside the sleeve (rho_S
    // 26, more than twice the limb's). The cut settles where the loop stops
    // shrinking faster than a limb tapers: within one limb radius of the
    // sleeve's end.
    LongLimb bare;
    bare.setLimbProfile([](int level) { return level == 1 ? 36.0 : level == 2 ? 30.0 : 12.0; });
    EXPECT_EQ(bare.cutLevel(), 3u);

    LongLimb sleeved;
    sleeved.setLimbProfile([](int level) { return std::max(12.0, 38.0 - 2.0 * (level - 1)); });
    const std::uint32_t level = sleeved.cutLevel();
    EXPECT_GE(level, 14u - 4u);
    EXPECT_LE(level, 14u);
    CutOptions midpointOnly;
    midpointOnly.limbTaper = 1.0;  // never moves past the midpoint level
    EXPECT_EQ(sleeved.cutLevel(midpointOnly), 7u) << "the rule this test guards";
}

TEST(CutPlacement, TaperingLimbKeepsItsCutAtTheBase) {
    // A limb that tapers gently all along (a trunk, a tentacle: 0.2 per
    // level from 14, about 13 % over a loop diameter) never shrinks faster
    // than a limb tapers: the cut stays at the midpoint level, where the
    // loop is first the limb's, and does not slide out along the limb.
    LongLimb cone;
    cone.setLimbProfile([](int level) { return level == 1 ? 34.0 : 14.0 - 0.2 * (level - 2); });
    EXPECT_EQ(cone.cutLevel(), 2u);
}

/// A limb (or a block) at `scale` whose loops straddle sigma_min: every
/// level reads 0.76 to 0.79 and none reaches 0.8 (digitised thin limbs,
/// docs/algorithm.md §8.7). rhoOfLevel(L) gives rho_S at level L.
template <class F>
LongLimb straddlingBranch(F rhoOfLevel) {
    LongLimb limb;
    limb.setLimbProfile(rhoOfLevel);
    const float sigmas[4] = {0.77f, 0.79f, 0.76f, 0.78f};
    for (std::size_t i = 3; i < limb.limb.size(); ++i)
        limb.set.point(limb.limb[i]).sigma = sigmas[i % 4];
    return limb;
}

CutOptions relaxedForLimbs(bool on) {
    CutOptions options;
    options.relaxSigmaMinForLimbs = on;
    return options;
}

TEST(CutPlacement, TubeWhoseLoopsStraddleSigmaMinIsCutAtTwoScales) {
    // A tube 8 (16) thick: its loops keep their length, so a run just
    // below sigma_min is taken as a limb's and cut where it starts.
    for (int scale = 1; scale <= 2; ++scale) {
        const LongLimb tube = straddlingBranch([scale](int) { return 8.0 * scale; });
        EXPECT_EQ(tube.cutLevel(relaxedForLimbs(true)), 1u) << "scale " << scale;
        EXPECT_EQ(tube.cutLevel(relaxedForLimbs(false)), 0u) << "the rule this test guards";
    }
}

TEST(CutPlacement, StrutWhoseLoopsStraddleSigmaMinBetweenTwoJunctionsIsNotCut) {
    // The same straddling tube, but it reaches a second junction: a strut
    // between two junctions, not a limb (a limb's skeleton ends free). Its
    // run below sigma_min gives no cut from either junction.
    const int length = 20;
    SkeletonPointSet set{Dims{60 + length + 8, 5, 3}};
    set.add({62, 2, 1}, 40.0f, 5000.0, 3);
    for (std::uint32_t v : set.chain({61, 2, 1}, {-1, 0, 0}, 60, 40.0f)) set.point(v).sigma = 0.9f;
    const std::vector<std::uint32_t> strut = set.chain({63, 2, 1}, {1, 0, 0}, length, 8.0f);
    const float sigmas[4] = {0.77f, 0.79f, 0.76f, 0.78f};
    for (std::size_t i = 0; i < strut.size(); ++i) set.point(strut[i]).sigma = sigmas[i % 4];
    set.add({63 + length, 2, 1}, 8.0f, 5000.0, 3);
    const std::vector<SkeletonPoint> points = set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
    ASSERT_EQ(g.junctions.size(), 2u);
    const CutPlan plan = placeCuts(g, points, {}, [](std::uint32_t) { return 0.0; });
    EXPECT_TRUE(plan.cutNodes.empty());
}

TEST(CutPlacement, BlockWhoseLoopsStraddleSigmaMinIsNotCutAtTwoScales) {
    // A block of about the same thickness whose loops go round its edges
    // and corners: their length swings between 6 and 12 (12 and 24) over a
    // block's width (coefficient of variation 0.2 and 0.11 over one limb
    // radius from the run's start), so the run below sigma_min is
    // not a limb's and nothing is cut. A level at sigma_min would still be
    // needed to cut it, as without the rule.
    for (int scale = 1; scale <= 2; ++scale) {
        const int period = 8 * scale;
        const LongLimb block = straddlingBranch([scale, period](int level) {
            return scale * (6.0 + 6.0 * std::abs(level % period - period / 2) / (period / 2));
        });
        EXPECT_EQ(block.cutLevel(relaxedForLimbs(true)), 0u) << "scale " << scale;
        CutOptions anyVariation = relaxedForLimbs(true);
        anyVariation.limbLoopVariation = 1.0;
        EXPECT_GT(block.cutLevel(anyVariation), 0u) << "the rule this test guards";
    }
}

/// The body test of a branch that stays as thick as the body (a chest,
/// rho_S 1.1 times the junction's) for `chest` levels, narrows to 0.75 of
/// the junction's for 12 levels and then to a waist of half the junction's,
/// at `scale` times the levels and loop lengths of scale 1. Returns the
/// branch's candidate.
CutCandidate waistCandidate(int scale) {
    const int length = 60 * scale;
    SkeletonPointSet set{Dims{2 * length + 5, 5, 3}};
    const float junction = 40.0f * float(scale);
    set.add({length + 2, 2, 1}, junction, 5000.0, 3);
    const std::vector<std::uint32_t> body =
        set.chain({length + 1, 2, 1}, {-1, 0, 0}, length, junction);
    const std::vector<std::uint32_t> trunk = set.chain({length + 3, 2, 1}, {1, 0, 0}, length);
    for (std::uint32_t v : body) set.point(v).sigma = 0.9f;
    for (std::uint32_t v : trunk) set.point(v).sigma = 0.9f;
    const int chest = 10 * scale, narrowing = 12 * scale;
    for (std::size_t i = 3; i < trunk.size(); ++i) {
        const int level = int(i) - 2;
        set.point(trunk[i]).rhoS = level <= chest               ? 1.1f * junction
                                   : level <= chest + narrowing ? 0.75f * junction
                                                                : 0.5f * junction;
    }
    const std::vector<SkeletonPoint> points = set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
    const CutPlan plan = placeCuts(g, points, {}, [](std::uint32_t) { return 0.0; });
    for (const CutCandidate& c : plan.candidates)
        if (points[g.point[c.node]].voxel == trunk[3] || c.level > 1) return c;
    ADD_FAILURE() << "no candidate on the trunk";
    return {};
}

TEST(CutPlacement, LimbWindowStartsPastTheLoopsAsLongAsTheBodysAtTwoScales) {
    // The window for the limb's circumference is one body radius (13 levels
    // at scale 1): from the candidate it would end in the 0.75 stretch and
    // read the branch as body; the chest's loops are body loops, so the
    // window starts after them and reaches the waist (dino.off's waist: the
    // front junction read it as body at 320 only, docs/algorithm.md §8.6).
    for (const int scale : {1, 2}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        const CutCandidate c = waistCandidate(scale);
        EXPECT_FLOAT_EQ(c.limbRhoS, 20.0f * float(scale));
        EXPECT_NEAR(c.similarity, 1.0f - 0.6f / 1.1f, 1e-5f) << "against the chest's loop";
        EXPECT_TRUE(c.isCut);
    }
}

/// A body (rho_S 40 s) and one limb of constant rho_S 20 s (loop radius 6.4
/// s) whose skeleton goes on `levelsPastCut` levels past its first level,
/// where it is cut, at scale s: lengths grow with the resolution. With
/// `secondJunction` the limb ends at another junction (its region takes the
/// limb's last three voxels).
CutPlan limbEndingPastItsCut(int scale, int levelsPastCut, bool secondJunction = false) {
    const int limbLength = 3 + 1 + levelsPastCut + (secondJunction ? 3 : 0);
    SkeletonPointSet set = test::bodyWithOneLimb(scale, limbLength);
    if (secondJunction)
        set.add({30 * scale + 3 + limbLength, 2, 1}, 20.0f * float(scale), 5000.0, 3);
    const std::vector<SkeletonPoint> points = set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
    return placeCuts(g, points, {}, [](std::uint32_t) { return 0.0; });
}

const CutCandidate* limbCandidate(const CutPlan& plan) {
    for (const CutCandidate& c : plan.candidates)
        if (c.junction == 0 && !c.onBody) return &c;
    return nullptr;
}

/// Cut placement on a Y junction whose arm 0 is a limb of area about tau:
/// C_tau holds only its base, 12 levels whose loops (8 around against a body
/// of 20) still wrap the body (sigma 0.6 to 0.7, no run even below
/// sigma_min; the best loop is level 4's). pieceReach answers
/// reachAtLevel(level) for arm 0's loops.
CutPlan stubLimbPlan(const std::function<double(int)>& reachAtLevel, bool stubLimbs) {
    Junction y;
    y.setRhoS(0, 8.0f);
    y.setSigma(0, {0.62f, 0.66f, 0.6f, 0.7f, 0.64f, 0.68f, 0.6f, 0.66f, 0.62f, 0.7f, 0.6f, 0.64f});
    for (int arm : {1, 2}) y.setSigma(arm, std::vector<float>(12, 0.95f)), y.setRhoS(arm, 20.0f);
    const std::vector<SkeletonPoint> points = y.set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, y.set.dims(), {});
    CutOptions options;
    options.stubLimbs = stubLimbs;
    const int width = y.set.dims().x;
    return placeCuts(
        g, points, options, [](std::uint32_t) { return 0.0; }, {},
        [&](std::uint32_t node, std::uint32_t) {
            // Arm 0 runs along +x from the centre (22, 22): level l at x = 25 + l.
            const std::uint32_t voxel = points[g.point[node]].voxel;
            const int x = int(voxel) % width, row = int(voxel) / width % width;
            return row == 22 && x > 25 ? reachAtLevel(x - 25) : 0.0;
        });
}

CutPlan stubLimbPlan(double reach, bool stubLimbs) {
    return stubLimbPlan([reach](int) { return reach; }, stubLimbs);
}

TEST(CutPlacement, LimbOfAboutTauWhoseLoopsNeverTightenIsCutWhereItsPieceReachesFar) {
    // The piece past the stub's best loop reaches past twice the loop's
    // size (the flood's limit, 2 cornerReach): a limb, cut. A piece that
    // stays within the ball its loop spans is a cap, and the rule off gives
    // no candidate at all (docs/algorithm.md §8.12).
    const CutPlan limb = stubLimbPlan(2.32, true);
    ASSERT_EQ(limb.cutNodes.size(), 1u);
    ASSERT_EQ(limb.candidates.size(), 3u);
    const auto cut = std::find_if(limb.candidates.begin(), limb.candidates.end(),
                                  [](const CutCandidate& c) { return c.isCut; });
    ASSERT_NE(cut, limb.candidates.end());
    EXPECT_TRUE(cut->belowSigmaMin);
    EXPECT_TRUE(cut->stubLimb) << "reported as found by the stub rule";
    EXPECT_LT(cut->similarity, 0.6f);
    EXPECT_FLOAT_EQ(cut->sigma, 0.7f) << "the stub's best loop";
    EXPECT_TRUE(stubLimbPlan(1.0, true).cutNodes.empty()) << "a cap is no limb";
    EXPECT_TRUE(stubLimbPlan(2.32, false).cutNodes.empty()) << "the rule this test guards";
}

TEST(CutPlacement, LimbOfAboutTauIsCutWhereALoopPastItsBestReachesAsAPart) {
    // The best loop (level 4) still wraps the base and its piece reaches
    // only 1.5 loop sizes; from level 9 on the loops are the limb's and the
    // piece past them reaches 1.8: a limb, cut at its best loop. A stump of
    // the body's end reaches about 1.4 (a hand's wrist), a part 1.75 or
    // more, as in the end rule (docs/algorithm.md §8.12).
    const auto outerLoopsReach = [](int level) { return level >= 9 ? 1.8 : 1.5; };
    const CutPlan limb = stubLimbPlan(outerLoopsReach, true);
    ASSERT_EQ(limb.cutNodes.size(), 1u);
    const auto cut = std::find_if(limb.candidates.begin(), limb.candidates.end(),
                                  [](const CutCandidate& c) { return c.isCut; });
    ASSERT_NE(cut, limb.candidates.end());
    EXPECT_TRUE(cut->stubLimb);
    EXPECT_FLOAT_EQ(cut->sigma, 0.7f) << "cut at the best loop, not where the reach was read";
    EXPECT_EQ(stubLimbPlan(1.8, true).cutNodes.size(), 1u) << "1.75 loop sizes make a part";
    EXPECT_TRUE(stubLimbPlan(1.7, true).cutNodes.empty()) << "a stump";
    // Loops before the best one are the base's: their reach tells nothing.
    const auto innerLoopsReach = [](int level) { return level < 4 ? 1.8 : 1.5; };
    EXPECT_TRUE(stubLimbPlan(innerLoopsReach, true).cutNodes.empty());
    EXPECT_TRUE(stubLimbPlan(outerLoopsReach, false).cutNodes.empty());
}

TEST(CutPlacement, CornerOfTheBodyIsNotALimb) {
    // A skeleton that ends less than half a loop radius (3.2 s levels) past
    // the cut is a corner of a flat end (hand.off's forearm end forks into
    // two such prongs, docs/algorithm.md §8.6); one that goes on 8 s levels
    // is a limb. The same at two scales.
    EXPECT_TRUE(isCornerOfTheBody(10, 11, 12.0f, 0.5));
    EXPECT_FALSE(isCornerOfTheBody(10, 12, 12.0f, 0.5)) << "half a radius (1.9) is enough";
    EXPECT_TRUE(isCornerOfTheBody(12, 10, 12.0f, 0.5)) << "a cut past the skeleton's end";
    EXPECT_FALSE(isCornerOfTheBody(10, kNoJunction, 12.0f, 0.5)) << "ends at a junction";
    for (int scale : {1, 2}) {
        const CutPlan corner = limbEndingPastItsCut(scale, 2 * scale);
        const CutCandidate* c = limbCandidate(corner);
        ASSERT_NE(c, nullptr) << "scale " << scale;
        EXPECT_LT(c->similarity, 0.6f) << "the body test alone would cut it";
        EXPECT_TRUE(c->isCorner) << "scale " << scale;
        EXPECT_FALSE(c->isCut) << "scale " << scale;
        EXPECT_TRUE(corner.cutNodes.empty()) << "scale " << scale;
        EXPECT_EQ(corner.junctions[0].cuts, 0u);

        const CutPlan limb = limbEndingPastItsCut(scale, 8 * scale);
        c = limbCandidate(limb);
        ASSERT_NE(c, nullptr) << "scale " << scale;
        EXPECT_FALSE(c->isCorner) << "scale " << scale;
        EXPECT_TRUE(c->isCut) << "scale " << scale;
        EXPECT_EQ(limb.cutNodes.size(), 1u) << "scale " << scale;
    }
}

TEST(CutPlacement, ShortBranchToAnotherJunctionIsStillCut) {
    // The same short limb ending at a second junction (a waist between the
    // chest's and the hips' junctions) goes on past that junction: it is cut.
    const CutPlan plan = limbEndingPastItsCut(1, 2, true);
    ASSERT_EQ(plan.junctions.size(), 2u);
    const CutCandidate* c = limbCandidate(plan);
    ASSERT_NE(c, nullptr);
    EXPECT_FALSE(c->isCorner);
    EXPECT_TRUE(c->isCut);
}

/// The cut plan of a generated skeleton, with each point's rho_C as its
/// exact component area (the "more than two" rule's measure).
CutPlan placeCutsWithExactAreas(const SkeletonPointSet& set, const CutOptions& options) {
    const std::vector<SkeletonPoint> points = set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
    return placeCuts(g, points, options,
                     [&points](std::uint32_t pointIndex) { return points[pointIndex].rhoC; });
}

/// Two junctions (rho_S 40 s) joined along x by a passage as thick as they
/// are, each with two handles (rho_S 28 s, 0.7 of the body: body-similar)
/// at scale s; the junctions' cores are `gap` voxels apart. The passage
/// carries the most surface (rho_C `passageRhoC`, by default 9000, against
/// 1000).
CutPlan twoJunctionsWithHandles(int scale, int gap, const CutOptions& options,
                                double passageRhoC = 9000.0) {
    const int arm = 15 * scale, a = arm + 2, c = arm + 2;
    SkeletonPointSet set{Dims{2 * arm + gap + 5, 2 * arm + 5, 3}};
    const float body = 40.0f * float(scale), handle = 28.0f * float(scale);
    for (const int x : {a, a + gap}) {
        set.add({x, c, 1}, body, 9000.0, 3);
        const int out = x == a ? -1 : 1;
        for (const int side : {-1, 1})
            for (std::uint32_t v : set.chain({x + out, c + side, 1}, {out, side, 0}, arm, handle))
                set.point(v).sigma = 0.9f;
    }
    for (std::uint32_t v : set.chain({a + 1, c, 1}, {1, 0, 0}, gap - 1, body, passageRhoC))
        set.point(v).sigma = 0.9f;
    return placeCutsWithExactAreas(set, options);
}

TEST(CutPlacement, PassageBetweenJunctionsIsBodyAtTwoScales) {
    // A pair of pliers: where the passage between the two junctions is long
    // enough for a run of tight levels (scale 2), each junction has three
    // body-similar candidates and rule 3 cuts both handles; where it is too
    // short for a run (scale 1, one level outside the regions: PSB plier 202
    // at resolution 128) the passage is still body, and the handles are cut
    // the same way (docs/algorithm.md §8.6, "Passages").
    for (const int scale : {1, 2}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        const CutPlan plan = twoJunctionsWithHandles(scale, 8 * scale, {});
        ASSERT_EQ(plan.junctions.size(), 2u);
        EXPECT_EQ(plan.candidates.size(), scale == 1 ? 4u : 6u)
            << "scale 1: no candidate on the passage; scale 2: one from each end";
        std::size_t handleCuts = 0;
        for (const CutCandidate& c : plan.candidates) {
            EXPECT_GE(c.similarity, 0.6f);
            handleCuts += c.isCut ? 1 : 0;
        }
        EXPECT_EQ(handleCuts, 4u);
        EXPECT_EQ(plan.junctions[0].cuts, 2u);
        EXPECT_EQ(plan.junctions[1].cuts, 2u);
        EXPECT_EQ(plan.cutNodes.size(), 4u);
    }
    CutOptions without;
    without.passagesAreBody = false;
    EXPECT_TRUE(twoJunctionsWithHandles(1, 8, without).cutNodes.empty())
        << "two body candidates and nothing else: the handles stay on the body";
}

TEST(CutPlacement, APassageRoundAHandleCarriesNoAreaWhereHandlesAreArtefacts) {
    // The pliers of the test above with the passage's loop round a handle of
    // the model (rho_C infinite): it carries the most surface, and both
    // handles of each junction are cut. Where the model's handles are not
    // the shape's (handleLoopsCarryNoArea: a closed mesh's voxel model of a
    // higher genus), that infinity is the artefact's: the passage pushes
    // nothing off the body, and the handles stay, as with two body
    // candidates and nothing else. A finite passage is read as before.
    const double handleLoop = std::numeric_limits<double>::infinity();
    for (const int scale : {1, 2}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        EXPECT_EQ(twoJunctionsWithHandles(scale, 8 * scale, {}, handleLoop).cutNodes.size(), 4u);
        CutOptions artefacts;
        artefacts.handleLoopsCarryNoArea = true;
        EXPECT_TRUE(
            twoJunctionsWithHandles(scale, 8 * scale, artefacts, handleLoop).cutNodes.empty());
        EXPECT_EQ(twoJunctionsWithHandles(scale, 8 * scale, artefacts).cutNodes.size(), 4u);
    }
}

TEST(CutPlacement, PliersWhosePivotRegionsTouchCutEveryHandleAtTwoScales) {
    // The pliers' two pivot junctions 7 voxels apart (1.1 part radii: rho_S
    // 20 s, radius 6.4 s) at scale 1, where their 3-step regions touch, and
    // 14 apart at scale 2, where the branch between them gives a candidate
    // from each end: both are two junctions joined by the body, and all four
    // handles are cut (PSB plier 203 at resolution 128 and 192). As one
    // junction of four body-similar handles, rule 3 would keep one on the body.
    const auto pliers = [](int scale, double mergeRadii) {
        const int arm = 15 * scale, a = arm + 2, c = arm + 2, gap = 7 * scale;
        SkeletonPointSet set{Dims{2 * arm + gap + 5, 2 * arm + 5, 3}};
        const float body = 20.0f * float(scale), handle = 14.0f * float(scale);
        for (const int x : {a, a + gap}) {
            set.add({x, c, 1}, body, 9000.0, 3);
            const int out = x == a ? -1 : 1;
            for (const int side : {-1, 1})
                for (std::uint32_t v :
                     set.chain({x + out, c + side, 1}, {out, side, 0}, arm, handle))
                    set.point(v).sigma = 0.9f;
        }
        for (std::uint32_t v : set.chain({a + 1, c, 1}, {1, 0, 0}, gap - 1, body, 9000.0))
            set.point(v).sigma = 0.9f;
        const std::vector<SkeletonPoint> points = set.points();
        SkeletonGraphOptions graphOptions;
        graphOptions.junctionMergeRadii = mergeRadii;
        const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), graphOptions);
        return placeCuts(g, points, {},
                         [&points](std::uint32_t pointIndex) { return points[pointIndex].rhoC; });
    };
    for (const int scale : {1, 2}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        const CutPlan plan = pliers(scale, SkeletonGraphOptions{}.junctionMergeRadii);
        ASSERT_EQ(plan.junctions.size(), 2u);
        EXPECT_EQ(plan.junctions[0].cuts, 2u);
        EXPECT_EQ(plan.junctions[1].cuts, 2u);
        EXPECT_EQ(plan.cutNodes.size(), 4u);
    }
    const CutPlan merged = pliers(1, 0.0);
    ASSERT_EQ(merged.junctions.size(), 1u);
    EXPECT_EQ(merged.cutNodes.size(), 3u) << "one junction: one handle stays on the body";
}

TEST(CutPlacement, OneBodyCandidateBesidePassagesStaysBody) {
    // A plate whose skeleton branches into a row of junctions (a chair's
    // seat): the middle junction has passages to both neighbours, one branch
    // as thick as the body and one thin limb. The body branch stays body
    // even where a passage carries more surface; only the limb is cut.
    SkeletonPointSet set{Dims{40, 40, 3}};
    const float body = 40.0f;
    for (const int x : {12, 20, 28}) set.add({x, 20, 1}, body, 9000.0, 3);
    for (const int x : {12, 20})
        for (std::uint32_t v : set.chain({x + 1, 20, 1}, {1, 0, 0}, 7, body, 9000.0))
            set.point(v).sigma = 0.9f;
    const std::vector<std::uint32_t> thick = set.chain({20, 21, 1}, {0, 1, 0}, 15, body, 5000.0);
    const std::vector<std::uint32_t> limb = set.chain({20, 19, 1}, {0, -1, 0}, 15, 12.0f, 1000.0);
    for (const auto* branch : {&thick, &limb})
        for (std::uint32_t v : *branch) set.point(v).sigma = 0.9f;
    const std::vector<SkeletonPoint> points = set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
    const CutPlan plan = placeCuts(
        g, points, {}, [&points](std::uint32_t pointIndex) { return points[pointIndex].rhoC; });
    ASSERT_EQ(plan.junctions.size(), 3u);
    ASSERT_EQ(plan.candidates.size(), 2u);
    for (const CutCandidate& c : plan.candidates) {
        const bool onLimb = c.limbRhoS < 0.5f * body;
        EXPECT_EQ(c.isCut, onLimb) << "limb rho_S " << c.limbRhoS;
    }
    EXPECT_EQ(plan.cutNodes.size(), 1u);
}

TEST(CutPlacement, PassageCountsInTheSiblingTest) {
    // One handle at 0.7 of the body, its sibling at 0.55 (within 25 % of the
    // thinner body member): with the passage as the second body member the
    // sibling is pulled in and rule 3 cuts both, as when the passage gives a
    // candidate.
    std::vector<CutCandidate> candidates(2);
    candidates[0].baseRhoS = candidates[0].limbRhoS = 28.0f;
    candidates[1].baseRhoS = candidates[1].limbRhoS = 22.0f;
    markBodyCandidates(40.0f, {}, candidates.data(), candidates.size(), {40.0f});
    EXPECT_TRUE(candidates[0].onBody);
    EXPECT_TRUE(candidates[1].onBody) << "sibling of the thinner body member";
    markBodyCandidates(40.0f, {}, candidates.data(), candidates.size());
    EXPECT_FALSE(candidates[1].onBody) << "without the passage: one body candidate";
}

TEST(CutPlacement, ArmBesideAThinPassageIsNoSiblingOfItAtTwoScales) {
    // A shoulder junction (rho_S 100 s) on a figure whose hand makes a
    // junction of its own: the forearm between them has no tight run and is
    // a passage (loop 14 s), the way to the other shoulder a passage too
    // (85 s), and the upper arm gives a candidate (29 s, similarity 0.29).
    // The forearm is the thinner body member; the upper arm is twice as
    // thick, no sibling of it, and stays a limb (modelled on a held-out
    // character at 320, docs/quality.md "flips15").
    for (const float scale : {1.0f, 2.0f}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        std::vector<CutCandidate> arm(1);
        arm[0].baseRhoS = 37.0f * scale;
        arm[0].limbRhoS = 29.0f * scale;
        const std::vector<float> passages{14.0f * scale, 85.0f * scale};
        markBodyCandidates(100.0f * scale, {}, arm.data(), arm.size(), passages);
        EXPECT_LT(arm[0].similarity, 0.6f);
        EXPECT_FALSE(arm[0].onBody) << "twice the thinner member is no sibling";
        CutOptions oneSided;
        oneSided.siblingsBothWays = false;
        markBodyCandidates(100.0f * scale, oneSided, arm.data(), arm.size(), passages);
        EXPECT_TRUE(arm[0].onBody) << "the one-sided bound pulls it in";
        // A candidate nearly as thick as the forearm is still its sibling.
        arm[0].baseRhoS = arm[0].limbRhoS = 12.0f * scale;
        markBodyCandidates(100.0f * scale, {}, arm.data(), arm.size(), passages);
        EXPECT_TRUE(arm[0].onBody);
    }
}

/// A torso junction (rho_S 80 s) with the torso (80 s) and a leg (20 s), and
/// a shoulder junction (68 s) with a neck (44 s) and an arm (20 s), at scale
/// s; the junctions' cores are `gap` voxels apart along x, joined by a
/// branch as thick as the shoulder. With gap 8 that branch is a passage (one
/// level outside the regions, no candidate); with gap 6 the regions touch
/// and the two junctions are one (a teddy's shoulders at resolution 128 and
/// 192, PSB 163).
CutPlan torsoAndShoulder(int scale, int gap, const CutOptions& options) {
    const int arm = 30 * scale, a = arm + 2, c = arm + 2, b = a + gap;
    const float s = float(scale);
    SkeletonPointSet set{Dims{2 * arm + gap + 5, 2 * arm + 5, 3}};
    set.add({a, c, 1}, 80.0f * s, 9000.0, 3);
    set.add({b, c, 1}, 68.0f * s, 9000.0, 3);
    std::vector<std::vector<std::uint32_t>> branches;
    branches.push_back(set.chain({a, c - 1, 1}, {0, -1, 0}, arm, 80.0f * s));      // torso
    branches.push_back(set.chain({a - 1, c + 1, 1}, {-1, 1, 0}, arm, 20.0f * s));  // leg
    branches.push_back(set.chain({b, c - 1, 1}, {0, -1, 0}, arm, 44.0f * s));      // neck
    branches.push_back(set.chain({b + 1, c + 1, 1}, {1, 1, 0}, arm, 20.0f * s));   // arm
    branches.push_back(set.chain({a + 1, c, 1}, {1, 0, 0}, gap - 1, 68.0f * s));   // between
    for (const auto& branch : branches)
        for (std::uint32_t v : branch) set.point(v).sigma = 0.9f;
    return placeCutsWithExactAreas(set, options);
}

/// The candidate whose limb circumference is `limb` (the neck).
const CutCandidate* candidateOfLimb(const CutPlan& plan, float limb) {
    for (const CutCandidate& c : plan.candidates)
        if (std::fabs(c.limbRhoS - limb) < 0.5f) return &c;
    return nullptr;
}

TEST(CutPlacement, NeckIsJudgedAgainstTheBodyAcrossAPassageAtTwoScales) {
    // The neck (0.55 of the torso, 0.65 of the shoulder junction) is cut
    // where the shoulder and torso junctions are one (gap 6) and where they
    // are two joined by a passage (gap 8): the body passes through both, so
    // they share the torso's reference (docs/algorithm.md §8.6, "One body
    // reference across passages").
    for (const int scale : {1, 2}) {
        for (const int gap : {6, 8}) {
            SCOPED_TRACE("scale " + std::to_string(scale) + ", gap " + std::to_string(gap));
            const CutPlan plan = torsoAndShoulder(scale, gap, {});
            ASSERT_EQ(plan.junctions.size(), gap == 6 ? 1u : 2u);
            const CutCandidate* neck = candidateOfLimb(plan, 44.0f * float(scale));
            ASSERT_NE(neck, nullptr);
            EXPECT_FLOAT_EQ(neck->bodyRhoS, 80.0f * float(scale));
            EXPECT_NEAR(neck->similarity, 0.55f, 1e-4f);
            EXPECT_TRUE(neck->isCut);
            const CutCandidate* torso = candidateOfLimb(plan, 80.0f * float(scale));
            ASSERT_NE(torso, nullptr);
            EXPECT_FALSE(torso->isCut);
        }
        // Against the shoulder junction alone the neck is body-similar; the
        // end rule (§8.14), off here, would cut it too.
        CutOptions without;
        without.shareBodyAcrossPassages = false;
        without.endBodyRatio = 0.0;
        const CutPlan plan = torsoAndShoulder(scale, 8, without);
        const CutCandidate* neck = candidateOfLimb(plan, 44.0f * float(scale));
        ASSERT_NE(neck, nullptr);
        EXPECT_FALSE(neck->isCut) << "against the shoulder junction alone the neck is body";
        without.endBodyRatio = CutOptions{}.endBodyRatio;
        const CutPlan endRulePlan = torsoAndShoulder(scale, 8, without);
        const CutCandidate* ended = candidateOfLimb(endRulePlan, 44.0f * float(scale));
        ASSERT_NE(ended, nullptr);
        EXPECT_TRUE(ended->isCut) << "the body goes on through the passage; the neck ends";
    }
    // Where the branch between the junctions is long enough to give
    // candidates (gap 16) it is no passage: each junction keeps its own
    // reference, and the neck reads body-similar at the shoulder (0.65).
    // The body goes on through the shoulder to the torso junction, where the
    // leg leaves it, and the neck ends there: the end rule (§8.14) cuts it,
    // as in the two layouts above; without that rule it stays.
    const CutPlan apart = torsoAndShoulder(1, 16, {});
    ASSERT_EQ(apart.junctions.size(), 2u);
    const CutCandidate* neck = candidateOfLimb(apart, 44.0f);
    ASSERT_NE(neck, nullptr);
    EXPECT_FLOAT_EQ(neck->bodyRhoS, 68.0f);
    EXPECT_TRUE(neck->isCut);
    CutOptions noEndRule;
    noEndRule.endBodyRatio = 0.0;
    const CutPlan withoutEndRule = torsoAndShoulder(1, 16, noEndRule);
    const CutCandidate* kept = candidateOfLimb(withoutEndRule, 44.0f);
    ASSERT_NE(kept, nullptr);
    EXPECT_FALSE(kept->isCut);
}

/// A shoulder junction and a hip junction (rho_S 80 s each) 20 s voxels
/// apart along x, joined by the torso (80 s), at scale s. At the shoulder a
/// head (rho_S `head` s) and an arm (20 s) end free; at the hips two legs (20 s) do, or with `legs`
/// false one branch as thick as the torso (nothing leaves the body there).
/// With `waist`, a third junction on the torso halfway (40 s voxels between
/// shoulder and hips) where only the torso passes; `arm2` sets the arm's
/// rho_S (s).
CutPlan headBesideTheTorso(int scale, float head, bool legs, const CutOptions& options,
                           const PieceReach& pieceReach = {}, bool waist = false,
                           float arm2 = 20.0f) {
    const int arm = 15 * scale, gap = 20 * scale, a = arm + 2, c = arm + 2;
    const int b = a + (waist ? 2 : 1) * gap;
    const float s = float(scale);
    SkeletonPointSet set{Dims{b + arm + 5, 2 * arm + 5, 3}};
    set.add({a, c, 1}, 80.0f * s, 9000.0, 3);
    set.add({b, c, 1}, 80.0f * s, 9000.0, 3);
    std::vector<std::vector<std::uint32_t>> branches;
    branches.push_back(set.chain({a - 1, c - 1, 1}, {-1, -1, 0}, arm, head * s, 2000.0));
    branches.push_back(set.chain({a - 1, c + 1, 1}, {-1, 1, 0}, arm, arm2 * s));
    branches.push_back(set.chain({a + 1, c, 1}, {1, 0, 0}, gap - 1, 80.0f * s, 6000.0));
    if (waist) {
        set.add({a + gap, c, 1}, 80.0f * s, 9000.0, 3);
        branches.push_back(set.chain({a + gap + 1, c, 1}, {1, 0, 0}, gap - 1, 80.0f * s, 6000.0));
    }
    if (legs) {
        branches.push_back(set.chain({b + 1, c - 1, 1}, {1, -1, 0}, arm, 20.0f * s));
        branches.push_back(set.chain({b + 1, c + 1, 1}, {1, 1, 0}, arm, 20.0f * s));
    } else {
        branches.push_back(set.chain({b + 1, c, 1}, {1, 0, 0}, arm, 76.0f * s));
    }
    for (const auto& branch : branches)
        for (std::uint32_t v : branch) set.point(v).sigma = 0.9f;
    const std::vector<SkeletonPoint> points = set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
    return placeCuts(
        g, points, options, [&points](std::uint32_t pointIndex) { return points[pointIndex].rhoC; },
        {}, pieceReach);
}

TEST(CutPlacement, HeadBesideTheWayOnIsCutBelowTheEndRatioAtTwoScales) {
    // wolfp1 (a held-out pose sequence): the head reads 0.595, 0.554, 0.615
    // and 0.610 of the body at the shoulders, so bodyRatio cut it in two
    // poses of four. The body goes on through the shoulders (the torso leads
    // to the hips, where legs leave it) and the head ends there: below
    // endBodyRatio (0.75) it is cut in every pose (docs/algorithm.md §8.14).
    for (const int scale : {1, 2}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        const float s = float(scale);
        const CutPlan plan = headBesideTheTorso(scale, 52.0f, true, {});
        ASSERT_EQ(plan.junctions.size(), 2u);
        const CutCandidate* head = candidateOfLimb(plan, 52.0f * s);
        ASSERT_NE(head, nullptr);
        EXPECT_NEAR(head->similarity, 0.65f, 1e-4f);
        EXPECT_TRUE(head->isCut);
        EXPECT_EQ(plan.junctions[0].cuts, 2u) << "the head and the arm";
        EXPECT_EQ(plan.junctions[1].cuts, 2u) << "the legs";

        CutOptions off;
        off.endBodyRatio = 0.0;
        const CutPlan without = headBesideTheTorso(scale, 52.0f, true, off);
        ASSERT_NE(candidateOfLimb(without, 52.0f * s), nullptr);
        EXPECT_FALSE(candidateOfLimb(without, 52.0f * s)->isCut) << "the rule this test guards";

        // Nearly as thick as the body (0.8): the body's end, not cut.
        const CutPlan thick = headBesideTheTorso(scale, 64.0f, true, {});
        ASSERT_NE(candidateOfLimb(thick, 64.0f * s), nullptr);
        EXPECT_FALSE(candidateOfLimb(thick, 64.0f * s)->isCut);
        // The piece past the head's loop must reach as a part does: a stump
        // of the body's end (reach 1.4, a hand's wrist) stays; a reach of 0
        // (no piece past the loop's plane: a head bent back) tells nothing.
        for (const double reach : {1.4, 0.0, 2.0}) {
            const auto reachOf = [reach](std::uint32_t, std::uint32_t) { return reach; };
            const CutPlan reached = headBesideTheTorso(scale, 52.0f, true, {}, reachOf);
            ASSERT_NE(candidateOfLimb(reached, 52.0f * s), nullptr);
            EXPECT_EQ(candidateOfLimb(reached, 52.0f * s)->isCut, reach != 1.4)
                << "reach " << reach;
        }
        // No limb leaves at the hips: the torso is no way on to the rest of
        // the shape, and the head is judged by bodyRatio alone.
        const CutPlan noLegs = headBesideTheTorso(scale, 52.0f, false, {});
        ASSERT_NE(candidateOfLimb(noLegs, 52.0f * s), nullptr);
        EXPECT_FALSE(candidateOfLimb(noLegs, 52.0f * s)->isCut);
    }
}

TEST(CutPlacement, HeadIsCutWhereTheWayOnReachesLimbsThroughAJunctionWhereNothingLeaves) {
    // pcow (a held-out pose sequence), frame 50: the neck reads 0.63 of the
    // body at the chest, whose torso leads to a junction where only the
    // body passes (the tail's stub gives no cut) and on to the hind legs.
    // The body goes on through the chest all the same: the head ends there
    // and is cut (docs/algorithm.md §8.14).
    for (const int scale : {1, 2}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        const float s = float(scale);
        const CutPlan plan = headBesideTheTorso(scale, 52.0f, true, {}, {}, true);
        ASSERT_EQ(plan.junctions.size(), 3u);
        EXPECT_EQ(plan.junctions[2].cuts, 0u) << "nothing leaves the body at the waist";
        const CutCandidate* head = candidateOfLimb(plan, 52.0f * s);
        ASSERT_NE(head, nullptr);
        EXPECT_NEAR(head->similarity, 0.65f, 1e-4f);
        EXPECT_TRUE(head->isCut);
        EXPECT_EQ(plan.cutNodes.size(), 4u) << "the head, the arm and the legs";
        // No limb anywhere past the waist: no way on, the head stays.
        const CutPlan noLegs = headBesideTheTorso(scale, 52.0f, false, {}, {}, true);
        ASSERT_NE(candidateOfLimb(noLegs, 52.0f * s), nullptr);
        EXPECT_FALSE(candidateOfLimb(noLegs, 52.0f * s)->isCut);
    }
}

/// Two prongs (rho_S 52 s and 62 s: 0.65 and 0.775 of the body) end at a
/// shoulder junction whose torso (80 s, the most surface) leads to the hips,
/// where two legs (20 s) leave and a tail (56 s: 0.7) ends, at scale s.
CutPlan prongsBesideTheTorso(int scale) {
    const int arm = 15 * scale, gap = 20 * scale, a = arm + 2, c = arm + 2, b = a + gap;
    const float s = float(scale);
    SkeletonPointSet set{Dims{b + arm + 5, 2 * arm + 5, 3}};
    set.add({a, c, 1}, 80.0f * s, 9000.0, 3);
    set.add({b, c, 1}, 80.0f * s, 9000.0, 3);
    std::vector<std::vector<std::uint32_t>> branches;
    branches.push_back(set.chain({a - 1, c - 1, 1}, {-1, -1, 0}, arm, 52.0f * s, 2000.0));
    branches.push_back(set.chain({a - 1, c + 1, 1}, {-1, 1, 0}, arm, 62.0f * s, 2000.0));
    branches.push_back(set.chain({a + 1, c, 1}, {1, 0, 0}, gap - 1, 80.0f * s, 6000.0));
    branches.push_back(set.chain({b + 1, c - 1, 1}, {1, -1, 0}, arm, 20.0f * s));
    branches.push_back(set.chain({b + 1, c + 1, 1}, {1, 1, 0}, arm, 20.0f * s));
    branches.push_back(set.chain({b + 1, c, 1}, {1, 0, 0}, arm, 56.0f * s, 2000.0));
    for (const auto& branch : branches)
        for (std::uint32_t v : branch) set.point(v).sigma = 0.9f;
    const std::vector<SkeletonPoint> points = set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
    return placeCuts(g, points, {},
                     [&points](std::uint32_t pointIndex) { return points[pointIndex].rhoC; });
}

TEST(CutPlacement, EndRuleReadsWhatTheMoreThanTwoRuleLeftOnTheBodyAtTwoScales) {
    // PSB fish 223: the tail's two prongs read 0.659 and 0.789 of the body
    // where the body goes on. Three body members there (the prongs and the
    // way on): the "more than two" rule keeps the one with the most surface
    // and cuts both prongs. The end rule reads what that rule left; had it
    // taken the thinner prong off first, the thicker one would have been
    // left alone on the body beside the way on (docs/algorithm.md §8.14).
    // The tail at the hips (0.7, ending beside the way on) makes the end
    // rule's plan happen at all.
    for (const int scale : {1, 2}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        const float s = float(scale);
        const CutPlan plan = prongsBesideTheTorso(scale);
        ASSERT_EQ(plan.junctions.size(), 2u);
        for (const float prong : {52.0f, 62.0f}) {
            const CutCandidate* c = candidateOfLimb(plan, prong * s);
            ASSERT_NE(c, nullptr) << prong;
            EXPECT_TRUE(c->isCut) << prong;
        }
        const CutCandidate* tail = candidateOfLimb(plan, 56.0f * s);
        ASSERT_NE(tail, nullptr);
        EXPECT_NEAR(tail->similarity, 0.7f, 1e-4f);
        EXPECT_TRUE(tail->isCut) << "the end rule acts at the hips";
        const CutCandidate* torso = candidateOfLimb(plan, 80.0f * s);
        ASSERT_NE(torso, nullptr);
        EXPECT_FALSE(torso->isCut);
    }
}

TEST(CutPlacement, JunctionModeCutsAtTheJunction) {
    Junction j;
    for (int arm = 0; arm < 3; ++arm) j.setSigma(arm, {0.9f, 0.9f, 0.9f});
    CutOptions options;
    options.mode = CutMode::Junctions;
    const auto r = place(j, options);
    EXPECT_TRUE(r->plan.candidates.empty());
    EXPECT_EQ(r->cutVoxels, std::vector<std::uint32_t>{j.centre});
    EXPECT_EQ(r->plan.junctions[0].cuts, 1u);
    EXPECT_EQ(r->plan.junctions[0].branches, 3u);
}

TEST(CutPlacement, NoJunctionNoCut) {
    SkeletonPointSet set(Dims{20, 5, 3});
    for (std::uint32_t v : set.chain({2, 2, 1}, {1, 0, 0}, 15)) set.point(v).sigma = 0.95f;
    const std::vector<SkeletonPoint> points = set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
    const CutPlan plan = placeCuts(g, points, {}, [](std::uint32_t) { return 0.0; });
    EXPECT_TRUE(plan.junctions.empty());
    EXPECT_TRUE(plan.cutNodes.empty());
}

/// A body (rho_S 40 s on both sides of the junction, exact rho_C 9000 and
/// 8000) with a third branch at `scale` s whose sigma straddles sigma_min
/// (0.76 to 0.79, found only by the walk below it), rho_S `third` s and
/// rho_C 1000, ending free. `thirdAtSigmaMin` puts a fourth branch like it
/// at sigma 0.9 beside it (a twin).
CutPlan bodyWithAStraddlingBranch(int scale, float third, bool thirdAtSigmaMin,
                                  const CutOptions& options) {
    const int length = 30 * scale, side = 20 * scale;
    SkeletonPointSet set{Dims{2 * length + 5, 2 * side + 5, 3}};
    const int cx = length + 2, cy = side + 2;
    const float body = 40.0f * float(scale);
    set.add({cx, cy, 1}, body, 9000.0, 3);
    for (std::uint32_t v : set.chain({cx - 1, cy, 1}, {-1, 0, 0}, length, body, 9000.0))
        set.point(v).sigma = 0.9f;
    for (std::uint32_t v : set.chain({cx + 1, cy, 1}, {1, 0, 0}, length, body, 8000.0))
        set.point(v).sigma = 0.9f;
    const std::vector<std::uint32_t> straddling =
        set.chain({cx, cy + 1, 1}, {0, 1, 0}, side, third * float(scale), 1000.0);
    const float sigmas[4] = {0.77f, 0.79f, 0.76f, 0.78f};
    for (std::size_t i = 0; i < straddling.size(); ++i)
        set.point(straddling[i]).sigma = sigmas[i % 4];
    if (thirdAtSigmaMin)
        for (std::uint32_t v :
             set.chain({cx, cy - 1, 1}, {0, -1, 0}, side, third * float(scale), 1000.0))
            set.point(v).sigma = 0.9f;
    return placeCutsWithExactAreas(set, options);
}

CutOptions belowSigmaMinOnlyLimbs(bool on) {
    CutOptions options;
    options.belowSigmaMinOnlyLimbs = on;
    return options;
}

TEST(CutPlacement, HumpFromTheWalkBelowSigmaMinDoesNotCutTheBodyAtTwoScales) {
    // A hump on the body (camel.off at 400): its loops (0.7 of the body's)
    // read body and straddle sigma_min. Counted as a third body member it
    // made the "more than two" rule cut the body and the hump; the walk
    // below sigma_min only finds limbs, so it gives no candidate here and
    // nothing is cut (docs/algorithm.md §8.8).
    for (const int scale : {1, 2}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        const CutPlan plan = bodyWithAStraddlingBranch(scale, 28.0f, false, {});
        EXPECT_EQ(plan.candidates.size(), 2u);
        EXPECT_TRUE(plan.cutNodes.empty());
        const CutPlan without =
            bodyWithAStraddlingBranch(scale, 28.0f, false, belowSigmaMinOnlyLimbs(false));
        EXPECT_EQ(without.candidates.size(), 3u);
        EXPECT_EQ(without.cutNodes.size(), 2u) << "the rule this test guards";
    }
}

TEST(CutPlacement, StraddlingProngWithATwinAtSigmaMinIsStillCutAtTwoScales) {
    // A tail's two prongs (PSB bird 242 at 192): one reaches sigma_min, the
    // other only straddles it; both read body. The twin at sigma_min, ending
    // free and alike, shows the straddling one is a limb too: the "more than
    // two" rule keeps the body and cuts both prongs.
    for (const int scale : {1, 2}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        const CutPlan plan = bodyWithAStraddlingBranch(scale, 28.0f, true, {});
        EXPECT_EQ(plan.candidates.size(), 4u);
        std::size_t prongCuts = 0;
        for (const CutCandidate& c : plan.candidates)
            prongCuts += c.isCut && c.limbRhoS < 30.0f * float(scale) ? 1 : 0;
        EXPECT_EQ(prongCuts, 2u);
    }
}

/// Two junctions (rho_S 40 s) joined along x by a passage as thick as they
/// are (rho_C 9000) too short for a run of tight levels at both scales. The
/// first junction has a torso (rho_S 28 s, rho_C 20000: more surface than
/// the passage) and a body branch (40 s, rho_C 30000); the second two thin
/// limbs (12 s, rho_C 1000).
CutPlan torsoBesideAPassage(int scale, const CutOptions& options) {
    const int arm = 15 * scale, gap = 8, a = arm + 2, c = arm + 2;
    SkeletonPointSet set{Dims{2 * arm + gap + 5, 2 * arm + 5, 3}};
    const float body = 40.0f * float(scale);
    for (const int x : {a, a + gap}) set.add({x, c, 1}, body, 9000.0, 3);
    const auto branch = [&](int x, int out, int side, float rhoS, double rhoC) {
        for (std::uint32_t v :
             set.chain({x + out, c + side, 1}, {out, side, 0}, arm, rhoS * float(scale), rhoC))
            set.point(v).sigma = 0.9f;
    };
    branch(a, -1, -1, 28.0f, 20000.0);
    branch(a, -1, 1, 40.0f, 30000.0);
    branch(a + gap, 1, -1, 12.0f, 1000.0);
    branch(a + gap, 1, 1, 12.0f, 1000.0);
    for (std::uint32_t v : set.chain({a + 1, c, 1}, {1, 0, 0}, gap - 1, body, 9000.0))
        set.point(v).sigma = 0.9f;
    return placeCutsWithExactAreas(set, options);
}

TEST(CutPlacement, TorsoCarryingMoreSurfaceThanAPassageStaysBodyAtTwoScales) {
    // mannequin.off at 400: beside the torso (similarity 0.63) and the body
    // branch, short passages join the junction to its neighbours inside the
    // body. The passage carries less surface than the torso, so it does not
    // push the torso off the body; the thin limbs of the other junction are
    // cut as before. The end rule (§8.14) is off: on the mannequin no limb
    // leaves the body at any junction, so it does not act there, while here
    // the thin limbs would make the passage a way on.
    CutOptions options;
    options.endBodyRatio = 0.0;
    for (const int scale : {1, 2}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        const CutPlan plan = torsoBesideAPassage(scale, options);
        ASSERT_EQ(plan.junctions.size(), 2u);
        ASSERT_EQ(plan.candidates.size(), 4u) << "no candidate on the passage";
        EXPECT_EQ(plan.junctions[0].cuts, 0u);
        EXPECT_EQ(plan.junctions[1].cuts, 2u);
        CutOptions without = options;
        without.passageCutsOnlySmallerCandidates = false;
        EXPECT_EQ(torsoBesideAPassage(scale, without).junctions[0].cuts, 1u)
            << "the rule this test guards";
    }
}

/// A round end of the body (a mantle, rho_S 40 s) whose junction has one
/// branch, at scale s: the branch keeps the mantle's loop (36 s) for 8 s
/// levels, narrows to a neck (20 s) and, with `mouth`, reaches a second
/// junction (20 s) with two thin arms (8 s); without, it ends free (a ball
/// on a handle). Modelled on octopus.off's mantle (docs/algorithm.md §8.9).
CutPlan roundEndOfTheBody(int scale, bool mouth, const CutOptions& options) {
    const int branch = 30 * scale, arm = 20 * scale, mouthX = 3 + branch;
    const float s = float(scale);
    SkeletonPointSet set{Dims{mouthX + arm + 3, 2 * arm + 5, 3}};
    const int y = arm + 2;
    set.add({2, y, 1}, 40.0f * s, 9000.0, 3);
    const std::vector<std::uint32_t> neck = set.chain({3, y, 1}, {1, 0, 0}, branch, 20.0f * s);
    for (std::size_t i = 0; i < neck.size(); ++i) {
        set.point(neck[i]).sigma = 0.9f;
        if (int(i) < 3 + 8 * scale) set.point(neck[i]).rhoS = 36.0f * s;
    }
    if (mouth) {
        set.add({mouthX, y, 1}, 20.0f * s, 9000.0, 3);
        for (const int dy : {-1, 1})
            for (std::uint32_t v : set.chain({mouthX + 1, y + dy, 1}, {1, dy, 0}, arm, 8.0f * s))
                set.point(v).sigma = 0.9f;
    }
    const std::vector<SkeletonPoint> points = set.points();
    const SkeletonGraph g = buildSkeletonGraph(points, set.dims(), {});
    return placeCuts(g, points, options, [](std::uint32_t) { return 0.0; });
}

TEST(CutPlacement, OneBranchJunctionDoesNotCutTheWayToAnotherJunctionAtTwoScales) {
    // The mantle's junction has one branch, which narrows to a neck (0.5 of
    // the mantle) and reaches the mouth's junction: the body ends in the
    // mantle and goes on through the neck to the mouth, which judges that
    // branch (body there) and cuts the arms. A ball on a handle that ends
    // free is still cut.
    for (const int scale : {1, 2}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        const CutPlan plan = roundEndOfTheBody(scale, true, {});
        ASSERT_EQ(plan.junctions.size(), 2u);
        const std::uint32_t mantle = plan.junctions[0].branches == 1 ? 0 : 1;
        ASSERT_EQ(plan.junctions[mantle].branches, 1u);
        ASSERT_EQ(plan.junctions[1 - mantle].branches, 3u);
        const CutCandidate* neck = nullptr;
        for (const CutCandidate& c : plan.candidates)
            if (c.junction == mantle) neck = &c;
        ASSERT_NE(neck, nullptr);
        EXPECT_NEAR(neck->similarity, 0.5f, 1e-4f) << "the body test alone would cut it";
        EXPECT_FALSE(neck->isCut);
        EXPECT_EQ(plan.junctions[mantle].cuts, 0u);
        EXPECT_EQ(plan.junctions[1 - mantle].cuts, 2u) << "the arms";
        EXPECT_EQ(plan.cutNodes.size(), 2u);

        CutOptions without;
        without.oneBranchJunctionsEndTheBody = false;
        EXPECT_EQ(roundEndOfTheBody(scale, true, without).junctions[mantle].cuts, 1u)
            << "the rule this test guards";

        const CutPlan handle = roundEndOfTheBody(scale, false, {});
        ASSERT_EQ(handle.junctions.size(), 1u);
        EXPECT_EQ(handle.junctions[0].cuts, 1u) << "a handle that ends free is a limb";
    }
}

/// A limb (rho_S 10 s) leaving a body junction (rho_S 40 s) reaches a
/// junction of its own (PSB octopus 121 at 320: a thin bridge to the next arm
/// leaves there, the stub along y) and goes on to a free tip, at scale s. A
/// handle through the bridge joins the limb to the rest again before that
/// junction: the loops there separate nothing unless the stub is cut too (the
/// two loops then cut off the limb's base and the bridge together); the
/// loops of the body and the tip separate. With `withTip` false the limb
/// ends at its junction; with `stubIsLimb` the stub is tight and thin, so
/// its junction cuts it.
struct LimbThroughAHandle {
    int scale = 1;
    int a = 0, b = 0;  // x of the body junction and of the limb's junction
    int width = 0;
    std::vector<SkeletonPoint> points;
    SkeletonGraph graph;
    LimbThroughAHandle(int s, bool withTip, bool stubIsLimb = false) : scale(s) {
        const int body = 20 * s, limb = 20 * s, tipLength = 15 * s, stub = 8 * s;
        a = body + 1, b = a + limb + 1, width = b + tipLength + 3;
        SkeletonPointSet set{Dims{width, stub + 8, 3}};
        set.add({a, 5, 1}, 40.0f * float(s), 9000.0, 3);
        for (std::uint32_t v : set.chain({a - 1, 5, 1}, {-1, 0, 0}, body, 40.0f * float(s)))
            set.point(v).sigma = 0.9f;
        for (std::uint32_t v : set.chain({a + 1, 5, 1}, {1, 0, 0}, limb, 10.0f * float(s)))
            set.point(v).sigma = 0.9f;
        set.add({b, 5, 1}, 10.0f * float(s), 9000.0, 3);
        for (std::uint32_t v : set.chain({b, 6, 1}, {0, 1, 0}, stub, 2.0f * float(s), 2000.0))
            set.point(v).sigma = stubIsLimb ? 0.9f : 0.3f;
        if (withTip)
            for (std::uint32_t v : set.chain({b + 1, 5, 1}, {1, 0, 0}, tipLength, 10.0f * float(s)))
                set.point(v).sigma = 0.9f;
        points = set.points();
        graph = buildSkeletonGraph(points, set.dims(), {});
    }
    int xOf(std::uint32_t voxel) const { return int(voxel % std::uint32_t(width)); }
    int yOf(std::uint32_t voxel) const {
        return int(voxel / std::uint32_t(width)) % (8 * scale + 8);
    }
    bool onHandle(std::uint32_t pointIndex) const {
        const std::uint32_t v = points[pointIndex].voxel;
        return yOf(v) > 5 || (xOf(v) > a && xOf(v) < b);
    }
    CutPlan place(const CutOptions& options) const {
        return placeCuts(
            graph, points, options, [](std::uint32_t) { return 0.0; },
            [this](const std::vector<std::uint32_t>& loops) {
                // Loops on the handle separate only when it is cut twice.
                const auto onIt = std::count_if(loops.begin(), loops.end(),
                                                [this](std::uint32_t p) { return onHandle(p); });
                std::vector<std::uint8_t> separates;
                for (std::uint32_t p : loops) separates.push_back(!onHandle(p) || onIt >= 2);
                return separates;
            });
    }
    int cutX(const CutPlan& plan, std::size_t k = 0) const {
        return xOf(points[graph.point[plan.cutNodes[k]]].voxel);
    }
};

TEST(CutPlacement, CutWhoseLoopSeparatesNothingMovesPastTheHandleAtTwoScales) {
    for (const int scale : {1, 2}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        const LimbThroughAHandle shape(scale, true);
        ASSERT_EQ(shape.graph.junctions.size(), 2u);
        const CutPlan plan = shape.place({});
        ASSERT_EQ(plan.cutNodes.size(), 1u);
        EXPECT_GT(shape.cutX(plan), shape.b) << "the cut separates the tip";
        EXPECT_LE(shape.cutX(plan), shape.b + 5 * scale) << "at the tip's first tight levels";
        const auto cut = std::find_if(plan.candidates.begin(), plan.candidates.end(),
                                      [](const CutCandidate& c) { return c.isCut; });
        ASSERT_NE(cut, plan.candidates.end());
        EXPECT_EQ(cut->junction, 0u);
        EXPECT_FALSE(cut->loopSeparates);
        EXPECT_TRUE(cut->movedToSeparate);
        EXPECT_EQ(plan.junctions[0].cuts, 1u);
        EXPECT_EQ(plan.junctions[1].cuts, 0u) << "the limb passes through its junction";

        CutOptions without;
        without.separatingCutsOnly = false;
        const CutPlan old = shape.place(without);
        ASSERT_EQ(old.cutNodes.size(), 1u);
        EXPECT_LT(shape.cutX(old), shape.b)
            << "the rule this test guards: a loop that separates nothing";
    }
}

TEST(CutPlacement, CutThatNoLoopFurtherOnCanReplaceIsDroppedAtTwoScales) {
    // Without a tip the limb only goes round the handle: no loop along it
    // separates anything, so there is nothing to cut (PSB cup 21's handle).
    for (const int scale : {1, 2}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        const LimbThroughAHandle shape(scale, false);
        const CutPlan plan = shape.place({});
        EXPECT_TRUE(plan.cutNodes.empty());
        const auto dropped = std::find_if(plan.candidates.begin(), plan.candidates.end(),
                                          [](const CutCandidate& c) { return !c.loopSeparates; });
        ASSERT_NE(dropped, plan.candidates.end());
        EXPECT_FALSE(dropped->isCut);
        EXPECT_FALSE(dropped->onBody);
    }
}

TEST(CutPlacement, TwoCutsThatSeparateTogetherStayAtTwoScales) {
    // The limb cut at its base and the bridge cut at the limb's junction
    // together cut off the limb: each loop borders two pieces, nothing moves.
    for (const int scale : {1, 2}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        const LimbThroughAHandle shape(scale, true, true);
        const CutPlan plan = shape.place({});
        ASSERT_EQ(plan.cutNodes.size(), 2u);
        for (const CutCandidate& c : plan.candidates) {
            EXPECT_TRUE(c.loopSeparates);
            EXPECT_FALSE(c.movedToSeparate);
        }
        EXPECT_EQ(plan.junctions[0].cuts, 1u);
        EXPECT_EQ(plan.junctions[1].cuts, 1u);
        EXPECT_LT(std::min(shape.cutX(plan, 0), shape.cutX(plan, 1)), shape.b);
    }
}

}  // namespace
}  // namespace skelseg
