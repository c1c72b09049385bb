// The recipe half of the FuzzVdb target: fuzzed bytes describe one or two
// OpenVDB grids (type, class, transform, name, voxels, tiles, far-away
// coordinates), which OpenVDB writes to memory as a .vdb stream.
//
// This is test scaffolding, not code under test, so it lives in its own
// translation unit that CMakeLists.txt compiles without the fuzzer's coverage
// and sanitizer instrumentation: instrumenting OpenVDB's writer templates
// made that unit the slowest compile of CI, and coverage of the writer would
// only steer libFuzzer towards exploring OpenVDB's writer instead of
// skelseg's reader. The reader (io/volume/VdbIO.cpp) stays instrumented.
#pragma once

#include <fuzzer/FuzzedDataProvider.h>

#include <string>

namespace skelseg::fuzz {

/// Initialises OpenVDB and limits TBB to one thread (OpenVDB's parallel loops
/// on tiny grids cost more in wake-ups than they save; one thread is
/// reproducible). Call once, from LLVMFuzzerInitialize.
void initialiseVdbRecipes();

/// Consumes a recipe from `in` and returns the .vdb bytes OpenVDB writes for
/// it in `bytes`. Returns false when OpenVDB refuses to write the recipe
/// (for example a singular transform); `bytes` is then unspecified.
bool writeVdbRecipe(FuzzedDataProvider& in, std::string& bytes);

}  // namespace skelseg::fuzz
