// skelseg version and build, for --version, report.json and the batch's done
// markers.
#pragma once

#include <string>

namespace skelseg {

/// The release version ("0.2.0").
const char* versionString() noexcept;

/// Which build of the engine is running: the size and CRC-32 of the file its
/// code was loaded from (the skelseg executable, or the Python module), as
/// "SIZE-CRC" in hexadecimal, e.g. "614048-1f2e3d4c"; empty if that file cannot
/// be read. The version alone does not change when the outputs do (it names
/// a release, and any commit may move a cut); the build does, and only then:
/// builds of the same sources with the same compiler are byte-identical, so a
/// rebuild after a change of documentation keeps its id. Computed once per
/// process (a few milliseconds).
const std::string& engineBuildId();

}  // namespace skelseg
