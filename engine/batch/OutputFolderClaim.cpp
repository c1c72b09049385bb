#include "engine/batch/OutputFolderClaim.h"

#include "engine/SegmentCommand.h"
#include "engine/batch/StagingCleanup.h"
#include "io/files/OutputDirectory.h"
#include "kernels/base/Error.h"

namespace fs = std::filesystem;

namespace skelseg {

namespace {

/// Throws UsageError if a marker in `outdir` records another input than `input`.
void refuseAnotherInputsFolder(const fs::path& outdir, const fs::path& input) {
    for (const char* name : {kDoneMarkerName, kPendingMarkerName}) {
        // A marker that cannot be read is still the batch's own file: the
        // folder is the batch's, for whichever input.
        const auto marker = readDoneMarker(outdir, name);
        if (marker && !marker->isOf(input))
            throw UsageError(outdir.string() + ": holds the results of another input (" +
                             marker->input.string() + ", " + name +
                             "); use --force to replace them");
    }
}

}  // namespace

OutputFolderClaim claimOutputFolder(const fs::path& outdir, const DoneMarker& pending, bool force) {
    std::error_code ec;
    checkOutputDirectoryPath(outdir);
    OutputFolderClaim claim;
    claim.createdFolder = !fs::exists(fs::symlink_status(outdir, ec));
    fs::create_directories(outdir, ec);
    if (ec) throw OutputError(outdir.string() + ": cannot create directory: " + ec.message());
    // Locked before anything is looked at or changed: the markers and staging
    // directories of a run writing here are that run's (the batch used to
    // delete them first and was refused only by `segment`'s lock after).
    // Refused, the folder stays even if this call created it: the other run
    // may have created it at the same moment.
    claim.lock = std::make_shared<const DirectoryLock>(outdir);
    try {
        claim.hadRecord = fs::exists(fs::symlink_status(outdir / kDoneMarkerName, ec)) ||
                          fs::exists(fs::symlink_status(outdir / kPendingMarkerName, ec));
        if (claim.hadRecord && !force) refuseAnotherInputsFolder(outdir, pending.input);
        // The batch's own earlier outputs are replaced without --force;
        // anything else only with it, and what no run writes never.
        checkEarlierOutputs(outdir, segmentOutputLayout(), force || claim.hadRecord);
        if (claim.lock->isHeld()) removeStagingLeftovers(outdir);
        writeDoneMarker(outdir, pending, kPendingMarkerName);
        removeDoneMarker(outdir);
    } catch (...) {
        releaseOutputFolder(outdir, claim);
        throw;
    }
    return claim;
}

void releaseOutputFolder(const fs::path& outdir, const OutputFolderClaim& claim) noexcept {
    std::error_code ec;
    if (!claim.hadRecord) fs::remove(outdir / kPendingMarkerName, ec);
    // fs::remove() removes only an empty folder.
    if (claim.createdFolder) fs::remove(outdir, ec);
}

}  // namespace skelseg
