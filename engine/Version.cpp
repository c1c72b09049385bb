#include "engine/Version.h"

namespace skelseg {
const char* versionString() noexcept {
    return "0.2.0";
}
}  // namespace skelseg
