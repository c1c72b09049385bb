// segmentVolume() on small objects that touch the grid's faces: the crop with
// one voxel of padding then starts at -1, which the copy into the crop and the
// label write-back must handle (the ASan/UBSan build runs these, label unit).
#include <gtest/gtest.h>

#include <map>
#include <utility>

#include "engine/Segmenter.h"
#include "io/shapes/SyntheticShapes.h"
#include "tests/engine/RobustnessHelpers.h"

using namespace skelseg;
using skelseg::test::makeMask;

namespace {

/// Every object voxel carries a listed label, background none, and the
/// segments' voxel counts are those of the label volume.
void expectLabelsCoverTheObject(const MaskVolume& mask, const SegmentationResult& result) {
    ASSERT_EQ(result.labels.dims(), mask.dims());
    std::map<std::uint16_t, std::uint64_t> counted;
    const Dims d = mask.dims();
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) {
                const std::uint16_t label = result.labels(x, y, z);
                if (!mask(x, y, z)) {
                    ASSERT_EQ(label, 0)
                        << "background voxel " << x << ',' << y << ',' << z << " labelled";
                    continue;
                }
                ASSERT_GE(label, 1)
                    << "object voxel " << x << ',' << y << ',' << z << " unlabelled";
                ASSERT_LE(label, result.segments.size());
                ++counted[label];
            }
    ASSERT_EQ(counted.size(), result.segments.size());
    for (const SegmentInfo& s : result.segments)
        EXPECT_EQ(counted[s.label], s.voxelCount) << "label " << s.label;
}

SegmentationResult segmentWith(const MaskVolume& mask, bool threaded) {
    SegmentationParameters p;
    p.threaded = threaded;
    return segmentVolume(mask, p);
}

}  // namespace

TEST(Segmenter, TubeThroughOppositeGridFacesIsLabelledCompletely) {
    // A tube from x = 0 to x = max, lying on the y = 0 face: its crop starts at
    // (-1, -1, z0 - 1).
    const MaskVolume mask = makeMask(Dims{36, 14, 14}, [](int, int y, int z) {
        const double dy = y - 3.0, dz = z - 7.0;
        return dy * dy + dz * dz <= 16.0;
    });
    const SegmentationResult result = segmentWith(mask, true);
    expectLabelsCoverTheObject(mask, result);
    ASSERT_EQ(result.objects.size(), 1u);
    EXPECT_EQ(result.objects[0].bboxMin[0], 0);
    EXPECT_EQ(result.objects[0].bboxMax[0], 35);
    EXPECT_EQ(result.objects[0].bboxMin[1], 0);
}

TEST(Segmenter, BoxFillingTheGridSerialAndParallelAgree) {
    const MaskVolume mask = makeMask(Dims{10, 9, 8}, [](int, int, int) { return true; });
    const SegmentationResult parallel = segmentWith(mask, true);
    const SegmentationResult serial = segmentWith(mask, false);
    expectLabelsCoverTheObject(mask, parallel);
    ASSERT_EQ(parallel.objects.size(), 1u);
    EXPECT_EQ(parallel.objects[0].voxelCount, 10u * 9u * 8u);
    EXPECT_TRUE(std::equal(parallel.labels.data(), parallel.labels.data() + parallel.labels.size(),
                           serial.labels.data()));
}

