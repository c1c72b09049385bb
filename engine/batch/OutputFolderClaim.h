// skelseg: which output folders a batch may write, and its claim on one.
//
// A batch segments each input into OUTROOT/<name>/ and replaces what is
// there. It may replace only what a batch made for that input: a folder
// whose done marker or pending marker (engine/batch/DoneMarker.h) records
// the same input file. Without --force it refuses, as `segment` does,
//   - a folder holding outputs but no marker: the results of an earlier run
//     it has no record of (made by `skelseg segment`, or by hand);
//   - a folder whose marker records another input file: another manifest's
//     input of the same name (d1/a.off and d2/a.obj both go to a/), whose
//     results would be lost without a word.
// With or without --force it refuses outputs holding what no run writes
// (checkEarlierOutputs(), io/files/OutputDirectory.h): --force replaces
// skelseg's outputs, never a user's files.
//
// Claiming first takes the folder's lock (io/files/DirectoryLock.h), the one
// a `segment` run or another batch's share holds while it writes there: a
// folder locked by another run is refused and left exactly as it was, its
// markers and staging directories included. The claim keeps the lock, hands
// it to the segment run, and holds it until the batch has written done.json.
// Then it writes the pending marker before anything else changes and then
// removes done.json, so at every moment the folder records that its outputs
// are the batch's: a batch killed while (re)doing an input, even between
// `segment`'s commit and the new done marker, can still redo it.
#pragma once

#include <filesystem>
#include <memory>

#include "engine/batch/DoneMarker.h"
#include "io/files/DirectoryLock.h"

namespace skelseg {

/// What claimOutputFolder() found and did, for releaseOutputFolder().
struct OutputFolderClaim {
    bool hadRecord = false;      // the folder held a done or pending marker before
    bool createdFolder = false;  // the claim created the folder
    /// The folder's lock, taken before anything in it changed; shared with
    /// the segment run (SegmentCommandOptions::outdirLock).
    std::shared_ptr<const DirectoryLock> lock;
};

/// Creates the folder if needed and locks it, checks that the batch may
/// write `outdir` for the input `pending.input` (see above), then removes
/// the staging leftovers of killed runs there, writes `pending` as its
/// pending marker and removes its done marker.
/// @throw UsageError when another run holds the folder's lock ("another
///        skelseg run is writing to it", nothing changed), or the folder
///        is not the batch's to replace (one line
///        naming the folder and what it holds; "use --force" where that
///        helps); OutputError when the folder or the markers cannot be
///        written. A folder it created is removed again when it throws.
OutputFolderClaim claimOutputFolder(const std::filesystem::path& outdir, const DoneMarker& pending,
                                    bool force);

/// After the input failed: a pending marker the claim wrote where the batch
/// had no record goes again (the outputs there, if any, are not the
/// batch's), and so does the folder if the claim created it and it is empty
/// again. A marker over an earlier record stays: the outputs are still the
/// batch's to redo.
void releaseOutputFolder(const std::filesystem::path& outdir,
                         const OutputFolderClaim& claim) noexcept;

}  // namespace skelseg
