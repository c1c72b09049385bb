// The band search (kernels/SkeletonBand.h, the default) against the
// exhaustive search (--exhaustive) through the command line: on every
// generated shape the curve skeleton, the cuts and the labels are
// byte-identical (issue 14). The shared data are compared in
// SlowBandSearch.cpp.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "io/shapes/SyntheticShapes.h"
#include "tests/support/FileBytes.h"
#include "tests/support/QuietCommand.h"
#include "tests/support/TempDir.h"
#include "tests/support/TestPaths.h"

namespace skelseg::test {
namespace {

/// Segments `input` both ways and expects identical outputs; returns the
/// band run's report.
nlohmann::json expectSameAnswer(const TempDir& dir, const std::filesystem::path& input,
                                const std::string& extra = "") {
    const std::string exe = skelsegBinary();
    const auto band = dir / (input.stem().string() + "-band");
    const auto exhaustive = dir / (input.stem().string() + "-exhaustive");
    EXPECT_EQ(runQuietly(exe + " segment " + input.string() + " -o " + band.string() +
                         " -q --no-preview " + extra),
              0);
    EXPECT_EQ(runQuietly(exe + " segment " + input.string() + " -o " + exhaustive.string() +
                         " -q --no-preview --exhaustive " + extra),
              0);
    for (const char* name : {"labels.nrrd", "skeleton.ply", "cuts.ply"}) {
        const std::string a = fileBytes(band / name);
        EXPECT_FALSE(a.empty()) << name;
        EXPECT_EQ(a, fileBytes(exhaustive / name)) << input.filename() << ": " << name;
    }
    std::ifstream in(band / "report.json");
    nlohmann::json report = nlohmann::json::parse(in);
    std::ifstream inExhaustive(exhaustive / "report.json");
    const nlohmann::json reference = nlohmann::json::parse(inExhaustive);
    EXPECT_EQ(report["parameters"]["skeleton_search"], "band");
    EXPECT_EQ(reference["parameters"]["skeleton_search"], "exhaustive");
    EXPECT_EQ(report["counts"]["skeleton_points"], reference["counts"]["skeleton_points"]);
    EXPECT_EQ(reference["work"]["candidates_measured"], reference["counts"]["candidates"]);
    EXPECT_LE(report["work"]["candidates_measured"].get<std::uint64_t>(),
              report["counts"]["candidates"].get<std::uint64_t>());
    return report;
}

TEST(SceneBandSearch, EveryGeneratedShapeGivesTheExhaustiveAnswer) {
    TempDir dir;
    const std::string exe = skelsegBinary();
    for (const std::string& shape : shapeNames()) {
        const auto input = dir / (shape + ".nrrd");
        ASSERT_EQ(runQuietly(exe + " generate " + shape + " -o " + input.string() + " --size 80"),
                  0);
        expectSameAnswer(dir, input);
    }
}

TEST(SceneBandSearch, FigurePosesAndNoiseGiveTheExhaustiveAnswer) {
    TempDir dir;
    const std::string exe = skelsegBinary();
    for (int pose = 0; pose < 3; ++pose) {
        const auto input = dir / ("figure" + std::to_string(pose) + ".nrrd");
        ASSERT_EQ(runQuietly(exe + " generate figure -o " + input.string() + " --size 112 --pose " +
                             std::to_string(pose)),
                  0);
        const nlohmann::json report = expectSameAnswer(dir, input);
        // The point of the band: it measures a part of the candidates.
        EXPECT_LT(report["work"]["candidates_measured"].get<std::uint64_t>(),
                  report["counts"]["candidates"].get<std::uint64_t>());
    }
    const auto noisy = dir / "noisy.nrrd";
    ASSERT_EQ(runQuietly(exe + " generate figure -o " + noisy.string() +
                         " --size 96 --pose 1 --noise 0.02 --seed 11"),
              0);
    expectSameAnswer(dir, noisy);
    expectSameAnswer(dir, noisy, "--tau 1% --force");  // the same output folders again
}

}  // namespace
}  // namespace skelseg::test
