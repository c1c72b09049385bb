#include "engine/SegmentOptions.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/NumberText.h"
#include "kernels/base/Error.h"

namespace skelseg {

std::uint64_t parseMemoryLimit(const std::string& text) {
    const auto notASize = [&] {
        return UsageError("--max-memory '" + text + "' is not a size such as 4G or 512M");
    };
    std::size_t used = 0;
    double value = 0;
    try {
        value = std::stod(text, &used);
    } catch (const std::exception&) {
        throw notASize();
    }
    if (!isDecimalNumberText(text.substr(0, used))) throw notASize();
    std::string unit = text.substr(used);
    double scale = 1;
    if (unit == "K" || unit == "KB")
        scale = 1e3;
    else if (unit == "M" || unit == "MB")
        scale = 1e6;
    else if (unit == "G" || unit == "GB")
        scale = 1e9;
    else if (!unit.empty())
        throw UsageError("--max-memory '" + text + "': unknown unit '" + unit + "'");
    // "nan" was told it must be positive, "inf" taken as no limit.
    if (!std::isfinite(value)) throw notASize();
    if (!(value > 0)) throw UsageError("--max-memory must be positive");
    // Sizes past 2^64 bytes mean "no limit"; converting them would be undefined.
    const double bytes = value * scale;
    if (bytes >= 18446744073709549568.0) return ~std::uint64_t(0);
    if (bytes < 1) throw UsageError("--max-memory '" + text + "' is less than one byte");
    return std::uint64_t(bytes);
}

namespace {

constexpr double kMaxSeconds = 1e9;

/// --time-limit, --time-budget: a one-line refusal that says what is wanted.
CLI::Validator positiveSeconds() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            double seconds = 0.0;
            try {
                std::size_t used = 0;
                seconds = std::stod(text, &used);
                if (used != text.size() || !isDecimalNumberText(text)) seconds = 0.0;
            } catch (const std::exception&) {
                seconds = 0.0;
            }
            // Past kMaxSeconds a deadline no longer fits the clocks' range.
            if (seconds >= kMaxSeconds && std::isfinite(seconds))
                return "'" + text + "' is more than the longest time accepted (1e9 seconds)";
            if (seconds > 0 && seconds < kMaxSeconds) return {};
            return "'" + text + "' is not a positive number of seconds";
        },
        "SECONDS");
}

}  // namespace

CLI::Validator numberText() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            double value = 0.0;
            if (!isDecimalNumberText(text) || !CLI::detail::lexical_cast(text, value))
                return "'" + text + "' is not a number";
            if (std::isnan(value)) return "Value " + text + " is not a number";
            return {};
        },
        "");
}

CLI::Validator nonEmptyValue(const std::string& wanted) {
    return CLI::Validator(
        [wanted](std::string& text) -> std::string {
            return text.empty() ? "the value is empty; give " + wanted : "";
        },
        "");
}

CLI::Validator integerText() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            // Decimal only, and without leading zeros, which CLI11 reads as
            // octal. Digits too many for 64 bits pass: the range check says
            // what is wrong.
            const std::optional<std::string> decimal = decimalIntegerText(text);
            if (!decimal) return "'" + text + "' is not an integer";
            text = *decimal;
            return {};
        },
        "");
}

