#include "engine/batch/Manifest.h"

#include <glob.h>
#include <limits.h>
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <functional>
#include <map>
#include <numeric>
#include <queue>
#include <regex>
#include <set>
#include <tuple>

#include "engine/SegmentCommand.h"
#include "engine/batch/DoneMarker.h"
#include "io/files/CsvRecords.h"
#include "io/files/OutputDirectory.h"
#include "io/files/TextFile.h"
#include "kernels/base/Error.h"

namespace fs = std::filesystem;

namespace skelseg {

namespace {

std::string lowerExtension(const fs::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

std::string trim(const std::string& text) {
    const auto first = text.find_first_not_of(" \t\r\n");
    if (first == std::string::npos) return {};
    const auto last = text.find_last_not_of(" \t\r\n");
    return text.substr(first, last - first + 1);
}

/// Whether a listed path stands in matching double or single quotes.
bool isQuoted(const std::string& listed) {
    return listed.size() >= 3 && (listed.front() == '"' || listed.front() == '\'') &&
           listed.back() == listed.front();
}

/// A listed path as the batch opens it. A path in matching quotes ("my
/// shapes/a.off" or 'a.off', as a shell or a script writing paths with
/// spaces quotes them) means the path inside them, unless a file of that
/// name, quotes included, exists.
fs::path resolveListedPath(const fs::path& base, const std::string& listed) {
    const auto resolved = [&](const std::string& text) {
        const fs::path path(text);
        return path.is_absolute() ? path : base / path;
    };
    if (!isQuoted(listed)) return resolved(listed);
    std::error_code ec;
    const fs::path literal = resolved(listed);
    if (fs::exists(literal, ec)) return literal;
    return resolved(listed.substr(1, listed.size() - 2));
}

/// The identity of a file for duplicate detection: its device and inode
/// when it exists (hard and symbolic links and "a/../b" spellings agree),
/// the lexically normal absolute path otherwise.
std::string identityOf(const fs::path& path) {
    struct stat status {};
    if (::stat(path.c_str(), &status) == 0)
        return "inode " + std::to_string(status.st_dev) + ":" + std::to_string(status.st_ino);
    std::error_code ec;
    fs::path canonical = fs::weakly_canonical(path, ec);
    if (ec) canonical = fs::absolute(path, ec).lexically_normal();
    return canonical.string();
}

int parseIntegerVariable(const char* name, const char* text) {
    try {
        std::size_t used = 0;
        const long value = std::stol(text, &used);
        if (used == std::string(text).size() && value >= 0 && value < (1L << 30)) return int(value);
    } catch (const std::exception&) {
    }
    throw UsageError(std::string(name) + "='" + text + "' is not a non-negative integer");
}

/// The longest file name Linux file systems take (NAME_MAX): a longer output
/// folder cannot be created, and the input would fail for its name alone.
constexpr std::size_t kMaxOutputNameBytes = 255;

/// `text` cut to at most `bytes` bytes, never inside a UTF-8 sequence.
std::string cutToBytes(const std::string& text, std::size_t bytes) {
    if (text.size() <= bytes) return text;
    std::size_t end = bytes;
    while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80) --end;
    return text.substr(0, end);
}

/// The files the batch writes beside the output folders: an input named
/// like one of them would find a file where its folder goes (the lock file
/// of engine/batch/BatchLock.h included).
bool isBatchFileName(const std::string& name) {
    static const std::regex summaryName(
        R"(summary(\.shard-\d+-of-\d+)?\.(json|csv)|\.summary(\.shard-\d+-of-\d+)?\.lock)");
    return std::regex_match(name, summaryName);
}

}  // namespace

bool isSupportedInputPath(const fs::path& path) {
    static const std::set<std::string> extensions = {".nrrd", ".nhdr", ".binvox", ".vdb",
                                                     ".off",  ".obj",  ".stl",    ".ply"};
    return extensions.count(lowerExtension(path)) != 0;
}

namespace {

/// The folder names of `path` from the innermost out ("." and ".." and the
/// root left out).
std::vector<std::string> foldersInnermostFirst(const fs::path& path) {
    std::vector<std::string> folders;
    for (const auto& part : path.lexically_normal().parent_path()) {
        const std::string name = part.string();
        if (!name.empty() && name != "." && name != ".." && name != "/") folders.push_back(name);
    }
    std::reverse(folders.begin(), folders.end());
    return folders;
}

}  // namespace

std::vector<std::string> uniqueOutputNames(const std::vector<fs::path>& inputs) {
    std::vector<std::string> stems(inputs.size());
    std::map<std::string, std::vector<std::size_t>> sameStem;
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        stems[i] = inputs[i].stem().string();
        if (stems[i].empty() || stems[i] == "." || stems[i] == "..") stems[i] = "input";
        sameStem[stems[i]].push_back(i);
    }
    std::vector<std::string> names = stems;
    // Inputs that share a stem get as many of their innermost folders in
    // front as tell each apart from the others of that stem: the names depend
    // on which inputs the manifest lists, not on their order.
    for (const auto& [stem, group] : sameStem) {
        if (group.size() < 2) continue;
        std::vector<std::vector<std::string>> folders;
        std::size_t deepest = 0;
        for (const std::size_t i : group) {
            folders.push_back(foldersInnermostFirst(inputs[i]));
            deepest = std::max(deepest, folders.back().size());
        }
        // The key of an input at `depth` folders: those folders, or all of
        // them, marked, when it has fewer (only such an input can equal it).
        const auto keyAt = [&](std::size_t member, std::size_t depth) {
            const auto& mine = folders[member];
            std::string key = depth > mine.size() ? "\n" : "";
            for (std::size_t d = 0; d < std::min(depth, mine.size()); ++d) key += mine[d] + "/";
            return key;
        };
        std::vector<std::size_t> depthOf(group.size(), 0);
        std::vector<bool> told(group.size(), false);
        for (std::size_t depth = 1; depth <= deepest; ++depth) {
            std::map<std::string, int> count;
            for (std::size_t m = 0; m < group.size(); ++m) ++count[keyAt(m, depth)];
            for (std::size_t m = 0; m < group.size(); ++m)
                if (!told[m] && count[keyAt(m, depth)] == 1) {
                    told[m] = true;
                    depthOf[m] = depth;
                }
        }
        for (std::size_t m = 0; m < group.size(); ++m) {
            // Inputs no folder tells apart (3.off and 3.obj) take all their
            // folders, and the counter below.
            const std::size_t depth = told[m] ? depthOf[m] : std::min(deepest, folders[m].size());
            std::string prefix;
            for (std::size_t d = std::min(depth, folders[m].size()); d-- > 0;)
                prefix += folders[m][d] + (d ? "-" : "");
            // The stem is what tells inputs apart: long folder names are cut, not it.
            if (!prefix.empty() && stem.size() + 1 < kMaxOutputNameBytes)
                names[group[m]] =
                    cutToBytes(prefix, kMaxOutputNameBytes - 1 - stem.size()) + "-" + stem;
        }
    }
    // Still equal (no folder tells them apart, or cut to the same bytes), or
    // equal to another stem's name: the first keeps the name,
    // later ones get a counter in manifest order, skipping names that
    // another input has. The batch's own files count as taken.
    std::set<std::string> firstPass(names.begin(), names.end()), taken;
    for (const auto& name : names)
        if (isBatchFileName(name)) taken.insert(name);
    // An input named by its stem alone claims its name before an input
    // whose folders made the same name: b-c.off keeps "b-c" and a/b/c.off
    // (b-c beside a-b/c.off) takes "b-c-2". In manifest order the first of
    // them kept it, so the same inputs listed in another order swapped the
    // two names and were refused as each other's results.
    std::vector<std::size_t> claimOrder(names.size());
    std::iota(claimOrder.begin(), claimOrder.end(), std::size_t(0));
    std::stable_partition(claimOrder.begin(), claimOrder.end(),
                          [&](std::size_t i) { return names[i] == stems[i]; });
    // The counter each name reached: candidates below it are taken for good,
    // so a manifest of thousands of equal names costs no quadratic search.
    std::map<std::string, int> nextCounter;
    for (const std::size_t i : claimOrder) {
        std::string& name = names[i];
        if (!taken.count(name)) {
            taken.insert(name);
            continue;
        }
        std::string candidate;
        int& counter = nextCounter.emplace(name, 2).first->second;
        for (;; ++counter) {
            const std::string suffix = "-" + std::to_string(counter);
            candidate = cutToBytes(name, kMaxOutputNameBytes - suffix.size()) + suffix;
            if (!taken.count(candidate) && !firstPass.count(candidate)) break;
        }
        taken.insert(candidate);
        name = candidate;
    }
    return names;
}

