#include "tests/support/SmallTmpfs.h"

#include <sys/mount.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace skelseg::test {

SmallTmpfs::SmallTmpfs(std::size_t bytes, bool readOnly, std::size_t inodes)
    : mPoint(mDir / "tmpfs") {
    std::filesystem::create_directory(mPoint);
    if (::geteuid() != 0) {
        mSkipReason = "mounting a tmpfs needs root";
        return;
    }
    std::string options = "size=" + std::to_string(bytes);
    if (inodes > 0) options += ",nr_inodes=" + std::to_string(inodes);
    if (::mount("tmpfs", mPoint.c_str(), "tmpfs", readOnly ? MS_RDONLY : 0, options.c_str()) != 0) {
        mSkipReason = std::string("cannot mount a tmpfs here: ") + std::strerror(errno);
        return;
    }
    mMounted = true;
}

SmallTmpfs::~SmallTmpfs() {
    if (mMounted) ::umount2(mPoint.c_str(), MNT_DETACH);
}

}  // namespace skelseg::test