void SegmentOptionTexts::finish() {
    options.grownContactSeams = !noGrownContactSeams;
    std::vector<TauSpec> taus = parseTauList(tauText);
    options.parameters.tau = taus.back();
    taus.pop_back();
    options.parameters.finerTaus = std::move(taus);
    options.parameters.mode = modeText == "junctions" ? CutMode::Junctions : CutMode::JunctionRule;
    // --exhaustive is the name for the reference search; it may
    // repeat --skeleton-search exhaustive but not contradict it.
    if (exhaustive && skeletonSearchText == "band")
        throw UsageError("--exhaustive contradicts --skeleton-search band: give one of them");
    // Both asked for: the run wrote no preview and said nothing of the
    // levels' previews the user wanted.
    if (options.writeLevelPreviews && !options.writePreview)
        throw UsageError("--level-previews contradicts --no-preview: give one of them");
    // A run without levels writes no level previews, and a joint threshold
    // changes nothing without --joints: the user who gave one expected an
    // output or a cut the run would silently not make. A threshold left at
    // its default is accepted, so the Python module may pass every keyword.
    if (options.writeLevelPreviews && options.parameters.finerTaus.empty() &&
        !options.parameters.joints)
        throw UsageError("--level-previews needs levels: give a --tau list (1%,3%) or --joints");
    if (!options.parameters.joints) {
        const JointOptions defaults;
        const JointOptions& given = options.parameters.jointOptions;
        if (given.narrowingRatio != defaults.narrowingRatio)
            throw UsageError("--joint-ratio needs --joints: without it no joint cuts are made");
        if (given.bendAngleDegrees != defaults.bendAngleDegrees)
            throw UsageError("--bend-angle needs --joints: without it no joint cuts are made");
        if (given.minSegmentTauFraction != defaults.minSegmentTauFraction)
            throw UsageError("--joint-min-part needs --joints: without it no joint cuts are made");
    }
    // A limb turns by at most 180 degrees: a larger angle meant "no bends"
    // without a word (the default, kNoBends, says so by itself).
    const double bend = options.parameters.jointOptions.bendAngleDegrees;
    if (bend > 180.0 && bend != JointOptions{}.bendAngleDegrees) {
        char text[32];
        std::snprintf(text, sizeof text, "%g", bend);
        throw UsageError(std::string("--bend-angle ") + text +
                         ": a limb turns by at most 180 degrees");
    }
    // The budget's own options change nothing without a budget.
    if (options.timeBudgetSeconds <= 0) {
        if (options.budgetPasses != SegmentCommandOptions{}.budgetPasses)
            throw UsageError("--budget-passes needs --time-budget: without it nothing is chosen");
        if (!budgetCalibrationText.empty() && budgetCalibrationText != "probe")
            throw UsageError(
                "--budget-calibration needs --time-budget: without it nothing is chosen");
    }
    if (exhaustive || skeletonSearchText == "exhaustive")
        options.parameters.skeletonSearch = SkeletonSearch::Exhaustive;
    else if (skeletonSearchText == "band")
        options.parameters.skeletonSearch = SkeletonSearch::Band;
    if (!maxMemoryText.empty()) options.maxMemoryBytes = parseMemoryLimit(maxMemoryText);
    options.calibrateTimeBudget = budgetCalibrationText == "probe";
    // A hierarchy runs the exhaustive search (skeletonSearchToRun): an
    // explicit band with a list is refused before any work.
    if (!options.parameters.finerTaus.empty() && skeletonSearchText == "band")
        throw UsageError("--skeleton-search band takes a single --tau, not a list of levels");
}

