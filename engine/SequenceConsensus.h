// skelseg: one segmentation for every frame of a pose sequence.
//
// The frames of an animated character share their faces (same faces in the
// same order; only the vertex positions move), so one face labelling is a
// segmentation of every frame. Segmented one by one, the frames can differ
// where a measure sits near a threshold (docs/quality.md, "Pose and
// resolution invariance"); the consensus gives them all the labels of one
// frame, the sequence's most typical:
//   1. the modal part count: the count most frames have (a tie: every tied
//      count stays in);
//   2. among the frames with that count, the one whose labels are closest to
//      all frames' (least mean Rand Index error to the others, faces counted
//      once each); a tie goes to the earlier frame.
// Frames the caller does not trust (`skelseg sequence`: a frame whose voxel
// model has handles its mesh lacks, where touching or interpenetrating
// surfaces stayed joined and parts come out wrong) neither vote in 1 nor are
// chosen in 2, unless no frame is trusted; their errors still count in every
// frame's mean.
// A medoid, not a merge of cut places: a cut lies a few faces apart in two
// poses, so a vote per face edge would drop cuts every frame has.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace skelseg {

struct SequenceConsensus {
    /// The frame whose labels every frame takes.
    std::size_t reference = 0;
    /// The part count most frames have (the reference's).
    std::size_t modalParts = 0;
    /// Per frame: distinct labels.
    std::vector<std::size_t> parts;
    /// Per frame: whether it voted for the part count and could be chosen
    /// (every frame when none is trusted).
    std::vector<bool> voted;
    /// Per frame: mean Rand Index error to the other frames.
    std::vector<double> meanErrorToOthers;
    /// Rand Index error of every pair of frames, row-major (frames x frames).
    std::vector<double> pairErrors;
    /// Mean over all pairs of frames (each pair once).
    double meanPairError = 0.0;
};

/// Chooses the consensus of `frameLabels` (one label per face, any integers;
/// every frame the same number of faces). `trusted`: per frame, or empty for
/// every frame trusted.
/// @throw UsageError with fewer than two frames, no faces, frames of
/// different face counts, or a `trusted` of another size than the frames.
SequenceConsensus chooseSequenceConsensus(const std::vector<std::vector<std::int64_t>>& frameLabels,
                                          const std::vector<bool>& trusted = {});

}  // namespace skelseg
