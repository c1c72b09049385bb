#include "engine/BatchCommand.h"

#include <tbb/flow_graph.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>
#include <optional>
#include <sstream>
#include <thread>

#include "engine/Version.h"
#include "engine/batch/BatchLock.h"
#include "engine/batch/BatchSummary.h"
#include "engine/batch/DoneMarker.h"
#include "engine/batch/FreedMemoryReuse.h"
#include "engine/batch/InputMemoryEstimate.h"
#include "engine/batch/MemoryBudget.h"
#include "engine/batch/OutputFolderClaim.h"
#include "engine/batch/StagingCleanup.h"
#include "io/files/DirectoryLock.h"
#include "io/files/OutputDirectory.h"
#include "io/files/ReplacedOutputs.h"
#include "io/volume/VolumeReader.h"
#include "kernels/base/Error.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace skelseg {

namespace {

/// One input on its way through the graph.
struct BatchJob {
    std::size_t slot = 0;  // index into the shard's entries
    ManifestEntry input;
    std::uint64_t estimatedBytes = 0;
};

struct FinishedJob {
    BatchJob job;
    BatchEntry entry;
    DoneMarker marker;  // valid when entry.status == "done"
    /// The output folder's lock, held until done.json is written: another
    /// run taking the folder between the commit and the marker would be
    /// marked done with outputs it did not make.
    std::shared_ptr<const DirectoryLock> folderLock;
    std::string warnings;  // what the segment command printed, lines
    bool userInterrupt = false;
};

/// The figures of a finished run, from its report.json.
void readReportFigures(const fs::path& outdir, BatchEntry& entry) {
    std::ifstream in(outdir / "report.json", std::ios::binary);
    if (!in) return;
    try {
        const json report = json::parse(in);
        entry.parts = report.value("segment_count", std::uint64_t(0));
        entry.wallSeconds = report.at("timing").value("wall_seconds", 0.0);
        entry.cpuSeconds = report.at("timing").value("cpu_seconds", 0.0);
        entry.peakMemoryBytes = report.at("memory").value("peak_resident_bytes", std::uint64_t(0));
    } catch (const std::exception&) {
        // The outputs are committed; a report we cannot parse only loses figures.
    }
}

/// Runs `segment` for one input: the body of the parallel node. Never throws.
FinishedJob segmentOne(const BatchJob& job, const BatchCommandOptions& options,
                       const std::string& optionsText, std::atomic<bool>& processStartCharged) {
    FinishedJob finished;
    finished.job = job;
    BatchEntry& entry = finished.entry;
    entry.name = job.input.name;
    entry.input = job.input.input;
    entry.line = job.input.line;
    entry.estimatedMemoryBytes = job.estimatedBytes;
    const fs::path outdir = options.outroot / job.input.name;
    const auto start = std::chrono::steady_clock::now();
    char* captured = nullptr;
    std::size_t capturedSize = 0;
    std::FILE* messages = ::open_memstream(&captured, &capturedSize);
    std::optional<OutputFolderClaim> claim;
    try {
        DoneMarker& marker = finished.marker;
        marker.skelsegVersion = versionString();
        marker.skelsegBuild = engineBuildId();
        marker.input = job.input.input;
        std::error_code ec;
        marker.absoluteInput = fs::absolute(job.input.input, ec).lexically_normal();
        marker.fingerprint = fingerprintInput(job.input.input);
        marker.options = optionsText;
        marker.run = runIdentity();
        // The pending marker goes in before the done marker goes: a run
        // killed from here on leaves the input not done, and the folder the
        // batch's to redo.
        claim = claimOutputFolder(outdir, marker, options.segment.force);
        finished.folderLock = claim->lock;
        SegmentCommandOptions segment = options.segment;
        segment.input = job.input.input;
        segment.outdir = outdir;
        segment.outdirLock = claim->lock;
        segment.force = true;  // claimed: the earlier outputs are the batch's, or --force
        // Only the first input started is charged for the process start;
        // the others would be charged for the ones before them.
        segment.budgetFromProcessStart =
            options.segment.budgetFromProcessStart && !processStartCharged.exchange(true);
        {
            ProgressReporter reporter(ProgressReporter::Display::Quiet, segment.timeLimitSeconds,
                                      messages ? messages : stderr);
            tbb::this_task_arena::isolate([&] { runSegmentCommand(segment, reporter); });
        }
        entry.status = "done";
        readReportFigures(outdir, entry);
        marker.parts = entry.parts;
        marker.wallSeconds = entry.wallSeconds;
        marker.cpuSeconds = entry.cpuSeconds;
        marker.peakMemoryBytes = entry.peakMemoryBytes;
    } catch (const InterruptedError& error) {
        entry.status = "failed";
        entry.error = error.what();
        finished.userInterrupt = error.reason() == InterruptedError::Reason::UserInterrupt;
    } catch (const Error& error) {
        entry.status = "failed";
        entry.error = error.what();
        // Still missing: the note says why the listed path named no file.
        std::error_code ec;
        if (!job.input.missingNote.empty() && !fs::exists(job.input.input, ec))
            entry.error += " (" + job.input.missingNote + ")";
    } catch (const std::bad_alloc&) {
        entry.status = "failed";
        entry.error = job.input.input.string() + ": out of memory";
    } catch (const std::exception& error) {
        entry.status = "failed";
        entry.error = job.input.input.string() + ": internal error: " + error.what();
    }
    if (entry.status == "failed") {
        if (claim) releaseOutputFolder(outdir, *claim);
        entry.wallSeconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    if (messages) {
        std::fclose(messages);
        finished.warnings.assign(captured, capturedSize);
        std::free(captured);
    }
    return finished;
}

/// Refuses a manifest in which the run of one input would replace the file
/// of another: OUTROOT/a/labels.nrrd listed beside a.off. `segment` refuses an
/// input among its own outputs; here the writer is another input, so the file
/// changed under the batch (the other input read the old or the new one,
/// depending on the order) and its done marker never matched again. An input
/// whose path lies under OUTROOT is named by the one folder it lies in; any
/// other name of an output (a hard link, OUTROOT through a bind mount) is
/// found by file identity. A shape's own outputs are left to its segment run.
/// @throw InputError naming the manifest, before anything is written.
void refuseInputsAmongOutputs(const Manifest& manifest, const fs::path& outroot) {
    std::error_code ec;
    const fs::path root = fs::weakly_canonical(outroot, ec);
    const bool rootResolved = !ec;
    std::map<std::string, const ManifestEntry*> byName;
    for (const auto& entry : manifest.entries) byName.emplace(entry.name, &entry);
    ReplacedOutputs replaced;
    for (const auto& [name, entry] : byName)
        replaced.add(outroot / name, segmentOutputNames(), name);
    const auto lineOf = [](int line) {
        return line > 0 ? "line " + std::to_string(line) + ": " : std::string();
    };
    // OUTROOT itself on a line was a missing input on the first run and a
    // folder of the batch's outputs on the next. `canonical`: weakly_canonical(path).
    const auto refuseOutroot = [&](const fs::path& path, const fs::path& canonical, int line) {
        if (rootResolved && canonical == root)
            throw InputError(manifest.source.string(),
                             lineOf(line) + path.string() +
                                 " is OUTROOT, where the batch writes; choose another OUTROOT");
    };
    for (const auto& [folder, line] : manifest.listedFolders) {
        const fs::path canonical = fs::weakly_canonical(folder, ec);
        if (!ec) refuseOutroot(folder, canonical, line);
    }
    for (const auto& entry : manifest.entries) {
        // A missing input is checked by its path alone (its outputs may not
        // exist yet: the next run would refuse what this one took for a
        // missing file); a FIFO's header is not peeked at. A regular file
        // with a bad header cannot be OUTROOT (a directory, or not yet made).
        std::vector<fs::path> files = {entry.input};
        try {
            if (entry.exists) files = volumeInputFiles(entry.input);
        } catch (const Error&) {
            continue;  // a bad header: the input fails on its own
        }
        for (const fs::path& file : files) {
            std::string output;
            auto writer = byName.end();
            const fs::path canonical = fs::weakly_canonical(file, ec);
            if (!ec) refuseOutroot(file, canonical, entry.line);
            const fs::path relative = canonical.lexically_relative(root);
            if (rootResolved && !ec && !relative.empty() && *relative.begin() != "..") {
                writer = byName.find(relative.begin()->string());
                if (writer != byName.end())
                    output = outputReplacing(file, outroot / writer->first, segmentOutputNames());
            }
            if (output.empty()) {
                const ReplacedOutputs::Entry* other = replaced.find(file);
                if (other == nullptr) continue;
                writer = byName.find(other->owner);
                output = other->output;
            }
            if (writer == byName.end() || writer->second == &entry) continue;
            const fs::path outdir = outroot / writer->first;
            throw InputError(manifest.source.string(),
                             lineOf(entry.line) + file.string() + " is " + output + " in " +
                                 outdir.string() + ", which the batch rewrites for " +
                                 writer->second->input.string() + "; choose another OUTROOT");
        }
    }
}

/// True for the name of a summary that a batch or its merge writes:
/// summary.json, summary.csv, summary.shard-I-of-N.json or .csv.
bool isSummaryFileName(const std::string& fileName) {
    const std::size_t dot = fileName.rfind('.');
    if (dot == std::string::npos) return false;
    const std::string stem = fileName.substr(0, dot), extension = fileName.substr(dot);
    if (extension != ".json" && extension != ".csv") return false;
    if (stem == "summary") return true;
    const std::string shardPrefix = "summary.shard-";
    if (stem.rfind(shardPrefix, 0) != 0) return false;
    const std::string share = stem.substr(shardPrefix.size());
    const std::size_t of = share.find("-of-");
    const auto isNumber = [](const std::string& text) {
        return !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
    };
    return of != std::string::npos && isNumber(share.substr(0, of)) &&
           isNumber(share.substr(of + 4));
}

/// Refuses a manifest that is one of the summaries the batch (or its shards,
/// or their merge) writes in OUTROOT: `batch OUT/summary.csv -o OUT` replaced
/// the user's manifest by its own summary without a word, and a rerun then
/// read the summary as a manifest. Compared as the same file (device and
/// inode: a hard link, a symlink to it) and as the same path (a summary's
/// name in OUTROOT, through whatever path reaches that folder).
/// @throw UsageError naming the manifest, before anything is read or written.
void refuseManifestAmongOutputs(const fs::path& manifest, const fs::path& outroot,
                                const std::string& stem) {
    const auto refuse = [&](const fs::path& summary) {
        throw UsageError(manifest.string() + ": the manifest is the batch's summary " +
                         summary.string() +
                         ", which the batch rewrites; copy it out of OUTROOT or choose another "
                         "OUTROOT");
    };
    std::error_code ec;
    for (const std::string& name :
         {stem + ".json", stem + ".csv", std::string("summary.json"), std::string("summary.csv")})
        if (fs::equivalent(manifest, outroot / name, ec)) refuse(outroot / name);
    const fs::path folder = manifest.has_parent_path() ? manifest.parent_path() : fs::path(".");
    const std::string name = manifest.filename().string();
    if (isSummaryFileName(name) && fs::equivalent(folder, outroot, ec)) refuse(outroot / name);
}

}  // namespace

BatchOutcome runBatchCommand(const BatchCommandOptions& options, std::FILE* stream) {
    const auto wallStart = std::chrono::steady_clock::now();
    keepFreedMemoryForReuse();  // where it fails, the batch is only slower
    refuseManifestAmongOutputs(options.manifest, options.outroot, options.shard.summaryStem());
    const Manifest manifest = readManifest(options.manifest);
    const ShardSpec shard = options.shard;
    std::vector<std::uint64_t> sizes;
    for (const auto& e : manifest.entries) sizes.push_back(e.fileBytes);
    const std::vector<int> shardOf = assignShards(sizes, shard.count);

    std::error_code ec;
    checkOutputDirectoryPath(options.outroot);
    refuseInputsAmongOutputs(manifest, options.outroot);
    // A batch that fails as a whole (an unwritable summary) leaves no OUTROOT
    // it created; one that ran keeps it, with the summary.
    struct RemoveIfFailed {
        fs::path created, lockFile;
        ~RemoveIfFailed() {
            std::error_code ignored;
            if (created.empty() || std::uncaught_exceptions() == 0) return;
            if (!lockFile.empty()) fs::remove(lockFile, ignored);
            fs::remove(created, ignored);
        }
    } removeIfFailed;
    if (!fs::exists(fs::symlink_status(options.outroot, ec)))
        removeIfFailed.created = options.outroot;
    fs::create_directories(options.outroot, ec);
    if (ec || !fs::is_directory(options.outroot))
        throw OutputError(options.outroot.string() + ": cannot create the output directory" +
                          (ec ? ": " + ec.message() : std::string()));
    const std::string stem = shard.summaryStem();
    // Before anything of the batch's is touched, leftovers included.
    std::optional<BatchLock> lock;
    try {
        lock.emplace(options.outroot, stem);
    } catch (const UsageError&) {
        removeIfFailed.created.clear();  // the other batch's, if both created it
        throw;
    }
    removeIfFailed.lockFile = lock->file();
    for (const auto& item : fs::directory_iterator(options.outroot, ec)) {
        const std::string file = item.path().filename().string();
        if (file.rfind("." + stem + ".", 0) == 0 && isStagingLeftoverName(file))
            fs::remove(item.path(), ec);
    }

    const std::string optionsText = outputAffectingOptions(options.segment);
    const int threads =
        options.segment.threads > 0 ? options.segment.threads : tbb::info::default_concurrency();
    BatchSummary summary;
    summary.skelsegVersion = versionString();
    summary.skelsegBuild = engineBuildId();
    summary.manifest = options.manifest;
    summary.shard = shard;
    summary.options = optionsText;
    summary.run = runIdentity();
    summary.startedAt = utcTimestamp();
    std::vector<ManifestEntry> mine;
    for (std::size_t i = 0; i < manifest.entries.size(); ++i) {
        summary.manifestNames.push_back(manifest.entries[i].name);
        if (shardOf[i] != shard.index) continue;
        mine.push_back(manifest.entries[i]);
        BatchEntry entry;
        entry.name = manifest.entries[i].name;
        entry.input = manifest.entries[i].input;
        entry.line = manifest.entries[i].line;
        summary.entries.push_back(entry);
    }

    // Done earlier, with the same input, options and skelseg: skipped.
    std::vector<BatchJob> jobs;
    for (std::size_t slot = 0; slot < mine.size(); ++slot) {
        const fs::path outdir = options.outroot / mine[slot].name;
        if (!options.segment.force && mine[slot].exists) {
            if (const auto marker = readDoneMarker(outdir)) {
                bool matches = false;
                try {
                    matches = marker->matches(fingerprintInput(mine[slot].input), optionsText);
                } catch (const InputError&) {
                    // Unreadable now: the run reports it.
                }
                // Tidied only under the folder's lock; a folder another run
                // is writing to is that run's, and this input fails.
                std::optional<DirectoryLock> folderLock;
                if (matches) {
                    try {
                        folderLock.emplace(outdir);
                    } catch (const UsageError& error) {
                        summary.entries[slot].status = "failed";
                        summary.entries[slot].error = error.what();
                        continue;
                    }
                }
                if (matches) {
                    BatchEntry& entry = summary.entries[slot];
                    entry.status = "skipped";
                    entry.parts = marker->parts;
                    entry.wallSeconds = marker->wallSeconds;
                    entry.cpuSeconds = marker->cpuSeconds;
                    entry.peakMemoryBytes = marker->peakMemoryBytes;
                    entry.finishedAt = marker->finishedAt;
                    if (folderLock->isHeld()) {
                        removeStagingLeftovers(outdir);
                        // Left by a batch killed between the two markers.
                        std::error_code ignored;
                        fs::remove(outdir / kPendingMarkerName, ignored);
                    }
                    continue;
                }
            }
        }
        BatchJob job;
        job.slot = slot;
        job.input = mine[slot];
        job.estimatedBytes = estimateInputMemory(mine[slot].input, options.segment, threads);
        jobs.push_back(job);
    }
    // Largest first: the long ones start early, the small ones fill the gaps
    // at the end.
    std::stable_sort(jobs.begin(), jobs.end(), [](const BatchJob& a, const BatchJob& b) {
        return a.estimatedBytes > b.estimatedBytes;
    });

    BatchProgress progress(mine.size(), mine.size() - jobs.size(), options.display, stream);
    for (const auto& warning : manifest.warnings) progress.message("skelseg: warning: " + warning);
    if (shard.count > 1 && options.display != BatchProgress::Display::Quiet)
        progress.message("skelseg batch: shard " + shard.toString() + ": " +
                         std::to_string(mine.size()) + " of " +
                         std::to_string(manifest.entries.size()) + " inputs");
    summary.updatedAt = utcTimestamp();
    writeBatchSummary(options.outroot, stem, summary);

    const std::uint64_t memoryLimit =
        options.segment.maxMemoryBytes ? options.segment.maxMemoryBytes : defaultMemoryLimit();
    const std::size_t inFlight =
        options.shapesInFlight > 0 ? std::size_t(options.shapesInFlight) : std::size_t(threads) + 1;
    MemoryBudget budget(memoryLimit, inFlight);
    ProgressReporter interruptWatch(ProgressReporter::Display::Quiet);
    std::atomic<bool> interrupted{false};
    auto stopRequested = [&] { return interrupted.load() || interruptWatch.wasInterrupted(); };

    std::atomic<bool> processStartCharged{false};
    tbb::flow::graph graph;
    tbb::flow::function_node<BatchJob, FinishedJob> segmentNode(
        graph, tbb::flow::unlimited, [&](const BatchJob& job) {
            return segmentOne(job, options, optionsText, processStartCharged);
        });
    auto lastSummaryWrite = std::chrono::steady_clock::now();
    std::chrono::steady_clock::duration summaryInterval = std::chrono::seconds(1);
    std::string recordError;
    tbb::flow::function_node<FinishedJob> recordNode(
        graph, tbb::flow::serial, [&](FinishedJob finished) {
            BatchEntry& entry = finished.entry;
            if (finished.userInterrupt) interrupted = true;
            if (entry.status == "done") {
                finished.marker.finishedAt = utcTimestamp();
                try {
                    writeDoneMarker(options.outroot / entry.name, finished.marker);
                    removeDoneMarker(options.outroot / entry.name, kPendingMarkerName);
                } catch (const Error& error) {
                    entry.status = "failed";
                    entry.error = error.what();
                }
            }
            finished.folderLock.reset();
            entry.finishedAt = utcTimestamp();
            std::istringstream lines(finished.warnings);
            for (std::string line; std::getline(lines, line);)
                if (!line.empty()) progress.message(line);
            // An interrupted shape is not a failed one: it stays pending.
            if (finished.userInterrupt) {
                BatchEntry pending;
                pending.name = entry.name;
                pending.input = entry.input;
                entry = pending;
            }
            summary.entries[finished.job.slot] = entry;
            if (!finished.userInterrupt) progress.shapeFinished(entry);
            budget.release(finished.job.estimatedBytes);
            const auto now = std::chrono::steady_clock::now();
            if (now - lastSummaryWrite > summaryInterval) {
                summary.updatedAt = utcTimestamp();
                summary.wallSeconds = std::chrono::duration<double>(now - wallStart).count();
                try {
                    writeBatchSummary(options.outroot, stem, summary);
                } catch (const Error& error) {
                    recordError = error.what();
                }
                // A summary of 100000 inputs takes seconds to write: wait
                // four times that long before the next, so that writing it
                // stays a fifth of the time at most instead of all of it.
                lastSummaryWrite = std::chrono::steady_clock::now();
                summaryInterval = std::max<std::chrono::steady_clock::duration>(
                    std::chrono::seconds(1), 4 * (lastSummaryWrite - now));
            }
        });
    tbb::flow::make_edge(segmentNode, recordNode);

    // The feeder waits for memory on its own thread, so no TBB worker (nor
    // the thread below, which works in wait_for_all) sits idle in a wait.
    graph.reserve_wait();
    std::thread feeder([&] {
        for (const auto& job : jobs) {
            if (!budget.acquire(job.estimatedBytes, stopRequested)) {
                interrupted = true;
                break;
            }
            segmentNode.try_put(job);
        }
        graph.release_wait();
    });
    graph.wait_for_all();
    feeder.join();

    BatchOutcome outcome;
    outcome.interrupted = interrupted.load() || interruptWatch.wasInterrupted();
    summary.complete = !outcome.interrupted;
    summary.updatedAt = utcTimestamp();
    summary.wallSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
    writeBatchSummary(options.outroot, stem, summary);
    if (!recordError.empty()) throw OutputError(recordError);

    outcome.inputs = mine.size();
    outcome.done = summary.count("done");
    outcome.skipped = summary.count("skipped");
    outcome.failed = summary.count("failed");
    outcome.pending = summary.count("pending");
    for (const auto& e : summary.entries)
        if (e.status == "failed")
            outcome.failedNames.push_back(escapeControlCharacters(nameAndLine(e) + ": " + e.error));
    outcome.peakShapesInFlight = budget.peakShapesInFlight();
    outcome.summaryJson = options.outroot / (stem + ".json");
    return outcome;
}

int runBatchMerge(const fs::path& outroot, std::FILE* stream) {
    const MergeResult result = mergeBatchSummaries(outroot);
    const BatchSummary& merged = result.merged;
    std::fprintf(stream,
                 "skelseg batch --merge: %zu shard summaries, %zu inputs: %zu done, %zu failed, "
                 "%zu missing; wrote %s\n",
                 result.shardFiles.size(), merged.entries.size(),
                 merged.entries.size() - result.missing.size(), result.failed.size(),
                 result.missing.size() - result.failed.size(),
                 escapeControlCharacters((outroot / "summary.json").string()).c_str());
    for (const auto& shard : result.missingShards)
        std::fprintf(stream, "skelseg batch --merge: no summary from shard%s %s\n",
                     shard.find('-') == std::string::npos ? "" : "s", shard.c_str());
    for (const auto& e : merged.entries) {
        if (e.isDone()) continue;
        std::fprintf(stream, "skelseg batch --merge: %s: %s%s%s\n",
                     escapeControlCharacters(e.name).c_str(), e.status.c_str(),
                     e.error.empty() ? "" : ": ", escapeControlCharacters(e.error).c_str());
    }
    // A share without a summary whose inputs are all done (its summary lost,
    // its task resubmitted) leaves nothing to do: said above, not a failure.
    return result.missing.empty() ? 0 : kExitSomeInputsFailed;
}

}  // namespace skelseg
