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
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>

#include "engine/BatchCommand.h"
#include "engine/ProgressReporter.h"
#include "engine/ScoreCommand.h"
#include "engine/SegmentCommand.h"
#include "engine/SegmentOptions.h"
#include "engine/SequenceCommand.h"
#include "engine/Version.h"
#include "io/files/TextFile.h"
#include "io/shapes/SyntheticShapes.h"
#include "io/volume/BinvoxIO.h"
#include "io/volume/NrrdIO.h"
#include "kernels/base/Error.h"

namespace {

int runCommandLine(int argc, char** argv) {
    CLI::App app{"skelseg: part-type segmentation of 3D shapes with the junction rule"};
    // A callback: the build id reads the executable, which only --version needs here.
    app.set_version_flag("--version", [] {
        const std::string& build = skelseg::engineBuildId();
        return std::string("skelseg ") + skelseg::versionString() +
               (build.empty() ? std::string() : " (build " + build + ")");
    });
    app.require_subcommand(1);
    // An empty path named no file in its message (": no such file") and, as
    // an output, was an internal error (": cannot create directory: Invalid
    // argument", exit 1): it is bad usage.
    const CLI::Validator nonEmptyPath(
        [](std::string& text) -> std::string { return text.empty() ? "the path is empty" : ""; },
        "");
    const auto addRequiredPath = [&nonEmptyPath](CLI::App* command, const std::string& name,
                                                 auto& target, const std::string& help) {
        return command->add_option(name, target, help)->required()->check(nonEmptyPath);
    };

    // segment
    skelseg::SegmentOptionTexts segmentCli;
    auto* segment = app.add_subcommand(
        "segment", "Segment a volume (.nrrd .binvox .vdb) or a mesh (.off .obj .stl .ply)");
    addRequiredPath(segment, "input", segmentCli.options.input, "Input file");
    addRequiredPath(segment, "-o,--output", segmentCli.options.outdir, "Output directory");
    skelseg::addSegmentOptions(segment, segmentCli);

    // batch
    skelseg::SegmentOptionTexts batchCli;
    std::string manifestText, outrootText, shardText, mergeText;
    int shards = 0, shapesInFlight = 0;
    auto* batch = app.add_subcommand(
        "batch", "Segment every input of a manifest (or a folder) into OUTROOT/<name>/, resumably");
    batch
        ->add_option("manifest", manifestText,
                     "Text file with one input path per line (# comments; relative to the "
                     "manifest), a .csv whose header names a path column (path, input or "
                     "file), or a folder of inputs")
        ->check(nonEmptyPath);
    batch->add_option("-o,--output", outrootText, "Output root: one folder per input")
        ->check(nonEmptyPath);
    // An empty --shard ran the whole manifest, every input in every task.
    batch
        ->add_option("--shard", shardText,
                     "Process share I of N (0 <= I < N), e.g. 0/4; default: from "
                     "SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX, else all")
        ->check(skelseg::nonEmptyValue("I/N, e.g. 0/4"));
    batch
        ->add_option("--shards", shards,
                     "Number of shares when the index comes from JOB_COMPLETION_INDEX "
                     "(Kubernetes Indexed Job)")
        ->transform(skelseg::integerText())
        ->check(CLI::Range(1, 1000000));
    batch
        ->add_option("--shapes-in-flight", shapesInFlight,
                     "Most shapes in flight at once (default: threads + 1; --max-memory bounds "
                     "them too)")
        ->transform(skelseg::integerText())
        ->check(CLI::Range(1, 1024));
    batch
        ->add_option("--merge", mergeText,
                     "Combine the shard summaries in this output root into summary.json/csv and "
                     "report missing inputs")
        ->check(nonEmptyPath);
    skelseg::addSegmentOptions(batch, batchCli);

    // sequence
    skelseg::SegmentOptionTexts sequenceCli;
    std::vector<std::string> sequenceFrames;
    std::string sequenceOut;
    auto* sequence = app.add_subcommand(
        "sequence",
        "Segment the frames of a pose sequence (meshes sharing their faces) and give them one "
        "segmentation");
    addRequiredPath(sequence, "frames", sequenceFrames, "Frame meshes, in order");
    addRequiredPath(sequence, "-o,--output", sequenceOut, "Output directory");
    skelseg::addSegmentOptions(sequence, sequenceCli);

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
    addRequiredPath(generate, "-o,--output", generateOut, "Output file (.nrrd or .binvox)");
    generate->add_option("--size", size, "Voxels along the longest side")
        ->capture_default_str()
        ->transform(skelseg::integerText())
        ->check(CLI::Range(16, 2048));
    generate
        ->add_option("--pose", pose,
                     "figure: pose 0, 1 or 2; capsule-chain, bent-capsule-chain, bent-tube: "
                     "orientation 0, 1 or 2")
        ->capture_default_str()
        ->transform(skelseg::integerText())
        ->check(CLI::Range(0, 2));
    generate->add_option("--noise", noise, "Fraction of boundary voxels to flip")
        ->check(skelseg::numberText())
        ->check(CLI::Range(0.0, 0.5));
    // -1 and values past 2^64 became 18446744073709551615 without a word.
    generate->add_option("--seed", seed, "Noise seed (0 to 18446744073709551615)")
        ->capture_default_str()
        ->check(CLI::Validator(
            [](std::string& text) -> std::string {
                const bool digits = !text.empty() && text.size() <= 20 &&
                                    text.find_first_not_of("0123456789") == std::string::npos;
                if (digits && (text.size() < 20 || text <= "18446744073709551615")) return "";
                return "'" + text + "' is not a whole number from 0 to 18446744073709551615";
            },
            ""));

    // score
    std::string scoreMesh, candidate;
    std::vector<std::string> humans;
    bool scoreJson = false;
    auto* score = app.add_subcommand(
        "score", "Rand Index error and Hamming distance of a face segmentation against human ones");
    addRequiredPath(score, "mesh", scoreMesh, "The mesh the segmentations label");
    addRequiredPath(score, "candidate", candidate, "Candidate .seg (or .seg.gz)");
    addRequiredPath(score, "humans", humans, "Human .seg or .seg.gz files");
    score->add_flag("--json", scoreJson, "JSON output");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
        // One line, like every other error (CLI11's default adds a second).
        std::cerr << "skelseg: error: " << skelseg::oneLineMessage(e.what())
                  << " (run skelseg --help)\n";
        return 2;
    }