void addSegmentOptions(CLI::App* command, SegmentOptionTexts& cli) {
    SegmentCommandOptions& seg = cli.options;
    // A flag takes no value: CLI11 would read `--no-stub-limbs=3` as "on"
    // and `--joints=0` as "off" without a word.
    command->option_defaults()->disable_flag_override();
    command
        ->add_option(
            "--tau", cli.tauText,
            "Skeleton simplification: voxel area, or percent of the boundary area (e.g. 3%); "
            "a list (1%,3%,9%) gives nested levels")
        ->capture_default_str();
    // A threshold: a number in [0, most], its default shown.
    const auto addThreshold = [command](const std::string& name, double& value,
                                        const std::string& help, double most) {
        command->add_option(name, value, help)
            ->capture_default_str()
            ->check(numberText())
            ->check(CLI::Range(0.0, most));
    };
    addThreshold("--sigma-min", seg.parameters.sigmaMin, "Minimum geodesicness of a cut point",
                 1.0);
    addThreshold("--body-ratio", seg.parameters.bodyRatio,
                 "Circumference similarity above which a candidate is on the body", 1.0);
    CutOptions& rules = seg.parameters.cutRules;
    addThreshold("--sibling-tolerance", rules.siblingTolerance,
                 "A candidate whose limb is within this fraction of the thinner of two body "
                 "candidates is body too",
                 1.0);
    addThreshold("--end-body-ratio", rules.endBodyRatio,
                 "Where the body goes on through a junction, a branch that ends there is on the "
                 "body only from this circumference similarity up (0: off)",
                 1.0);
    addThreshold("--limb-taper", rules.limbTaper,
                 "A cut moves out along its limb while the loop shrinks by more than this fraction "
                 "over one loop diameter",
                 1.0);
    addThreshold("--corner-length", rules.cornerLength,
                 "A cut past which the skeleton ends within this many loop radii is a corner of a "
                 "flat end, not cut (if --corner-reach agrees)",
                 10.0);
    addThreshold("--corner-reach", rules.cornerReach,
                 "... and if the piece it cuts off stays within this many times its loop's size "
                 "from the loop's centre",
                 10.0);
    addThreshold("--junction-merge-radii", seg.parameters.junctionMergeRadii,
                 "Junctions whose regions touch are one only if their cores are within this many "
                 "part radii (0: always)",
                 10.0);
    addThreshold("--limb-sigma-margin", rules.limbSigmaMargin,
                 "A branch with no run at --sigma-min may give a limb from a run this far below it",
                 1.0);
    addThreshold("--limb-loop-variation", rules.limbLoopVariation,
                 "... when its loops vary by at most this coefficient of variation over one limb "
                 "radius",
                 1.0);
    command->add_flag("!--no-limbs-below-sigma-min", rules.relaxSigmaMinForLimbs,
                      "Take no limb from a run below --sigma-min");
    command->add_flag("!--no-passages-as-body", rules.passagesAreBody,
                      "A branch between two junctions without a run of tight levels is not body");
    command->add_flag("!--no-shared-body-reference", rules.shareBodyAcrossPassages,
                      "Junctions joined through a passage keep their own body reference");
    command->add_flag("!--no-two-sided-siblings", rules.siblingsBothWays,
                      "Pull onto the body any candidate above 1 - --sibling-tolerance of the "
                      "thinner body member, however much thicker");
    command->add_flag("!--no-body-check-below-sigma-min", rules.belowSigmaMinOnlyLimbs,
                      "Keep a candidate of the walk below --sigma-min even where it reads body");
    command->add_flag("!--no-passage-area-check", rules.passageCutsOnlySmallerCandidates,
                      "Beside two body candidates a passage may cut one carrying more surface");
    command->add_flag("!--no-body-end-check", rules.oneBranchJunctionsEndTheBody,
                      "A junction with one branch may cut that branch where it reaches another "
                      "junction");
    command->add_flag("!--no-body-radius-window", rules.windowFromBodyReference,
                      "Read the limb circumference over one radius of the junction's median "
                      "rho_S, not of the body reference");
    command->add_flag("--surface-loops", rules.surfaceLoops,
                      "Compare half the surface's loop length in the body test, not rho_S (the "
                      "longest feature-pair geodesic)");
    command->add_flag("--tight-levels-in-runs", rules.tightLevelsInRuns,
                      "Read a cut's loop lengths (limb circumference, border, taper) only on "
                      "tight levels in a run of three, not on a single tight level");
    command->add_flag("!--no-stub-limbs", rules.stubLimbs,
                      "A free branch with no tight loop is not cut even where its piece reaches "
                      "far past its best loop (a limb of about tau)");
    command->add_flag(
        "!--no-separation-check", rules.separatingCutsOnly,
        "Keep a cut whose loop separates nothing (a handle joins the limb to the rest)");
    command->add_flag("!--no-fork-junctions", seg.parameters.forkJunctions,
                      "Branchings of the skeleton are junctions only where J_tau points are");
    command->add_flag("!--keep-handle-areas", seg.parameters.artefactHandlesCarryNoArea,
                      "Meshes whose voxel model has handles the mesh lacks: loops round handles "
                      "keep their infinite area in the body test, as on other inputs");
    command->add_flag("--handles-on-genus-zero", seg.parameters.handleFlagOnGenusZero,
                      "Read rims that meet as a loop round a handle on objects of genus 0 too "
                      "(rho_C infinite) instead of as one side of the path set");
    command->add_flag("!--no-grow-regions", seg.parameters.growRegionsToSplits,
                      "A junction's region does not grow to where its branches separate");
    command->add_flag(
        "--joints", seg.parameters.joints,
        "Also cut inside parts at joints: where a branch narrows clearly (bends: --bend-angle)");
    addThreshold("--joint-ratio", seg.parameters.jointOptions.narrowingRatio,
                 "--joints: a narrowing is at most this fraction of the limb's median thickness on "
                 "both sides",
                 1.0);
    addThreshold("--bend-angle", seg.parameters.jointOptions.bendAngleDegrees,
                 "--joints: also cut at bends turning at least this many degrees (30 is a good "
                 "choice; default: no bends)",
                 360.0);
    addThreshold("--joint-min-part", seg.parameters.jointOptions.minSegmentTauFraction,
                 "--joints: smallest part, as a fraction of tau", 1.0);
    command
        ->add_option("--mode", cli.modeText,
                     "junction-rule (default) or junctions (the RT07 baseline)")
        ->check(CLI::IsMember({"junction-rule", "junctions"}));
    command->add_option("--threads", seg.threads, "Worker threads (default: all cores)")
        ->transform(integerText())
        ->check(CLI::Range(1, 1024));
    command->add_option("--resolution", seg.resolution, "Meshes: voxels along the longest side")
        ->capture_default_str()
        ->transform(integerText())
        ->check(CLI::Range(8, 2048));
    command
        ->add_option(
            "--self-overlap-clearance", seg.selfOverlapClearance,
            "Meshes: where the mesh passes through itself and the 2-voxel clearing "
            "would add a handle, retry wider, up to this many voxels where that removes a handle "
            "(2: no retry)")
        ->capture_default_str()
        ->transform(integerText())
        ->check(CLI::Range(2, 4));
    command->add_flag("--contact-patch-seams", seg.contactPatchSeams,
                      "Meshes: where a contact's seam is refused, try a seam between the two "
                      "mesh patches of the contact, kept where it removes a handle of the voxel "
                      "model");
    command->add_flag("--no-grown-contact-seams", cli.noGrownContactSeams,
                      "Meshes: do not retry a refused contact seam grown by one voxel "
                      "(kept where it removes a handle of the voxel model)");
    command->add_flag("--keep-voxel-aspect", seg.keepVoxelAspect,
                      "Volumes of anisotropic voxels: segment the file's own voxels as if they "
                      "were cubes (default: resampled to cubic voxels, labels written on the "
                      "file's grid)");
    command->add_option("--grid", seg.gridName,
                        "VDB input: name of the grid to read (default: the first)");
    command
        ->add_option("--time-limit", seg.timeLimitSeconds,
                     "Stop after this many seconds (exit code 3, no output)")
        ->check(positiveSeconds());
    command
        ->add_option("--skeleton-search", cli.skeletonSearchText,
                     "band (default: measures a band around the skeleton, docs/algorithm.md 3.5) "
                     "or exhaustive (every candidate: the reference)")
        ->check(CLI::IsMember({"exhaustive", "band"}));
    command->add_flag("--exhaustive", cli.exhaustive,
                      "Same as --skeleton-search exhaustive: the reference search, which measures "
                      "every candidate (slower on large grids, same answer)");
    command
        ->add_option("--time-budget", seg.timeBudgetSeconds,
                     "Choose the resolution (meshes) or coarsening (volumes) predicted to finish "
                     "within this many seconds; stops like --time-limit only when nothing fits")
        ->check(positiveSeconds());
    command
        ->add_option("--budget-calibration", cli.budgetCalibrationText,
                     "--time-budget, meshes: probe (default: the probe's own time turns the "
                     "predicted CPU seconds into this machine's wall seconds now) or cpu (CPU "
                     "seconds compared with the budget, the cautious choice before)")
        ->check(CLI::IsMember({"probe", "cpu"}));
    command
        ->add_option("--budget-passes", seg.budgetPasses,
                     "--time-budget: 2 (default) tries a finer resolution or coarsening in the "
                     "time a first pass leaves, keeping the first pass's output if the finer "
                     "pass cannot finish by the budget; 1 keeps the first choice")
        ->capture_default_str()
        ->transform(integerText())
        ->check(CLI::IsMember({1, 2}));
    command
        ->add_option("--max-memory", cli.maxMemoryText,
                     "Refuse runs estimated to need more (e.g. 4G; K, M, G or KB, MB, GB; "
                     "default 75% of RAM)")
        ->check(nonEmptyValue("a size such as 4G"));
    command->add_flag("--force", seg.force,
                      "Replace results of an earlier run in the output directory");
    command->add_flag("--quiet,-q", cli.quiet,
                      "No progress output (warnings and errors are still printed)");
    command->add_flag("!--no-preview", seg.writePreview, "Skip preview.png");
    command->add_flag("--level-previews", seg.writeLevelPreviews,
                      "Hierarchy runs (--tau list, --joints): also levels/k/preview.png per level");
}

