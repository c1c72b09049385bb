// usableThreads: how many threads a run of `--threads N` (Python `threads=N`)
// gets.
//
// oneTBB sizes its pool of workers at its first use to the cores it may run
// on (the affinity mask: a Slurm task's cpuset, a container's CPU set). An
// arena asking for more printed a two-line "TBB Warning: The number of
// workers is currently limited to ..." on stderr (also with --quiet, and from
// the Python module, which promises to print nothing) and ran on those cores
// anyway. Raising the pool's limit instead would start every thread asked for,
// each with its own path caches, on cores that cannot run them: slower and
// many times the memory (docs/robustness.md). So a run uses at most the cores
// it may run on, the warning never comes, and the report gives the threads
// used. The labels do not depend on the thread count.
#pragma once

#include <tbb/info.h>

#include <algorithm>

namespace skelseg {

/// `requested` threads (0 or less: all the cores) capped at the cores oneTBB
/// may run on.
inline int usableThreads(int requested) {
    const int cores = std::max(1, tbb::info::default_concurrency());
    return requested > 0 ? std::min(requested, cores) : cores;
}

}  // namespace skelseg
