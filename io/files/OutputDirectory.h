// skelseg: all-or-nothing output.
//
// OutputDirectory stages every output file of a run in a hidden directory
// inside OUTDIR and moves them into place only in commit(). A run that is
// interrupted, times out or fails leaves OUTDIR as it was: the destructor
// removes the staging directory unless commit() succeeded, and OUTDIR itself
// if the run created it. Each final name is
// replaced by rename(2), which is atomic on one file system, so a reader never
// sees a half-written file under a final name. The staging directory lies in
// OUTDIR, so no rename crosses file systems whatever TMPDIR is.
//
// A run holds an flock(2) on OUTDIR (io/files/DirectoryLock.h) from the
// constructor to the destructor, or is handed the lock by a batch that took
// it before touching the folder: two runs committing into one OUTDIR file by
// file would leave a mix of both, so the second is refused. Holding the lock
// also proves that no live run on a file system with locks stages in OUTDIR,
// so the constructor then removes the staging directories a killed run left
// (SIGKILL, a power cut): see isLeftoverStagingDirectory() for what proves a
// directory is one. Where the file system has no locks (some network
// mounts), runs are not guarded and leftovers stay.
//
// The outputs are those of an OutputLayout (io/files/OutputLayout.h): a run
// replaces, with --force, only what a run writes. An output holding anything
// else (a user's folder named levels/, a note inside an earlier levels/) is
// refused with and without --force, and is never moved or removed.
#pragma once

#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "io/files/DirectoryLock.h"
#include "io/files/OutputLayout.h"

namespace skelseg {

class OutputDirectory {
public:
    /// Opens (creating if needed) OUTDIR and locks it. Throws UsageError
    /// where checkEarlierOutputs() does (an output of `layout` holding what no
    /// run writes; without `force`, any earlier output), if OUTDIR is an
    /// existing non-directory, or if another process holds its lock (a run
    /// writing to it). `heldLock`, when given, is this process's lock on the
    /// existing OUTDIR (a batch takes it before it writes its markers there)
    /// and is used instead of locking OUTDIR again, which would be refused.
    OutputDirectory(const std::filesystem::path& outdir, bool force, OutputLayout layout,
                    std::shared_ptr<const DirectoryLock> heldLock = nullptr);
    ~OutputDirectory();
    OutputDirectory(const OutputDirectory&) = delete;
    OutputDirectory& operator=(const OutputDirectory&) = delete;

    /// Where to write output `name` (a plain file or directory name) before
    /// commit(); a directory is created by the caller and replaces an earlier
    /// one of the same name on commit.
    /// Thread-safe: the writers of one run call it concurrently.
    std::filesystem::path stagingPath(const std::string& name);
    /// Marks OUTDIR/name (a file or directory an earlier run wrote) to be
    /// removed by commit(), when this run writes no such output: a run
    /// without levels replaces an earlier hierarchy run's levels/ by nothing.
    void removeOnCommit(const std::string& name);
    /// Moves every staged file to OUTDIR/name and removes the names marked
    /// by removeOnCommit(). Throws OutputError on failure, after putting back
    /// the earlier outputs it had moved aside (a crash in between leaves them
    /// in the staging directory, which the next run on OUTDIR removes), and
    /// UsageError, changing nothing, when an output it would replace or
    /// remove now holds what no run writes (put there while this run ran).
    void commit();
    /// Keeps everything staged so far apart, inside the staging directory,
    /// and starts an empty staging: a second attempt at the outputs (the
    /// finer pass of --time-budget, engine/SegmentCommand.cpp) stages into
    /// it, and restoreSetAside() brings the first back if the attempt is
    /// given up. What removeOnCommit() marked stays marked. Throws
    /// OutputError when the files cannot be moved (nothing is lost: what
    /// was moved stays in the staging directory until discard()).
    void setAside();
    /// Drops what was staged since setAside() and puts back what it kept,
    /// with the marks of removeOnCommit() as they were then. Throws
    /// OutputError when a file cannot be moved back.
    void restoreSetAside();
    /// Drops what setAside() kept: the second attempt's outputs stand.
    void dropSetAside() noexcept;
    /// Drops everything staged (also done by the destructor if not committed),
    /// and removes OUTDIR again if this object created it and it is empty.
    void discard() noexcept;

