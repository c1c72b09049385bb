#include "kernels/SkeletonBand.h"

#include <gtest/gtest.h>

#include <limits>
#include <map>
#include <memory>
#include <string>
#include <utility>

#include "io/shapes/SyntheticShapes.h"
#include "kernels/FeatureTransform.h"
#include "kernels/base/Error.h"
#include "tests/kernels/KernelTestSupport.h"

namespace skelseg {
namespace {

/// A rasterised synthetic shape with its candidates and landmarks.
struct ShapeForBand {
    MaskVolume mask;
    Volume<std::uint32_t> ft;
    BoundaryGraph graph;
    std::vector<SkeletonCandidate> candidates;
    Landmarks landmarks;

    ShapeForBand(const std::string& shape, int size)
        : ShapeForBand(rasterise(makeShape(shape), {size, 2})) {}
    explicit ShapeForBand(MaskVolume object) : mask(std::move(object)) {
        ft = featureTransform(boundaryVoxels(mask, {false}), {false});
        graph = buildBoundaryGraph(mask, {false});
        CandidateOptions options;
        options.threaded = false;
        candidates = selectSkeletonCandidates(mask, ft, graph, options);
        landmarks = computeLandmarks(graph, false);
    }
    /// The engine's options at the default tau (3% of the boundary area).
    SkeletonMeasureOptions options(bool threaded) const {
        SkeletonMeasureOptions o;
        o.tau = 0.03 * double(graph.nodeCount());
        o.noiseArea = std::min(std::max(10.0, 0.002 * double(graph.nodeCount())), o.tau);
        o.threaded = threaded;
        o.landmarks = &landmarks;
        return o;
    }
};

const ShapeForBand& shapeForBand(const std::string& shape, int size) {
    static std::map<std::pair<std::string, int>, std::unique_ptr<ShapeForBand>> cache;
    auto& slot = cache[{shape, size}];
    if (!slot) slot = std::make_unique<ShapeForBand>(shape, size);
    return *slot;
}

std::vector<SkeletonPoint> inTau(const std::vector<SkeletonPoint>& points, double tau) {
    std::vector<SkeletonPoint> kept;
    for (const SkeletonPoint& p : points)
        if (p.rhoC >= tau) kept.push_back(p);
    return kept;
}

void expectSamePoints(const std::vector<SkeletonPoint>& a, const std::vector<SkeletonPoint>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) test::expectSamePoint(a[i], b[i]);
}

class SkeletonBandShapes : public ::testing::TestWithParam<std::string> {};

/// The band without its thin-wall seeds: at the small sizes of these tests
/// nearly every part is thinner than the thin-wall threshold, which would
/// measure everything in the first round and leave coarse seeds and closure
/// untested.
SkeletonBandOptions coarseSeedsOnly() {
    SkeletonBandOptions band;
    band.thinWallDepth = 0;
    band.unresolvedRadius = -1;
    return band;
}

TEST_P(SkeletonBandShapes, FindsTheExhaustiveSimplifiedSkeleton) {
    const ShapeForBand& p = shapeForBand(GetParam(), 72);
    const SkeletonMeasureOptions o = p.options(false);
    const auto exhaustive = inTau(measureSkeleton(p.graph, p.candidates, o), o.tau);
    ASSERT_FALSE(exhaustive.empty()) << "every test shape has a simplified skeleton";
    expectSamePoints(inTau(measureSkeletonInBand(p.graph, p.candidates, p.mask, p.ft, o), o.tau),
                     exhaustive);
    SkeletonBandStats stats;
    const auto band = inTau(
        measureSkeletonInBand(p.graph, p.candidates, p.mask, p.ft, o, coarseSeedsOnly(), &stats),
        o.tau);
    expectSamePoints(band, exhaustive);
    EXPECT_GE(stats.closureRounds, 2u) << "the closure must run after the seeds";
    EXPECT_LE(stats.candidatesMeasured, p.candidates.size());
}

// The sphere's skeleton is a small web at its centre, apart from any other
// piece: only the coarse seeds find it.
INSTANTIATE_TEST_SUITE_P(GeneratedShapes, SkeletonBandShapes,
                         ::testing::Values("disc-limbs", "y-arms", "t-body", "box-tubes",
                                           "torus-limb", "sphere", "slab", "figure"));

TEST(SkeletonBand, SerialAndParallelGiveIdenticalPoints) {
    const ShapeForBand& p = shapeForBand("figure", 72);
    // The defaults (thin-wall seeds), and coarse seeds with one more level.
    SkeletonBandOptions recursive = coarseSeedsOnly();
    recursive.exhaustiveBelow = 500;
    for (const SkeletonBandOptions& band : {SkeletonBandOptions{}, recursive}) {
        SkeletonBandStats serialStats, parallelStats;
        SkeletonMeasureStats serialMeasures, parallelMeasures;
        const auto serial =
            measureSkeletonInBand(p.graph, p.candidates, p.mask, p.ft, p.options(false), band,
                                  &serialStats, &serialMeasures);
        const auto parallel =
            measureSkeletonInBand(p.graph, p.candidates, p.mask, p.ft, p.options(true), band,
                                  &parallelStats, &parallelMeasures);
        ASSERT_FALSE(serial.empty());
        expectSamePoints(parallel, serial);
        EXPECT_EQ(parallelStats.seeds, serialStats.seeds);
        EXPECT_EQ(parallelStats.thinWallSeeds, serialStats.thinWallSeeds);
        EXPECT_EQ(parallelStats.candidatesMeasured, serialStats.candidatesMeasured);
        EXPECT_EQ(parallelStats.coarseMeasured, serialStats.coarseMeasured);
        EXPECT_EQ(parallelStats.levels, serialStats.levels);
        EXPECT_EQ(parallelStats.closureRounds, serialStats.closureRounds);
        EXPECT_EQ(parallelMeasures.skeletonPoints, serialMeasures.skeletonPoints);
    }
}

TEST(SkeletonBand, SpacingOneMeasuresEveryCandidateLikeTheExhaustiveSearch) {
    const ShapeForBand& p = shapeForBand("y-arms", 64);
    const SkeletonMeasureOptions o = p.options(false);
    SkeletonBandOptions everything;
    everything.seedSpacing = 1;
    SkeletonBandStats stats;
    const auto band =
        measureSkeletonInBand(p.graph, p.candidates, p.mask, p.ft, o, everything, &stats);
    EXPECT_EQ(stats.seeds, p.candidates.size());
    EXPECT_EQ(stats.candidatesMeasured, p.candidates.size());
    EXPECT_EQ(stats.closureRounds, 1u);
    // All of C, not only C_tau: every candidate was measured.
    expectSamePoints(band, measureSkeleton(p.graph, p.candidates, o));
}

TEST(SkeletonBand, MeasuresFewerCandidatesWhereTheSkeletonIsSmall) {
    // A large ball body with thin limbs: most candidates are medial-surface
    // voxels of the body, far from its skeleton.
    const ShapeForBand& p = shapeForBand("disc-limbs", 96);
    SkeletonBandStats stats;
    SkeletonMeasureStats measures;
    measureSkeletonInBand(p.graph, p.candidates, p.mask, p.ft, p.options(false), coarseSeedsOnly(),
                          &stats, &measures);
    EXPECT_LT(stats.candidatesMeasured, p.candidates.size());
    EXPECT_GT(stats.seeds, 0u);
    EXPECT_LT(stats.seeds, stats.candidatesMeasured);
    EXPECT_GT(measures.rimTests, 0u);
}

TEST(SkeletonBand, RefusesANegativeSpacingOrARadiusBelowOne) {
    const ShapeForBand& p = shapeForBand("y-arms", 64);
    SkeletonBandOptions bad;
    bad.seedSpacing = -1;
    EXPECT_THROW(measureSkeletonInBand(p.graph, p.candidates, p.mask, p.ft, p.options(false), bad),
                 UsageError);
    bad.seedSpacing = 0;
    bad.closureRadius = 0;
    EXPECT_THROW(measureSkeletonInBand(p.graph, p.candidates, p.mask, p.ft, p.options(false), bad),
                 UsageError);
    bad.closureRadius = 4;
    bad.coarseClosureRadius = 0;
    EXPECT_THROW(measureSkeletonInBand(p.graph, p.candidates, p.mask, p.ft, p.options(false), bad),
                 UsageError);
}

TEST(SkeletonBand, ClosureAloneRecoversTheSkeletonFromOneSeedPiece) {
    // Without coarse seeds, plane seeds far apart still find the whole
    // connected skeleton of the figure through the closure.
    const ShapeForBand& p = shapeForBand("figure", 72);
    const SkeletonMeasureOptions o = p.options(false);
    SkeletonBandOptions planesOnly;
    planesOnly.coarseSeeds = false;
    planesOnly.seedSpacing = 16;
    SkeletonBandStats stats;
    const auto band = inTau(
        measureSkeletonInBand(p.graph, p.candidates, p.mask, p.ft, o, planesOnly, &stats), o.tau);
    expectSamePoints(band, inTau(measureSkeleton(p.graph, p.candidates, o), o.tau));
    EXPECT_EQ(stats.coarseCandidates, 0u);
    EXPECT_GE(stats.closureRounds, 3u);
}

/// A square plate `thickness` voxels thick: half the resolution does not
/// resolve it, so the coarse search sees no skeleton on it.
MaskVolume thinPlate(int side, int thickness) {
    MaskVolume mask(Dims{side + 4, side + 4, thickness + 4}, 0);
    for (int z = 2; z < thickness + 2; ++z)
        for (int y = 2; y < side + 2; ++y)
            for (int x = 2; x < side + 2; ++x) mask(x, y, z) = 1;
    return mask;
}

TEST(SkeletonBand, ThinWallSeedsFindTheSkeletonOfAThinPlate) {
    const ShapeForBand p(thinPlate(56, 3));
    const SkeletonMeasureOptions o = p.options(false);
    const auto exhaustive = inTau(measureSkeleton(p.graph, p.candidates, o), o.tau);
    ASSERT_FALSE(exhaustive.empty()) << "a plate has a simplified curve skeleton";
    const auto blind = inTau(
        measureSkeletonInBand(p.graph, p.candidates, p.mask, p.ft, o, coarseSeedsOnly()), o.tau);
    EXPECT_LT(blind.size(), exhaustive.size()) << "the coarse grid alone misses the plate";
    SkeletonBandStats stats;
    const auto band =
        inTau(measureSkeletonInBand(p.graph, p.candidates, p.mask, p.ft, o, {}, &stats), o.tau);
    expectSamePoints(band, exhaustive);
    EXPECT_GT(stats.thinWallSeeds, 0u);
}

TEST(SkeletonBand, RecursiveCoarseLevelsFindTheSameSkeleton) {
    // One level deeper: the search at half the resolution, which has more
    // candidates than the threshold, is a band search seeded from a quarter
    // of the resolution. Without the thin-wall seeds, which cover most of a
    // shape this small, the half-resolution level measures only a band.
    const ShapeForBand& p = shapeForBand("disc-limbs", 96);
    const SkeletonMeasureOptions o = p.options(false);
    SkeletonBandOptions flat = coarseSeedsOnly();
    flat.exhaustiveBelow = std::numeric_limits<std::size_t>::max();
    SkeletonBandStats flatStats, stats;
    const auto exhaustive = inTau(measureSkeleton(p.graph, p.candidates, o), o.tau);
    expectSamePoints(
        inTau(measureSkeletonInBand(p.graph, p.candidates, p.mask, p.ft, o, flat, &flatStats),
              o.tau),
        exhaustive);
    EXPECT_EQ(flatStats.levels, 1u);
    EXPECT_EQ(flatStats.coarseMeasured, flatStats.coarseCandidates);
    SkeletonBandOptions recursive = flat;
    recursive.exhaustiveBelow = flatStats.coarseCandidates - 1;
    const auto band = inTau(
        measureSkeletonInBand(p.graph, p.candidates, p.mask, p.ft, o, recursive, &stats), o.tau);
    expectSamePoints(band, exhaustive);
    EXPECT_EQ(stats.levels, 2u);
    EXPECT_LT(stats.coarseMeasured, stats.coarseCandidates) << "the coarse level is a band too";
}

TEST(SkeletonBand, ACoarseBandOfOneVoxelSeedsEveryPieceAndNoneDoesNot) {
    // The coarse band's radius is what puts a seed on each piece of C_tau;
    // the closure does the rest. On the t-body at 96 the coarse skeleton
    // runs beside the fine one: a band of radius 0 (the coarse voxel's own
    // fine voxels) misses it entirely, the default radius finds all of it.
    const ShapeForBand& p = shapeForBand("t-body", 96);
    const SkeletonMeasureOptions o = p.options(false);
    const auto exhaustive = inTau(measureSkeleton(p.graph, p.candidates, o), o.tau);
    ASSERT_FALSE(exhaustive.empty());
    SkeletonBandOptions none = coarseSeedsOnly();
    none.coarseBandRadius = 0;
    EXPECT_LT(
        inTau(measureSkeletonInBand(p.graph, p.candidates, p.mask, p.ft, o, none), o.tau).size(),
        exhaustive.size())
        << "without a band around the coarse points the t-body has no seed";
    expectSamePoints(
        inTau(measureSkeletonInBand(p.graph, p.candidates, p.mask, p.ft, o, coarseSeedsOnly()),
              o.tau),
        exhaustive);
}

class CoarseClosureShapes : public ::testing::TestWithParam<std::string> {};

TEST_P(CoarseClosureShapes, ACoarseClosureOfOneVoxelKeepsTheSkeletonAndMeasuresLess) {
    // Two coarser levels (a threshold of 500 candidates), coarse seeds
    // only: the coarse levels follow their skeleton with radius 1 and the
    // full resolution still finds every point of C_tau.
    const ShapeForBand& p = shapeForBand(GetParam(), 96);
    const SkeletonMeasureOptions o = p.options(false);
    const auto exhaustive = inTau(measureSkeleton(p.graph, p.candidates, o), o.tau);
    ASSERT_FALSE(exhaustive.empty());
    SkeletonBandOptions narrow = coarseSeedsOnly();
    narrow.exhaustiveBelow = 500;
    SkeletonBandOptions wide = narrow;
    wide.coarseClosureRadius = wide.closureRadius;
    SkeletonBandStats narrowStats, wideStats;
    expectSamePoints(
        inTau(measureSkeletonInBand(p.graph, p.candidates, p.mask, p.ft, o, narrow, &narrowStats),
              o.tau),
        exhaustive);
    expectSamePoints(
        inTau(measureSkeletonInBand(p.graph, p.candidates, p.mask, p.ft, o, wide, &wideStats),
              o.tau),
        exhaustive);
    ASSERT_GE(narrowStats.levels, 2u);
    EXPECT_LT(narrowStats.coarseMeasured, wideStats.coarseMeasured);
}

INSTANTIATE_TEST_SUITE_P(GeneratedShapes, CoarseClosureShapes,
                         ::testing::Values("disc-limbs", "y-arms", "t-body", "box-tubes",
                                           "torus-limb", "sphere", "slab", "figure"));

TEST(SkeletonBand, AddMeasureStatsSumsEveryCounter) {
    SkeletonMeasureStats a, b;
    a.search.searches = 2, a.rimTests = 3, a.skeletonPoints = 4, a.sigmaSearch.nodesSettled = 5;
    b.search.searches = 10, b.rimTests = 20, b.skeletonPoints = 30, b.sigmaSearch.nodesSettled = 40;
    b.pathCacheHits = 7, b.componentGrowthSteps = 8, b.repeatedFeatureSets = 9;
    addMeasureStats(a, b);
    EXPECT_EQ(a.search.searches, 12u);
    EXPECT_EQ(a.rimTests, 23u);
    EXPECT_EQ(a.skeletonPoints, 34u);
    EXPECT_EQ(a.sigmaSearch.nodesSettled, 45u);
    EXPECT_EQ(a.pathCacheHits, 7u);
    EXPECT_EQ(a.componentGrowthSteps, 8u);
    EXPECT_EQ(a.repeatedFeatureSets, 9u);
}

}  // namespace
}  // namespace skelseg