TEST(Segmenter, ObjectsInOppositeCornersKeepTheirVoxels) {
    // Two boxes, each in a corner of the grid (touching three faces), plus a
    // 2x2x2 cube in a third corner. (A single voxel would be an island,
    // kernels/Islands.h: below the boxes' noise area of 7.5 voxels.)
    const Dims dims{20, 16, 12};
    auto objects = [](int x, int y, int z) {
        return (x <= 5 && y <= 5 && z <= 5) || (x >= 12 && y >= 9 && z >= 6) ||
               (x >= 18 && y <= 1 && z <= 1);
    };
    const SegmentationResult result = segmentWith(makeMask(dims, objects), true);
    expectLabelsCoverTheObject(makeMask(dims, objects), result);
    EXPECT_EQ(result.objects.size(), 3u);
    EXPECT_EQ(result.islands.count, 0u);

    // The same with a single voxel in a fourth corner: an island, label 0,
    // and everything else labelled as before.
    const MaskVolume withIsland = makeMask(dims, [&](int x, int y, int z) {
        return objects(x, y, z) || (x == 19 && y == 15 && z == 0);
    });
    const SegmentationResult islanded = segmentWith(withIsland, true);
    EXPECT_EQ(islanded.objects.size(), 3u);
    EXPECT_EQ(islanded.islands.count, 1u);
    EXPECT_EQ(islanded.islands.voxels, 1u);
    EXPECT_EQ(islanded.labels(19, 15, 0), 0);
    EXPECT_EQ(islanded.labels.values(), result.labels.values());
}

TEST(Segmenter, TauListsAreSortedAndCheckedWhole) {
    const std::vector<TauSpec> taus = parseTauList("9%,1%,3%");
    ASSERT_EQ(taus.size(), 3u);
    EXPECT_EQ(taus[0].toString(), "1%");
    EXPECT_EQ(taus[1].toString(), "3%");
    EXPECT_EQ(taus[2].toString(), "9%");
    SegmentationParameters p;
    p.tau = taus[2];
    p.finerTaus = {taus[0], taus[1]};
    EXPECT_EQ(p.tauListString(), "1%,3%,9%");
    EXPECT_EQ(parseTauList("250").front().toString(), "250");
    // Levels that differ in the seventh digit keep distinct names, and every
    // name reads back as its level.
    const std::vector<TauSpec> close = parseTauList("3%,3.0000001%");
    ASSERT_EQ(close.size(), 2u);
    EXPECT_EQ(close[0].toString(), "3%");
    EXPECT_EQ(close[1].toString(), "3.0000001%");
    const TauSpec voxels = TauSpec::parse("1234567.5");
    EXPECT_EQ(voxels.toString(), "1234567.5");
    for (const TauSpec& tau : {close[0], close[1], voxels})
        EXPECT_EQ(TauSpec::parse(tau.toString()).value, tau.value);
    SegmentationParameters single;
    EXPECT_EQ(single.tauListString(), single.tau.toString());
    for (const char* bad : {"", ",", "1%,", "1%,,3%", "x", "3%,3.0%", "1%,250", "1%,-2%"})
        EXPECT_THROW(parseTauList(bad), UsageError) << bad;
}

TEST(Segmenter, ForkVoxelsAreReportedOnlyWhenForksAreJunctions) {
    // The figure in pose 1 has a fork beside a junction point (a limb's
    // skeleton leaves the junction's ball apart from the J_tau cluster): the
    // report names those core voxels, and none without the fork rule.
    RasterOptions raster;
    raster.size = 112;
    const MaskVolume mask = rasterise(makeShape("figure", 1), raster);
    auto forkAndCoreVoxels = [&](bool forks) {
        SegmentationParameters p;
        p.forkJunctions = forks;
        const SegmentationResult result = segmentVolume(mask, p);
        std::uint32_t fork = 0, core = 0;
        for (const ObjectSegmentation& o : result.objects)
            for (const JunctionInfo& j : o.junctions) {
                EXPECT_LE(j.forkVoxels, j.coreVoxels);
                fork += j.forkVoxels;
                core += j.coreVoxels;
            }
        return std::pair{fork, core};
    };
    const auto [forks, coreWithForks] = forkAndCoreVoxels(true);
    const auto [none, coreWithout] = forkAndCoreVoxels(false);
    EXPECT_GT(forks, 0u);
    EXPECT_EQ(none, 0u);
    EXPECT_EQ(coreWithForks - forks, coreWithout) << "the J_tau points are the same either way";
}
