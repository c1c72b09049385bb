// skelseg: the existing files that a run's outputs would replace or remove,
// known by identity rather than by name.
//
// --force replaces the outputs of an earlier run, and a run must never
// replace what it reads. Comparing paths (outputReplacing() in
// io/files/OutputDirectory.h, symbolic links resolved) misses every other
// name of the same file: a hard link, OUTDIR seen through a bind mount, an NFS
// export mounted twice. The identity of a file, its device and inode numbers
// (stat(2)), is the same through all of them. So ReplacedOutputs records the
// identity of each existing output and of everything inside an output folder
// (levels/, frames/), and an input is looked up by the identity of the file
// it reads.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace skelseg {

/// A file's identity on this system: st_dev and st_ino, the same through
/// every path that reaches the file.
struct FileIdentity {
    std::uint64_t device = 0;
    std::uint64_t inode = 0;

    bool operator<(const FileIdentity& other) const {
        return device != other.device ? device < other.device : inode < other.inode;
    }
};

/// The identity of the file `path` names, symbolic links followed (the file
/// that opening `path` reads); nullopt where it does not exist or cannot be
/// examined.
std::optional<FileIdentity> fileIdentity(const std::filesystem::path& path);

/// The identities of the entries that writing outputs into output folders
/// would replace or remove, each with the output folder's owner and the entry's
/// path relative to that folder ("levels/0/labels.nrrd").
class ReplacedOutputs {
public:
    /// An entry a run would replace or remove.
    struct Entry {
        std::string owner;  ///< the label given to add() (a batch entry's name)
        std::string
            output;  ///< relative to the output folder: "report.json", "levels/0/labels.nrrd"
    };

    /// Records every existing `outdir`/NAME of `outputNames` (symbolic link
    /// followed, as outputReplacing() resolves it) and, for a folder,
    /// everything beneath it. Links inside a folder are recorded as links, not
    /// followed: removing a link leaves its target. An entry that cannot be
    /// examined (a folder without read permission) is left out; the run fails
    /// on it later without having read anything through it. Where two owners
    /// share an entry, the first recorded is kept.
    void add(const std::filesystem::path& outdir, const std::vector<std::string>& outputNames,
             const std::string& owner = {});

    /// The recorded entry that is the file `file` reads (symbolic links
    /// followed), or nullptr if none is.
    const Entry* find(const std::filesystem::path& file) const;

private:
    std::map<FileIdentity, Entry> mEntries;
};

}  // namespace skelseg
