#include "engine/SegmentCommand.h"

#include <fmt/format.h>
#include <tbb/flow_graph.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <memory>
#include <mutex>
#include <tuple>

#include "engine/SegmentOptions.h"
#include "engine/SegmentOutput.h"
#include "engine/SegmentReport.h"
#include "engine/SegmentSteps.h"
#include "engine/Stage.h"
#include "engine/UsableThreads.h"
#include "io/files/OutputDirectory.h"
#include "io/files/ReplacedOutputs.h"
#include "io/volume/VdbIO.h"
#include "io/volume/VolumeReader.h"
#include "kernels/base/ArenaPool.h"

namespace fs = std::filesystem;

namespace skelseg {

const OutputLayout& segmentOutputLayout() {
    static const OutputLayout layout = [] {
        // levels/k/ as engine/SegmentOutput.cpp writes it.
        auto level = std::make_shared<OutputLayout>(
            OutputLayout{"labels.nrrd", "cuts.ply", "segmentation.seg", "preview.png"});
        auto levels = std::make_shared<OutputLayout>();
        const auto isLevelNumber = [](const std::string& name) {
            return !name.empty() && name.size() <= 9 &&
                   name.find_first_not_of("0123456789") == std::string::npos &&
                   (name == "0" || name[0] != '0');
        };
        levels->folders.push_back({"", isLevelNumber, level});
        OutputLayout top{"labels.nrrd",  "labels.vdb",  "skeleton.ply",  "cuts.ply",
                         "segments.ply", "preview.png", "report.json",   "segmentation.seg",
                         "segments.glb", "viewer.html", "hierarchy.json"};
        top.folders.push_back({"levels", {}, levels});
        return top;
    }();
    return layout;
}

const std::vector<std::string>& segmentOutputNames() {
    static const std::vector<std::string> names = segmentOutputLayout().names();
    return names;
}

std::uint64_t defaultMemoryLimit() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), pageSize = ::sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || pageSize <= 0) return std::uint64_t(8) << 30;
    return std::uint64_t(pages) * std::uint64_t(pageSize) / 4 * 3;
}

namespace {

using SourceMessage = std::shared_ptr<SegmentSource>;  // the mask node moves a volume out
using MaskMessage = std::shared_ptr<const SegmentMask>;
using SegmentingMessage =
    std::shared_ptr<SegmentedShape>;  // filled in by segment, refine, complete
using ShapeMessage = std::shared_ptr<const SegmentedShape>;

/// Never replace the input: with --force, an input stored in OUTDIR under an
/// output name (a labels.nrrd fed back in, a level's labels, a detached
/// header's data file) would be overwritten or removed. The path comparison
/// names the plain cases; the identity comparison also catches the other
/// names of an output (a hard link, OUTDIR through a bind mount).
void refuseInputAmongOutputs(const SegmentCommandOptions& options) {
    ReplacedOutputs replaced;
    replaced.add(options.outdir, segmentOutputNames());
    for (const fs::path& file : volumeInputFiles(options.input)) {
        std::string output = outputReplacing(file, options.outdir, segmentOutputNames());
        if (const ReplacedOutputs::Entry* entry = output.empty() ? replaced.find(file) : nullptr)
            output = entry->output;
        if (output.empty()) continue;
        const std::string what =
            file == options.input ? "the input" : "its data file " + file.string();
        throw UsageError(options.input.string() + ": " + what + " is " + output +
                         " in the output directory and would be replaced; choose another "
                         "output directory");
    }
}

/// Everything a node needs besides its message: fixed for the run, or a
/// thread-safe service.
struct RunContext {
    const SegmentCommandOptions& options;
    ProgressReporter& progress;
    StageTimer& timer;
    OutputDirectory& out;
    SegmentInputOptions inputOptions;
    int threads;
    std::chrono::steady_clock::time_point wallStart;
    double cpuStart;
    /// Set by the surfaces writer when --time-budget left no time for preview.png.
    std::atomic<bool>& previewSkippedForBudget;
    /// Under --time-budget, the budget as a limit on the progress clock
    /// (seconds since this run's start); 0 without a budget.
    double budgetAsTimeLimit;
    /// Under --time-budget, when the writers must be done, in seconds of the
    /// budget's clock: 0 for the budget itself; a finer pass's deadline.
    double budgetDeadlineSeconds = 0.0;
    /// A finer pass: its plan, for its report.json (null in a first pass).
    const BudgetRefinement* refinement = nullptr;

