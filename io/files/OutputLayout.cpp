#include "io/files/OutputLayout.h"

#include <algorithm>

namespace fs = std::filesystem;

namespace skelseg {

std::vector<std::string> OutputLayout::names() const {
    std::vector<std::string> all = files;
    for (const Folder& folder : folders)
        if (!folder.name.empty()) all.push_back(folder.name);
    return all;
}

namespace {

const OutputLayout::Folder* folderNamed(const OutputLayout& layout, const std::string& name) {
    for (const auto& folder : layout.folders)
        if (folder.name.empty() ? folder.isName && folder.isName(name) : folder.name == name)
            return &folder;
    return nullptr;
}

std::optional<fs::path> foreignInFolder(const fs::path& folder, const OutputLayout& contents) {
    std::error_code ec;
    if (!fs::is_directory(fs::symlink_status(folder, ec))) return folder;
    std::vector<std::string> names;
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
        names.push_back(it->path().filename().string());
    if (ec) return folder;
    // Name order: the message names the same entry on every run.
    std::sort(names.begin(), names.end());
    for (const std::string& name : names) {
        const fs::path entry = folder / name;
        const bool isFile =
            std::find(contents.files.begin(), contents.files.end(), name) != contents.files.end();
        if (isFile) {
            if (fs::is_directory(fs::symlink_status(entry, ec))) return entry;
            continue;
        }
        const OutputLayout::Folder* inner = folderNamed(contents, name);
        if (!inner || !inner->contents) return entry;
        if (auto foreign = foreignInFolder(entry, *inner->contents)) return foreign;
    }
    return std::nullopt;
}

}  // namespace

std::optional<fs::path> foreignEntry(const fs::path& directory, const std::string& name,
                                     const OutputLayout& layout) {
    std::error_code ec;
    const fs::path entry = directory / name;
    const fs::file_status status = fs::symlink_status(entry, ec);
    if (!fs::exists(status)) return std::nullopt;
    if (std::find(layout.files.begin(), layout.files.end(), name) != layout.files.end())
        return fs::is_directory(status) ? std::optional<fs::path>(entry) : std::nullopt;
    for (const auto& folder : layout.folders)
        if (folder.name == name && folder.contents) return foreignInFolder(entry, *folder.contents);
    return std::nullopt;
}

}  // namespace skelseg