    const std::filesystem::path& directory() const noexcept { return mDirectory; }

    /// `message` (an Error's what()) with the staging directory's path replaced
    /// by OUTDIR's: an
    /// error while writing names the file the user will look for, not the
    /// hidden directory that is gone when the message is read.
    std::string withFinalPaths(std::string message) const;

private:
    std::filesystem::path mDirectory, mStaging;
    OutputLayout mLayout;
    std::mutex mStagedMutex;  // guards mStaged
    std::vector<std::string> mStaged;
    std::vector<std::string> mObsolete;  // removed by commit(); guarded by mStagedMutex
    // What setAside() kept (guarded by mStagedMutex); mHasSetAside while kept.
    std::vector<std::string> mSetAsideStaged, mSetAsideObsolete;
    bool mHasSetAside = false;
    std::vector<std::filesystem::path>
        mCreated;  // directories the constructor created, deepest first
    bool mCommitted = false;
    std::shared_ptr<const DirectoryLock> mLock;  // OUTDIR's, held until the destructor

    void removeCreatedDirectories() noexcept;
};

/// Throws UsageError when `outdir` exists as something other than a
/// directory: a regular file ("exists and is not a directory"), or a symbolic
/// link to nothing, which no run can create a directory through (and which a
/// failed run took for a folder of its own, and removed).
void checkOutputDirectoryPath(const std::filesystem::path& outdir);

/// Throws UsageError when `outdir` holds an output of `layout` that a run may
/// not replace: one at or in which foreignEntry() finds what no run writes
/// (with or without `force`: "OUT/levels/notes.txt: not written by skelseg
/// ..."), or, without `force`, any earlier output ("holds results of an
/// earlier run (report.json); use --force to replace them"). Changes nothing.
void checkEarlierOutputs(const std::filesystem::path& outdir, const OutputLayout& layout,
                         bool force);

/// The output of `outputNames` in `outdir` whose writing would replace or
/// remove `file` (`file` is that output, or lies inside that output directory,
/// with symlinks resolved where they exist); empty if none. --force replaces
/// earlier outputs, so a command refuses an input for which this is not empty.
std::string outputReplacing(const std::filesystem::path& file, const std::filesystem::path& outdir,
                            const std::vector<std::string>& outputNames);

/// True for the name of a run's staging directory (".skelseg-staging-PID-N",
/// PID and N decimal), the one name pattern OutputDirectory and the batch's
/// cleanup (engine/batch/StagingCleanup.h) both recognise.
bool isStagingDirectoryName(const std::string& fileName);

/// The file OutputDirectory writes into its staging directory as soon as it
/// creates it: "HOST PID\n", the run that stages there.
inline constexpr const char* kStagingOwnerFileName = ".skelseg-run";

/// The content of kStagingOwnerFileName for process `pid` on this host.
std::string stagingOwnerRecord(long pid);

/// True when the process `pid` runs on this host (kill(pid, 0) finds it,
/// whoever owns it).
bool isLiveProcess(long pid);

/// True when `path` is a staging directory that a run which is no longer
/// alive left, and so may be removed by a run that holds its folder's lock.
/// The name alone proves nothing (a user may name a folder anything), so it
/// takes all of: a name isStagingDirectoryName() accepts; a directory, not
/// a symbolic link; kStagingOwnerFileName in it, or nothing at all in it (a
/// run killed between creating it and writing the record); and the run it
/// names (the PID of the name, for an empty one) not alive on this host. A
/// run on another host sharing the folder is not alive when the lock is
/// free. A directory that fails any of these is kept: clutter at worst,
/// never a user's files lost.
bool isLeftoverStagingDirectory(const std::filesystem::path& path);

/// Writes `bytes` to `path` through a temporary file in the same directory and
/// rename(2). Throws OutputError naming the path and the system's reason
/// ("no space left on device") on failure; the temporary file is removed.
void writeFileAtomically(const std::filesystem::path& path, const std::string& bytes);

}  // namespace skelseg
