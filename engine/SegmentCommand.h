// skelseg: `skelseg segment INPUT -o OUTDIR`, end to end.
//
// Input: a volume (.nrrd/.nhdr, .binvox, .vdb) or a closed triangle mesh
// (.off, .obj, .stl, .ply) voxelised at `resolution`. Output, staged and
// moved into OUTDIR only when everything succeeded (OutputDirectory):
//   labels.nrrd, labels.vdb, skeleton.ply, cuts.ply, segments.ply,
//   segments.glb, viewer.html, preview.png, report.json, for meshes
//   segmentation.seg, and for hierarchy runs (--tau 1%,3%) levels/ and
//   hierarchy.json.
//
// The run is a oneTBB flow graph whose edges carry values (shared pointers
// to immutable results; the volume's mask is moved, not copied):
//
//   read ──SegmentSource──> mask ──SegmentMask──> segment ──SegmentedShape──>
//   (SegmentInput.h)        (SegmentInput.h;      (segmentVolume)
//                            --time-budget probe
//                            and choice)
//   ──> refine ──SegmentedShape──> complete ──SegmentedShape─────────────────┐
//       (a volume coarsened        (face labels, every                      │
//        for --time-budget:        level's faces and cuts,                  │
//        TimeBudget.h)             world geometry)                          │
//        ┌──────────────────┬───────────────────┬───────────────────┬───────┴──────┐
//        v                  v                   v                   v              v
//   write labels.nrrd  write labels.vdb  write skeleton.ply,  segment surfaces,  write levels/,
//                                        cuts.ply             views, preview     hierarchy.json
//        └──────────────────┴─────────┬─────────┴───────────────────┴──────────────┘
//                                     v  (join: all five done)
//                                   report ──> report.json (SegmentReport.h)
//
// The nodes from mask to complete run the steps of SegmentSteps.h (the
// Python module runs them in a row). The five writers (SegmentOutput.h) run
// concurrently (levels/ only in hierarchy runs, engine/SegmentationLevels.h). Shared by every node
// and thread-safe: the StageTimer, the ProgressReporter and the
// OutputDirectory. The whole graph runs in a task arena of `threads` slots,
// so concurrent calls (one per shape) each keep their own thread limit. An
// exception in any node cancels the graph and comes out of wait_for_all();
// then nothing is committed to OUTDIR.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/ProgressReporter.h"
#include "engine/SegmentInput.h"
#include "engine/Segmenter.h"
#include "io/files/DirectoryLock.h"
#include "io/files/OutputLayout.h"

namespace skelseg {

struct SegmentCommandOptions {
    std::filesystem::path input;
    std::filesystem::path outdir;
    std::string gridName;  // .vdb: grid to read (default: the first)
    int resolution = 256;  // meshes: voxels along the longest side
    /// Meshes: widest clearing, in voxels, of a place where the mesh passes
    /// through itself, in [2, 4] (SelfOverlapOptions::maxClearance).
    int selfOverlapClearance = 4;
    /// Meshes: seams between the two mesh patches of a contact kept by the
    /// box check (ContactSeparationOptions::patchSeams).
    bool contactPatchSeams = false;
    /// Meshes: a refused contact seam is retried grown by one voxel
    /// (ContactSeparationOptions::grownSeams).
    bool grownContactSeams = true;
    /// Volumes of anisotropic voxels: segment the file's own voxels instead
    /// of cubic ones (SegmentInputOptions::cubicVoxels false).
    bool keepVoxelAspect = false;
    SegmentationParameters parameters;
    int threads = 0;               // 0: all cores
    double timeLimitSeconds = 0;   // 0: none
    double timeBudgetSeconds = 0;  // 0: none; engine/TimeBudget.h
    /// The budget also counts the process's life before the call (loading
    /// the libraries, static initialisation), which the user of `skelseg
    /// segment` waits for: set by the CLI for its first run. Otherwise it
    /// counts from the call, as a library caller (Python, a test) expects.
    bool budgetFromProcessStart = false;
    bool calibrateTimeBudget = true;  // --budget-calibration probe (engine/BudgetCalibration.h)
    /// --budget-passes: 2 lets a budget run that ends early try a finer
    /// choice in the time left (engine/TimeBudget.h BudgetRefinement); 1
    /// keeps the first choice.
    int budgetPasses = 2;
    /// With --time-budget: a first choice already made, taken instead of the
    /// probe's (a caller that planned once for many similar inputs; tests).
    /// budgetSeconds and secondsLeft are the caller's.
    std::optional<BudgetChoice> budgetChoice;
    bool force = false;                // replace earlier results in OUTDIR
    std::uint64_t maxMemoryBytes = 0;  // 0: default share of physical memory
    bool writePreview = true;
    /// Hierarchy runs: also levels/k/preview.png for every level (each costs
    /// a preview, so off by default).
    bool writeLevelPreviews = false;
    bool writeVdb = true;
    /// This process's lock on the existing OUTDIR, when the caller took it
    /// (a batch, before it writes its markers there); null: the run locks
    /// OUTDIR itself.
    std::shared_ptr<const DirectoryLock> outdirLock;
    /// The options given on the command line, as it names them
    /// ("--resolution"): a run warns about those that do not apply to its
    /// input's kind (optionsNotApplying, engine/SegmentOptions.h). Empty for
    /// a batch, which passes one set of options to inputs of both kinds.
    std::vector<std::string> givenOptions;
};

/// Every file name a run may write into OUTDIR.
const std::vector<std::string>& segmentOutputNames();

/// What a run writes into OUTDIR: the files of segmentOutputNames() and the
/// folder levels/, which holds level folders named 0, 1, ... of labels.nrrd,
/// cuts.ply, segmentation.seg and preview.png. --force replaces only an OUTDIR
/// whose outputs hold nothing else (io/files/OutputLayout.h).
const OutputLayout& segmentOutputLayout();

/// Default memory cap: 75% of physical memory.
std::uint64_t defaultMemoryLimit();

/// Runs the command. Throws skelseg::Error subclasses (see kernels/base/Error.h).
/// Warnings go to `progress.message()`. Re-entrant: calls from several
/// threads at once share nothing but `progress` (if the caller passes the same).
void runSegmentCommand(const SegmentCommandOptions& options, ProgressReporter& progress);

}  // namespace skelseg