namespace {

/// True for an output of a batch: a file `skelseg segment` writes
/// (labels.nrrd, cuts.ply, levels/0/labels.nrrd, ...) in a folder that holds
/// a batch's done or pending marker. A pattern such as data/*/* with
/// OUTROOT data/res matched the outputs of every done input on the next
/// run: the batch refused to start, and another batch's outputs were
/// segmented as inputs.
bool isBatchOutputFile(const fs::path& file) {
    const fs::path parent = file.parent_path();
    std::vector<fs::path> folders = {parent};
    if (parent.parent_path().filename() == "levels")
        folders.push_back(parent.parent_path().parent_path());
    for (const fs::path& folder : folders) {
        if (folder.empty() ||
            (!readDoneMarker(folder) && !readDoneMarker(folder, kPendingMarkerName)))
            continue;
        if (!outputReplacing(file, folder, segmentOutputNames()).empty()) return true;
    }
    return false;
}

/// The supported input files directly in `directory`, by name.
/// @throw InputError naming the directory if it cannot be listed.
std::vector<fs::path> supportedFilesIn(const fs::path& directory) {
    std::error_code ec;
    std::vector<fs::path> files;
    // Hidden files are left out, as a shell's * leaves them out: "._a.off"
    // is the resource fork a Mac writes beside a.off on a shared disk. So
    // are a batch's outputs: they are not shapes to segment.
    for (const auto& item : fs::directory_iterator(directory, ec))
        if (item.path().filename().string().front() != '.' && item.is_regular_file(ec) &&
            isSupportedInputPath(item.path()) && !isBatchOutputFile(item.path()))
            files.push_back(item.path());
    if (ec) throw InputError(directory.string(), "cannot list the directory: " + ec.message());
    std::sort(files.begin(), files.end());
    return files;
}

bool hasWildcard(const std::string& path) {
    return path.find_first_of("*?[") != std::string::npos;
}

/// The glob(3) pattern of a listed path with wildcards: the path inside its
/// quotes, joined to the manifest's folder with that folder's own wildcard
/// characters escaped (a folder named "[2026]" is a name, not a pattern).
std::string globPatternOf(const fs::path& base, std::string listed) {
    if (isQuoted(listed)) listed = listed.substr(1, listed.size() - 2);
    if (fs::path(listed).is_absolute() || base.empty()) return listed;
    std::string escaped;
    for (const char c : base.string()) {
        if (c == '*' || c == '?' || c == '[' || c == '\\') escaped += '\\';
        escaped += c;
    }
    return escaped + "/" + listed;
}

/// The supported input files a shell pattern names (glob(3), no brace or
/// tilde expansion), by name; a folder it names stands for its files.
std::vector<fs::path> supportedFilesMatching(const std::string& pattern) {
    glob_t matches{};
    const int status = ::glob(pattern.c_str(), 0, nullptr, &matches);
    std::vector<fs::path> found;
    if (status == 0)
        for (std::size_t i = 0; i < matches.gl_pathc; ++i) found.emplace_back(matches.gl_pathv[i]);
    ::globfree(&matches);
    if (status != 0 && status != GLOB_NOMATCH)
        throw InputError(pattern, "cannot expand the pattern");
    std::sort(found.begin(), found.end());
    std::vector<fs::path> files;
    std::error_code ec;
    for (const auto& path : found) {
        if (fs::is_directory(path, ec)) {
            const std::vector<fs::path> inside = supportedFilesIn(path);
            files.insert(files.end(), inside.begin(), inside.end());
        } else if (fs::is_regular_file(path, ec) && isSupportedInputPath(path) &&
                   !isBatchOutputFile(path)) {
            files.push_back(path);
        }
    }
    return files;
}

/// Why a listed path that names no file may have been meant otherwise, or
/// empty: a line a shell would have expanded (~, $HOME), or a path that is
/// relative to the working directory rather than to the manifest's folder
/// (`ls data/*.off > /tmp/list.txt` lists data/a.off, read as
/// /tmp/data/a.off). Every such input failed with "no such file" and a path
/// the user never wrote.
std::string missingPathNote(const fs::path& base, const std::string& listed) {
    const std::string text = isQuoted(listed) ? listed.substr(1, listed.size() - 2) : listed;
    if (!text.empty() && (text[0] == '~' || text.find('$') != std::string::npos))
        return "a manifest's paths are not expanded as a shell expands them: ~ and $NAME are "
               "part of the name; write the path out";
    std::error_code ec;
    if (fs::path(text).is_absolute() || base.empty() || !fs::is_regular_file(text, ec)) return {};
    return "relative paths are read from the manifest's folder, " + base.string() + "; " + text +
           " is a file from the working directory: list it as " +
           fs::absolute(text, ec).lexically_normal().string();
}

/// A manifest named *.csv whose first record names a path column: each
/// later record's field in that column is a listed path (addListed), as a
/// line is in a text manifest. false: no such file, read line by line (a
/// .csv listing one path per line). The column is the first of path, input,
/// file, filename, file_name, filepath, file_path, mesh, volume, shape
/// (any case) in the header; a summary.csv of an earlier batch names its
/// inputs "input" (as that batch read them: relative ones are relative to
/// the folder it ran in).
bool readCsvManifest(const fs::path& source, std::string_view text,
                     const std::function<void(int, const std::string&)>& addListed,
                     std::vector<std::string>& warnings) {
    if (lowerExtension(source) != ".csv" || text.find('\0') != std::string_view::npos) return false;
    const std::vector<CsvRecord> records = readCsvRecords(source.string(), text);
    const auto blank = [](const CsvRecord& r) {
        return std::all_of(r.fields.begin(), r.fields.end(),
                           [](const std::string& f) { return trim(f).empty(); });
    };
    const auto comment = [](const CsvRecord& r) {
        return !r.fields.empty() && trim(r.fields[0]).rfind('#', 0) == 0;
    };
    std::size_t header = 0;
    while (header < records.size() && (blank(records[header]) || comment(records[header])))
        ++header;
    if (header == records.size()) return false;
    std::vector<std::string> names;
    for (const std::string& field : records[header].fields) {
        std::string name = trim(field);
        std::transform(name.begin(), name.end(), name.begin(),
                       [](unsigned char c) { return char(std::tolower(c)); });
        names.push_back(name);
    }
    std::size_t column = names.size();
    for (const char* wanted : {"path", "input", "file", "filename", "file_name", "filepath",
                               "file_path", "mesh", "volume", "shape"}) {
        column = std::size_t(std::find(names.begin(), names.end(), wanted) - names.begin());
        if (column < names.size()) break;
    }
    if (column == names.size()) {
        // Several columns and none named: the rows' commas would be read as
        // parts of paths, and every row would fail as a missing file.
        std::error_code ec;
        std::size_t lineStart = 0;
        for (int line = 1; line < records[header].line; ++line)
            lineStart = text.find('\n', lineStart) + 1;
        const std::string firstLine =
            trim(std::string(text.substr(lineStart, text.find('\n', lineStart) - lineStart)));
        if (names.size() > 1 && !fs::exists(resolveListedPath(source.parent_path(), firstLine), ec))
            throw InputError(source.string(),
                             "line " + std::to_string(records[header].line) +
                                 ": a CSV manifest's first line names its path column (path, "
                                 "input or file); this one names none: " +
                                 cutToBytes(firstLine, 200));
        return false;
    }
    for (std::size_t r = header + 1; r < records.size(); ++r) {
        const CsvRecord& record = records[r];
        if (blank(record) || comment(record)) continue;
        const std::string path = column < record.fields.size() ? trim(record.fields[column]) : "";
        if (path.empty()) {
            warnings.push_back(source.string() + ":" + std::to_string(record.line) +
                               ": no path in column '" + trim(records[header].fields[column]) +
                               "'; row skipped");
            continue;
        }
        addListed(record.line, path);
    }
    return true;
}

}  // namespace

