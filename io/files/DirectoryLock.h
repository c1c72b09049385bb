// skelseg: the lock that says "a skelseg run is writing to this folder".
//
// A run holds flock(2) on its output folder for as long as it may stage,
// commit or mark anything there: OutputDirectory (io/files/OutputDirectory.h)
// takes it for a `segment` or `sequence` run, and a batch takes it for each
// OUTROOT/<name>/ before it touches the folder at all (its markers, a killed
// run's leftovers) and hands it to the segment run, which must not lock the
// folder a second time: flock(2) locks belong to one open file description,
// so a second open() in the same process is refused like another process.
//
// Holding the lock is what proves that no live run stages in the folder, so
// a run removes leftovers and rewrites markers only while it holds it. A
// folder whose lock another process holds is refused and left alone. Where
// the file system has no locks (some network mounts), isHeld() is false: runs
// are not guarded, and nothing that a run might be using is removed.
#pragma once

#include <filesystem>

namespace skelseg {

class DirectoryLock {
public:
    /// Locks the existing directory `directory` for this object's lifetime.
    /// @throw UsageError ("DIR: another skelseg run is writing to it; ...")
    ///        when another open file description holds its lock. A directory
    ///        that cannot be opened, or a file system without locks, gives an
    ///        object that does not hold the lock (isHeld() false).
    explicit DirectoryLock(const std::filesystem::path& directory);
    ~DirectoryLock();
    DirectoryLock(const DirectoryLock&) = delete;
    DirectoryLock& operator=(const DirectoryLock&) = delete;

    /// True when this object holds the lock; false where there are no locks.
    bool isHeld() const noexcept { return mFd >= 0; }
    const std::filesystem::path& directory() const noexcept { return mDirectory; }

private:
    std::filesystem::path mDirectory;
    int mFd = -1;  // the directory opened for flock(2); -1 when not locked
};

}  // namespace skelseg