std::string oneLineMessage(std::string message) {
    // CLI11 breaks some messages into lines; what the user typed (a file
    // name) may hold any other control character.
    std::replace(message.begin(), message.end(), '\n', ' ');
    return escapeControlCharacters(message);
}

std::vector<std::string> givenOptionNames(const CLI::App& command) {
    std::vector<std::string> names;
    for (const CLI::Option* option : command.get_options())
        if (option->count() > 0 && !option->get_lnames().empty())
            names.push_back("--" + option->get_lnames().front());
    return names;
}

std::vector<std::string> optionsNotApplying(const std::vector<std::string>& given, bool isMesh) {
    static const std::vector<std::string> meshOnly = {
        "--resolution", "--self-overlap-clearance", "--contact-patch-seams",
        "--no-grown-contact-seams", "--budget-calibration"};
    static const std::vector<std::string> volumeOnly = {"--keep-voxel-aspect"};
    const std::vector<std::string>& otherKind = isMesh ? volumeOnly : meshOnly;
    std::vector<std::string> names;
    for (const std::string& name : given)
        if (std::find(otherKind.begin(), otherKind.end(), name) != otherKind.end() &&
            std::find(names.begin(), names.end(), name) == names.end())
            names.push_back(name);
    return names;
}

std::string optionsNotApplyingWarning(const std::string& input,
                                      const std::vector<std::string>& names, bool isMesh) {
    std::string list;
    for (std::size_t i = 0; i < names.size(); ++i)
        list += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i];
    const bool one = names.size() == 1;
    return input + ": " + list + (one ? " applies" : " apply") + " only to " +
           (isMesh ? "volumes" : "meshes") + " and " + (one ? "is" : "are") + " ignored for this " +
           (isMesh ? "mesh" : "volume");
}

std::vector<SegmentOptionDescription> segmentOptionDescriptions() {
    CLI::App app;
    SegmentOptionTexts texts;
    addSegmentOptions(&app, texts);
    std::vector<SegmentOptionDescription> descriptions;
    for (const CLI::Option* option : app.get_options()) {
        if (option->get_lnames().empty() || option->get_lnames().front() == "help") continue;
        SegmentOptionDescription d;
        d.name = "--" + option->get_lnames().front();
        d.flag = option->get_expected_max() == 0;
        d.defaultText = option->get_default_str();
        d.help = option->get_description();
        descriptions.push_back(std::move(d));
    }
    return descriptions;
}

SegmentCommandOptions parseSegmentOptions(const std::vector<std::string>& arguments) {
    CLI::App app;
    SegmentOptionTexts texts;
    addSegmentOptions(&app, texts);
    // CLI11 takes a vector of arguments last first.
    std::vector<std::string> reversed(arguments.rbegin(), arguments.rend());
    try {
        app.parse(reversed);
    } catch (const CLI::ParseError& error) {
        throw UsageError(oneLineMessage(error.what()));
    }
    texts.finish();
    return texts.options;
}

}  // namespace skelseg