Manifest readManifest(const fs::path& source) {
    Manifest manifest;
    manifest.source = source;
    std::error_code ec;
    std::vector<std::pair<fs::path, int>> listed;
    std::map<std::size_t, std::string> missingNotes;  // by index into listed
    if (fs::is_directory(source, ec)) {
        for (const auto& file : supportedFilesIn(source)) listed.emplace_back(file, 0);
    } else {
        // A shape given where the manifest goes would read as a list of
        // garbage paths, each a failed input.
        if (isSupportedInputPath(source))
            throw InputError(source.string(),
                             "is an input file, not a manifest (segment it with skelseg segment, "
                             "or list its path in a text file)");
        // `find ... | skelseg batch -` and `skelseg batch <(ls *.off)` were
        // "-: no such file" and "/dev/fd/63: is not a regular file". A list
        // read once cannot serve the re-runs and shards that read it again.
        const fs::file_type type = fs::status(source, ec).type();
        if ((source == "-" && type == fs::file_type::not_found) || type == fs::file_type::fifo ||
            type == fs::file_type::character)
            throw InputError(source.string(),
                             std::string(source == "-" ? "standard input is not read as a manifest"
                                                       : "is a pipe or a device, not a file") +
                                 "; write the list to a file and give its path (a re-run and "
                                 "every shard read the manifest again)");
        const std::string bytes = readFileBytes(source);
        std::string_view text(bytes);
        text.remove_prefix(textContentStart(source.string(), text));
        const fs::path base = source.parent_path();
        // One listed path (a line, or a CSV record's path field) as the
        // inputs it stands for.
        const auto addListed = [&](int line, const std::string& path) {
            // A path longer than the system takes names no file; as an input
            // it was echoed in every message and summary (a line of 50 MB
            // wrote 350 MB of them).
            if (path.size() >= PATH_MAX)
                throw InputError(source.string(), "line " + std::to_string(line) + " is " +
                                                      std::to_string(path.size()) +
                                                      " bytes long, longer than any path (" +
                                                      std::to_string(PATH_MAX - 1) +
                                                      " bytes): not a manifest");
            const fs::path resolved = resolveListedPath(base, path);
            // A pattern stands for the shapes it matches, unless a file of
            // that very name exists; a folder for its shapes, as when it is
            // the manifest. Either with none is a warning, not an input.
            const bool pattern = hasWildcard(path) && !fs::exists(resolved, ec);
            if (pattern || fs::is_directory(resolved, ec)) {
                const std::vector<fs::path> files =
                    pattern ? supportedFilesMatching(globPatternOf(base, path))
                            : supportedFilesIn(resolved);
                // A folder a pattern matched is not recorded: `*` beside
                // OUTROOT matched OUTROOT on every run after the first, which
                // was then refused as a line naming OUTROOT.
                if (!pattern) manifest.listedFolders.emplace_back(resolved, line);
                if (files.empty())
                    manifest.warnings.push_back(
                        source.string() + ":" + std::to_string(line) + ": " + resolved.string() +
                        (pattern ? " matches no supported input file"
                                 : " is a directory holding no supported input file") +
                        "; nothing to do for it");
                for (const auto& file : files) listed.emplace_back(file, line);
                return;
            }
            if (!fs::exists(resolved, ec))
                missingNotes[listed.size()] = missingPathNote(base, path);
            listed.emplace_back(resolved, line);
        };
        if (!readCsvManifest(source, text, addListed, manifest.warnings)) {
            std::size_t start = 0, contentLines = 0;
            for (int line = 1; start < text.size(); ++line) {
                std::size_t end = text.find('\n', start);
                if (end == std::string_view::npos) end = text.size();
                const std::string_view rawLine = text.substr(start, end - start);
                start = end + 1;
                // No path holds a NUL byte: this is binary data, not a list.
                if (rawLine.find('\0') != std::string_view::npos)
                    throw InputError(source.string(), "line " + std::to_string(line) +
                                                          " holds a NUL byte: not a text manifest");
                const std::string path = trim(std::string(rawLine));
                if (path.empty()) continue;
                if (path[0] == '#') {
                    // `ls > list.txt` lists "#1.off" as it is, and the line
                    // read as a comment dropped the shape without a word.
                    if (isSupportedInputPath(path) &&
                        fs::is_regular_file(resolveListedPath(base, path), ec))
                        manifest.warnings.push_back(
                            source.string() + ":" + std::to_string(line) + ": " + path +
                            " is a comment, though a shape of that name exists; write ./" + path +
                            " to segment it");
                    continue;
                }
                // A JSON list of paths had its quoted lines without a comma
                // read as paths and the others failed as missing files: half
                // a batch.
                if (++contentLines == 1 && (path == "[" || path == "{" ||
                                            path.rfind("[\"", 0) == 0 || path.rfind("{\"", 0) == 0))
                    throw InputError(source.string(),
                                     "line " + std::to_string(line) + " starts with '" +
                                         path.substr(0, 1) +
                                         "': this looks like JSON, and a manifest is a text file "
                                         "with one path per line");
                addListed(line, path);
            }
        }
    }
    std::map<std::string, int> firstLine;
    std::vector<fs::path> inputs;
    for (std::size_t index = 0; index < listed.size(); ++index) {
        const auto& [path, line] = listed[index];
        const auto [at, inserted] = firstLine.emplace(identityOf(path), line);
        if (!inserted) {
            manifest.warnings.push_back(source.string() + ":" + std::to_string(line) + ": " +
                                        path.string() + " is listed again (first on line " +
                                        std::to_string(at->second) + "); processed once");
            continue;
        }
        ManifestEntry entry;
        entry.input = path.lexically_normal();
        entry.line = line;
        entry.exists = fs::is_regular_file(path, ec);
        if (const auto note = missingNotes.find(index); note != missingNotes.end() && !entry.exists)
            entry.missingNote = note->second;
        entry.fileBytes = entry.exists ? fs::file_size(path, ec) : 0;
        if (ec) entry.fileBytes = 0;
        // Named by the absolute path: the folders that tell two inputs apart
        // do not depend on how the manifest spells them ("../a.off").
        fs::path absolute = fs::absolute(entry.input, ec);
        inputs.push_back(ec ? entry.input : absolute.lexically_normal());
        manifest.entries.push_back(std::move(entry));
    }
    if (manifest.entries.empty())
        throw InputError(source.string(), fs::is_directory(source, ec)
                                              ? "the directory holds no supported input file"
                                              : "the manifest lists no input");
    const std::vector<std::string> names = uniqueOutputNames(inputs);
    for (std::size_t i = 0; i < names.size(); ++i) manifest.entries[i].name = names[i];
    return manifest;
}

