#include "engine/Version.h"

namespace skelseg {
const char* versionString() noexcept {
    return "0.1.0";
}
}  // namespace skelseg