    void warn(const std::string& warning) const {
        progress.message("skelseg: warning: " + warning);
    }
};

MaskMessage maskShape(const RunContext& run, SourceMessage source) {
    const bool isMesh = source->isMesh();
    auto mask = std::make_shared<SegmentMask>(
        maskSegmentSource(std::move(source), run.inputOptions, run.timer, run.progress,
                          [&](const std::string& w) { run.warn(w); }));
    if (run.options.writeVdb && !vdbCanHoldVoxelVolume(mask->mask.dims(), mask->mask.geometry)) {
        const std::string warning =
            run.options.input.string() +
            ": labels.vdb is not written: OpenVDB cannot hold voxels this small (volume under "
            "3e-15 world units cubed); labels.nrrd holds the labels";
        mask->warnings.push_back(warning);
        run.warn(warning);
    }
    const std::vector<std::string> notApplying =
        optionsNotApplying(run.options.givenOptions, isMesh);
    if (!notApplying.empty()) {
        const std::string warning =
            optionsNotApplyingWarning(run.options.input.string(), notApplying, isMesh);
        mask->warnings.push_back(warning);
        run.warn(warning);
    }
    const double limit = limitTimeToBudget(*mask, run.progress.timeLimit(), run.budgetAsTimeLimit);
    if (limit != run.progress.timeLimit()) run.progress.setTimeLimit(limit);
    return mask;
}

SegmentingMessage segmentShape(const RunContext& run, MaskMessage input) {
    return segmentMaskStep(std::move(input), run.options.parameters, run.timer, run.progress,
                           [&](const std::string& w) { run.warn(w); });
}

/// What the writers need besides the result: face labels, world geometry.
ShapeMessage completeShape(const RunContext& run, SegmentingMessage shape) {
    completeStep(*shape, run.timer, run.progress);
    shape->world = gatherWorldGeometry(shape->result);
    return shape;
}

/// Under --time-budget: whether preview.png was planned (planPreview) and
/// still fits in what is left of the budget now; records a skip.
bool previewFitsBudget(const RunContext& run, const SegmentedShape& shape) {
    const std::optional<BudgetChoice>& budget = shape.input->budget;
    if (!budget) return true;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - run.inputOptions.start)
            .count();
    const double deadline =
        run.budgetDeadlineSeconds > 0.0 ? run.budgetDeadlineSeconds : budget->budgetSeconds;
    const bool fits = budget->writePreview &&
                      elapsed + budget->previewSeconds * (1.0 + budget->safetyMargin) <= deadline;
    if (!fits) {
        run.previewSkippedForBudget.store(true);
        run.warn(previewSkippedWarning(budget->budgetSeconds));
    }
    return fits;
}

void writeReport(const RunContext& run, const SegmentedShape& shape,
                 const BudgetRefinement* refinement) {
    // Last: the report holds the timings of every stage above.
    SegmentRunFigures figures;
    if (refinement) figures.budgetRefinement = *refinement;
    figures.threads = run.threads;
    figures.memoryLimit = run.inputOptions.memoryLimit;
    figures.wallSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - run.wallStart).count();
    figures.cpuSeconds = processCpuSeconds() - run.cpuStart;
    figures.previewSkippedForBudget = run.previewSkippedForBudget.load();
    writeFileAtomically(run.out.stagingPath("report.json"),
                        segmentReportJson(run.options, shape, run.timer.timings(), figures));
}

