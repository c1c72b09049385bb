#include "kernels/SeveredObjects.h"

#include <gtest/gtest.h>

#include "kernels/VoxelGenus.h"
#include "tests/support/StopAtOnce.h"

namespace skelseg {
namespace {

using test::StopAtOnce;

/// Clears the cells of `group` in `mask` and returns them.
ClearedGroup clear(MaskVolume& mask, const ClearedGroup& group) {
    for (const auto& c : group) mask(c[0], c[1], c[2]) = 0;
    return group;
}

/// A cross section of a bar along x (y, z in [1, 2]) at x.
ClearedGroup sectionAt(int x) {
    return {{x, 1, 1}, {x, 1, 2}, {x, 2, 1}, {x, 2, 2}};
}

MaskVolume bar(int length) {
    MaskVolume mask(Dims{length, 4, 4}, 0);
    for (int x = 1; x < length - 1; ++x)
        for (int y = 1; y <= 2; ++y)
            for (int z = 1; z <= 2; ++z) mask(x, y, z) = 1;
    return mask;
}

TEST(SeveredObjects, AGroupThatCutsABarIsSetBack) {
    MaskVolume mask = bar(12);
    const MaskVolume whole = bar(12);
    const std::vector<ClearedGroup> groups{clear(mask, sectionAt(6))};
    ASSERT_EQ(voxelTopology(mask).objects, 2u);
    EXPECT_EQ(rejoinSeveredObjects(mask, groups), std::vector<bool>{true});
    EXPECT_EQ(mask.values(), whole.values());
}

TEST(SeveredObjects, AGroupThatCutsNothingStays) {
    // Only the top layer of a section: the bar stays joined below it.
    MaskVolume mask = bar(12);
    const std::vector<ClearedGroup> groups{clear(mask, {{6, 1, 2}, {6, 2, 2}})};
    MaskVolume expected = bar(12);
    clear(expected, groups[0]);
    EXPECT_EQ(rejoinSeveredObjects(mask, groups), std::vector<bool>{false});
    EXPECT_EQ(mask.values(), expected.values());
}

TEST(SeveredObjects, OfTwoCutsThroughARingOnlyTheFirstIsSetBack) {
    // A square ring in the plane z = 1; each cut alone leaves it whole,
    // both cut it in two: setting back the first joins it again.
    MaskVolume mask(Dims{9, 9, 3}, 0);
    for (int i = 1; i <= 7; ++i) {
        mask(i, 1, 1) = mask(i, 7, 1) = 1;
        mask(1, i, 1) = mask(7, i, 1) = 1;
    }
    const std::vector<ClearedGroup> groups{clear(mask, {{4, 1, 1}}), clear(mask, {{4, 7, 1}})};
    ASSERT_EQ(voxelTopology(mask).objects, 2u);
    EXPECT_EQ(rejoinSeveredObjects(mask, groups), (std::vector<bool>{true, false}));
    const VoxelTopology topology = voxelTopology(mask);
    EXPECT_EQ(topology.objects, 1u);
    EXPECT_EQ(topology.genus, 0);
}

TEST(SeveredObjects, SerialEqualsParallel) {
    MaskVolume serial = bar(20), parallel = bar(20);
    const std::vector<ClearedGroup> cuts{sectionAt(5), sectionAt(10), {{15, 1, 2}}};
    for (const auto& g : cuts) {
        clear(serial, g);
        clear(parallel, g);
    }
    SeveredObjectsOptions serialOptions;
    serialOptions.threaded = false;
    EXPECT_EQ(rejoinSeveredObjects(serial, cuts, serialOptions),
              rejoinSeveredObjects(parallel, cuts));
    EXPECT_EQ(serial.values(), parallel.values());
}

TEST(SeveredObjects, CountsWithoutSettingBack) {
    MaskVolume mask = bar(12);
    const std::vector<ClearedGroup> groups{clear(mask, sectionAt(6))};
    MaskVolume cut = bar(12);
    clear(cut, groups[0]);
    SeveredObjectsOptions countOnly;
    countOnly.setBack = false;
    EXPECT_EQ(rejoinSeveredObjects(mask, groups, countOnly), std::vector<bool>{true});
    EXPECT_EQ(mask.values(), cut.values());
}

TEST(SeveredObjects, StopsWhenInterrupted) {
    MaskVolume mask = bar(12);
    const std::vector<ClearedGroup> groups{clear(mask, sectionAt(6))};
    StopAtOnce stop;
    EXPECT_THROW(rejoinSeveredObjects(mask, groups, {}, stop), InterruptedError);
}

}  // namespace
}  // namespace skelseg
