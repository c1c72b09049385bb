// The options of `skelseg segment` parsed from an argument list, as the
// Python module parses its keywords (engine/SegmentOptions.h): the CLI's
// definitions, defaults and messages.
#include "engine/SegmentOptions.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "kernels/base/Error.h"

namespace skelseg {
namespace {

std::string usageMessage(const std::vector<std::string>& arguments) {
    try {
        parseSegmentOptions(arguments);
    } catch (const UsageError& error) {
        return error.what();
    }
    return "no error";
}

TEST(SegmentOptions, NoArgumentsGiveTheCommandDefaults) {
    const SegmentCommandOptions parsed = parseSegmentOptions({});
    const SegmentCommandOptions defaults;
    EXPECT_EQ(parsed.parameters.tau.toString(), "3%");
    EXPECT_EQ(parsed.parameters.sigmaMin, defaults.parameters.sigmaMin);
    EXPECT_EQ(parsed.parameters.cutRules.stubLimbs, defaults.parameters.cutRules.stubLimbs);
    EXPECT_EQ(parsed.resolution, defaults.resolution);
    EXPECT_EQ(parsed.timeBudgetSeconds, 0.0);
    EXPECT_TRUE(parsed.calibrateTimeBudget);
}

TEST(SegmentOptions, ArgumentsSetTheirOptions) {
    const SegmentCommandOptions parsed = parseSegmentOptions(
        {"--sigma-min", "0.7", "--no-stub-limbs", "--exhaustive", "--time-budget", "2.5",
         "--budget-calibration", "cpu", "--contact-patch-seams", "--max-memory", "2G"});
    EXPECT_EQ(parsed.parameters.sigmaMin, 0.7);
    EXPECT_FALSE(parsed.parameters.cutRules.stubLimbs);
    EXPECT_EQ(parsed.parameters.skeletonSearch, SkeletonSearch::Exhaustive);
    EXPECT_EQ(parsed.timeBudgetSeconds, 2.5);
    EXPECT_FALSE(parsed.calibrateTimeBudget);
    EXPECT_TRUE(parsed.contactPatchSeams);
    EXPECT_EQ(parsed.maxMemoryBytes, 2000000000u);
}

TEST(SegmentOptions, BadValuesGiveTheCommandLineMessages) {
    EXPECT_EQ(usageMessage({"--sigma-min", "2"}),
              "--sigma-min: Value 2 not in range 0.000000 to 1.000000");
    EXPECT_EQ(usageMessage({"--time-budget", "0"}),
              "--time-budget: '0' is not a positive number of seconds");
    EXPECT_EQ(usageMessage({"--exhaustive", "--skeleton-search", "band"}),
              "--exhaustive contradicts --skeleton-search band: give one of them");
    EXPECT_EQ(usageMessage({"--tau", "1%,3%", "--level-previews", "--no-preview"}),
              "--level-previews contradicts --no-preview: give one of them");
    EXPECT_EQ(usageMessage({"--max-memory", "4X"}), "--max-memory '4X': unknown unit 'X'");
    EXPECT_NE(usageMessage({"--no-such-option"}), "no error");
}

// CLI11 and std::stod read hexadecimal, octal ("0100" was 64) and binary
// forms; a value typed in one of them by mistake ran another run silently.
TEST(SegmentOptions, NumbersAreDecimal) {
    EXPECT_EQ(usageMessage({"--resolution", "0x30"}), "--resolution: '0x30' is not an integer");
    EXPECT_EQ(usageMessage({"--resolution", "0o60"}), "--resolution: '0o60' is not an integer");
    EXPECT_EQ(usageMessage({"--threads", "0b10"}), "--threads: '0b10' is not an integer");
    EXPECT_EQ(usageMessage({"--tau", "0x10"}),
              "--tau '0x10' is not a number of voxels or a percentage such as 3%");
    EXPECT_EQ(usageMessage({"--sigma-min", "0x0.8p0"}), "--sigma-min: '0x0.8p0' is not a number");
    EXPECT_EQ(usageMessage({"--time-limit", "0x10"}),
              "--time-limit: '0x10' is not a positive number of seconds");
    EXPECT_EQ(usageMessage({"--max-memory", "0x100M"}),
              "--max-memory '0x100M' is not a size such as 4G or 512M");
    // Leading zeros and a plus sign are decimal: 0100 is a hundred.
    EXPECT_EQ(parseSegmentOptions({"--resolution", "0100"}).resolution, 100);
    EXPECT_EQ(parseSegmentOptions({"--resolution", "+048"}).resolution, 48);
    EXPECT_EQ(parseSegmentOptions({"--tau", "1e1%"}).parameters.tau.toString(), "10%");
    EXPECT_EQ(parseSegmentOptions({"--body-ratio", "5e-1"}).parameters.bodyRatio, 0.5);
}

// A time past what the clocks hold is refused for that, not called negative.
TEST(SegmentOptions, TimesPastTheLongestAcceptedSaySo) {
    EXPECT_EQ(usageMessage({"--time-limit", "1e300"}),
              "--time-limit: '1e300' is more than the longest time accepted (1e9 seconds)");
    EXPECT_EQ(usageMessage({"--time-budget", "2e9"}),
              "--time-budget: '2e9' is more than the longest time accepted (1e9 seconds)");
    EXPECT_EQ(usageMessage({"--time-limit", "inf"}),
              "--time-limit: 'inf' is not a positive number of seconds");
    EXPECT_EQ(parseSegmentOptions({"--time-limit", "9.9e8"}).timeLimitSeconds, 9.9e8);
}

// Without --joints no joint cut is made, and without levels no level
// preview is written: a threshold or a flag given for them would change
// nothing, silently.
TEST(SegmentOptions, JointThresholdsAndLevelPreviewsNeedWhatTheyApplyTo) {
    EXPECT_EQ(usageMessage({"--bend-angle", "30"}),
              "--bend-angle needs --joints: without it no joint cuts are made");
    EXPECT_EQ(usageMessage({"--joint-ratio", "0.7"}),
              "--joint-ratio needs --joints: without it no joint cuts are made");
    EXPECT_EQ(usageMessage({"--joint-min-part", "0.5"}),
              "--joint-min-part needs --joints: without it no joint cuts are made");
    EXPECT_EQ(usageMessage({"--level-previews"}),
              "--level-previews needs levels: give a --tau list (1%,3%) or --joints");
    // With what they apply to, or at their defaults (as the Python module
    // passes every keyword), they are taken.
    EXPECT_EQ(usageMessage({"--joints", "--bend-angle", "30", "--joint-ratio", "0.7"}), "no error");
    EXPECT_EQ(usageMessage({"--joint-ratio", "0.82", "--joint-min-part", "0.25"}), "no error");
    EXPECT_EQ(usageMessage({"--joints", "--level-previews"}), "no error");
    EXPECT_EQ(usageMessage({"--tau", "1%,3%", "--level-previews"}), "no error");
    EXPECT_EQ(parseSegmentOptions({"--joints", "--bend-angle", "30"})
                  .parameters.jointOptions.bendAngleDegrees,
              30.0);
}

TEST(SegmentOptions, DescriptionsNameEveryOptionOnce) {
    const std::vector<SegmentOptionDescription> options = segmentOptionDescriptions();
    const auto find = [&](const std::string& name) {
        return std::find_if(options.begin(), options.end(),
                            [&](const auto& o) { return o.name == name; });
    };
    ASSERT_NE(find("--no-stub-limbs"), options.end());
    EXPECT_TRUE(find("--no-stub-limbs")->flag);
    ASSERT_NE(find("--sigma-min"), options.end());
    EXPECT_FALSE(find("--sigma-min")->flag);
    EXPECT_EQ(find("--sigma-min")->defaultText, "0.8");
    EXPECT_FALSE(find("--time-budget")->help.empty());
    EXPECT_EQ(find("--help"), options.end());
    for (const auto& o : options)
        EXPECT_EQ(std::count_if(options.begin(), options.end(),
                                [&](const auto& p) { return p.name == o.name; }),
                  1)
            << o.name;
}

// A volume segmented with --resolution was segmented on its own grid
// without a word; a mesh with --keep-voxel-aspect likewise.
TEST(SegmentOptions, OptionsOfTheOtherKindOfInputAreNamedOnce) {
    const std::vector<std::string> given = {
        "--tau",        "--resolution",        "--keep-voxel-aspect", "--contact-patch-seams",
        "--resolution", "--budget-calibration"};
    EXPECT_EQ(optionsNotApplying(given, /*isMesh=*/false),
              (std::vector<std::string>{"--resolution", "--contact-patch-seams",
                                        "--budget-calibration"}));
    EXPECT_EQ(optionsNotApplying(given, /*isMesh=*/true),
              std::vector<std::string>{"--keep-voxel-aspect"});
    EXPECT_TRUE(optionsNotApplying({"--tau", "--threads", "--grid"}, false).empty());
    EXPECT_TRUE(
        optionsNotApplying({"--self-overlap-clearance", "--no-grown-contact-seams"}, true).empty());
    EXPECT_EQ(optionsNotApplyingWarning("v.nrrd", {"--resolution"}, false),
              "v.nrrd: --resolution applies only to meshes and is ignored for this volume");
    EXPECT_EQ(optionsNotApplyingWarning("v.nrrd", {"--resolution", "--contact-patch-seams"}, false),
              "v.nrrd: --resolution and --contact-patch-seams apply only to meshes and are "
              "ignored for this volume");
    EXPECT_EQ(optionsNotApplyingWarning("v.nrrd", {"--a", "--b", "--c"}, false),
              "v.nrrd: --a, --b and --c apply only to meshes and are ignored for this volume");
    EXPECT_EQ(optionsNotApplyingWarning("m.off", {"--keep-voxel-aspect"}, true),
              "m.off: --keep-voxel-aspect applies only to volumes and is ignored for this mesh");
}

}  // namespace
}  // namespace skelseg
