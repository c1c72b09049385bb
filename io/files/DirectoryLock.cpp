#include "io/files/DirectoryLock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>

#include "kernels/base/Error.h"

namespace skelseg {

DirectoryLock::DirectoryLock(const std::filesystem::path& directory) : mDirectory(directory) {
    mFd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (mFd < 0) return;
    if (::flock(mFd, LOCK_EX | LOCK_NB) == 0) return;
    const int error = errno;
    ::close(mFd);
    mFd = -1;
    if (error != EWOULDBLOCK) return;  // no locks on this file system
    throw UsageError(directory.string() +
                     ": another skelseg run is writing to it; wait for it to end or choose "
                     "another output directory");
}

DirectoryLock::~DirectoryLock() {
    if (mFd >= 0) ::close(mFd);
}

}  // namespace skelseg
