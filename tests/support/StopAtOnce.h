// An Interrupter that asks to stop at its first poll, for the tests that
// check a kernel stops when asked and leaves no partial result.
#pragma once

#include "kernels/base/Interrupter.h"

namespace skelseg::test {

class StopAtOnce final : public Interrupter {
public:
    bool wasInterrupted(double) override { return true; }
};

}  // namespace skelseg::test
