// skelseg: the steps of `skelseg segment` between its input and its files.
//
// The command's flow graph (SegmentCommand.h) runs them as nodes; the Python
// module (engine/python/) runs the same steps in a row on the arrays it is
// given, so both give the same labels, face labels and report for the same
// options, time budget included:
//   segmentInputOptions()  the input step's options from the command's;
//   maskSegmentSource()    (SegmentInput.h) the mask, with --time-budget's choice;
//   limitTimeToBudget()    a budget nothing fits becomes a time limit;
//   parametersFor()        the parameters a mask is segmented with;
//   segmentMaskStep()      the segmentation (segmentVolume);
//   refineStep()           a volume coarsened for the budget back on its grid;
//   completeStep()         meshes: face labels; hierarchies: every level's
//                          faces and cut loops.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "engine/SegmentCommand.h"
#include "engine/SegmentInput.h"
#include "engine/SegmentOutput.h"
#include "engine/StageTimer.h"
#include "kernels/base/Interrupter.h"

namespace skelseg {

/// The options of the input step of a run of `options` on `threads` threads
/// that started at `start` (the time budget counts from there); the memory
/// limit is --max-memory or defaultMemoryLimit().
SegmentInputOptions segmentInputOptions(const SegmentCommandOptions& options, int threads,
                                        std::chrono::steady_clock::time_point start);

/// When the budget chose and nothing fits, the time left in the budget,
/// `budgetAsTimeLimit`, is the run's time limit (unless a lower one is
/// set): the run stops as with --time-limit. A run whose choice fits
/// finishes even when it overruns the prediction: a late answer is worth
/// more to the user than none. `currentLimit` <= 0: none. Returns the limit
/// to set, or `currentLimit` unchanged.
double limitTimeToBudget(const SegmentMask& mask, double currentLimit, double budgetAsTimeLimit);

/// The parameters `input` is segmented with: `requested`, with the cut rule
/// for loops round handles (CutOptions::handleLoopsCarryNoArea) on where the
/// input is a closed mesh whose voxel model has handles the mesh lacks (and
/// `requested.artefactHandlesCarryNoArea`, which --keep-handle-areas turns
/// off). The report records what ran.
SegmentationParameters parametersFor(const SegmentMask& input,
                                     const SegmentationParameters& requested);

/// Segments the mask with parametersFor(input, parameters); warnings go to
/// `warn` as they come and stay in the result.
std::shared_ptr<SegmentedShape> segmentMaskStep(
    std::shared_ptr<const SegmentMask> input, const SegmentationParameters& parameters,
    StageTimer& timer, Interrupter& interrupter,
    const std::function<void(const std::string&)>& warn);

/// A volume coarsened for --time-budget: its result back on the input grid
/// (stage "refine labels"); a volume of anisotropic voxels segmented on cubic
/// ones: its result back on the input grid (stage "labels on the input
/// grid"); nothing otherwise.
void refineStep(SegmentedShape& shape, StageTimer& timer, Interrupter& interrupter);

/// Meshes: the face labels (stage "face labels") and, in hierarchy runs,
/// every level's (stage "level face labels"); hierarchy runs: every level's
/// cut loops. Not the world geometry, which only the writers need.
void completeStep(SegmentedShape& shape, StageTimer& timer, Interrupter& interrupter);

}  // namespace skelseg
