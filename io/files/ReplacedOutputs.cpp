#include "io/files/ReplacedOutputs.h"

#include <sys/stat.h>

#include <system_error>

namespace skelseg {

namespace fs = std::filesystem;

namespace {

/// The identity from `stat(2)` (following links) or `lstat(2)` (not following).
std::optional<FileIdentity> identityOf(const fs::path& path, bool followLinks) {
    struct stat info {};
    const int result = followLinks ? ::stat(path.c_str(), &info) : ::lstat(path.c_str(), &info);
    if (result != 0) return std::nullopt;
    return FileIdentity{std::uint64_t(info.st_dev), std::uint64_t(info.st_ino)};
}

}  // namespace

std::optional<FileIdentity> fileIdentity(const fs::path& path) {
    return identityOf(path, true);
}

void ReplacedOutputs::add(const fs::path& outdir, const std::vector<std::string>& outputNames,
                          const std::string& owner) {
    for (const std::string& name : outputNames) {
        const fs::path output = outdir / name;
        const std::optional<FileIdentity> top = identityOf(output, true);
        if (!top) continue;
        mEntries.emplace(*top, Entry{owner, name});
        std::error_code ec;
        if (!fs::is_directory(output, ec)) continue;
        // Without follow_directory_symlink: a link inside is removed, not its target.
        fs::recursive_directory_iterator it(output, fs::directory_options::skip_permission_denied,
                                            ec);
        for (; !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
            if (const std::optional<FileIdentity> entry = identityOf(it->path(), false))
                mEntries.emplace(
                    *entry,
                    Entry{
                        owner,
                        (fs::path(name) / it->path().lexically_relative(output)).generic_string()});
        }
    }
}

const ReplacedOutputs::Entry* ReplacedOutputs::find(const fs::path& file) const {
    const std::optional<FileIdentity> identity = fileIdentity(file);
    if (!identity) return nullptr;
    const auto found = mEntries.find(*identity);
    return found == mEntries.end() ? nullptr : &found->second;
}

}  // namespace skelseg
