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
    EXPECT_GT(r["time_budget"]["coarsening"].get<int>(), 1);
    EXPECT_EQ(r["time_budget"]["coarsened"], true);
    EXPECT_EQ(r["grid"]["size"], full["grid"]["size"]);  // labels on the input grid
    EXPECT_GE(r["segment_count"].get<int>(), 1);
    EXPECT_TRUE(std::filesystem::exists(dir / "budget" / "preview.png"));
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