    try {
        if (*segment) {
            segmentCli.finish();
            segmentCli.options.budgetFromProcessStart = true;
            segmentCli.options.givenOptions = skelseg::givenOptionNames(*segment);
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
                // The merge segments nothing: a --shard or --force given with
                // it was ignored without a word.
                for (const CLI::Option* option : batch->get_options())
                    if (option->count() > 0 && option->get_name() != "--merge" &&
                        option->get_name() != "--quiet")
                        throw skelseg::UsageError("batch --merge OUTROOT takes no other option (" +
                                                  option->get_name() + " given)");
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
            options.segment.budgetFromProcessStart = true;  // the first input's
            options.shapesInFlight = shapesInFlight;
            options.display = batchCli.quiet ? skelseg::BatchProgress::Display::Quiet
                                             : skelseg::BatchProgress::Display::Auto;
            if (!shardText.empty()) {
                options.shard = skelseg::ShardSpec::parse(shardText);
                // --shard won without a word, and the shares of such a job's
                // pods overlapped or left inputs out.
                if (shards > 0 && shards != options.shard.count)
                    throw skelseg::UsageError("--shard " + shardText + " contradicts --shards " +
                                              std::to_string(shards) + ": give one of them");
            } else if (const auto fromScheduler = skelseg::shardFromEnvironment(
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
                          << "; summary in "
                          << skelseg::escapeControlCharacters(outcome.summaryJson.string()) << "\n";
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
        } else if (*sequence) {
            sequenceCli.finish();
            skelseg::SequenceCommandOptions options;
            options.frames.assign(sequenceFrames.begin(), sequenceFrames.end());
            options.outdir = sequenceOut;
            options.segment = sequenceCli.options;
            options.segment.budgetFromProcessStart = true;  // the first frame's
            options.segment.givenOptions = skelseg::givenOptionNames(*sequence);
            options.announceFrames = !sequenceCli.quiet;
            options.display = sequenceCli.quiet ? skelseg::ProgressReporter::Display::Quiet
                                                : skelseg::ProgressReporter::Display::Auto;
            skelseg::ProgressReporter::installSignalHandlers();
            skelseg::ProgressReporter progress(options.display);
            skelseg::runSequenceCommand(options, progress);
            if (!sequenceCli.quiet) progress.message("skelseg: wrote " + options.outdir.string());
        } else if (*generate) {
            skelseg::MaskVolume mask =
                skelseg::rasterise(skelseg::makeShape(shapeName, pose), {size, 3});
            if (noise > 0) skelseg::addBoundaryNoise(mask, noise, seed);
            // Any case, as the readers take it (G.NRRD was refused).
            const std::string ext =
                skelseg::lowercase(std::filesystem::path(generateOut).extension().string());
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

/// `code`, unless the command's result on standard output (`score`, --help,
/// --version) was not all written: a full disk or a closed stream then
/// exited 0 with the result lost.
int checkStandardOutput(int code) {
    std::cout.flush();
    const bool written = std::cout.good() && std::fflush(stdout) == 0 && !std::ferror(stdout);
    // A reader that stopped reading (`| head -1`) took what it wanted.
    if (written || code != 0 || errno == EPIPE) return code;
    std::cerr << "skelseg: error: cannot write to standard output: " << std::strerror(errno)
              << "\n";
    return 1;
}

}  // namespace

int main(int argc, char** argv) {
    // A reader that closes the pipe skelseg's messages go to (`2>&1 | head -1`)
    // killed the run with SIGPIPE, leaving its staging folder; ignored, the
    // write fails and the run goes on.
    std::signal(SIGPIPE, SIG_IGN);
    return checkStandardOutput(runCommandLine(argc, argv));
}