std::vector<int> assignShards(const std::vector<std::uint64_t>& sizes, int shardCount) {
    if (shardCount < 1) throw UsageError("the number of shards must be at least 1");
    std::vector<std::size_t> order(sizes.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return sizes[a] > sizes[b]; });
    // Counts break ties between equal loads, so zero-size inputs (missing
    // files) spread too; the lowest index breaks the remaining ties. With
    // more shares than inputs the k-th largest input goes to share k either
    // way, so only as many shares as inputs are weighed: a count of 10^9 (a
    // typo, or a Slurm array of that size) made two tables of a billion
    // entries (docs/robustness.md). The least loaded share comes from a heap:
    // a scan of every share per input made the split quadratic for arrays of
    // as many tasks as inputs, and every task computes it (docs/scale-out.md).
    const std::size_t weighed =
        std::max<std::size_t>(1, std::min(std::size_t(shardCount), sizes.size()));
    using Share = std::tuple<std::uint64_t, std::size_t, std::size_t>;  // load, count, index
    std::priority_queue<Share, std::vector<Share>, std::greater<Share>> shares;
    for (std::size_t s = 0; s < weighed; ++s) shares.emplace(0, 0, s);
    std::vector<int> shard(sizes.size(), 0);
    for (std::size_t i : order) {
        auto [load, count, best] = shares.top();
        shares.pop();
        shard[i] = int(best);
        shares.emplace(load + sizes[i], count + 1, best);
    }
    return shard;
}

