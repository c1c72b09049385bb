// skelseg: one batch at a time per summary in an OUTROOT.
//
// Two `skelseg batch` runs of the same share on one OUTROOT (no --shard, or
// the same --shard twice) both segmented every input and both rewrote
// summary.json, the last to finish winning with entries the other had done;
// their overlapping inputs met in the same output folders. The second now
// stops at once. The lock is flock(2) on OUTROOT/.STEM.lock (STEM: summary
// or summary.shard-I-of-N), held until the batch ends; shards of one batch
// have their own files and run side by side. The file stays (removing a
// lock file lets a third run lock a new file while a second holds the old
// one), unless the batch created OUTROOT and failed as a whole. Where the
// file system has no locks, batches are not guarded.
#pragma once

#include <filesystem>
#include <string>

namespace skelseg {

class BatchLock {
public:
    /// Locks OUTROOT/.`stem`.lock. @throw UsageError naming OUTROOT when
    /// another process holds it.
    BatchLock(const std::filesystem::path& outroot, const std::string& stem);
    ~BatchLock();
    BatchLock(const BatchLock&) = delete;
    BatchLock& operator=(const BatchLock&) = delete;

    const std::filesystem::path& file() const noexcept { return mFile; }

private:
    std::filesystem::path mFile;
    int mFd = -1;
};

}  // namespace skelseg
