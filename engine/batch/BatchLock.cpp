#include "engine/batch/BatchLock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>

#include "kernels/base/Error.h"

namespace skelseg {

BatchLock::BatchLock(const std::filesystem::path& outroot, const std::string& stem)
    : mFile(outroot / ("." + stem + ".lock")) {
    mFd = ::open(mFile.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (mFd < 0) return;  // an unwritable OUTROOT fails at the summary, with its reason
    if (::flock(mFd, LOCK_EX | LOCK_NB) == 0) return;
    const int error = errno;
    ::close(mFd);
    mFd = -1;
    if (error == EWOULDBLOCK)
        throw UsageError(outroot.string() + ": another skelseg batch is writing " + stem +
                         ".json in it; wait for it to end, or split the inputs with --shard");
}

BatchLock::~BatchLock() {
    if (mFd >= 0) ::close(mFd);
}

}  // namespace skelseg
