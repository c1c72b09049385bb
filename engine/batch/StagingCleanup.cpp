#include "engine/batch/StagingCleanup.h"

#include <vector>

#include "io/files/OutputDirectory.h"

namespace fs = std::filesystem;

namespace skelseg {

bool isStagingLeftoverName(const std::string& fileName) {
    if (isStagingDirectoryName(fileName)) return true;
    return fileName.size() > 1 && fileName[0] == '.' && fileName.find(".tmp-") != std::string::npos;
}

std::size_t removeStagingLeftovers(const fs::path& directory) {
    std::error_code ec;
    std::vector<fs::path> leftovers;
    for (const auto& item : fs::directory_iterator(directory, ec))
        if (isStagingLeftoverName(item.path().filename().string()))
            leftovers.push_back(item.path());
    std::size_t removed = 0;
    for (const auto& path : leftovers) removed += fs::remove_all(path, ec) > 0 ? 1 : 0;
    return removed;
}

}  // namespace skelseg
