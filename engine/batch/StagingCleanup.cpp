#include "engine/batch/StagingCleanup.h"

#include <exception>
#include <string>
#include <vector>

#include "io/files/OutputDirectory.h"

namespace fs = std::filesystem;

namespace skelseg {

namespace {

/// True for a temporary of writeFileAtomically() (".NAME.tmp-PID-N") whose
/// process is not alive.
bool isDeadRunsTemporary(const std::string& fileName) {
    const std::size_t at = fileName.rfind(".tmp-");
    if (fileName.size() < 2 || fileName[0] != '.' || at == std::string::npos) return false;
    try {
        std::size_t used = 0;
        const long pid = std::stol(fileName.substr(at + 5), &used);
        return used > 0 && !isLiveProcess(pid);
    } catch (const std::exception&) {
        return false;  // no PID in the name: not one of ours
    }
}

}  // namespace

bool isStagingLeftoverName(const std::string& fileName) {
    if (isStagingDirectoryName(fileName)) return true;
    return fileName.size() > 1 && fileName[0] == '.' && fileName.find(".tmp-") != std::string::npos;
}

std::size_t removeStagingLeftovers(const fs::path& directory) {
    std::error_code ec;
    std::vector<fs::path> leftovers;
    for (const auto& item : fs::directory_iterator(directory, ec))
        if (isLeftoverStagingDirectory(item.path()) ||
            isDeadRunsTemporary(item.path().filename().string()))
            leftovers.push_back(item.path());
    std::size_t removed = 0;
    for (const auto& path : leftovers) removed += fs::remove_all(path, ec) > 0 ? 1 : 0;
    return removed;
}

}  // namespace skelseg
