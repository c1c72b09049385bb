// skelseg version string, for --version and report.json.
#pragma once

namespace skelseg {
const char* versionString() noexcept;
}
