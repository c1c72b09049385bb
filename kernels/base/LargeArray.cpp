#include "kernels/base/LargeArray.h"

#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>

namespace skelseg {

bool adviseHugePages(void* data, std::size_t bytes) noexcept {
#ifdef MADV_HUGEPAGE
    if (!data || bytes == 0) return false;
    const long pageSize = ::sysconf(_SC_PAGESIZE);
    if (pageSize <= 0) return false;
    const std::uintptr_t page = std::uintptr_t(pageSize);
    const std::uintptr_t begin = (std::uintptr_t(data) + page - 1) / page * page;
    const std::uintptr_t end = (std::uintptr_t(data) + bytes) / page * page;
    if (end <= begin) return false;
    return ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE) == 0;
#else
    (void)data;
    (void)bytes;
    return false;
#endif
}

}  // namespace skelseg