/// Builds the graph of SegmentCommand.h and runs it to the end; exceptions
/// of the nodes come out of here. Returns the shape the writers wrote.
ShapeMessage runGraph(const RunContext& run) {
    ShapeMessage written;
    namespace flow = tbb::flow;
    flow::graph graph;
    flow::function_node<flow::continue_msg, SourceMessage> read(
        graph, flow::serial, [&](flow::continue_msg) {
            return std::make_shared<SegmentSource>(
                readSegmentSource(run.options.input, run.inputOptions, run.timer, run.progress));
        });
    flow::function_node<SourceMessage, MaskMessage> mask(
        graph, flow::serial,
        [&](SourceMessage source) { return maskShape(run, std::move(source)); });
    flow::function_node<MaskMessage, SegmentingMessage> segment(
        graph, flow::serial,
        [&](MaskMessage input) { return segmentShape(run, std::move(input)); });
    flow::function_node<SegmentingMessage, SegmentingMessage> refine(
        graph, flow::serial, [&](SegmentingMessage shape) {
            refineStep(*shape, run.timer, run.progress);
            return shape;
        });
    flow::function_node<SegmentingMessage, ShapeMessage> complete(
        graph, flow::serial, [&](SegmentingMessage shape) {
            written = completeShape(run, std::move(shape));
            return written;
        });

    // The writers pass the shape on, so the join below hears when each is
    // done. A writer that fails passes nothing and keeps its error for after
    // the graph: a node that throws cancels the graph, and wait_for_all()
    // then returns while the other writers still run, so the run would
    // remove its staging directory (and the process could exit) under them.
    std::mutex writerErrorMutex;
    std::exception_ptr writerError;
    auto writer = [&](auto write) {
        return flow::function_node<ShapeMessage, ShapeMessage>(
            graph, flow::serial, [write, &writerErrorMutex, &writerError](ShapeMessage shape) {
                try {
                    write(*shape);
                    return shape;
                } catch (...) {
                    std::lock_guard<std::mutex> lock(writerErrorMutex);
                    if (!writerError) writerError = std::current_exception();
                    return ShapeMessage();
                }
            });
    };
    auto writeNrrd = writer([&](const SegmentedShape& shape) {
        writeLabelNrrd(run.out, shape, run.timer, run.progress);
    });
    auto writeVdb = writer([&](const SegmentedShape& shape) {
        if (run.options.writeVdb)
            writeLabelVdb(run.out, shape, run.timer, run.progress);
        else
            run.out.removeOnCommit("labels.vdb");
    });
    auto writeSkeleton = writer([&](const SegmentedShape& shape) {
        writeSkeletonAndCuts(run.out, shape, run.timer, run.progress);
    });
    auto writeSurfaces = writer([&](const SegmentedShape& shape) {
        const bool preview = run.options.writePreview && !shape.input->previewOverMemory &&
                             previewFitsBudget(run, shape);
        // What this run does not write must not stay from an earlier run in
        // OUTDIR (--force, a batch redoing an input): another run's picture,
        // a mesh run's face labels beside a volume's results.
        if (!preview) run.out.removeOnCommit("preview.png");
        if (!shape.input->source->isMesh()) run.out.removeOnCommit("segmentation.seg");
        writeSurfacesAndPreview(run.out, shape, run.options, preview, run.timer, run.progress);
    });
    auto writeLevelFiles = writer(
        [&](const SegmentedShape& shape) { writeLevels(run.out, shape, run.timer, run.progress); });
    using Written =
        std::tuple<ShapeMessage, ShapeMessage, ShapeMessage, ShapeMessage, ShapeMessage>;
    flow::join_node<Written, flow::queueing> allWritten(graph);
    flow::function_node<Written, flow::continue_msg> report(
        graph, flow::serial, [&](const Written& all) {
            const bool everyWriterDone = std::apply(
                [](const auto&... shapes) { return (static_cast<bool>(shapes) && ...); }, all);
            if (everyWriterDone) writeReport(run, *std::get<0>(all), run.refinement);
            return flow::continue_msg();
        });

    flow::make_edge(read, mask);
    flow::make_edge(mask, segment);
    flow::make_edge(segment, refine);
    flow::make_edge(refine, complete);
    flow::make_edge(complete, writeNrrd);
    flow::make_edge(complete, writeVdb);
    flow::make_edge(complete, writeSkeleton);
    flow::make_edge(complete, writeSurfaces);
    flow::make_edge(complete, writeLevelFiles);
    flow::make_edge(writeNrrd, flow::input_port<0>(allWritten));
    flow::make_edge(writeVdb, flow::input_port<1>(allWritten));
    flow::make_edge(writeSkeleton, flow::input_port<2>(allWritten));
    flow::make_edge(writeSurfaces, flow::input_port<3>(allWritten));
    flow::make_edge(writeLevelFiles, flow::input_port<4>(allWritten));
    flow::make_edge(allWritten, report);
    read.try_put(flow::continue_msg());
    graph.wait_for_all();
    if (writerError) std::rethrow_exception(writerError);
    return written;
}

/// A finer pass that did not finish: the first pass's outputs come back, with
/// a report.json that says why.
void giveTheFirstPass(const RunContext& run, const SegmentedShape& first, BudgetRefinement& plan) {
    run.out.restoreSetAside();
    plan.kept = false;
    writeReport(run, first, &plan);
}

