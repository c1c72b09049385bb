#include "engine/Stage.h"

namespace skelseg {

Stage::Stage(StageTimer& timer, Interrupter& interrupter, const char* name, bool parallel)
    : mTimer(timer),
      mName(name),
      mParallel(parallel),
      mStart(std::chrono::steady_clock::now()),
      mCpuStart(processCpuSeconds()),
      mScope(interrupter, name) {}

Stage::~Stage() {
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - mStart).count();
    mTimer.add(mName, mParallel, wall, processCpuSeconds() - mCpuStart);
}

}  // namespace skelseg
