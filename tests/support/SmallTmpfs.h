// A tmpfs of a few kilobytes, mounted for one test: a full disk on demand.
//
// Mounting needs root (CAP_SYS_ADMIN) and a kernel that lets this process
// mount; elsewhere mounted() is false and the test skips with skipReason().
// The destructor unmounts (lazily, so a file left open cannot keep the
// mount) before the temporary directory is removed.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

#include "tests/support/TempDir.h"

namespace skelseg::test {

class SmallTmpfs {
public:
    /// Mounts a tmpfs of `bytes` (rounded up to pages by the kernel) and, if
    /// `inodes` is not 0, room for that many files and folders (its root
    /// counts as one).
    explicit SmallTmpfs(std::size_t bytes, bool readOnly = false, std::size_t inodes = 0);
    ~SmallTmpfs();
    SmallTmpfs(const SmallTmpfs&) = delete;
    SmallTmpfs& operator=(const SmallTmpfs&) = delete;

    bool mounted() const { return mMounted; }
    const std::string& skipReason() const { return mSkipReason; }
    /// The mount point.
    const std::filesystem::path& path() const { return mPoint; }
    std::filesystem::path operator/(const std::string& name) const { return mPoint / name; }

private:
    TempDir mDir;
    std::filesystem::path mPoint;
    bool mMounted = false;
    std::string mSkipReason;
};

}  // namespace skelseg::test
