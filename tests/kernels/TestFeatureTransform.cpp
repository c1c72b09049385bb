#include "kernels/FeatureTransform.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <vector>

#include "io/shapes/SyntheticShapes.h"
#include "kernels/BoundaryGraph.h"
#include "tests/kernels/KernelTestSupport.h"
#include "tests/support/StopAtOnce.h"

namespace skelseg {
namespace {

/// Exact reference: the squared distance from every voxel to its nearest
/// site by exhaustive search (-1 when there is no site).
std::vector<std::int64_t> bruteForceSquaredDistance(const MaskVolume& sites) {
    const Dims d = sites.dims();
    std::vector<std::uint32_t> siteList;
    for (std::size_t i = 0; i < sites.size(); ++i)
        if (sites[i]) siteList.push_back(std::uint32_t(i));
    std::vector<std::int64_t> out(sites.size(), -1);
    for (std::size_t i = 0; i < sites.size(); ++i) {
        std::int64_t best = std::numeric_limits<std::int64_t>::max();
        for (std::uint32_t s : siteList)
            best = std::min(best, squaredDistance(d, std::uint32_t(i), s));
        if (!siteList.empty()) out[i] = best;
    }
    return out;
}

/// Checks FT against the brute-force reference: every voxel maps to a site
/// and its distance is the minimal one (ties may pick any site).
void expectExact(const MaskVolume& sites, const Volume<std::uint32_t>& ft) {
    ASSERT_EQ(ft.dims(), sites.dims());
    const std::vector<std::int64_t> reference = bruteForceSquaredDistance(sites);
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < sites.size(); ++i) {
        const std::uint32_t f = ft[i];
        if (reference[i] < 0) {
            if (f != kNoFeature) ++wrong;
            continue;
        }
        if (f == kNoFeature || f >= sites.size() || !sites[f] ||
            squaredDistance(sites.dims(), std::uint32_t(i), f) != reference[i]) {
            if (wrong < 5)
                ADD_FAILURE() << "voxel " << i << ": feature " << f << " at squared distance "
                              << (f < sites.size()
                                      ? squaredDistance(sites.dims(), std::uint32_t(i), f)
                                      : -1)
                              << ", nearest site at " << reference[i];
            ++wrong;
        }
    }
    EXPECT_EQ(wrong, 0u);
}

struct RandomCase {
    Dims dims;
    double density;
    std::uint32_t seed;
};

class FeatureTransformRandom : public ::testing::TestWithParam<RandomCase> {};

TEST_P(FeatureTransformRandom, MatchesBruteForceSerialAndParallel) {
    const RandomCase c = GetParam();
    const MaskVolume sites = test::randomMask(c.dims, c.density, c.seed);
    const Volume<std::uint32_t> serial = featureTransform(sites, {false});
    expectExact(sites, serial);
    const Volume<std::uint32_t> parallel = featureTransform(sites, {true});
    EXPECT_EQ(serial.values(), parallel.values()) << "thread count changed the feature transform";
}

INSTANTIATE_TEST_SUITE_P(
    Volumes, FeatureTransformRandom,
    ::testing::Values(RandomCase{{17, 23, 11}, 0.01, 1}, RandomCase{{17, 23, 11}, 0.3, 2},
                      RandomCase{{17, 23, 11}, 0.9, 3}, RandomCase{{23, 11, 17}, 0.003, 4},
                      RandomCase{{11, 17, 23}, 0.05, 5}, RandomCase{{31, 5, 9}, 0.02, 6},
                      RandomCase{{1, 1, 40}, 0.1, 7}, RandomCase{{40, 1, 1}, 0.1, 8},
                      RandomCase{{1, 29, 13}, 0.02, 9}, RandomCase{{12, 12, 12}, 0.0015, 10},
                      RandomCase{{9, 30, 2}, 0.5, 11}));

TEST(FeatureTransform, NoSiteGivesNoFeatureEverywhere) {
    const MaskVolume sites(Dims{17, 23, 11}, 0);
    for (bool threaded : {false, true}) {
        const Volume<std::uint32_t> ft = featureTransform(sites, {threaded});
        ASSERT_EQ(ft.size(), sites.size());
        for (std::size_t i = 0; i < ft.size(); ++i) ASSERT_EQ(ft[i], kNoFeature) << "voxel " << i;
    }
}

TEST(FeatureTransform, SingleSiteEveryVoxelPointsToIt) {
    MaskVolume sites(Dims{13, 9, 7}, 0);
    sites(12, 0, 6) = 1;  // a corner: the farthest voxels are a whole diagonal away
    const Volume<std::uint32_t> ft = featureTransform(sites, {false});
    const std::uint32_t site = std::uint32_t(sites.index(12, 0, 6));
    for (std::size_t i = 0; i < ft.size(); ++i) ASSERT_EQ(ft[i], site);
}

TEST(FeatureTransform, ExactWhereChamferWouldNotBe) {
    // Two sites where a city-block or chessboard metric picks the wrong one:
    // from the origin, (3,3,0) is at Euclidean 4.24 and (5,0,0) at 5, while
    // a chessboard metric ranks them 3 < 5 and city-block 6 > 5.
    MaskVolume sites(Dims{8, 8, 8}, 0);
    sites(5, 0, 0) = 1;
    sites(3, 3, 0) = 1;
    const Volume<std::uint32_t> ft = featureTransform(sites, {false});
    EXPECT_EQ(ft[ft.index(0, 0, 0)], std::uint32_t(sites.index(3, 3, 0)));
    expectExact(sites, ft);
}

TEST(FeatureTransform, BoundarySitesOfAShape) {
    // The way the engine uses it: sites = boundary voxels of a shape.
    const MaskVolume mask = rasterise(makeShape("t-body"), {28, 2});
    const MaskVolume sites = boundaryVoxels(mask, {false});
    const Volume<std::uint32_t> serial = featureTransform(sites, {false});
    expectExact(sites, serial);
    EXPECT_EQ(serial.values(), featureTransform(sites, {true}).values());
    // Boundary voxels are their own feature.
    for (std::size_t i = 0; i < sites.size(); ++i)
        if (sites[i]) {
            ASSERT_EQ(serial[i], std::uint32_t(i));
        }
}

TEST(FeatureTransform, SerialEqualsParallelOnLargerVolume) {
    const MaskVolume sites = test::randomMask(Dims{61, 47, 53}, 0.002, 42);
    const Volume<std::uint32_t> serial = featureTransform(sites, {false});
    const Volume<std::uint32_t> parallel = featureTransform(sites, {true});
    EXPECT_EQ(serial.values(), parallel.values());
    // Spot-check exactness against a brute force over a sample of voxels.
    std::vector<std::uint32_t> siteList;
    for (std::size_t i = 0; i < sites.size(); ++i)
        if (sites[i]) siteList.push_back(std::uint32_t(i));
    for (std::size_t i = 0; i < sites.size(); i += 97) {
        std::int64_t best = std::numeric_limits<std::int64_t>::max();
        for (std::uint32_t s : siteList)
            best = std::min(best, squaredDistance(sites.dims(), std::uint32_t(i), s));
        ASSERT_EQ(squaredDistance(sites.dims(), std::uint32_t(i), serial[i]), best)
            << "voxel " << i;
    }
}

TEST(FeatureTransform, InterruptionThrows) {
    struct StopAtOnce : Interrupter {
        bool wasInterrupted(double) override { return true; }
    } stop;
    const MaskVolume sites = test::randomMask(Dims{16, 16, 16}, 0.05, 3);
    EXPECT_THROW(featureTransform(sites, {false}, stop), InterruptedError);
}

TEST(FeatureTransform, AStopAnsweredOnceAtAnyPollThrows) {
    const MaskVolume sites = test::randomMask(Dims{16, 16, 16}, 0.05, 3);
    for (const bool threaded : {false, true}) {
        SCOPED_TRACE(threaded ? "threaded" : "serial");
        EXPECT_GT(test::expectAStopAtAnyPollThrows([&](Interrupter& interrupter) {
                      featureTransform(sites, {threaded}, interrupter);
                  }),
                  3);
    }
}

}  // namespace
}  // namespace skelseg
