// skelseg: running code that may crash, or allocate without end, in a child
// process.
//
// OpenVDB 10's reader trusts the sizes stored in a file. On some damaged files
// it corrupts the heap and glibc aborts the process; on others it allocates
// and reads gigabytes for a file of kilobytes. Neither can be caught where it
// happens: C++ catches exceptions, not aborts. runIsolated() runs the work in
// a forked child and says how it ended, so that the caller can turn a crash
// into a one-line input error and a runaway allocation into the
// --max-memory refusal (docs/robustness.md, "Damaged OpenVDB files"). The
// bytes the work returns come back through a memory file, so the parent
// never has to repeat the work on the untrusted input.
//
// fork() copies only the calling thread: the work must not wait on a lock
// that another thread may hold, nor start parallel work (oneTBB's worker
// threads are not in the child). Parsing bytes already in memory qualifies;
// the caller serialises what the parse locks (VdbIO.cpp). The child's
// standard error goes to /dev/null (glibc's abort message is not one line),
// and it ends with _exit(): no destructors, atexit handlers or leak checks of
// the parent's state run twice.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "kernels/base/Interrupter.h"

namespace skelseg {

struct IsolatedCallOptions {
    /// Bytes the child may allocate beyond what it inherits (RLIMIT_DATA); 0: no limit.
    std::uint64_t memoryLimit = 0;
    /// Polled while the child runs; when it asks to stop, the child is killed.
    Interrupter* interrupter = nullptr;
    /// A child that uses no CPU for this long is taken to wait on a lock it
    /// cannot get (a thread of the parent held it at the fork) and killed.
    double stallSeconds = 10.0;
};

struct IsolatedCallOutcome {
    enum class Ending {
        Finished,     ///< the work returned
        Threw,        ///< the work threw; `message` holds what (an InputError's problem)
        OutOfMemory,  ///< the work threw std::bad_alloc, or failed in any way after it
                      ///< reached the memory limit (reachedMemoryLimit)
        Crashed,      ///< the child died of signal `signal`
        Interrupted,  ///< the interrupter asked to stop; the child was killed
        NotIsolated,  ///< no child could be made, it stalled, or its output could not be
                      ///< read: the caller runs the work in-process
    };
    Ending ending = Ending::NotIsolated;
    std::string message;
    int signal = 0;
    /// The work's memory reached the limit: an allocation failed while it
    /// had grown by half the limit, or its resident memory grew by half the
    /// limit. An OutOfMemory ending without it is an allocation of an absurd
    /// size (a damaged file's), not the limit.
    bool reachedMemoryLimit = false;
    /// What the work returned (Finished only).
    std::string output;
};

/// Runs `work` in a forked child process and reports how it ended, with the
/// bytes it returned.
IsolatedCallOutcome runIsolated(const std::function<std::string()>& work,
                                const IsolatedCallOptions& options = {});

/// "SIGSEGV", "SIGABRT", ... or "signal N".
std::string signalName(int signal);

}  // namespace skelseg
