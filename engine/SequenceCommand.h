// skelseg: the `skelseg sequence` command.
//
// Segments every frame of a pose sequence (meshes with the same faces in the
// same order: the frames of an animated character) and gives the sequence
// one face labelling, the consensus of engine/SequenceConsensus.h, which is
// a segmentation of every frame. OUTDIR holds:
//   frames/NAME/       each frame's own `skelseg segment` outputs (NAME: the
//                      file name without its extension);
//   segmentation.seg   the consensus: one label per face, for every frame;
//   sequence.json      per frame its parts and its Rand Index errors, the
//                      frame chosen and why (docs/outputs.md).
// Nothing is written until every frame is segmented; a failure leaves OUTDIR
// as it was (OutputDirectory).
#pragma once

#include <filesystem>
#include <vector>

#include "engine/ProgressReporter.h"
#include "engine/SegmentCommand.h"

namespace skelseg {

struct SequenceCommandOptions {
    std::vector<std::filesystem::path> frames;
    std::filesystem::path outdir;
    /// Every frame's options; input and outdir are set per frame, force
    /// applies to OUTDIR. --time-limit and --time-budget apply to each frame,
    /// as in `skelseg batch`; budgetFromProcessStart charges the process
    /// start to the first frame only.
    SegmentCommandOptions segment;
    /// Each frame's progress display.
    ProgressReporter::Display display = ProgressReporter::Display::Auto;
    /// A line per frame as it starts (off with --quiet).
    bool announceFrames = true;
};

/// Every name the command may write into OUTDIR.
const std::vector<std::string>& sequenceOutputNames();

/// What the command writes into OUTDIR: segmentation.seg, sequence.json and
/// frames/, whose folders (one per frame, of any name) each hold what
/// `segment` writes (segmentOutputLayout()).
const OutputLayout& sequenceOutputLayout();

/// Runs the command; `progress` carries its own lines, each frame gets a
/// reporter of its own (its time limit counts from the frame's start).
/// @throw UsageError for fewer than two frames, a frame that is not a mesh,
/// two frames of one name, a frame whose name is only dots before its
/// extension ("..off": no folder frames/NAME of its own), a frame inside
/// OUTDIR's outputs, or OUTDIR holding earlier results without force; InputError
/// naming the frame whose faces differ from the first frame's (face count,
/// corners per face; vertex indices between frames whose files have them,
/// which STL files have not), or any error of `skelseg segment` on a frame.
void runSequenceCommand(const SequenceCommandOptions& options, ProgressReporter& progress);

}  // namespace skelseg