ShardSpec ShardSpec::parse(const std::string& given) {
    // Blanks around the value are a script's, as in a manifest line; inside
    // it (or a sign) it is not I/N. stoi() skipped blanks before a number
    // only, so " 0/2" was taken and "0/2 " refused.
    const std::string text = trim(given);
    const auto slash = text.find('/');
    ShardSpec spec;
    try {
        if (slash == std::string::npos) throw std::invalid_argument("no slash");
        if (text.find_first_not_of("0123456789/") != std::string::npos)
            throw std::invalid_argument("not digits");
        std::size_t usedIndex = 0, usedCount = 0;
        spec.index = std::stoi(text.substr(0, slash), &usedIndex);
        spec.count = std::stoi(text.substr(slash + 1), &usedCount);
        if (usedIndex != slash || usedCount != text.size() - slash - 1)
            throw std::invalid_argument("trailing text");
    } catch (const std::exception&) {
        throw UsageError("--shard '" + given + "' is not I/N (e.g. 0/4: the first of four shares)");
    }
    if (spec.count < 1 || spec.index < 0 || spec.index >= spec.count)
        throw UsageError("--shard '" + given + "': need 0 <= I < N");
    return spec;
}

std::string ShardSpec::toString() const {
    return std::to_string(index) + "/" + std::to_string(count);
}

