// skelseg command-line entry point.
//
//   skelseg segment INPUT -o OUTDIR [options]   segment a volume or a mesh
//   skelseg generate SHAPE -o FILE [options]    write a synthetic test shape
//   skelseg score MESH CANDIDATE.seg HUMAN.seg...  compare face segmentations
//   skelseg batch MANIFEST -o OUTROOT [segment options]  segment many inputs
//   skelseg batch --merge OUTROOT               combine the shard summaries
//
// Exit codes: 0 ok, 1 internal error, 2 bad input or usage, 3 time limit or
// interrupted, 4 over the memory limit, 5 batch: some inputs failed or are
// missing. Errors are one line on stderr.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <string>

#include "engine/BatchCommand.h"
#include "engine/ProgressReporter.h"
#include "engine/ScoreCommand.h"
#include "engine/SegmentCommand.h"
#include "engine/Version.h"
#include "io/shapes/SyntheticShapes.h"
#include "io/volume/BinvoxIO.h"
#include "io/volume/NrrdIO.h"
#include "kernels/base/Error.h"

namespace {

std::uint64_t parseBytes(const std::string& text) {
    std::size_t used = 0;
    double value = 0;
    try {
        value = std::stod(text, &used);
    } catch (const std::exception&) {
        throw skelseg::UsageError("--max-memory '" + text + "' is not a size such as 4G or 512M");
    }
    std::string unit = text.substr(used);
    double scale = 1;
    if (unit == "K" || unit == "KB")
        scale = 1e3;
    else if (unit == "M" || unit == "MB")
        scale = 1e6;
    else if (unit == "G" || unit == "GB")
        scale = 1e9;
    else if (!unit.empty())
        throw skelseg::UsageError("--max-memory '" + text + "': unknown unit '" + unit + "'");
    if (!(value > 0)) throw skelseg::UsageError("--max-memory must be positive");
    return std::uint64_t(value * scale);
}

/// The `segment` options other than the input and the output; `batch`
/// takes the same ones, defined once here.
struct SegmentCli {
    skelseg::SegmentCommandOptions options;
    std::string tauText = "3%", modeText = "junction-rule", maxMemoryText, skeletonSearchText;
    std::string budgetCalibrationText = "probe";
    bool quiet = false, exhaustive = false;

    /// Turns the texts into options. Throws UsageError.
    void finish() {
        std::vector<skelseg::TauSpec> taus = skelseg::parseTauList(tauText);
        options.parameters.tau = taus.back();
        taus.pop_back();
        options.parameters.finerTaus = std::move(taus);
        options.parameters.mode =
            modeText == "junctions" ? skelseg::CutMode::Junctions : skelseg::CutMode::JunctionRule;
        // --exhaustive is the name for the reference search; it may
        // repeat --skeleton-search exhaustive but not contradict it.
        if (exhaustive && skeletonSearchText == "band")
            throw skelseg::UsageError(
                "--exhaustive contradicts --skeleton-search band: give one of them");
        if (exhaustive || skeletonSearchText == "exhaustive")
            options.parameters.skeletonSearch = skelseg::SkeletonSearch::Exhaustive;
        else if (skeletonSearchText == "band")
            options.parameters.skeletonSearch = skelseg::SkeletonSearch::Band;
        if (!maxMemoryText.empty()) options.maxMemoryBytes = parseBytes(maxMemoryText);
        options.calibrateTimeBudget = budgetCalibrationText == "probe";
        // A hierarchy runs the exhaustive search (skeletonSearchToRun): an
        // explicit band with a list is refused before any work.
        if (!options.parameters.finerTaus.empty() && skeletonSearchText == "band")
            throw skelseg::UsageError(
                "--skeleton-search band takes a single --tau, not a list of levels");
    }
};

/// --time-limit, --time-budget: a one-line refusal that says what is wanted.
CLI::Validator positiveSeconds() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            try {
                std::size_t used = 0;
                const double seconds = std::stod(text, &used);
                if (used == text.size() && seconds > 0 && seconds < 1e9) return {};
            } catch (const std::exception&) {
            }
            return "'" + text + "' is not a positive number of seconds";
        },
        "SECONDS");
}

