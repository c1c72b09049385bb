// skelseg: what a command writes into its output directory.
//
// A run replaces an earlier run's outputs (with --force) and removes those it
// no longer writes (levels/ after a run without levels). Only what a skelseg
// run wrote may go: a user's folder that happens to be called levels/, or a
// note put into an earlier run's levels/, is not an earlier output, and
// --force removed it with the rest. OutputLayout lists the files a command
// writes and, for every folder it writes, what may lie in it; foreignEntry()
// finds the first thing in an existing output that no run would have written
// there, which OutputDirectory refuses to replace (io/files/OutputDirectory.h).
#pragma once

#include <filesystem>
#include <functional>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace skelseg {

struct OutputLayout {
    /// A folder a run writes: one of a fixed name ("levels"), or of any name
    /// `isName` accepts (the "0", "1", ... inside levels/), holding what
    /// `contents` lists.
    struct Folder {
        std::string name;  // empty: any name isName accepts
        std::function<bool(const std::string&)> isName;
        std::shared_ptr<const OutputLayout> contents;
    };

    std::vector<std::string> files;
    std::vector<Folder> folders;

    OutputLayout() = default;
    /// A layout of plain files only.
    OutputLayout(std::initializer_list<std::string> fileNames) : files(fileNames) {}

    /// The fixed names, files first, then folders.
    std::vector<std::string> names() const;
};

/// The first entry at or below `directory / name` that a run writing
/// `layout` into `directory` would not have written there, or nullopt when
/// all of it is such a run's (or nothing of that name exists, or `layout`
/// does not list `name`). That is `directory / name` itself when it is not of
/// the kind a run writes (a folder where a run writes a file; anything but a
/// folder, a symbolic link included, where a run writes a folder), else the
/// first unknown entry inside, in name order. A folder that cannot be listed
/// counts as foreign: what cannot be seen is not replaced.
std::optional<std::filesystem::path> foreignEntry(const std::filesystem::path& directory,
                                                  const std::string& name,
                                                  const OutputLayout& layout);

}  // namespace skelseg
