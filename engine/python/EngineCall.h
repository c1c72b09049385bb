// skelseg: running the engine from Python without holding the interpreter.
//
// runEngineCall() runs the engine's work on a worker thread (inside a oneTBB
// task_arena of `threads` threads when threads > 0, so one call's thread
// count does not change any other's) while the calling thread releases the
// GIL and waits. Every 50 ms the caller wakes, takes the GIL, and
//   - checks for signals (PyErr_CheckSignals): Ctrl-C raises
//     KeyboardInterrupt there, in the main thread, as Python expects;
//   - calls progress(stage, fraction) once for every stage started since the
//     last wake, in order, and when the current stage's fraction changed, at
//     most every 100 ms; at the end, for the stages not reported yet, then
//     once with ("done", 1.0).
// A Python exception from either cancels the engine through the interrupter;
// the caller waits for the worker to stop (the kernels poll every few
// milliseconds) and re-raises it, so the interpreter stays usable. Engine
// exceptions from the worker are rethrown on the calling thread as they are
// (Module.cpp maps them to Python exceptions).
//
// Why a worker thread rather than taking the GIL inside wasInterrupted():
// the kernels poll from every TBB thread, and a poll that blocks on the GIL
// stalls a parallel loop behind whatever Python code runs; here the engine's
// threads never touch Python, and the callback runs on the caller's thread.
#pragma once

#include <pybind11/pybind11.h>

#include <functional>

#include "engine/python/CallerPolledInterrupter.h"

namespace skelseg {

/// Runs `work` as described above. Call with the GIL held. threads <= 0: the
/// default concurrency. progress: a callable or None.
void runEngineCall(const std::function<void()>& work, CallerPolledInterrupter& interrupter,
                   int threads, const pybind11::object& progress);

/// Registered with Python's atexit (Module.cpp), so it runs while the
/// interpreter ends, before anything is torn down: cancels every call under
/// way and waits until their workers have stopped. From then on a call from
/// a thread other than the main one (a daemon thread) parks that thread
/// without the GIL and never returns, as CPython parks daemon threads; the
/// main thread's calls run as before. Call with the GIL held.
void stopEngineCallsForExit();

}  // namespace skelseg
