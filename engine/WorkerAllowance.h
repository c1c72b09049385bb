// WorkerAllowance: lets one run's task arena have the `--threads N` it asks
// for when N is over the machine's cores.
//
// oneTBB sizes its pool of workers at its first use, to the cores (or the
// affinity mask) less one. An arena asking for more printed "TBB Warning: The
// number of workers is currently limited to 1. The request for 63 workers is
// ignored. ..." on stderr (two lines, also with --quiet, and from the Python
// module, which promises to print nothing), and ran on fewer threads than
// asked. A global_control that allows N for the run raises the pool's limit
// first. It only ever raises it: a run of fewer threads holds none, so it
// never limits another run of the process (a batch's shapes, concurrent
// Python calls).
#pragma once

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <optional>

namespace skelseg {

class WorkerAllowance {
public:
    explicit WorkerAllowance(int threads) {
        if (threads > tbb::info::default_concurrency())
            mControl.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    }

private:
    std::optional<tbb::global_control> mControl;
};

}  // namespace skelseg
