// `skelseg segment --time-budget` through the command line (issue 14).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/support/FileBytes.h"
#include "tests/support/QuietCommand.h"
#include "tests/support/TempDir.h"
#include "tests/support/TestPaths.h"

namespace skelseg::test {
namespace {

nlohmann::json report(const std::filesystem::path& dir) {
    std::ifstream in(dir / "report.json");
    return nlohmann::json::parse(in);
}

TEST(SceneTimeBudget, AnAmpleBudgetChangesNothingAndIsReported) {
    TempDir dir;
    const std::string exe = skelsegBinary();
    const auto input = dir / "figure.nrrd";
    ASSERT_EQ(runQuietly(exe + " generate figure -o " + input.string() + " --size 96"), 0);
    ASSERT_EQ(runQuietly(exe + " segment " + input.string() + " -o " + (dir / "plain").string() +
                         " -q --no-preview"),
              0);
    ASSERT_EQ(runQuietly(exe + " segment " + input.string() + " -o " + (dir / "budget").string() +
                         " -q --no-preview --time-budget 1000"),
              0);
    EXPECT_EQ(fileBytes(dir / "plain" / "labels.nrrd"), fileBytes(dir / "budget" / "labels.nrrd"));
    const nlohmann::json r = report(dir / "budget");
    ASSERT_TRUE(r.contains("time_budget"));
    EXPECT_EQ(r["time_budget"]["coarsening"], 1);
    EXPECT_EQ(r["time_budget"]["coarsened"], false);
    EXPECT_EQ(r["time_budget"]["fits"], true);
    EXPECT_GT(r["time_budget"]["predicted_seconds"].get<double>(), 0.0);
    EXPECT_GT(r["time_budget"]["actual_seconds"].get<double>(), 0.0);
    EXPECT_FALSE(report(dir / "plain").contains("time_budget"));
}

TEST(SceneTimeBudget, ATightBudgetCoarsensAVolumeAndKeepsItsGrid) {
    TempDir dir;
    const std::string exe = skelsegBinary();
    const auto input = dir / "figure.nrrd";
    ASSERT_EQ(runQuietly(exe + " generate figure -o " + input.string() + " --size 160"), 0);
    ASSERT_EQ(runQuietly(exe + " segment " + input.string() + " -o " + (dir / "full").string() +
                         " -q --no-preview"),
              0);
    const nlohmann::json full = report(dir / "full");
    // A budget of a fifth of the full run's time cannot hold the full grid.
    const double seconds = std::max(0.3, full["timing"]["wall_seconds"].get<double>() / 5.0);
    const int code =
        runQuietly(exe + " segment " + input.string() + " -o " + (dir / "budget").string() +
                   " -q --time-budget " + std::to_string(seconds));
    if (code == 3) {
        // Nothing fitted: stopped as --time-limit does, without output.
        EXPECT_FALSE(std::filesystem::exists(dir / "budget"));
        return;
    }
    ASSERT_EQ(code, 0);
    const nlohmann::json r = report(dir / "budget");
    const nlohmann::json& refinement = r["time_budget"]["refinement"];
    const int first = refinement["first_coarsening"].get<int>();
    EXPECT_GT(first, 1);
    if (refinement["tried"].get<bool>() && refinement["kept"].get<bool>()) {
        // The first pass left time for a finer pass, which finished.
        EXPECT_LT(r["time_budget"]["coarsening"].get<int>(), first);
        EXPECT_EQ(r["time_budget"]["coarsening"], refinement["coarsening"]);
    } else {
        EXPECT_EQ(r["time_budget"]["coarsening"].get<int>(), first);
        EXPECT_EQ(r["time_budget"]["coarsened"], true);
    }
    EXPECT_EQ(r["grid"]["size"], full["grid"]["size"]);  // labels on the input grid
    EXPECT_GE(r["segment_count"].get<int>(), 1);
    // The preview is written unless the budget left no time for it, which
    // the report then says.
    const bool skipped = !r["time_budget"]["skipped"].empty();
    EXPECT_EQ(std::filesystem::exists(dir / "budget" / "preview.png"), !skipped);
    if (skipped) EXPECT_EQ(r["time_budget"]["skipped"][0], "preview.png");
}

/// Runs a shared mesh with a budget of `fraction` of its unbudgeted wall time:
/// it finishes with a choice predicted within the budget, or, when nothing
/// fits, stops with exit code 3 and no output.
void expectFittingChoiceOrStopped(const std::string& mesh, int resolution, double fraction) {
    TempDir dir;
    const std::string exe = skelsegBinary();
    const auto input = sharedDataDir() / "shapes" / mesh;
    const std::string common =
        exe + " segment " + input.string() + " -q --resolution " + std::to_string(resolution);
    ASSERT_EQ(runQuietly(common + " -o " + (dir / "full").string()), 0);
    const double full = report(dir / "full")["timing"]["wall_seconds"].get<double>();
    const double budget = fraction * full;
    const int code = runQuietly(common + " -o " + (dir / "budget").string() + " --time-budget " +
                                std::to_string(budget));
    if (code == 3) {
        // Nothing fitted: stopped as --time-limit does, nothing written.
        EXPECT_FALSE(std::filesystem::exists(dir / "budget"));
        return;
    }
    ASSERT_EQ(code, 0);
    const nlohmann::json r = report(dir / "budget");
    const nlohmann::json& b = r["time_budget"];
    EXPECT_TRUE(std::filesystem::exists(dir / "budget" / "segmentation.seg"));
    if (!b["fits"].get<bool>()) {
        // Nothing was predicted to fit, and the coarsest choice, run with the
        // budget as its time limit, ended within it (the prediction is
        // pessimistic): a whole output at the coarsest resolution the budget
        // considers (16, engine/TimeBudget.cpp). The verdict is against the
        // time left after the probe and the preview, which the report does
        // not give apart, so the prediction is not compared here.
        EXPECT_EQ(b["resolution"].get<int>(), 16);
        return;
    }
    // A choice that fits: its prediction with the safety margin is within the
    // budget (the engine's own figures, no clock of this test). Wall time
    // against the budget is a benchmark figure (bench/time_budget.py), not
    // asserted here.
    EXPECT_LE(b["predicted_seconds"].get<double>() * (1.0 + b["safety_margin"].get<double>()),
              b["budget_seconds"].get<double>());
    EXPECT_GT(b["actual_seconds"].get<double>(), 0.0);
    EXPECT_LE(b["resolution"].get<int>(), resolution);
    const bool skipped = !b["skipped"].empty();
    EXPECT_EQ(std::filesystem::exists(dir / "budget" / "preview.png"), !skipped);
}

TEST(SceneTimeBudget, AMeshRunWithASmallBudgetGetsAFittingChoiceOrStops) {
    if (!hasSharedData()) GTEST_SKIP() << "no shared data at " << sharedDataDir();
    // A third and two thirds of the unbudgeted run: the probe, the chosen
    // resolution and the preview decision all have to fit.
    expectFittingChoiceOrStopped("camel.off", 200, 1.0 / 3.0);
    expectFittingChoiceOrStopped("camel.off", 200, 2.0 / 3.0);
}

TEST(SceneTimeBudget, ABudgetNothingFitsStopsLikeTheTimeLimit) {
    TempDir dir;
    const std::string exe = skelsegBinary();
    const auto input = dir / "figure.nrrd";
    ASSERT_EQ(runQuietly(exe + " generate figure -o " + input.string() + " --size 160"), 0);
    EXPECT_EQ(runQuietly(exe + " segment " + input.string() + " -o " + (dir / "out").string() +
                         " -q --time-budget 0.001"),
              3);
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

}  // namespace
}  // namespace skelseg::test
