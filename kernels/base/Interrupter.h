// skelseg: progress reporting and cancellation for long kernels.
//
// Modelled on openvdb::util::NullInterrupter. Every long kernel takes an
// Interrupter& and
//   - calls start(stageName) once, end() once (also on the exceptional path,
//     via InterrupterScope),
//   - polls wasInterrupted(fraction) sparingly (every few thousand work items,
//     from any thread), where fraction in [0,1] is the stage's progress or
//     negative when unknown,
//   - on a true answer stops its work and throws InterruptedError through
//     throwIfInterrupted(); a kernel whose workers saw the answer and stopped
//     throws through throwInterrupted() without asking again, since an
//     interrupter need not repeat a true answer and the work is incomplete.
//     A kernel that was interrupted leaves its output arguments in an
//     unspecified (but destructible) state.
// Implementations must make wasInterrupted() thread-safe and cheap.
#pragma once

#include "kernels/base/Error.h"

namespace skelseg {

class Interrupter {
public:
    virtual ~Interrupter() = default;
    /// A stage begins. name is a static string (stage names are literals).
    virtual void start(const char* /*name*/) {}
    /// The stage started last has finished.
    virtual void end() {}
    /// True when the work should stop. fraction: progress of the current
    /// stage in [0,1], or < 0 if unknown. Thread-safe.
    virtual bool wasInterrupted(double /*fraction*/ = -1.0) { return false; }
    /// Why the run was interrupted (only meaningful after wasInterrupted()
    /// returned true).
    virtual InterruptedError::Reason reason() const {
        return InterruptedError::Reason::UserInterrupt;
    }
};

/// Never interrupts, reports nothing. The default for library callers.
class NullInterrupter final : public Interrupter {};

/// Returns a process-wide NullInterrupter for default arguments.
inline Interrupter& nullInterrupter() {
    static NullInterrupter instance;
    return instance;
}

/// Throws the InterruptedError of a stop `interrupter` asked for, without
/// polling it again: for a kernel that saw the stop, put its outputs back,
/// and must not go on whatever a second poll would say.
[[noreturn]] inline void throwInterrupted(Interrupter& interrupter) {
    auto reason = interrupter.reason();
    throw InterruptedError(reason, reason == InterruptedError::Reason::TimeLimit
                                       ? "time limit reached"
                                       : "interrupted");
}

/// Throws InterruptedError if the interrupter asks to stop.
inline void throwIfInterrupted(Interrupter& interrupter, double fraction = -1.0) {
    if (interrupter.wasInterrupted(fraction)) throwInterrupted(interrupter);
}

/// RAII start()/end() pair so that end() is called on every path.
class InterrupterScope {
public:
    InterrupterScope(Interrupter& interrupter, const char* name) : mInterrupter(interrupter) {
        mInterrupter.start(name);
    }
    ~InterrupterScope() { mInterrupter.end(); }
    InterrupterScope(const InterrupterScope&) = delete;
    InterrupterScope& operator=(const InterrupterScope&) = delete;

private:
    Interrupter& mInterrupter;
};

}  // namespace skelseg
