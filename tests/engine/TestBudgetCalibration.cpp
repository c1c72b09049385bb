#include "engine/BudgetCalibration.h"

#include <gtest/gtest.h>

#include "engine/TimeBudget.h"
#include "tests/support/WorkCountsFixture.h"

namespace skelseg {
namespace {

WorkCounts probeWork() {
    return test::workCounts({64, 48, 40}, 30000, 6000, 7000, 50000);
}

/// The resolution chosen for `seconds` when the probe of probeWork() took
/// `probeWall` wall seconds.
BudgetChoice chooseAfterProbe(double probeWall, double seconds, int maximum = 400) {
    const ProbeCostModel probeModel = ProbeCostModel::fitted();
    const BudgetCalibration c = calibrateFromProbe(probeModel, probeWork(), probeWall, probeWall);
    return chooseMeshResolution(calibratedCostModel(CostModel::fitted(), c), probeWork(), 64,
                                maximum, 16, seconds);
}

TEST(BudgetCalibration, ASlowerProbeNeverChoosesALargerResolution) {
    const double expected = ProbeCostModel::fitted().predictSeconds(probeWork());
    for (double seconds : {1.0, 2.0, 5.0, 20.0}) {
        int previous = 1 << 30;
        bool changed = false;
        for (double slowdown : {0.25, 0.5, 1.0, 2.0, 4.0, 8.0}) {
            const BudgetChoice c = chooseAfterProbe(slowdown * expected, seconds);
            EXPECT_LE(c.resolution, previous) << seconds << " s, probe " << slowdown;
            changed |= previous != 1 << 30 && c.resolution != previous;
            previous = c.resolution;
        }
        // The probe's time is used: some slowdown changes the choice.
        if (seconds <= 5.0) EXPECT_TRUE(changed) << seconds << " s";
    }
}

TEST(BudgetCalibration, NeverChoosesMoreThanTheCpuSecondsAllow) {
    // However fast the probe, the calibrated choice is at most the one the
    // uncalibrated CPU-second model makes; a slow probe can only lower it.
    const double expected = ProbeCostModel::fitted().predictSeconds(probeWork());
    for (double seconds : {0.5, 1.0, 2.0, 5.0, 20.0}) {
        const BudgetChoice cpu =
            chooseMeshResolution(CostModel::fitted(), probeWork(), 64, 400, 16, seconds);
        for (double speed : {0.0, 0.1, 0.5, 1.0}) {
            const BudgetChoice c = chooseAfterProbe(speed * expected, seconds);
            EXPECT_LE(c.resolution, cpu.resolution) << seconds << " s, probe " << speed;
        }
    }
}

TEST(BudgetCalibration, AFastProbeNeverExceedsTheRequestedResolution) {
    for (int maximum : {100, 256, 400})
        for (double probeWall : {0.0, 1e-6, 1e-3}) {
            const BudgetChoice c = chooseAfterProbe(probeWall, 1e6, maximum);
            EXPECT_EQ(c.resolution, maximum);
            EXPECT_FALSE(c.coarsened);
        }
    EXPECT_LE(chooseAfterProbe(0.0, 5.0, 400).resolution, 400);
}

TEST(BudgetCalibration, TheFactorFollowsTheProbeWithinItsBounds) {
    const ProbeCostModel m = ProbeCostModel::fitted();
    const double expected = m.predictSeconds(probeWork());
    ASSERT_GT(expected, 0.0);
    const BudgetCalibration same = calibrateFromProbe(m, probeWork(), expected, 0.1);
    EXPECT_TRUE(same.enabled);
    EXPECT_DOUBLE_EQ(same.wallPerCpuSecond, m.runWallPerProbeWall);
    EXPECT_FALSE(same.clamped);
    EXPECT_DOUBLE_EQ(same.probePredictedCpuSeconds, expected);
    EXPECT_DOUBLE_EQ(same.probeWallSeconds, expected);
    EXPECT_DOUBLE_EQ(same.probeCpuSeconds, 0.1);
    EXPECT_DOUBLE_EQ(same.safetyMargin, m.safetyMargin);
    const BudgetCalibration slower = calibrateFromProbe(m, probeWork(), 1.5 * expected, 0.1);
    EXPECT_NEAR(slower.wallPerCpuSecond, 1.5 * m.runWallPerProbeWall, 1e-12);
    const BudgetCalibration instant = calibrateFromProbe(m, probeWork(), 0.0, 0.0);
    EXPECT_DOUBLE_EQ(instant.wallPerCpuSecond, m.minimumFactor);
    EXPECT_TRUE(instant.clamped);
    const BudgetCalibration stalled = calibrateFromProbe(m, probeWork(), 1e3, 0.1);
    EXPECT_DOUBLE_EQ(stalled.wallPerCpuSecond, m.maximumFactor);
    EXPECT_TRUE(stalled.clamped);
}

TEST(BudgetCalibration, TheCalibratedModelPredictsTheFactorTimesTheCpuSeconds) {
    const CostModel cpu = CostModel::fitted();
    BudgetCalibration c;
    EXPECT_DOUBLE_EQ(calibratedCostModel(cpu, c).predictSeconds(probeWork()),
                     cpu.predictSeconds(probeWork()));
    EXPECT_DOUBLE_EQ(calibratedCostModel(cpu, c).safetyMargin, cpu.safetyMargin);
    c.enabled = true;
    c.wallPerCpuSecond = 0.7;
    c.safetyMargin = 0.3;
    const CostModel wall = calibratedCostModel(cpu, c);
    const WorkCounts large = cpu.scale(probeWork(), 4.0);
    EXPECT_NEAR(wall.predictSeconds(large), 0.7 * cpu.predictSeconds(large),
                1e-12 * cpu.predictSeconds(large));
    EXPECT_NEAR(wall.predictPreviewSeconds(2e5), 0.7 * cpu.predictPreviewSeconds(2e5), 1e-12);
    EXPECT_DOUBLE_EQ(wall.safetyMargin, 0.3);
    EXPECT_DOUBLE_EQ(wall.candidateExponent, cpu.candidateExponent);
}

}  // namespace
}  // namespace skelseg
