// Paths the tests need: the shared data folder (may be absent) and the CLI.
#pragma once

#include <filesystem>
#include <string>

namespace skelseg::test {

/// ../shared/data beside the source tree; tests that need it GTEST_SKIP()
/// with a message when it does not exist.
inline std::filesystem::path sharedDataDir() {
    return SKELSEG_SHARED_DATA_DIR;
}
inline bool hasSharedData() {
    return std::filesystem::is_directory(sharedDataDir());
}
/// The skelseg executable built beside the tests.
inline std::string skelsegBinary() {
    return SKELSEG_BINARY;
}

}  // namespace skelseg::test