/// --time-budget's finer pass (engine/TimeBudget.h BudgetRefinement): after
/// a first pass whose outputs are staged, plans a finer choice for the time
/// left and runs it into a fresh staging, stopped at the budget less a
/// reserve; the first pass's outputs come back if it is stopped. Either way
/// report.json ends up saying what was done.
void refineWithinBudget(const RunContext& run, const SegmentedShape& first,
                        const ArenaPool::Lease& arena) {
    BudgetRefinement plan =
        planFinerPass(*first.input->budget, first.input->source->isMesh(), run.options.resolution,
                      run.timer.timings(), run.inputOptions.start);
    if (!plan.tried) {
        writeReport(run, first, &plan);
        return;
    }
    // The progress clock started `offset` after the budget's; --time-limit
    // (on the progress clock) stops the finer pass when it comes first.
    const double offset = run.options.timeBudgetSeconds - run.budgetAsTimeLimit;
    const double userLimit = run.progress.timeLimit();
    if (userLimit > 0) plan.deadlineSeconds = std::min(plan.deadlineSeconds, userLimit + offset);
    run.progress.setTimeLimit(plan.deadlineSeconds - offset);
    plan.kept = true;  // what the finer pass's own report says if it finishes
    RunContext finer = run;
    finer.inputOptions.budgetChoice = plan.choice;
    finer.inputOptions.heldBytes = heldResultBytes(*first.input, run.inputOptions.levels);
    finer.budgetDeadlineSeconds = plan.deadlineSeconds;
    finer.refinement = &plan;
    run.out.setAside();
    try {
        arena.arena().execute([&] { runGraph(finer); });
        throwIfInterrupted(run.progress);
    } catch (const InterruptedError& error) {
        if (error.reason() != InterruptedError::Reason::TimeLimit) throw;
        giveTheFirstPass(run, first, plan);
        return;
    } catch (const MemoryLimitError&) {
        plan.overMemory = true;
        giveTheFirstPass(run, first, plan);
        return;
    }
    run.out.dropSetAside();
}

/// Why a run stopped at its time limit, in words: the budget when it was
/// the limit (no choice fitted it), otherwise --time-limit.
std::string timeLimitReached(const SegmentCommandOptions& options) {
    const auto seconds = [](double s) { return fmt::format("{:g} s", s); };
    const bool budgetWasTheLimit =
        options.timeBudgetSeconds > 0 &&
        (options.timeLimitSeconds <= 0 || options.timeLimitSeconds > options.timeBudgetSeconds);
    if (budgetWasTheLimit)
        return "time limit reached: no resolution or coarsening was predicted to fit "
               "--time-budget " +
               seconds(options.timeBudgetSeconds) + ", so the run stopped at it";
    return "time limit reached (--time-limit " + seconds(options.timeLimitSeconds) + ")";
}

}  // namespace

void runSegmentCommand(const SegmentCommandOptions& options, ProgressReporter& progress) {
    const auto wallStart = std::chrono::steady_clock::now();
    const double cpuStart = processCpuSeconds();
    const int threads = usableThreads(options.threads);
    SegmentInputOptions inputOptions = segmentInputOptions(options, threads, wallStart);

    refuseInputAmongOutputs(options);
    checkInputFileSize(options.input, inputOptions.memoryLimit);
    // Refuse to clobber earlier results before doing any work.
    OutputDirectory out(options.outdir, options.force, segmentOutputLayout(), options.outdirLock);
    // An earlier hierarchy run's levels would contradict this run's outputs.
    if (options.parameters.levelCount() < 2) {
        out.removeOnCommit("levels");
        out.removeOnCommit("hierarchy.json");
    }
    double budgetAsTimeLimit = 0.0;
    if (options.timeBudgetSeconds > 0) {
        // The CLI's first run counts from the start of the process: loading
        // the libraries is part of what the user of `skelseg segment` waits
        // for. Other runs (a batch's later inputs, library calls) count from
        // their own start, or each would be charged for what came before it.
        const double age = options.budgetFromProcessStart
                               ? std::max(processAgeSeconds(), progress.elapsedSeconds())
                               : progress.elapsedSeconds();
        inputOptions.start -= std::chrono::duration_cast<std::chrono::steady_clock::duration>(
            std::chrono::duration<double>(age));
        // (A limit <= 0 would mean none: a budget already spent stops at once.)
        budgetAsTimeLimit =
            std::max(1e-9, options.timeBudgetSeconds - (age - progress.elapsedSeconds()));
    }
    StageTimer timer;
    std::atomic<bool> previewSkippedForBudget{false};
    const RunContext run{options,
                         progress,
                         timer,
                         out,
                         inputOptions,
                         threads,
                         wallStart,
                         cpuStart,
                         previewSkippedForBudget,
                         budgetAsTimeLimit};
    // A pooled arena: one created per run is never freed by oneTBB when the
    // run starts inside a busy task (kernels/base/ArenaPool.h).
    const ArenaPool::Lease arena = ArenaPool::process().acquire(threads);
    try {
        ShapeMessage first;
        arena.arena().execute([&] { first = runGraph(run); });
        throwIfInterrupted(progress);
        if (first && first->input->budget && options.budgetPasses > 1)
            refineWithinBudget(run, *first, arena);
    } catch (const InterruptedError& error) {
        if (error.reason() != InterruptedError::Reason::TimeLimit) throw;
        throw InterruptedError(error.reason(),
                               options.input.string() + ": " + timeLimitReached(options));
    } catch (const OutputError& error) {
        throw OutputError(out.withFinalPaths(error.what()));
    }
    out.commit();
}

}  // namespace skelseg
