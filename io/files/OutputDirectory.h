// skelseg: all-or-nothing output.
//
// OutputDirectory stages every output file of a run in a hidden directory
// inside OUTDIR and moves them into place only in commit(). A run that is
// interrupted, times out or fails leaves OUTDIR as it was: the destructor
// removes the staging directory unless commit() succeeded, and OUTDIR itself
// if the run created it. Each final name is
// replaced by rename(2), which is atomic on one file system, so a reader never
// sees a half-written file under a final name.
#pragma once

#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

namespace skelseg {

class OutputDirectory {
public:
    /// Opens (creating if needed) OUTDIR. Throws UsageError if OUTDIR holds
    /// files from an earlier run (any name in `outputNames` exists) and
    /// `force` is false, or if OUTDIR is an existing non-directory.
    OutputDirectory(const std::filesystem::path& outdir, bool force,
                    const std::vector<std::string>& outputNames);
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
    /// by removeOnCommit(). Throws OutputError on failure.
    void commit();
    /// Drops everything staged (also done by the destructor if not committed),
    /// and removes OUTDIR again if this object created it and it is empty.
    void discard() noexcept;

    const std::filesystem::path& directory() const noexcept { return mDirectory; }

private:
    std::filesystem::path mDirectory, mStaging;
    std::mutex mStagedMutex;  // guards mStaged
    std::vector<std::string> mStaged;
    std::vector<std::string> mObsolete;  // removed by commit(); guarded by mStagedMutex
    std::vector<std::filesystem::path>
        mCreated;  // directories the constructor created, deepest first
    bool mCommitted = false;

    void removeCreatedDirectories() noexcept;
};

/// Throws UsageError when `outdir` exists as something other than a
/// directory: a regular file ("exists and is not a directory"), or a symbolic
/// link to nothing, which no run can create a directory through (and which a
/// failed run took for a folder of its own, and removed).
void checkOutputDirectoryPath(const std::filesystem::path& outdir);

/// The output of `outputNames` in `outdir` whose writing would replace or
/// remove `file` (`file` is that output, or lies inside that output directory,
/// with symlinks resolved where they exist); empty if none. --force replaces
/// earlier outputs, so a command refuses an input for which this is not empty.
std::string outputReplacing(const std::filesystem::path& file, const std::filesystem::path& outdir,
                            const std::vector<std::string>& outputNames);

/// Writes `bytes` to `path` through a temporary file in the same directory and
/// rename(2). Throws OutputError naming the path on failure.
void writeFileAtomically(const std::filesystem::path& path, const std::string& bytes);

}  // namespace skelseg
