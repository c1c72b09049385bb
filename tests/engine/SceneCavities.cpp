// Scene tests: cavities inside an object change none of its parts (issue 12,
// stray voxels; kernels/Cavities.h). Pores of a thresholded scan are missing
// voxels inside the shape; the parts are those of its outer surface.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "tests/kernels/KernelTestSupport.h"
#include "tests/support/SceneSupport.h"

namespace skelseg::test {
namespace {

/// Whether the 5^3 voxels around (x, y, z) are all object voxels: a voxel
/// removed there (or next to another such) is enclosed by the object.
bool deepInside(const MaskVolume& mask, int x, int y, int z) {
    for (int dz = -2; dz <= 2; ++dz)
        for (int dy = -2; dy <= 2; ++dy)
            for (int dx = -2; dx <= 2; ++dx)
                if (!mask.contains(x + dx, y + dy, z + dz) || !mask(x + dx, y + dy, z + dz))
                    return false;
    return true;
}

TEST(SceneCavities, PoresAndAHollowInsideAVolumeChangeNoPart) {
    const SceneRun clean = segmentShape("figure", 96);
    ASSERT_GE(partCount(clean), 5u);
    ASSERT_EQ(clean.result.objects.front().cavities, 0u);
    // About one deep voxel in 97 removed (single pores, some of them
    // touching), and a hollow of 3^3 voxels around the first deep voxel
    // whose whole neighbourhood is deep.
    MaskVolume mask = clean.mask;
    const Dims d = mask.dims();
    std::uint64_t removed = 0;
    bool hollowMade = false;
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) {
                if (!deepInside(clean.mask, x, y, z)) continue;
                const bool pore = (x * 7 + y * 13 + z * 29) % 97 == 0;
                bool hollow = !hollowMade && deepInside(clean.mask, x - 1, y - 1, z - 1) &&
                              deepInside(clean.mask, x + 1, y + 1, z + 1);
                if (hollow) {
                    for (int dz = -1; dz <= 1; ++dz)
                        for (int dy = -1; dy <= 1; ++dy)
                            for (int dx = -1; dx <= 1; ++dx) {
                                removed += mask(x + dx, y + dy, z + dz);
                                mask(x + dx, y + dy, z + dz) = 0;
                            }
                    hollowMade = true;
                } else if (pore && mask(x, y, z)) {
                    mask(x, y, z) = 0;
                    ++removed;
                }
            }
    ASSERT_TRUE(hollowMade);
    ASSERT_GT(removed, 50u);
    const SegmentationResult porous = segmentVolume(mask, {});

    ASSERT_EQ(porous.objects.size(), 1u);
    EXPECT_GT(porous.objects.front().cavities, 10u);
    EXPECT_EQ(porous.objects.front().cavityVoxels, removed);
    ASSERT_EQ(porous.segments.size(), clean.result.segments.size());
    // Every voxel of the shape keeps its label; the pores stay unlabelled.
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (mask[i])
            ASSERT_EQ(porous.labels[i], clean.result.labels[i]) << "voxel " << i;
        else
            ASSERT_EQ(porous.labels[i], 0) << "voxel " << i;
    }
}

TEST(SceneCavities, AnObjectInsideAnotherKeepsItsOwnLabelAndTheGapStaysBackground) {
    // A hollow ball (walls 6 voxels thick) holding a solid ball apart from it.
    const Dims d{72, 72, 72};
    const std::array<double, 3> centre{35.5, 35.5, 35.5};
    const MaskVolume outer = ballMask(d, centre, 32.0);
    const MaskVolume hollow = ballMask(d, centre, 26.0);
    const MaskVolume inner = ballMask(d, centre, 14.0);
    MaskVolume mask(d, 0);
    for (std::size_t i = 0; i < mask.size(); ++i)
        mask[i] = (outer[i] && !hollow[i]) || inner[i] ? 1 : 0;
    const SegmentationResult result = segmentVolume(mask, {});

    ASSERT_EQ(result.objects.size(), 2u);
    std::set<int> shellLabels, innerLabels;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (!mask[i]) {
            ASSERT_EQ(result.labels[i], 0) << "voxel " << i;
        } else {
            ASSERT_NE(result.labels[i], 0) << "voxel " << i;
            (inner[i] ? innerLabels : shellLabels).insert(result.labels[i]);
        }
    }
    EXPECT_EQ(innerLabels.size(), 1u);
    for (int label : innerLabels) EXPECT_EQ(shellLabels.count(label), 0u);
    // The shell's cavity (the gap and the inner ball's place) was filled
    // for its own segmentation only.
    std::uint64_t cavityVoxels = 0;
    for (const ObjectSegmentation& object : result.objects) cavityVoxels += object.cavityVoxels;
    std::uint64_t enclosed = 0;
    for (std::size_t i = 0; i < mask.size(); ++i) enclosed += hollow[i];
    EXPECT_EQ(cavityVoxels, enclosed);
}

}  // namespace
}  // namespace skelseg::test
