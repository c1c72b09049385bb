// Scene test: a corner or cap of the body is not a part (docs/algorithm.md
// §8.6, "Caps and corners are not limbs"). hand.off's forearm is cut off flat
// and obliquely; its skeleton forks into the flat end's corners, and at some
// resolutions a loop round one corner was cut as a part.
#include <gtest/gtest.h>

#include <algorithm>

#include "tests/support/SceneSupport.h"

namespace skelseg::test {
namespace {

/// A palm (ellipsoid), three fingers (capsules) and a short forearm stump of
/// flattened elliptic section cut off by an oblique plane, `size` voxels
/// along x; everything else scales with it.
MaskVolume palmWithFlatStump(int size) {
    const double h = 2.6 / size;
    const Dims dims{size, int(2.45 / h), int(1.2 / h)};
    MaskVolume mask(dims, 0);
    for (int k = 0; k < dims.z; ++k)
        for (int j = 0; j < dims.y; ++j)
            for (int i = 0; i < dims.x; ++i) {
                const double x = -1.3 + (i + 0.5) * h, y = -1.0 + (j + 0.5) * h,
                             z = -0.6 + (k + 0.5) * h;
                bool inside =
                    (x / 0.7) * (x / 0.7) + (y / 0.8) * (y / 0.8) + (z / 0.45) * (z / 0.45) <= 1.0;
                inside |= (x / 0.5) * (x / 0.5) + (z / 0.22) * (z / 0.22) <= 1.0 && y <= 0.0 &&
                          y >= -0.95 + 0.35 * x;
                for (double fingerX : {-0.35, 0.0, 0.35}) {
                    const double t = std::clamp((y - 0.6) / 0.7, 0.0, 1.0);
                    const double dy = y - (0.6 + 0.7 * t);
                    inside |= (x - fingerX) * (x - fingerX) + dy * dy + z * z <= 0.11 * 0.11;
                }
                mask(i, j, k) = inside ? 1 : 0;
            }
    return mask;
}

TEST(Scene, FlatStumpIsNoPartAtAnyScale) {
    // Before the rule, 96 voxels cut the stump's end off as two more parts
    // (loop rho_S 48, 2 discs of area) while 128 and 160 kept it on the palm.
    for (int size : {96, 128}) {
        const SegmentationResult result = segmentVolume(palmWithFlatStump(size), {});
        ASSERT_EQ(result.segments.size(), 4u) << "palm and three fingers at size " << size;
        // The palm with its stump is the largest part, the fingers are alike.
        const auto& s = result.segments;
        std::vector<std::uint64_t> fingers;
        for (std::size_t i = 1; i < s.size(); ++i) fingers.push_back(s[i].voxelCount);
        EXPECT_GT(s[0].voxelCount, 5 * *std::max_element(fingers.begin(), fingers.end()));
        EXPECT_LT(double(*std::max_element(fingers.begin(), fingers.end())),
                  1.3 * double(*std::min_element(fingers.begin(), fingers.end())));
        bool capFound = false;
        for (const auto& c : result.objects.at(0).criticalPoints) capFound |= c.isCap;
        if (size == 96) EXPECT_TRUE(capFound) << "the rule this test guards";
    }
}

}  // namespace
}  // namespace skelseg::test
