// The rule options of `skelseg segment` (run as a user runs it): each flag
// sets its parameter, report.json records it, and the cut placement runs
// with it (SegmentationParameters::cutOptions). Values out of range are
// refused like any other bad option (TestRobustness.cpp, UsageErrors).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/Segmenter.h"
#include "io/mesh/MeshIO.h"
#include "io/shapes/SyntheticShapes.h"
#include "io/volume/NrrdIO.h"
#include "tests/support/CliRunner.h"
#include "tests/support/CurledTube.h"
#include "tests/support/FileBytes.h"
#include "tests/support/TempDir.h"

namespace skelseg {
namespace {

namespace fs = std::filesystem;

/// report.json's `parameters` of `skelseg segment` on a three-armed shape
/// with `flags` added.
nlohmann::json reportedParameters(const test::TempDir& dir, const std::string& name,
                                  const std::vector<std::string>& flags) {
    const fs::path input = dir / "y-arms.nrrd";
    if (!fs::exists(input)) writeNrrdMask(input, rasterise(makeShape("y-arms"), {48, 2}));
    std::vector<std::string> arguments = {"segment", input.string(), "-o", (dir / name).string(),
                                          "-q",      "--no-preview"};
    arguments.insert(arguments.end(), flags.begin(), flags.end());
    const test::CliResult run = test::runSkelseg(arguments);
    EXPECT_EQ(run.exitCode, 0) << run.describe();
    return nlohmann::json::parse(test::fileBytes(dir / name / "report.json")).at("parameters");
}

TEST(CommandLineOptions, RuleFlagsReachReportJson) {
    const test::TempDir dir;
    const nlohmann::json defaults = reportedParameters(dir, "defaults", {});
    const CutOptions cut;
    EXPECT_EQ(defaults.at("sibling_tolerance"), cut.siblingTolerance);
    EXPECT_EQ(defaults.at("end_body_ratio"), cut.endBodyRatio);
    EXPECT_EQ(defaults.at("limb_taper"), cut.limbTaper);
    EXPECT_EQ(defaults.at("corner_length"), cut.cornerLength);
    EXPECT_EQ(defaults.at("corner_reach"), cut.cornerReach);
    EXPECT_EQ(defaults.at("limb_sigma_margin"), cut.limbSigmaMargin);
    EXPECT_EQ(defaults.at("limb_loop_variation"), cut.limbLoopVariation);
    EXPECT_EQ(defaults.at("limbs_below_sigma_min"), true);
    EXPECT_EQ(defaults.at("passages_are_body"), true);
    EXPECT_EQ(defaults.at("shared_body_reference"), true);
    EXPECT_EQ(defaults.at("below_sigma_min_only_limbs"), true);
    EXPECT_EQ(defaults.at("passage_cuts_only_smaller"), true);
    EXPECT_EQ(defaults.at("one_branch_junctions_end_the_body"), true);
    EXPECT_EQ(defaults.at("separating_cuts_only"), true);
    EXPECT_EQ(defaults.at("window_from_body_reference"), true);
    EXPECT_EQ(defaults.at("stub_limbs"), true);
    EXPECT_EQ(defaults.at("fork_junctions"), true);
    EXPECT_EQ(defaults.at("grow_regions_to_splits"), true);
    EXPECT_EQ(defaults.at("handles_on_genus_zero"), false);
    EXPECT_EQ(defaults.at("junction_merge_radii"), SegmentationParameters{}.junctionMergeRadii);

    const nlohmann::json set = reportedParameters(dir, "set",
                                                  {"--sibling-tolerance",
                                                   "0.125",
                                                   "--end-body-ratio",
                                                   "0",
                                                   "--limb-taper",
                                                   "0.5",
                                                   "--corner-length",
                                                   "1.5",
                                                   "--corner-reach",
                                                   "2.5",
                                                   "--junction-merge-radii",
                                                   "0",
                                                   "--limb-sigma-margin",
                                                   "0.25",
                                                   "--limb-loop-variation",
                                                   "0.75",
                                                   "--no-limbs-below-sigma-min",
                                                   "--no-passages-as-body",
                                                   "--no-shared-body-reference",
                                                   "--no-body-check-below-sigma-min",
                                                   "--no-passage-area-check",
                                                   "--no-body-end-check",
                                                   "--no-separation-check",
                                                   "--no-body-radius-window",
                                                   "--surface-loops",
                                                   "--tight-levels-in-runs",
                                                   "--no-stub-limbs",
                                                   "--no-fork-junctions",
                                                   "--no-grow-regions",
                                                   "--handles-on-genus-zero"});
    EXPECT_EQ(set.at("sibling_tolerance"), 0.125);
    EXPECT_EQ(set.at("end_body_ratio"), 0.0);
    EXPECT_EQ(set.at("limb_taper"), 0.5);
    EXPECT_EQ(set.at("corner_length"), 1.5);
    EXPECT_EQ(set.at("corner_reach"), 2.5);
    EXPECT_EQ(set.at("limb_sigma_margin"), 0.25);
    EXPECT_EQ(set.at("limb_loop_variation"), 0.75);
    EXPECT_EQ(set.at("limbs_below_sigma_min"), false);
    EXPECT_EQ(set.at("passages_are_body"), false);
    EXPECT_EQ(set.at("shared_body_reference"), false);
    EXPECT_EQ(set.at("below_sigma_min_only_limbs"), false);
    EXPECT_EQ(set.at("passage_cuts_only_smaller"), false);
    EXPECT_EQ(set.at("one_branch_junctions_end_the_body"), false);
    EXPECT_EQ(set.at("separating_cuts_only"), false);
    EXPECT_EQ(set.at("surface_loops"), true);
    EXPECT_EQ(set.at("tight_levels_in_runs"), true);
    EXPECT_EQ(set.at("window_from_body_reference"), false);
    EXPECT_EQ(set.at("stub_limbs"), false);
    EXPECT_EQ(set.at("fork_junctions"), false);
    EXPECT_EQ(set.at("grow_regions_to_splits"), false);
    EXPECT_EQ(set.at("handles_on_genus_zero"), true);
    EXPECT_EQ(set.at("junction_merge_radii"), 0.0);
}

TEST(CommandLineOptions, CutPlacementRunsWithTheRulesAndTheSharedThresholds) {
    SegmentationParameters parameters;
    parameters.sigmaMin = 0.7;
    parameters.bodyRatio = 0.5;
    parameters.consecutiveLevels = 4;
    parameters.mode = CutMode::Junctions;
    parameters.cutRules.sigmaMin = 0.1;  // replaced by parameters.sigmaMin
    parameters.cutRules.siblingTolerance = 0.125;
    parameters.cutRules.limbTaper = 0.5;
    parameters.cutRules.cornerLength = 1.5;
    parameters.cutRules.cornerReach = 2.5;
    parameters.cutRules.passagesAreBody = false;
    parameters.cutRules.shareBodyAcrossPassages = false;
    parameters.cutRules.belowSigmaMinOnlyLimbs = false;
    parameters.cutRules.passageCutsOnlySmallerCandidates = false;
    parameters.cutRules.oneBranchJunctionsEndTheBody = false;
    parameters.cutRules.separatingCutsOnly = false;
    parameters.cutRules.windowFromBodyReference = false;
    parameters.cutRules.surfaceLoops = true;
    parameters.cutRules.relaxSigmaMinForLimbs = false;
    parameters.cutRules.limbSigmaMargin = 0.25;
    parameters.cutRules.limbLoopVariation = 0.75;
    const CutOptions options = parameters.cutOptions();
    EXPECT_EQ(options.sigmaMin, 0.7);
    EXPECT_EQ(options.bodyRatio, 0.5);
    EXPECT_EQ(options.consecutiveLevels, 4);
    EXPECT_EQ(options.mode, CutMode::Junctions);
    EXPECT_EQ(options.siblingTolerance, 0.125);
    EXPECT_EQ(options.limbTaper, 0.5);
    EXPECT_EQ(options.cornerLength, 1.5);
    EXPECT_EQ(options.cornerReach, 2.5);
    EXPECT_FALSE(options.passagesAreBody);
    EXPECT_FALSE(options.shareBodyAcrossPassages);
    EXPECT_FALSE(options.belowSigmaMinOnlyLimbs);
    EXPECT_FALSE(options.passageCutsOnlySmallerCandidates);
    EXPECT_FALSE(options.oneBranchJunctionsEndTheBody);
    EXPECT_FALSE(options.separatingCutsOnly);
    EXPECT_FALSE(options.windowFromBodyReference);
    EXPECT_TRUE(options.surfaceLoops);
    EXPECT_FALSE(options.relaxSigmaMinForLimbs);
    EXPECT_EQ(options.limbSigmaMargin, 0.25);
    EXPECT_EQ(options.limbLoopVariation, 0.75);
}

TEST(CommandLineOptions, SelfOverlapClearanceReachesTheVoxeliserAndReportJson) {
    // Tubes wound beyond a turn whose end is sunk into their beginning: at
    // some of these resolutions clearing 2 voxels around the crossing would
    // add a ring and is refused (TestSelfOverlapSeparation.cpp); 4 voxels
    // separate every one.
    const test::TempDir dir;
    int refusedAtTwo = 0;
    for (double extraAngle : {1.2, 2.0}) {
        test::CurledTube tube;
        tube.endRadius = 0.3;
        tube.extraAngle = extraAngle;
        const fs::path input = dir / ("curled-tube-" + std::to_string(extraAngle) + ".off");
        writeOff(input, tube.mesh());
        for (const std::string resolution : {"64", "96"}) {
            const auto reportedInput = [&](const std::vector<std::string>& flags) {
                std::vector<std::string> arguments = {
                    "segment", input.string(), "-o",           (dir / "out").string(),
                    "-q",      "--force",      "--no-preview", "--resolution",
                    resolution};
                arguments.insert(arguments.end(), flags.begin(), flags.end());
                const test::CliResult run = test::runSkelseg(arguments);
                EXPECT_EQ(run.exitCode, 0) << run.describe();
                return nlohmann::json::parse(test::fileBytes(dir / "out" / "report.json"));
            };
            const nlohmann::json narrowReport = reportedInput({"--self-overlap-clearance", "2"});
            const nlohmann::json narrow = narrowReport.at("input");
            EXPECT_EQ(narrow.at("self_overlap_clearance"), 2);
            // Handles the mesh lacks: loops round them carry no area in the
            // cut placement, unless --keep-handle-areas.
            const bool extraHandles =
                narrow.at("voxel_genus").get<int>() > narrow.at("mesh_genus").get<int>();
            EXPECT_EQ(narrowReport.at("parameters").at("handle_loops_carry_no_area"), extraHandles);
            if (extraHandles)
                EXPECT_EQ(reportedInput({"--self-overlap-clearance", "2", "--keep-handle-areas"})
                              .at("parameters")
                              .at("handle_loops_carry_no_area"),
                          false);
            if (narrow.at("self_overlaps_kept").get<int>() == 0) continue;
            ++refusedAtTwo;
            const nlohmann::json wider = reportedInput({}).at("input");
            EXPECT_EQ(wider.at("self_overlap_clearance"), 4);
            EXPECT_EQ(wider.at("self_overlaps_kept"), 0)
                << "extra angle " << extraAngle << ", resolution " << resolution;
            EXPECT_GE(wider.at("self_overlaps_separated").get<int>(), 1);
            EXPECT_EQ(wider.at("voxel_genus"), wider.at("mesh_genus"))
                << "extra angle " << extraAngle << ", resolution " << resolution;
        }
    }
    // Without a case the default refuses, this test tests nothing.
    EXPECT_GE(refusedAtTwo, 1);
}

TEST(CommandLineOptions, BudgetCalibrationReachesReportJson) {
    // A small mesh under an ample budget: the choice is the requested
    // resolution either way; report.json says how the prediction was made.
    const test::TempDir dir;
    const fs::path input = dir / "sphere.off";
    writeOff(input, test::sphereMesh({0.0, 0.0, 0.0}, 1.0, 12, 16));
    const auto budgetReport = [&](const std::vector<std::string>& flags) {
        std::vector<std::string> arguments = {
            "segment",      input.string(), "-o", (dir / "out").string(), "-q",  "--force",
            "--no-preview", "--resolution", "16", "--time-budget",        "1000"};
        arguments.insert(arguments.end(), flags.begin(), flags.end());
        const test::CliResult run = test::runSkelseg(arguments);
        EXPECT_EQ(run.exitCode, 0) << run.describe();
        return nlohmann::json::parse(test::fileBytes(dir / "out" / "report.json"))
            .at("time_budget");
    };
    const nlohmann::json probe = budgetReport({});
    const nlohmann::json& calibration = probe.at("calibration");
    EXPECT_EQ(calibration.at("method"), "probe");
    EXPECT_GT(calibration.at("probe_predicted_cpu_seconds").get<double>(), 0.0);
    EXPECT_GT(calibration.at("probe_grid_voxels").get<double>(), 0.0);
    const double factor = calibration.at("wall_per_cpu_second").get<double>();
    EXPECT_GT(factor, 0.0);
    EXPECT_NEAR(probe.at("predicted_seconds").get<double>(),
                factor * probe.at("predicted_cpu_seconds").get<double>(), 1e-9);
    EXPECT_LT(probe.at("seconds_left_after_probe").get<double>(), 1000.0);
    EXPECT_EQ(probe.at("resolution"), 16);
    const nlohmann::json cpu = budgetReport({"--budget-calibration", "cpu"});
    EXPECT_EQ(cpu.at("calibration").at("method"), "cpu");
    EXPECT_EQ(cpu.at("calibration").at("wall_per_cpu_second"), 1.0);
    EXPECT_EQ(cpu.at("predicted_seconds"), cpu.at("predicted_cpu_seconds"));
    EXPECT_EQ(cpu.at("safety_margin"), 0.64);
    EXPECT_EQ(test::runSkelseg({"segment", input.string(), "-o", (dir / "bad").string(), "-q",
                                "--budget-calibration", "wall"})
                  .exitCode,
              2);
}

}  // namespace
}  // namespace skelseg
