#include "engine/TimeBudget.h"

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <vector>

#include "engine/Segmenter.h"
#include "io/shapes/SyntheticShapes.h"
#include "tests/support/WorkCountsFixture.h"

namespace skelseg {
namespace {

WorkCounts someWork() {
    return test::workCounts({64, 64, 64}, 50000, 8000, 9000, 20000);
}

TEST(TimeBudget, ScalingFollowsVolumeAndSurface) {
    const CostModel model = CostModel::fitted();
    const WorkCounts w = someWork(), s = model.scale(w, 2.0);
    EXPECT_DOUBLE_EQ(s.gridVoxels, 8 * w.gridVoxels);
    EXPECT_DOUBLE_EQ(s.objectVoxels, 8 * w.objectVoxels);
    EXPECT_DOUBLE_EQ(s.boundaryVoxels, 4 * w.boundaryVoxels);
    EXPECT_GT(s.candidates, w.candidates);
    EXPECT_DOUBLE_EQ(s.meshFaces, w.meshFaces);  // the mesh does not change
    EXPECT_GT(model.predictSeconds(s), model.predictSeconds(w));
}

TEST(TimeBudget, ALargerBudgetNeverChoosesASmallerResolution) {
    const CostModel model = CostModel::fitted();
    int previous = 0;
    for (double seconds : {0.5, 1.0, 2.0, 5.0, 20.0, 1000.0}) {
        const BudgetChoice c = chooseMeshResolution(model, someWork(), 64, 400, 16, seconds);
        EXPECT_GE(c.resolution, previous) << seconds;
        EXPECT_LE(c.resolution, 400);
        if (c.fits) EXPECT_LE(c.predictedSeconds, seconds);
        EXPECT_EQ(c.coarsened, c.resolution < 400);
        previous = c.resolution;
    }
    EXPECT_EQ(chooseMeshResolution(model, someWork(), 64, 400, 16, 1000.0).resolution, 400);
}

TEST(TimeBudget, NothingFitsTakesTheCoarsestChoiceAndSaysSo) {
    const CostModel model = CostModel::fitted();
    const BudgetChoice mesh = chooseMeshResolution(model, someWork(), 64, 400, 16, 1e-6);
    EXPECT_FALSE(mesh.fits);
    EXPECT_EQ(mesh.resolution, 16);
    const BudgetChoice volume = chooseVolumeCoarsening(model, someWork(), 1, 1e-6);
    EXPECT_FALSE(volume.fits);
    EXPECT_EQ(volume.coarsening, 4);
    EXPECT_TRUE(volume.coarsened);
    const BudgetChoice ample = chooseVolumeCoarsening(model, someWork(), 2, 1e6);
    EXPECT_TRUE(ample.fits);
    EXPECT_EQ(ample.coarsening, 1);
    EXPECT_FALSE(ample.coarsened);
}

TEST(TimeBudget, TheSafetyMarginLeavesRoomForAnUnderPrediction) {
    CostModel model = CostModel::fitted();
    model.safetyMargin = 0.0;
    const BudgetChoice bare = chooseMeshResolution(model, someWork(), 64, 400, 16, 2.0);
    model.safetyMargin = 0.5;
    const BudgetChoice margin = chooseMeshResolution(model, someWork(), 64, 400, 16, 2.0);
    ASSERT_TRUE(bare.fits);
    ASSERT_TRUE(margin.fits);
    EXPECT_LT(margin.resolution, bare.resolution);
    // The chosen run, 50% slower than predicted, still ends within the budget.
    EXPECT_LE(margin.predictedSeconds * 1.5, 2.0);
    EXPECT_DOUBLE_EQ(margin.safetyMargin, 0.5);
}

TEST(TimeBudget, ThePreviewIsSkippedWhenItTakesMoreThanAQuarterOfWhatIsLeft) {
    CostModel model;
    model.previewSeconds = 0.5;
    model.previewPerTriangle = 1e-6;  // 1 s for 500k triangles
    model.safetyMargin = 0.0;
    BudgetChoice small, large;
    // 0.6 s of preview with 10 s left: kept, 9.4 s left for the run.
    EXPECT_DOUBLE_EQ(planPreview(model, 1e5, 10.0, small), 10.0 - 0.6);
    EXPECT_TRUE(small.writePreview);
    EXPECT_DOUBLE_EQ(small.previewSeconds, 0.6);
    // 1 s of preview with 2 s left: skipped, the whole 2 s go to the run.
    EXPECT_DOUBLE_EQ(planPreview(model, 5e5, 2.0, large), 2.0);
    EXPECT_FALSE(large.writePreview);
    // With a margin the preview counts larger, also against what is left.
    model.safetyMargin = 1.0;
    BudgetChoice margin;
    EXPECT_DOUBLE_EQ(planPreview(model, 1e5, 10.0, margin), 10.0 - 1.2);
    EXPECT_TRUE(margin.writePreview);
    EXPECT_FALSE(planPreview(model, 1e5, 4.0, margin) < 4.0);
    EXPECT_FALSE(margin.writePreview);
}

/// A first mesh choice that fits and was coarsened to `resolution`.
BudgetChoice coarsenedMeshChoice(int resolution, double budget) {
    BudgetChoice first;
    first.budgetSeconds = budget;
    first.resolution = resolution;
    first.coarsened = true;
    first.fits = true;
    return first;
}

/// A first pass of 1 s: 0.2 s per face, 0.5 s over the grid, 0.2 s on the
/// surface, 0.1 s outside the stages; 0.05 s reading.
FirstPassTimes firstPassOfOneSecond() {
    FirstPassTimes times;
    times.seconds = 1.0;
    times.readSeconds = 0.05;
    times.stages = {{0.2, 0.0}, {0.5, 3.0}, {0.2, 2.5}};
    return times;
}

TEST(BudgetRefinement, AFinerPassGrowsEachStageByItsOwnPower) {
    const FirstPassTimes times = firstPassOfOneSecond();
    EXPECT_NEAR(predictFinerPass(times, 1.0), 1.05, 1e-12);  // read again, the rest as it was
    EXPECT_NEAR(predictFinerPass(times, 2.0),
                0.05 + 0.2 + 0.5 * 8.0 + 0.2 * std::pow(2.0, 2.5) + 0.1, 1e-12);
    // Overlapping stages (concurrent writers) add up to more than the pass:
    // nothing is counted outside them.
    FirstPassTimes overlapping = times;
    overlapping.seconds = 0.5;
    EXPECT_NEAR(predictFinerPass(overlapping, 1.0), 0.95, 1e-12);
}

TEST(BudgetRefinement, ChoosesTheLargestResolutionWhosePredictionFits) {
    const FirstPassTimes times = firstPassOfOneSecond();
    const BudgetChoice first = coarsenedMeshChoice(100, 10.0);
    const double left = 8.0;
    const BudgetRefinement plan = planBudgetRefinement(first, 400, times, left);
    ASSERT_TRUE(plan.tried) << plan.reason;
    const double usable = left - (kRefinementReserve * 10.0 + kRefinementReserveSeconds);
    const int r = plan.choice.resolution;
    EXPECT_GE(r, int(std::ceil(kRefinementMinimumGain * 100)));
    EXPECT_LE(plan.choice.predictedSeconds * (1.0 + kRefinementMargin), usable);
    EXPECT_NEAR(plan.choice.predictedSeconds, predictFinerPass(times, r / 100.0), 1e-12);
    // The next step up the ladder (about 10% larger) would not fit.
    int larger = 400;
    while (int(std::floor(larger * 0.9)) > r) larger = int(std::floor(larger * 0.9));
    ASSERT_GT(larger, r);
    EXPECT_GT(predictFinerPass(times, larger / 100.0) * (1.0 + kRefinementMargin), usable);
    EXPECT_TRUE(plan.choice.coarsened);
    EXPECT_EQ(plan.choice.safetyMargin, kRefinementMargin);
    EXPECT_EQ(plan.firstResolution, 100);
}

TEST(BudgetRefinement, AnAmpleRemainderGoesToTheRequestedResolution) {
    const BudgetRefinement plan =
        planBudgetRefinement(coarsenedMeshChoice(100, 1000.0), 400, firstPassOfOneSecond(), 990.0);
    ASSERT_TRUE(plan.tried);
    EXPECT_EQ(plan.choice.resolution, 400);
    EXPECT_FALSE(plan.choice.coarsened);
}

TEST(BudgetRefinement, NoFinerPassWhereNothingFinerFitsOrNothingWasCoarsened) {
    const FirstPassTimes times = firstPassOfOneSecond();
    // 1.25 times the resolution is about twice the grid time: over 1.5 s left.
    EXPECT_FALSE(planBudgetRefinement(coarsenedMeshChoice(100, 3.0), 400, times, 1.5).tried);
    BudgetChoice uncoarsened = coarsenedMeshChoice(400, 100.0);
    uncoarsened.coarsened = false;
    const BudgetRefinement asked = planBudgetRefinement(uncoarsened, 400, times, 90.0);
    EXPECT_FALSE(asked.tried);
    EXPECT_EQ(asked.reason, "the first choice was not coarsened");
    BudgetChoice over = coarsenedMeshChoice(16, 100.0);
    over.fits = false;  // the budget acted as the time limit
    EXPECT_FALSE(planBudgetRefinement(over, 400, times, 90.0).tried);
}

TEST(BudgetRefinement, AFinerPassStaysWithinTheMemoryCap) {
    // --max-memory allowed 300 of the 400 asked: with time for 400, the
    // finer pass takes 300, still below what was asked.
    BudgetChoice capped = coarsenedMeshChoice(100, 1000.0);
    capped.memoryCapResolution = 300;
    const BudgetRefinement plan =
        planFinerPass(capped, true, 400, {}, std::chrono::steady_clock::now());
    ASSERT_TRUE(plan.tried);
    EXPECT_EQ(plan.choice.resolution, 300);
    EXPECT_TRUE(plan.choice.coarsened);
    // A cap under 1.25 times the first choice leaves nothing finer to try.
    capped.memoryCapResolution = 120;
    const BudgetRefinement none =
        planFinerPass(capped, true, 400, {}, std::chrono::steady_clock::now());
    EXPECT_FALSE(none.tried);
    EXPECT_EQ(none.reason, "--max-memory allows nothing finer");
}

TEST(TimeBudget, AVolumeIsNotCoarsenedLessThanTheMemoryLimitAllows) {
    const CostModel model = CostModel::fitted();
    for (int finest : {1, 2, 4}) {
        const BudgetChoice ample = chooseVolumeCoarsening(model, someWork(), 2, 1e6, finest);
        EXPECT_TRUE(ample.fits);
        EXPECT_EQ(ample.coarsening, finest);
        EXPECT_EQ(ample.coarsened, finest > 1);
    }
    // With no time, still the coarsest.
    EXPECT_EQ(chooseVolumeCoarsening(model, someWork(), 1, 1e-6, 2).coarsening, 4);
}

TEST(BudgetRefinement, AFinerPassBesideTheFirstPassesResultStaysWithinTheMemoryCap) {
    // Meshes: --max-memory allowed 400 alone, 250 beside the first pass's
    // result; with time for 400 the finer pass takes 250.
    BudgetChoice mesh = coarsenedMeshChoice(100, 1000.0);
    mesh.finerMemoryCapResolution = 250;
    const BudgetRefinement meshPlan =
        planFinerPass(mesh, true, 400, {}, std::chrono::steady_clock::now());
    ASSERT_TRUE(meshPlan.tried);
    EXPECT_EQ(meshPlan.choice.resolution, 250);
    EXPECT_TRUE(meshPlan.choice.coarsened);
    mesh.finerMemoryCapResolution = 100;  // nothing beside it
    const BudgetRefinement meshNone =
        planFinerPass(mesh, true, 400, {}, std::chrono::steady_clock::now());
    EXPECT_FALSE(meshNone.tried);
    EXPECT_EQ(meshNone.reason, "--max-memory allows nothing finer");
    // Volumes: the first pass 4x coarser, time for the volume's own grid.
    BudgetChoice volume;
    volume.budgetSeconds = 1000.0;
    volume.coarsening = 4;
    volume.coarsened = true;
    FirstPassTimes times;
    times.seconds = 0.5;
    times.stages = {{0.5, 3.0}};
    ASSERT_EQ(planBudgetRefinement(volume, 0, times, 900.0).choice.coarsening, 1);
    volume.finerMemoryCapCoarsening = 2;
    const BudgetRefinement volumePlan = planBudgetRefinement(volume, 0, times, 900.0);
    ASSERT_TRUE(volumePlan.tried);
    EXPECT_EQ(volumePlan.choice.coarsening, 2);
    EXPECT_TRUE(volumePlan.choice.coarsened);
    for (int cap : {4, 8}) {
        volume.finerMemoryCapCoarsening = cap;
        const BudgetRefinement volumeNone = planBudgetRefinement(volume, 0, times, 900.0);
        EXPECT_FALSE(volumeNone.tried);
        EXPECT_EQ(volumeNone.reason, "--max-memory allows nothing finer");
    }
}

TEST(BudgetRefinement, AVolumeGoesToTheSmallestCoarseningThatFits) {
    BudgetChoice first;
    first.budgetSeconds = 20.0;
    first.coarsening = 4;
    first.coarsened = true;
    FirstPassTimes times;
    times.seconds = 0.5;
    times.stages = {{0.5, 3.0}};
    // Twice finer: 4 s; four times: 32 s.
    BudgetRefinement plan = planBudgetRefinement(first, 0, times, 10.0);
    ASSERT_TRUE(plan.tried);
    EXPECT_EQ(plan.choice.coarsening, 2);
    EXPECT_TRUE(plan.choice.coarsened);
    plan = planBudgetRefinement(first, 0, times, 50.0);
    ASSERT_TRUE(plan.tried);
    EXPECT_EQ(plan.choice.coarsening, 1);
    EXPECT_FALSE(plan.choice.coarsened);
    EXPECT_FALSE(planBudgetRefinement(first, 0, times, 4.0).tried);
}

TEST(BudgetRefinement, TheFirstPassesStagesKeepReadingApartAndLeaveOutTheProbe) {
    const auto stage = [](const char* name, double seconds) {
        StageTiming t;
        t.name = name;
        t.wallSeconds = seconds;
        return t;
    };
    const FirstPassTimes times = firstPassTimes(
        {stage("read mesh", 0.1), stage("time budget probe", 0.3), stage("voxelise", 0.4),
         stage("face labels", 0.05), stage("segment surfaces and preview", 0.2),
         stage("write segments.glb, viewer.html", 0.1)},
        true, 0.9);
    EXPECT_EQ(times.seconds, 0.9);
    EXPECT_EQ(times.readSeconds, 0.1);
    const std::vector<std::pair<double, double>> expected = {{0.4, 2.0}, {0.05, 0.0}, {0.2, 0.0}};
    EXPECT_EQ(times.stages, expected);
}

TEST(BudgetRefinement, TheWholePlanTimesTheFirstPassOnTheBudgetsClock) {
    // A budget of 100 s that started a second ago, its probe ended at 0.2 s:
    // the first pass took about 0.8 s, and a finer pass stops at the
    // budget less the reserve.
    BudgetChoice first = coarsenedMeshChoice(100, 100.0);
    first.secondsLeft = 99.8;
    const auto start = std::chrono::steady_clock::now() - std::chrono::seconds(1);
    const BudgetRefinement plan = planFinerPass(first, true, 400, {}, start);
    ASSERT_TRUE(plan.tried) << plan.reason;
    EXPECT_NEAR(plan.firstPassSeconds, 0.8, 0.5);
    EXPECT_GE(plan.firstPassSeconds, 0.8);
    EXPECT_EQ(plan.choice.resolution, 400);
    EXPECT_DOUBLE_EQ(refinementReserve(100.0),
                     kRefinementReserve * 100.0 + kRefinementReserveSeconds);
    EXPECT_DOUBLE_EQ(plan.deadlineSeconds, 100.0 - refinementReserve(100.0));
}

TEST(BudgetRefinement, StagesGrowAsMeasured) {
    EXPECT_EQ(stageGrowthExponent("face labels", true), 0.0);
    EXPECT_EQ(stageGrowthExponent("segment surfaces and preview", true), 0.0);
    EXPECT_EQ(stageGrowthExponent("segment surfaces and preview", false), 3.0);
    EXPECT_EQ(stageGrowthExponent("voxelise with thin parts filled", true), 2.0);
    EXPECT_EQ(stageGrowthExponent("path sets, rims, areas, sigma", true), 2.5);
    EXPECT_EQ(stageGrowthExponent("feature transform", true), 3.0);
    EXPECT_EQ(stageGrowthExponent("a stage added later", true), 3.0);
    EXPECT_LT(stageGrowthExponent("time budget probe", true), 0.0);
}

TEST(TimeBudget, CoarsenedMaskKeepsEveryObjectVoxelAndRefinesBack) {
    const MaskVolume fine = rasterise(makeShape("y-arms"), {48, 2});
    const MaskVolume coarse = coarsenMask(fine, 2);
    const Dims d = fine.dims(), cd = coarse.dims();
    EXPECT_EQ(cd.x, (d.x + 1) / 2);
    EXPECT_DOUBLE_EQ(coarse.geometry.voxelSize(), 2 * fine.geometry.voxelSize());
    LabelVolume coarseLabels(cd, 0);
    for (int z = 0; z < cd.z; ++z)
        for (int y = 0; y < cd.y; ++y)
            for (int x = 0; x < cd.x; ++x)
                if (coarse(x, y, z)) coarseLabels(x, y, z) = std::uint16_t(1 + (x + y + z) % 3);
    const LabelVolume labels = refineLabels(coarseLabels, fine, 2);
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) {
                if (fine(x, y, z)) {
                    ASSERT_TRUE(coarse(x / 2, y / 2, z / 2));
                    EXPECT_EQ(labels(x, y, z), coarseLabels(x / 2, y / 2, z / 2));
                } else {
                    EXPECT_EQ(labels(x, y, z), 0);
                }
            }
}

TEST(TimeBudget, CoarsenAndRefineSerialEqualsParallel) {
    const MaskVolume fine = rasterise(makeShape("figure"), {72, 2});
    for (int factor : {2, 4}) {
        const MaskVolume parallel = coarsenMask(fine, factor, true);
        const MaskVolume serial = coarsenMask(fine, factor, false);
        EXPECT_EQ(parallel.values(), serial.values()) << factor;
        LabelVolume coarseLabels(parallel.dims(), 0);
        for (std::size_t i = 0; i < parallel.values().size(); ++i)
            if (parallel.values()[i]) coarseLabels.values()[i] = std::uint16_t(1 + i % 5);
        EXPECT_EQ(refineLabels(coarseLabels, fine, factor, true).values(),
                  refineLabels(coarseLabels, fine, factor, false).values())
            << factor;
    }
}

TEST(TimeBudget, ARefinedResultDescribesTheInputGrid) {
    const MaskVolume fine = rasterise(makeShape("y-arms"), {64, 2});
    const int factor = 2;
    SegmentationResult result = segmentVolume(coarsenMask(fine, factor), {});
    ASSERT_GT(result.segments.size(), 1u);
    // The skeleton's voxels, then the cuts' (report.json "cuts" places them).
    const auto voxelsOf = [](const SegmentationResult& r) {
        std::vector<std::array<int, 3>> skeleton, cuts;
        for (const auto& o : r.objects) {
            for (const auto& v : o.skeleton) skeleton.push_back(v.voxel);
            for (const auto& c : o.cuts) cuts.push_back(c.voxel);
        }
        return std::make_pair(skeleton, cuts);
    };
    const auto [coarseSkeleton, coarseCuts] = voxelsOf(result);
    ASSERT_FALSE(coarseSkeleton.empty());
    ASSERT_FALSE(coarseCuts.empty());
    refineSegmentationResult(result, fine, factor);
    const auto [fineSkeleton, fineCuts] = voxelsOf(result);
    ASSERT_EQ(fineSkeleton.size(), coarseSkeleton.size());
    ASSERT_EQ(fineCuts.size(), coarseCuts.size());
    for (std::size_t k = 0; k < coarseSkeleton.size(); ++k)
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(fineSkeleton[k][c], coarseSkeleton[k][c] * factor + factor / 2);
    for (std::size_t k = 0; k < coarseCuts.size(); ++k)
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(fineCuts[k][c], coarseCuts[k][c] * factor + factor / 2);
    EXPECT_EQ(result.labels.dims(), fine.dims());
    std::vector<std::uint64_t> counted(result.segments.size(), 0);
    std::uint64_t objectVoxels = 0;
    for (std::size_t i = 0; i < fine.values().size(); ++i) {
        const std::uint16_t l = result.labels.values()[i];
        EXPECT_EQ(l != 0, fine.values()[i] != 0);
        objectVoxels += fine.values()[i] != 0;
        if (l) ++counted[l - 1u];
    }
    std::uint64_t summed = 0;
    for (std::size_t s = 0; s < result.segments.size(); ++s) {
        EXPECT_EQ(result.segments[s].voxelCount, counted[s]) << "segment " << s;
        summed += result.segments[s].voxelCount;
    }
    EXPECT_EQ(summed, objectVoxels);
}

TEST(TimeBudget, CountWorkSeesTheShape) {
    const MaskVolume mask = rasterise(makeShape("figure"), {48, 2});
    const WorkCounts w = countWork(mask, false);
    EXPECT_EQ(w.gridVoxels, double(mask.dims().voxelCount()));
    EXPECT_GT(w.objectVoxels, w.boundaryVoxels);
    EXPECT_GT(w.boundaryVoxels, 0.0);
    EXPECT_GT(w.candidates, 0.0);
    EXPECT_LT(w.candidates, w.objectVoxels);
    const WorkCounts parallel = countWork(mask, true);
    EXPECT_EQ(parallel.candidates, w.candidates);
    EXPECT_EQ(parallel.boundaryVoxels, w.boundaryVoxels);
}

TEST(TimeBudget, TheChoiceInWordsNamesWhatWasChosen) {
    BudgetChoice choice;
    choice.predictedSeconds = 0.4;
    choice.budgetSeconds = 2.0;
    choice.coarsening = 1;
    choice.resolution = 0;  // a volume kept at its own grid
    EXPECT_EQ(describeBudgetChoice(choice),
              "volume at its own grid (0.4 s predicted, budget 2.0 s)");
    choice.coarsening = 2;
    EXPECT_EQ(describeBudgetChoice(choice), "volume 2x coarser (0.4 s predicted, budget 2.0 s)");
    choice.coarsening = 1;
    choice.resolution = 192;  // a mesh voxelised at 192
    EXPECT_EQ(describeBudgetChoice(choice), "resolution 192 (0.4 s predicted, budget 2.0 s)");
}

}  // namespace
}  // namespace skelseg
