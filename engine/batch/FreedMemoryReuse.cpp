#include "engine/batch/FreedMemoryReuse.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace skelseg {

bool keepFreedMemoryForReuse() {
#if defined(__GLIBC__)
    // Fixed thresholds also turn off glibc's own adjustment, which raised the
    // mmap threshold to a freed block's size but trimmed three panels' worth.
    const bool mmapSet = ::mallopt(M_MMAP_THRESHOLD, int(kBatchMmapThresholdBytes)) == 1;
    const bool trimSet = ::mallopt(M_TRIM_THRESHOLD, int(kBatchTrimThresholdBytes)) == 1;
    return mmapSet && trimSet;
#else
    return false;
#endif
}

}  // namespace skelseg