std::string ShardSpec::summaryStem() const {
    if (count == 1) return "summary";
    return "summary.shard-" + std::to_string(index) + "-of-" + std::to_string(count);
}

std::optional<ShardSpec> shardFromEnvironment(
    const std::function<const char*(const char*)>& environment, int shardsOption) {
    auto value = [&](const char* name) -> std::optional<int> {
        const char* text = environment(name);
        if (!text || !*text) return std::nullopt;
        return parseIntegerVariable(name, text);
    };
    // An array variable without its task id (set but empty, or the id
    // missing) would run the whole manifest in every task of the array.
    for (const char* name : {"SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"}) {
        const char* text = environment(name);
        if (text && !*text)
            throw UsageError(std::string(name) + " is set but empty; pass --shard I/N");
    }
    if (!environment("SLURM_ARRAY_TASK_ID"))
        for (const char* name :
             {"SLURM_ARRAY_TASK_COUNT", "SLURM_ARRAY_TASK_MIN", "SLURM_ARRAY_TASK_MAX"})
            if (const char* text = environment(name); text && *text)
                throw UsageError(std::string(name) +
                                 " is set but SLURM_ARRAY_TASK_ID is not; pass --shard I/N");
    if (const auto task = value("SLURM_ARRAY_TASK_ID")) {
        const int minimum = value("SLURM_ARRAY_TASK_MIN").value_or(0);
        const int step = std::max(1, value("SLURM_ARRAY_TASK_STEP").value_or(1));
        std::optional<int> count = value("SLURM_ARRAY_TASK_COUNT");
        if (!count) {
            const auto maximum = value("SLURM_ARRAY_TASK_MAX");
            if (!maximum)
                throw UsageError(
                    "SLURM_ARRAY_TASK_ID is set but neither SLURM_ARRAY_TASK_COUNT nor "
                    "SLURM_ARRAY_TASK_MAX is; pass --shard I/N");
            count = (*maximum - minimum) / step + 1;
        }
        ShardSpec spec;
        spec.index = (*task - minimum) / step;
        spec.count = *count;
        if (*task < minimum || spec.index >= spec.count)
            throw UsageError("Slurm array task " + std::to_string(*task) +
                             " is outside the array (min " + std::to_string(minimum) + ", count " +
                             std::to_string(*count) + ")");
        // Between two steps the division took the share of the task below:
        // two tasks did one share and none did the other.
        if ((*task - minimum) % step != 0)
            throw UsageError(
                "SLURM_ARRAY_TASK_ID=" + std::to_string(*task) +
                " is not on the array's steps (SLURM_ARRAY_TASK_MIN=" + std::to_string(minimum) +
                ", SLURM_ARRAY_TASK_STEP=" + std::to_string(step) +
                "): the ids are MIN + k * STEP; pass --shard I/N");
        return spec;
    }
    if (const auto index = value("JOB_COMPLETION_INDEX")) {
        if (shardsOption < 1)
            throw UsageError(
                "JOB_COMPLETION_INDEX is set: pass --shards N (the Job's completions) too");
        if (*index >= shardsOption)
            throw UsageError("JOB_COMPLETION_INDEX=" + std::to_string(*index) +
                             " is not below --shards " + std::to_string(shardsOption));
        return ShardSpec{*index, shardsOption};
    }
    return std::nullopt;
}

}  // namespace skelseg
