#include "kernels/SkeletonMeasures.h"

#include <gtest/gtest.h>

#include <cmath>

#include <algorithm>
#include <limits>
#include <map>
#include <memory>

#include "io/shapes/SyntheticShapes.h"
#include "kernels/FeatureTransform.h"
#include "tests/kernels/KernelTestSupport.h"
#include "tests/support/StopAtOnce.h"

namespace skelseg {
namespace {

/// A rasterised synthetic shape with everything measureSkeleton needs.
struct ShapeToMeasure {
    MaskVolume mask;
    Volume<std::uint32_t> ft;
    BoundaryGraph graph;
    std::vector<SkeletonCandidate> candidates;
    Landmarks landmarks;  // as the engine uses them

    ShapeToMeasure(const std::string& shape, int size) {
        mask = rasterise(makeShape(shape), {size, 2});
        ft = featureTransform(boundaryVoxels(mask, {false}), {false});
        graph = buildBoundaryGraph(mask, {false});
        CandidateOptions options;
        options.threaded = false;
        candidates = selectSkeletonCandidates(mask, ft, graph, options);
        landmarks = computeLandmarks(graph, false);
    }
    Coord coord(std::uint32_t voxel) const {
        const Dims d = mask.dims();
        return Coord{int(voxel % std::uint32_t(d.x)),
                     int((voxel / std::uint32_t(d.x)) % std::uint32_t(d.y)),
                     int(voxel / (std::uint32_t(d.x) * std::uint32_t(d.y)))};
    }
    SkeletonMeasureOptions options(double tauFraction, bool exact = false,
                                   bool threaded = false) const {
        SkeletonMeasureOptions o;
        o.tau = tauFraction * double(graph.nodeCount());
        o.noiseArea = 10.0;
        o.exactRhoC = exact;
        o.threaded = threaded;
        o.landmarks = &landmarks;
        return o;
    }
};

/// Shapes are shared between tests of this file (built on first use).
const ShapeToMeasure& shapeToMeasure(const std::string& shape, int size) {
    static std::map<std::pair<std::string, int>, std::unique_ptr<ShapeToMeasure>> cache;
    auto& slot = cache[{shape, size}];
    if (!slot) slot = std::make_unique<ShapeToMeasure>(shape, size);
    return *slot;
}

TEST(SkeletonMeasures, RhoCGrowsFromTheCapsuleTipsToItsMiddle) {
    const ShapeToMeasure& p = shapeToMeasure("capsule", 80);  // axis along x
    const std::vector<SkeletonPoint> points =
        measureSkeleton(p.graph, p.candidates, p.options(0.0, true));
    // Largest rho_C per x along the axis.
    std::map<int, double> rhoCAtX;
    for (const SkeletonPoint& s : points) {
        EXPECT_TRUE(s.rhoCExact);
        EXPECT_FALSE(s.isHandle);
        EXPECT_GE(s.rims, 2u);
        EXPECT_LE(s.rhoC, double(p.graph.nodeCount()));
        const int x = p.coord(s.voxel).x;
        rhoCAtX[x] = std::max(rhoCAtX[x], s.rhoC);
    }
    ASSERT_GE(rhoCAtX.size(), 40u) << "the capsule's skeleton should span most of its length";
    const int xFirst = rhoCAtX.begin()->first, xLast = rhoCAtX.rbegin()->first;
    const int middle = (xFirst + xLast) / 2;
    double previous = -1.0;
    for (auto it = rhoCAtX.begin(); it != rhoCAtX.end() && it->first <= middle; ++it) {
        EXPECT_GE(it->second, previous) << "rho_C drops at x = " << it->first << " (left half)";
        previous = it->second;
    }
    previous = -1.0;
    for (auto it = rhoCAtX.rbegin(); it != rhoCAtX.rend() && it->first >= middle; ++it) {
        EXPECT_GE(it->second, previous) << "rho_C drops at x = " << it->first << " (right half)";
        previous = it->second;
    }
    // At the middle the loop cuts off about half the surface; near the tips
    // much less.
    EXPECT_GT(rhoCAtX.at(middle), 0.45 * p.graph.nodeCount());
    EXPECT_LT(rhoCAtX.begin()->second, 0.2 * p.graph.nodeCount());
    EXPECT_GT(rhoCAtX.at(middle), 3.0 * rhoCAtX.begin()->second);
}

TEST(SkeletonMeasures, SigmaIsHighInTheMiddleOfACylinder) {
    const ShapeToMeasure& p = shapeToMeasure("cylinder", 80);
    const std::vector<SkeletonPoint> points =
        measureSkeleton(p.graph, p.candidates, p.options(0.03));
    int xMin = p.mask.dims().x, xMax = 0;
    for (std::uint32_t n = 0; n < p.graph.nodeCount(); ++n)
        xMin = std::min(xMin, p.graph.coord[n].x), xMax = std::max(xMax, p.graph.coord[n].x);
    const int third = (xMax - xMin) / 3;
    int inMiddle = 0;
    for (const SkeletonPoint& s : points) {
        const int x = p.coord(s.voxel).x;
        if (x <= xMin + third || x >= xMax - third) continue;
        ++inMiddle;
        EXPECT_GE(s.sigma, 0.9f) << "at x = " << x;
        EXPECT_LE(s.sigma, 1.0f);
        EXPECT_EQ(s.robustRims, 2u);
        // rho_S: half the circumference of the loop, about pi * radius.
        const double radius = 0.15 / p.mask.geometry.voxelSize();
        EXPECT_NEAR(s.rhoS, test::kPi * radius, 0.2 * test::kPi * radius);
    }
    EXPECT_GE(inMiddle, 15);
}

TEST(SkeletonMeasures, SigmaIsLowNextToTheTJunction) {
    // t-body: a thick capsule along x (radius 0.25) with a thin limb along +y
    // (radius 0.07) starting inside it at y = 0.1. Limb skeleton points next
    // to the body have kinked loops; further out the loops are straight.
    const ShapeToMeasure& p = shapeToMeasure("t-body", 96);
    const std::vector<SkeletonPoint> points =
        measureSkeleton(p.graph, p.candidates, p.options(0.03));
    const double voxel = p.mask.geometry.voxelSize();
    const auto& origin = p.mask.geometry.origin;
    auto world = [&](const Coord& c) {
        return std::array<double, 3>{origin[0] + c.x * voxel, origin[1] + c.y * voxel,
                                     origin[2] + c.z * voxel};
    };
    float nearMin = 2.0f, farMax = -1.0f;
    int near = 0, far = 0;
    for (const SkeletonPoint& s : points) {
        if (s.sigma < 0.0f) continue;  // below tau: no sigma
        const auto w = world(p.coord(s.voxel));
        if (std::fabs(w[0]) > 0.04 || std::fabs(w[2]) > 0.04) continue;  // not on the limb's axis
        if (w[1] > 0.03 && w[1] < 0.2)
            ++near, nearMin = std::min(nearMin, s.sigma);  // inside the body, by the junction
        if (w[1] > 0.45 && w[1] < 0.7)
            ++far, farMax = std::max(farMax, s.sigma);  // well inside the limb
    }
    ASSERT_GT(near, 3);
    ASSERT_GT(far, 3);
    // The cylinder's value (same resolution class) for comparison.
    const ShapeToMeasure& cylinder = shapeToMeasure("cylinder", 80);
    float cylinderSigma = 0.0f;
    for (const SkeletonPoint& s :
         measureSkeleton(cylinder.graph, cylinder.candidates, cylinder.options(0.03)))
        cylinderSigma = std::max(cylinderSigma, s.sigma);
    // With lengths measured independently of the digitisation (Geodesicness.h)
    // straight loops read about 1 and the loop around the limb's base about
    // 0.87; the contrast, not a fixed level, is what marks the kink.
    EXPECT_LT(nearMin, 0.9f);
    EXPECT_GE(cylinderSigma - nearMin, 0.1f);
    EXPECT_GT(farMax, nearMin + 0.05f) << "sigma should rise into the limb";
}

TEST(SkeletonMeasures, SerialEqualsParallel) {
    for (const char* shape : {"figure", "t-body"}) {
        const ShapeToMeasure& p = shapeToMeasure(shape, 64);
        SCOPED_TRACE(shape);
        SkeletonMeasureStats serialStats, parallelStats;
        const std::vector<SkeletonPoint> serial =
            measureSkeleton(p.graph, p.candidates, p.options(0.03, false, false), &serialStats);
        const std::vector<SkeletonPoint> parallel =
            measureSkeleton(p.graph, p.candidates, p.options(0.03, false, true), &parallelStats);
        ASSERT_GT(serial.size(), 20u);
        ASSERT_EQ(serial.size(), parallel.size());
        for (std::size_t i = 0; i < serial.size(); ++i)
            test::expectSamePoint(serial[i], parallel[i]);
        EXPECT_EQ(serialStats.skeletonPoints, serial.size());
        EXPECT_EQ(parallelStats.skeletonPoints, parallel.size());
        // Work counts may differ (each thread has its own path and feature-set
        // caches); the results above may not.
        EXPECT_GT(serialStats.search.searches, 0u);
        EXPECT_GT(serialStats.repeatedFeatureSets, 0u);
        EXPECT_LE(serialStats.rimTests + serialStats.repeatedFeatureSets, p.candidates.size());
    }
}

TEST(SkeletonMeasures, KeptWorkspacesAnswerAsFreshOnes) {
    // The band search measures a candidate list in rounds on kept workspaces,
    // whose path caches and feature-set memo then hold answers of earlier
    // rounds (asked with other sheet bounds, in another order). Every point
    // must be what a fresh, serial measure of the whole list gives.
    for (const char* shape : {"figure", "disc-limbs"}) {
        const ShapeToMeasure& p = shapeToMeasure(shape, 64);
        SCOPED_TRACE(shape);
        for (bool threaded : {false, true}) {
            const SkeletonMeasureOptions options = p.options(0.03, false, threaded);
            const std::vector<SkeletonPoint> reference =
                measureSkeleton(p.graph, p.candidates, p.options(0.03, false, false));
            std::map<std::uint32_t, SkeletonPoint> byVoxel;
            for (const SkeletonPoint& q : reference) byVoxel[q.voxel] = q;
            // Rounds: every third candidate backwards, then the rest forwards,
            // then everything again (all answered from the kept caches).
            std::vector<SkeletonCandidate> first, second;
            for (std::size_t i = p.candidates.size(); i-- > 0;)
                (i % 3 == 0 ? first : second).push_back(p.candidates[i]);
            std::reverse(second.begin(), second.end());
            SkeletonMeasureWorkspaces kept;
            std::size_t found = 0;
            for (const std::vector<SkeletonCandidate>* round :
                 std::initializer_list<const std::vector<SkeletonCandidate>*>{&first, &second,
                                                                              &p.candidates}) {
                SkeletonMeasureStats stats;
                const std::vector<SkeletonPoint> points =
                    measureSkeleton(p.graph, *round, options, kept, &stats);
                EXPECT_LE(stats.rimTests + stats.repeatedFeatureSets, round->size());
                for (const SkeletonPoint& q : points) {
                    const auto it = byVoxel.find(q.voxel);
                    ASSERT_NE(it, byVoxel.end()) << "voxel " << q.voxel << " is no point";
                    SkeletonPoint expected = it->second;
                    expected.candidate = q.candidate;
                    test::expectSamePoint(expected, q);
                }
                if (round != &p.candidates)
                    found += points.size();
                else
                    EXPECT_EQ(points.size(), reference.size());
            }
            EXPECT_EQ(found, reference.size());
            // Other options on the same workspaces: as fresh ones with them.
            const std::vector<SkeletonPoint> exact =
                measureSkeleton(p.graph, p.candidates, p.options(0.03, true, threaded), kept);
            const std::vector<SkeletonPoint> exactFresh =
                measureSkeleton(p.graph, p.candidates, p.options(0.03, true, false));
            ASSERT_EQ(exact.size(), exactFresh.size());
            for (std::size_t i = 0; i < exact.size(); ++i)
                test::expectSamePoint(exactFresh[i], exact[i]);
        }
    }
}

TEST(SkeletonMeasures, WithoutSigmaEverythingElseIsTheSame) {
    // The band's coarser levels skip sigma: the points and every other
    // measure must be those of a run with it, on kept workspaces too.
    const ShapeToMeasure& p = shapeToMeasure("figure", 64);
    for (bool threaded : {false, true}) {
        SkeletonMeasureStats withStats, withoutStats;
        const std::vector<SkeletonPoint> with =
            measureSkeleton(p.graph, p.candidates, p.options(0.03, false, threaded), &withStats);
        SkeletonMeasureOptions noSigma = p.options(0.03, false, threaded);
        noSigma.evaluateSigma = false;
        SkeletonMeasureWorkspaces kept;
        measureSkeleton(p.graph, p.candidates, p.options(0.03, false, threaded), kept);
        const std::vector<SkeletonPoint> without =
            measureSkeleton(p.graph, p.candidates, noSigma, kept, &withoutStats);
        EXPECT_GT(withStats.sigmaEvaluations, 0u);
        EXPECT_EQ(withoutStats.sigmaEvaluations, 0u);
        ASSERT_EQ(with.size(), without.size());
        for (std::size_t i = 0; i < with.size(); ++i) {
            EXPECT_EQ(without[i].sigma, -1.0f);
            SkeletonPoint expected = with[i];
            expected.sigma = -1.0f;
            test::expectSamePoint(expected, without[i]);
        }
    }
}

TEST(SkeletonMeasures, CappedRhoCDecidesTauLikeExact) {
    // The growth cap changes only rho_C's value above tau (a lower bound),
    // never which points are in C, their rims, or the tau decision.
    const ShapeToMeasure& p = shapeToMeasure("figure", 64);
    const SkeletonMeasureOptions cappedOptions = p.options(0.03),
                                 exactOptions = p.options(0.03, true);
    const std::vector<SkeletonPoint> capped = measureSkeleton(p.graph, p.candidates, cappedOptions);
    const std::vector<SkeletonPoint> exact = measureSkeleton(p.graph, p.candidates, exactOptions);
    ASSERT_EQ(capped.size(), exact.size());
    int lowerBounds = 0;
    for (std::size_t i = 0; i < capped.size(); ++i) {
        const SkeletonPoint &c = capped[i], &e = exact[i];
        ASSERT_EQ(c.voxel, e.voxel);
        EXPECT_EQ(c.rims, e.rims);
        EXPECT_EQ(c.robustRims, e.robustRims);
        EXPECT_EQ(c.isHandle, e.isHandle);
        EXPECT_EQ(c.rhoS, e.rhoS);
        EXPECT_EQ(c.rhoC >= cappedOptions.tau, e.rhoC >= exactOptions.tau);
        EXPECT_LE(c.rhoC, e.rhoC);
        EXPECT_EQ(c.sigma, e.sigma);
        EXPECT_TRUE(e.rhoCExact);
        if (c.rhoCExact) {
            EXPECT_EQ(c.rhoC, e.rhoC);
        } else {
            ++lowerBounds;
            EXPECT_GE(c.rhoC, cappedOptions.tau);
        }
    }
    EXPECT_GT(lowerBounds, 0) << "the cap should have stopped some growth early";
}

TEST(SkeletonMeasures, OneMeasureAtTheCoarsestTauServesFinerTaus) {
    // Hierarchy runs measure once at the largest tau with sigma down to the
    // smallest: every decision of a run at the smaller tau follows from it.
    const ShapeToMeasure& p = shapeToMeasure("figure", 64);
    SkeletonMeasureOptions coarseOptions = p.options(0.25);
    const SkeletonMeasureOptions fineOptions = p.options(0.01);
    coarseOptions.sigmaTau = fineOptions.tau;
    const std::vector<SkeletonPoint> coarse = measureSkeleton(p.graph, p.candidates, coarseOptions);
    const std::vector<SkeletonPoint> fine = measureSkeleton(p.graph, p.candidates, fineOptions);
    ASSERT_EQ(coarse.size(), fine.size());
    int fineSkeleton = 0, coarseSkeleton = 0;
    for (std::size_t i = 0; i < coarse.size(); ++i) {
        const SkeletonPoint &c = coarse[i], &f = fine[i];
        ASSERT_EQ(c.voxel, f.voxel);
        EXPECT_EQ(c.rims, f.rims);
        EXPECT_EQ(c.rhoC >= fineOptions.tau, f.rhoC >= fineOptions.tau);
        EXPECT_EQ(c.junctionArea >= fineOptions.tau, isJunctionPoint(f));
        EXPECT_EQ(c.junctionArea >= coarseOptions.tau, isJunctionPoint(c));
        if (f.rhoC >= fineOptions.tau) {
            EXPECT_EQ(c.sigma, f.sigma);
        }
        fineSkeleton += f.rhoC >= fineOptions.tau;
        coarseSkeleton += c.rhoC >= coarseOptions.tau;
    }
    EXPECT_GT(fineSkeleton, coarseSkeleton) << "the two taus should differ somewhere";
}

TEST(SkeletonMeasures, PointsAreConsistent) {
    const ShapeToMeasure& p = shapeToMeasure("figure", 64);
    const SkeletonMeasureOptions options = p.options(0.03);
    const std::vector<SkeletonPoint> points = measureSkeleton(p.graph, p.candidates, options);
    std::uint32_t previous = 0;
    GeodesicSearch search(p.graph);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const SkeletonPoint& s = points[i];
        ASSERT_LT(s.candidate, p.candidates.size());
        EXPECT_EQ(p.candidates[s.candidate].voxel, s.voxel);
        if (i) {
            EXPECT_GT(s.candidate, previous) << "not in candidate order";
        }
        previous = s.candidate;
        EXPECT_GE(s.rims, 2u);
        EXPECT_LE(s.robustRims, s.rims);
        EXPECT_EQ(s.sigma >= 0.0f, s.rhoC >= options.tau) << "sigma computed exactly for C_tau";
        EXPECT_LE(s.sigma, 1.0f);
        if (isJunctionPoint(s)) {
            EXPECT_GE(s.rhoC, options.tau);
        }
        // rho_S is realised by the reported feature pair.
        ASSERT_NE(s.featureA, kNoNode);
        ASSERT_NE(s.featureB, kNoNode);
        EXPECT_NEAR(search.shortestPath(s.featureA, s.featureB), s.rhoS,
                    1e-4 * double(std::max(1.0f, s.rhoS)));
        float rhoS = 0.0f;
        const std::vector<std::uint32_t> gamma =
            pathSet(p.graph, p.candidates[s.candidate], search, &rhoS);
        EXPECT_NEAR(rhoS, s.rhoS, 1e-4 * double(std::max(1.0f, s.rhoS)));
        EXPECT_TRUE(std::is_sorted(gamma.begin(), gamma.end()));
    }
}

TEST(SkeletonMeasures, TubeOfATorusIsAHandle) {
    // A torus: loops around the tube have two rims bounding one component.
    const ShapeToMeasure& p = shapeToMeasure("torus", 56);
    const std::vector<SkeletonPoint> points =
        measureSkeleton(p.graph, p.candidates, p.options(0.03, true));
    int handles = 0;
    for (const SkeletonPoint& s : points)
        if (s.isHandle) {
            ++handles;
            EXPECT_EQ(s.rhoC, std::numeric_limits<double>::infinity());
        }
    EXPECT_GT(handles, 20);
}

TEST(SkeletonMeasures, HandleLoopsStayInCTauWithTheGrowthCap) {
    // With the engine's growth cap the two fronts of a handle loop may stop
    // before they meet; the point must still be kept, with the same rims.
    const ShapeToMeasure& p = shapeToMeasure("torus", 56);
    const SkeletonMeasureOptions cappedOptions = p.options(0.03),
                                 exactOptions = p.options(0.03, true);
    const std::vector<SkeletonPoint> capped = measureSkeleton(p.graph, p.candidates, cappedOptions);
    const std::vector<SkeletonPoint> exact = measureSkeleton(p.graph, p.candidates, exactOptions);
    ASSERT_EQ(capped.size(), exact.size());
    for (std::size_t i = 0; i < capped.size(); ++i) {
        ASSERT_EQ(capped[i].voxel, exact[i].voxel);
        EXPECT_EQ(capped[i].rhoC >= cappedOptions.tau, exact[i].rhoC >= exactOptions.tau);
        EXPECT_EQ(capped[i].robustRims, exact[i].robustRims);
        EXPECT_EQ(capped[i].rims, exact[i].rims);
    }
}

TEST(SkeletonMeasures, HandleFlagIsExactOnlyWithExactAreas) {
    // SkeletonMeasures.h: isHandle is decided exactly with exactRhoC; with the
    // growth cap (the engine's default) the two fronts of a handle loop stop
    // at the cap before they meet, so the point is not flagged but keeps a
    // rho_C bound >= tau: membership in C_tau is the same either way.
    const ShapeToMeasure& p = shapeToMeasure("torus", 56);
    const SkeletonMeasureOptions cappedOptions = p.options(0.03);
    const std::vector<SkeletonPoint> capped = measureSkeleton(p.graph, p.candidates, cappedOptions);
    const std::vector<SkeletonPoint> exact =
        measureSkeleton(p.graph, p.candidates, p.options(0.03, true));
    ASSERT_EQ(capped.size(), exact.size());
    int flaggedExact = 0;
    for (std::size_t i = 0; i < capped.size(); ++i) {
        flaggedExact += exact[i].isHandle;
        if (exact[i].isHandle) {
            EXPECT_TRUE(std::isinf(exact[i].rhoC));
            EXPECT_GE(capped[i].rhoC, cappedOptions.tau)
                << "a handle loop must stay in C_tau under the cap";
        }
    }
    EXPECT_GT(flaggedExact, 20);
}

TEST(SkeletonMeasures, OnAGenusZeroSurfaceRimsThatMeetCountOnce) {
    // surfaceHasGenusZero: rims whose pieces meet are one side of Gamma(p).
    // On the torus (where the caller would not set it) this turns every
    // handle point into a point with one side, which is not in C, and
    // leaves every other point as it was.
    const ShapeToMeasure& p = shapeToMeasure("torus", 56);
    const SkeletonMeasureOptions handles = p.options(0.03, true);
    SkeletonMeasureOptions genusZero = handles;
    genusZero.surfaceHasGenusZero = true;
    const std::vector<SkeletonPoint> before = measureSkeleton(p.graph, p.candidates, handles);
    const std::vector<SkeletonPoint> after = measureSkeleton(p.graph, p.candidates, genusZero);
    std::map<std::uint32_t, const SkeletonPoint*> afterByCandidate;
    for (const SkeletonPoint& s : after) {
        EXPECT_FALSE(s.isHandle);
        EXPECT_FALSE(std::isinf(s.rhoC));
        afterByCandidate[s.candidate] = &s;
    }
    std::size_t handlePoints = 0;
    for (const SkeletonPoint& s : before) {
        const auto it = afterByCandidate.find(s.candidate);
        if (s.isHandle) {
            ++handlePoints;
            // Two rims of one component: one side, so not a loop.
            if (s.rims == 2) EXPECT_EQ(it, afterByCandidate.end());
            continue;
        }
        ASSERT_NE(it, afterByCandidate.end());
        EXPECT_EQ(it->second->rims, s.rims);
        EXPECT_EQ(it->second->robustRims, s.robustRims);
        EXPECT_EQ(it->second->rhoC, s.rhoC);
    }
    EXPECT_GT(handlePoints, 20u);
    EXPECT_LT(after.size(), before.size());
}

TEST(SkeletonMeasures, KeptWorkspacesForgetAnswersOfTheOtherGenusReading) {
    // The feature-set memo holds whole answers; one kept from the handle
    // reading must not answer for the genus-0 reading.
    const ShapeToMeasure& p = shapeToMeasure("torus", 56);
    const SkeletonMeasureOptions handles = p.options(0.03, true);
    SkeletonMeasureOptions genusZero = handles;
    genusZero.surfaceHasGenusZero = true;
    SkeletonMeasureWorkspaces kept;
    const std::vector<SkeletonPoint> first = measureSkeleton(p.graph, p.candidates, handles, kept);
    const std::vector<SkeletonPoint> again =
        measureSkeleton(p.graph, p.candidates, genusZero, kept);
    const std::vector<SkeletonPoint> fresh = measureSkeleton(p.graph, p.candidates, genusZero);
    ASSERT_EQ(again.size(), fresh.size());
    EXPECT_LT(fresh.size(), first.size());
    for (std::size_t i = 0; i < fresh.size(); ++i) test::expectSamePoint(fresh[i], again[i]);
}

class MeasurePointAgreement : public ::testing::TestWithParam<bool> {};

TEST_P(MeasurePointAgreement, MeasurePointEqualsMeasureSkeletonWithExactRhoC) {
    // measurePoint() is what the cut placement's tie rule calls for the exact
    // rho_C of a candidate; it must describe the same Gamma(p) as the
    // measured skeleton point, with or without landmarks (which change the
    // choice among equally short paths).
    const ShapeToMeasure& p = shapeToMeasure("figure", 64);
    SkeletonMeasureOptions options = p.options(0.03, true);
    if (!GetParam()) options.landmarks = nullptr;
    const std::vector<SkeletonPoint> points = measureSkeleton(p.graph, p.candidates, options);
    ASSERT_GT(points.size(), 20u);
    int differ = 0;
    for (const SkeletonPoint& s : points) {
        SkeletonPoint single;
        const bool inC = measurePoint(p.graph, p.candidates[s.candidate], options, single);
        if (!inC || single.rhoC != s.rhoC || single.rims != s.rims || single.sigma != s.sigma ||
            single.featureA != s.featureA || single.featureB != s.featureB)
            ++differ;
    }
    EXPECT_EQ(differ, 0) << differ << " of " << points.size()
                         << " points measure differently through measurePoint()";
}

INSTANTIATE_TEST_SUITE_P(Landmarks, MeasurePointAgreement, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& param) {
                             return param.param ? std::string("WithLandmarks")
                                                : std::string("WithoutLandmarks");
                         });

TEST(SkeletonMeasures, AStopAnsweredOnceAtAnyPollThrows) {
    const ShapeToMeasure& p = shapeToMeasure("capsule", 40);
    for (const bool threaded : {false, true}) {
        SCOPED_TRACE(threaded ? "threaded" : "serial");
        const SkeletonMeasureOptions options = p.options(0.03, false, threaded);
        EXPECT_GT(test::expectAStopAtAnyPollThrows(
                      [&](Interrupter& interrupter) {
                          measureSkeleton(p.graph, p.candidates, options, nullptr, interrupter);
                      },
                      16),
                  3);
    }
}

}  // namespace
}  // namespace skelseg
