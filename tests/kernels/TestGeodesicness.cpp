#include "kernels/Geodesicness.h"

#include <gtest/gtest.h>

#include "tests/kernels/KernelTestSupport.h"

namespace skelseg {
namespace {

class GeodesicnessOnSphere : public test::BallBoundaryFixture {
protected:
    /// sigma of a loop of four geodesic arcs through points at `latitude`,
    /// with a, b the points at longitudes 0 and 180.
    GeodesicnessResult loopSigma(double latitude) const {
        GeodesicSearch search(*graph);
        const auto loop = loopAt(latitude, search);
        RimCounter rims(*graph);
        EXPECT_EQ(rims.countRims(loop).pieceCount, 2u);
        GeodesicnessEvaluator evaluator(*graph);
        return evaluator.evaluate(rims, at(latitude, 0), at(latitude, 180), search);
    }
};

TEST_F(GeodesicnessOnSphere, GreatCircleIsAGeodesic) {
    const GeodesicnessResult r = loopSigma(0.0);
    EXPECT_EQ(r.arcCount, 2u);
    EXPECT_GE(r.sigma, 0.9f);
    EXPECT_LE(r.sigma, 1.0f);
    // The loop is the equator: about 2 pi r long; the midpoints c, d lie near
    // longitudes 90 and 270.
    EXPECT_NEAR(r.loopLength, 2.0 * test::kPi * kBallRadius, 0.15 * 2.0 * test::kPi * kBallRadius);
    ASSERT_NE(r.midpointC, kNoNode);
    ASSERT_NE(r.midpointD, kNoNode);
    const Coord c = graph->coord[r.midpointC], d = graph->coord[r.midpointD];
    EXPECT_NEAR(std::fabs(double(c.y) - kBallCentre[1]), kBallRadius, 3.0);
    EXPECT_NEAR(std::fabs(double(d.y) - kBallCentre[1]), kBallRadius, 3.0);
    EXPECT_LT((double(c.y) - kBallCentre[1]) * (double(d.y) - kBallCentre[1]), 0.0)
        << "c and d on the same side";
}

TEST_F(GeodesicnessOnSphere, LoopWithKinksIsLessGeodesic) {
    // Four great-circle arcs through points at latitude 45 make a loop with
    // a kink at each point. Continuous value: the c-d geodesic over the pole
    // spans 90 degrees, the loop from c over a to d 2 * 60 degrees: 0.75.
    const GeodesicnessResult equator = loopSigma(0.0);
    const GeodesicnessResult kinked = loopSigma(45.0);
    EXPECT_EQ(kinked.arcCount, 2u);
    EXPECT_LT(kinked.sigma, 0.85f);
    EXPECT_GT(kinked.sigma, 0.6f);
    EXPECT_GT(equator.sigma - kinked.sigma, 0.1f);
}

TEST_F(GeodesicnessOnSphere, NoLoopGivesZero) {
    GeodesicSearch search(*graph);
    RimCounter rims(*graph);
    GeodesicnessEvaluator evaluator(*graph);
    // An open path has one arc only.
    const std::uint32_t a = at(0, 0), b = at(0, 120);
    rims.countRims(test::pathThrough(search, {a, b}, false));
    const GeodesicnessResult open = evaluator.evaluate(rims, a, b, search);
    EXPECT_EQ(open.sigma, 0.0f);
    EXPECT_LT(open.arcCount, 2u);
    // a == b.
    rims.countRims(test::pathThrough(search, {at(0, 0), at(0, 90), at(0, 180), at(0, 270)}, true));
    EXPECT_EQ(evaluator.evaluate(rims, a, a, search).sigma, 0.0f);
    // An empty path set.
    rims.countRims({});
    EXPECT_EQ(evaluator.evaluate(rims, a, b, search).sigma, 0.0f);
}

TEST(Geodesicness, RingAroundACylinderIsAGeodesic) {
    // A cylinder along x, radius 7, with a ring of four geodesic arcs around
    // it at x = 20.
    MaskVolume mask(Dims{40, 19, 19}, 0);
    for (int z = 0; z < 19; ++z)
        for (int y = 0; y < 19; ++y)
            for (int x = 2; x < 38; ++x) {
                const double dy = y - 9.0, dz = z - 9.0;
                mask(x, y, z) = dy * dy + dz * dz <= 49.0 ? 1 : 0;
            }
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    std::vector<std::uint32_t> ring;
    for (double angle : {0.0, 90.0, 180.0, 270.0}) {
        const double t = angle * test::kPi / 180.0;
        ring.push_back(
            test::nearestNode(graph, {20.0, 9.0 + 7.0 * std::cos(t), 9.0 + 7.0 * std::sin(t)}));
    }
    GeodesicSearch search(graph);
    RimCounter rims(graph);
    ASSERT_EQ(rims.countRims(test::pathThrough(search, ring, true)).pieceCount, 2u);
    GeodesicnessEvaluator evaluator(graph);
    const GeodesicnessResult straight = evaluator.evaluate(rims, ring[0], ring[2], search);
    EXPECT_GE(straight.sigma, 0.9f);
    EXPECT_EQ(straight.arcCount, 2u);

    // A slanted loop: 0 and 180 degrees at x = 14, 90 and 270 at x = 26. The
    // loop zig-zags (kinks at every point), so sigma drops.
    std::vector<std::uint32_t> zigzag;
    for (double angle : {0.0, 90.0, 180.0, 270.0}) {
        const double t = angle * test::kPi / 180.0;
        const double x = (angle == 0.0 || angle == 180.0) ? 14.0 : 26.0;
        zigzag.push_back(
            test::nearestNode(graph, {x, 9.0 + 7.0 * std::cos(t), 9.0 + 7.0 * std::sin(t)}));
    }
    ASSERT_EQ(rims.countRims(test::pathThrough(search, zigzag, true)).pieceCount, 2u);
    const GeodesicnessResult slanted = evaluator.evaluate(rims, zigzag[0], zigzag[2], search);
    EXPECT_LT(slanted.sigma, straight.sigma - 0.1f);
}

}  // namespace
}  // namespace skelseg