void addSegmentOptions(CLI::App* command, SegmentCli& cli) {
    skelseg::SegmentCommandOptions& seg = cli.options;
    command
        ->add_option(
            "--tau", cli.tauText,
            "Skeleton simplification: voxel area, or percent of the boundary area (e.g. 3%); "
            "a list (1%,3%,9%) gives nested levels")
        ->capture_default_str();
    // A threshold: a number in [0, most], its default shown.
    const auto addThreshold = [command](const std::string& name, double& value,
                                        const std::string& help, double most) {
        command->add_option(name, value, help)->capture_default_str()->check(CLI::Range(0.0, most));
    };
    addThreshold("--sigma-min", seg.parameters.sigmaMin, "Minimum geodesicness of a cut point",
                 1.0);
    addThreshold("--body-ratio", seg.parameters.bodyRatio,
                 "Circumference similarity above which a candidate is on the body", 1.0);
    skelseg::CutOptions& rules = seg.parameters.cutRules;
    addThreshold("--sibling-tolerance", rules.siblingTolerance,
                 "A candidate whose limb is within this fraction of the thinner of two body "
                 "candidates is body too",
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
        ->check(CLI::Range(1, 1024));
    command->add_option("--resolution", seg.resolution, "Meshes: voxels along the longest side")
        ->capture_default_str()
        ->check(CLI::Range(8, 2048));
    command
        ->add_option(
            "--self-overlap-clearance", seg.selfOverlapClearance,
            "Meshes: where the mesh passes through itself and the 2-voxel clearing "
            "would add a handle, retry wider, up to this many voxels where that removes a handle "
            "(2: no retry)")
        ->capture_default_str()
        ->check(CLI::Range(2, 4));
    command->add_flag("--contact-patch-seams", seg.contactPatchSeams,
                      "Meshes: where a contact's seam is refused, try a seam between the two "
                      "mesh patches of the contact, kept where it removes a handle of the voxel "
                      "model");
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
    command->add_option("--max-memory", cli.maxMemoryText,
                        "Refuse runs estimated to need more (e.g. 4G; default 75% of RAM)");
    command->add_flag("--force", seg.force,
                      "Replace results of an earlier run in the output directory");
    command->add_flag("--quiet,-q", cli.quiet,
                      "No progress output (warnings and errors are still printed)");
    command->add_flag("!--no-preview", seg.writePreview, "Skip preview.png");
    command->add_flag("--level-previews", seg.writeLevelPreviews,
                      "Hierarchy runs (--tau list, --joints): also levels/k/preview.png per level");
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"skelseg: part-type segmentation of 3D shapes with the junction rule"};
    app.set_version_flag("--version", std::string("skelseg ") + skelseg::versionString());
    app.require_subcommand(1);

    // segment
    SegmentCli segmentCli;
    auto* segment = app.add_subcommand(
        "segment", "Segment a volume (.nrrd .binvox .vdb) or a mesh (.off .obj .stl .ply)");
    segment->add_option("input", segmentCli.options.input, "Input file")->required();
    segment->add_option("-o,--output", segmentCli.options.outdir, "Output directory")->required();
    addSegmentOptions(segment, segmentCli);

    // batch
    SegmentCli batchCli;
    std::string manifestText, outrootText, shardText, mergeText;
    int shards = 0, shapesInFlight = 0;
    auto* batch = app.add_subcommand(
        "batch", "Segment every input of a manifest (or a folder) into OUTROOT/<name>/, resumably");
    batch->add_option("manifest", manifestText,
                      "Text file with one input path per line (# comments; relative to the "
                      "manifest), or a folder of inputs");
    batch->add_option("-o,--output", outrootText, "Output root: one folder per input");
    batch->add_option("--shard", shardText,
                      "Process share I of N (0 <= I < N), e.g. 0/4; default: from "
                      "SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX, else all");
    batch
        ->add_option("--shards", shards,
                     "Number of shares when the index comes from JOB_COMPLETION_INDEX "
                     "(Kubernetes Indexed Job)")
        ->check(CLI::Range(1, 1000000));
    batch
        ->add_option("--shapes-in-flight", shapesInFlight,
                     "Most shapes in flight at once (default: threads + 1; --max-memory bounds "
                     "them too)")
        ->check(CLI::Range(1, 1024));
    batch->add_option("--merge", mergeText,
                      "Combine the shard summaries in this output root into summary.json/csv and "
                      "report missing inputs");
    addSegmentOptions(batch, batchCli);

    // generate
    std::string shapeName, generateOut;
    int size = 128, pose = 0;
    double noise = 0.0;
    std::uint64_t seed = 1;
    auto* generate =
        app.add_subcommand("generate", "Write a synthetic shape as a volume (.nrrd or .binvox)");
    std::string shapeList;
    for (const auto& n : skelseg::shapeNames()) shapeList += (shapeList.empty() ? "" : ", ") + n;
    generate->add_option("shape", shapeName, "One of: " + shapeList)->required();
    generate->add_option("-o,--output", generateOut, "Output file (.nrrd or .binvox)")->required();
    generate->add_option("--size", size, "Voxels along the longest side")
        ->capture_default_str()
        ->check(CLI::Range(16, 2048));
    generate
        ->add_option("--pose", pose,
                     "figure: pose 0, 1 or 2; capsule-chain, bent-capsule-chain, bent-tube: "
                     "orientation 0, 1 or 2")
        ->capture_default_str()
        ->check(CLI::Range(0, 2));
    generate->add_option("--noise", noise, "Fraction of boundary voxels to flip")
        ->check(CLI::Range(0.0, 0.5));
    generate->add_option("--seed", seed, "Noise seed")->capture_default_str();

    // score
    std::string scoreMesh, candidate;
    std::vector<std::string> humans;
    bool scoreJson = false;
    auto* score = app.add_subcommand(
        "score", "Rand Index error and Hamming distance of a face segmentation against human ones");
    score->add_option("mesh", scoreMesh, "The mesh the segmentations label")->required();
    score->add_option("candidate", candidate, "Candidate .seg (or .seg.gz)")->required();
    score->add_option("humans", humans, "Human .seg or .seg.gz files")->required();
    score->add_flag("--json", scoreJson, "JSON output");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
        // One line, like every other error (CLI11's default adds a second).
        std::string problem = e.what();
        std::replace(problem.begin(), problem.end(), '\n', ' ');
        std::cerr << "skelseg: error: " << problem << " (run skelseg --help)\n";
        return 2;
    }

    try {
        if (*segment) {
            segmentCli.finish();
            const skelseg::SegmentCommandOptions& seg = segmentCli.options;
            const bool quiet = segmentCli.quiet;
            skelseg::ProgressReporter::installSignalHandlers();
            skelseg::ProgressReporter progress(quiet ? skelseg::ProgressReporter::Display::Quiet
                                                     : skelseg::ProgressReporter::Display::Auto,
                                               seg.timeLimitSeconds);
            skelseg::runSegmentCommand(seg, progress);
            if (!quiet)
                progress.message("skelseg: wrote " + seg.outdir.string() + " in " +
                                 std::to_string(progress.elapsedSeconds()).substr(0, 5) + " s");
        } else if (*batch) {
            if (!mergeText.empty()) {
                if (!manifestText.empty() || !outrootText.empty())
                    throw skelseg::UsageError("batch --merge OUTROOT takes no manifest and no -o");
                return skelseg::runBatchMerge(mergeText);
            }
            if (manifestText.empty() || outrootText.empty())
                throw skelseg::UsageError(
                    "batch needs a MANIFEST and -o OUTROOT (or --merge OUTROOT)");
            batchCli.finish();
            skelseg::BatchCommandOptions options;
            options.manifest = manifestText;
            options.outroot = outrootText;
            options.segment = batchCli.options;
            options.shapesInFlight = shapesInFlight;
            options.display = batchCli.quiet ? skelseg::BatchProgress::Display::Quiet
                                             : skelseg::BatchProgress::Display::Auto;
            if (!shardText.empty())
                options.shard = skelseg::ShardSpec::parse(shardText);
            else if (const auto fromScheduler = skelseg::shardFromEnvironment(
                         [](const char* name) { return std::getenv(name); }, shards))
                options.shard = *fromScheduler;
            else if (shards > 0)
                throw skelseg::UsageError(
                    "--shards N needs JOB_COMPLETION_INDEX (or use --shard I/N)");
            skelseg::ProgressReporter::installSignalHandlers();
            const skelseg::BatchOutcome outcome = skelseg::runBatchCommand(options);
            if (!batchCli.quiet)
                std::cerr << "skelseg batch: " << outcome.inputs << " inputs: " << outcome.done
                          << " done, " << outcome.skipped << " already done, " << outcome.failed
                          << " failed" << (outcome.pending ? ", " : "")
                          << (outcome.pending ? std::to_string(outcome.pending) + " not started"
                                              : std::string())
                          << "; summary in " << outcome.summaryJson.string() << "\n";
            if (outcome.interrupted) {
                std::cerr << "skelseg: error: batch interrupted; run it again to finish\n";
                return 3;
            }
            if (outcome.failed > 0) {
                std::cerr << "skelseg: error: " << outcome.failed << " of " << outcome.inputs
                          << " inputs failed:\n";
                for (const auto& line : outcome.failedNames) std::cerr << "  " << line << "\n";
                return skelseg::kExitSomeInputsFailed;
            }
        } else if (*generate) {
            skelseg::MaskVolume mask =
                skelseg::rasterise(skelseg::makeShape(shapeName, pose), {size, 3});
            if (noise > 0) skelseg::addBoundaryNoise(mask, noise, seed);
            const std::string ext = std::filesystem::path(generateOut).extension().string();
            if (ext == ".binvox")
                skelseg::writeBinvox(generateOut, mask);
            else if (ext == ".nrrd")
                skelseg::writeNrrdMask(generateOut, mask);
            else
                throw skelseg::UsageError(generateOut + ": output must end in .nrrd or .binvox");
        } else if (*score) {
            std::vector<std::filesystem::path> humanPaths(humans.begin(), humans.end());
            return skelseg::runScoreCommand(scoreMesh, candidate, humanPaths, scoreJson, std::cout);
        }
    } catch (const skelseg::Error& e) {
        std::cerr << "skelseg: error: " << e.what() << "\n";
        return e.exitCode();
    } catch (const std::bad_alloc&) {
        std::cerr << "skelseg: error: out of memory\n";
        return 4;
    } catch (const std::exception& e) {
        std::cerr << "skelseg: internal error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
