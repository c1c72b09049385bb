#include "engine/Version.h"

#include <dlfcn.h>
#include <errno.h>

#include <cstdio>
#include <cstring>
#include <filesystem>

#include "engine/batch/DoneMarker.h"

namespace skelseg {

const char* versionString() noexcept {
    return "0.2.0";
}

namespace {

/// The file this code was loaded from. dladdr names a shared object (the
/// Python module) by the path it was loaded with; for the executable it
/// gives argv[0], which need not name the file from this working directory,
/// so the kernel's link to the executable is read instead.
std::filesystem::path fileOfThisCode() {
    Dl_info info{};
    if (::dladdr(reinterpret_cast<const void*>(&engineBuildId), &info) != 0 && info.dli_fname &&
        *info.dli_fname && std::strcmp(info.dli_fname, program_invocation_name) != 0)
        return info.dli_fname;
    return "/proc/self/exe";
}

std::string buildIdOfThisCode() {
    try {
        const InputFingerprint file = fingerprintFile(fileOfThisCode());
        char id[48];
        std::snprintf(id, sizeof id, "%llx-%08x", static_cast<unsigned long long>(file.bytes),
                      file.crc32);
        return id;
    } catch (const std::exception&) {
        return {};  // a build that cannot be told from another matches only another such
    }
}

}  // namespace

const std::string& engineBuildId() {
    static const std::string id = buildIdOfThisCode();
    return id;
}

}  // namespace skelseg
