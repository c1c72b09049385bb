#include "tests/support/TempDir.h"

#include <unistd.h>

#include <atomic>
#include <system_error>

namespace skelseg::test {

TempDir::TempDir() {
    static std::atomic<int> counter{0};
    mPath = std::filesystem::temp_directory_path() /
            ("skelseg-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    std::filesystem::create_directories(mPath);
}

TempDir::~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(mPath, ec);
}

}  // namespace skelseg::test
