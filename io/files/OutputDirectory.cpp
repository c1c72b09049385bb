#include "io/files/OutputDirectory.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <system_error>

#include "kernels/base/Error.h"

namespace fs = std::filesystem;

namespace skelseg {

namespace {
std::string uniqueSuffix() {
    static std::atomic<unsigned> counter{0};
    return std::to_string(::getpid()) + "-" + std::to_string(counter++);
}
}  // namespace

OutputDirectory::OutputDirectory(const fs::path& outdir, bool force,
                                 const std::vector<std::string>& outputNames)
    : mDirectory(outdir) {
    std::error_code ec;
    checkOutputDirectoryPath(outdir);
    if (!force) {
        for (const auto& name : outputNames)
            if (fs::exists(outdir / name, ec))
                throw UsageError(outdir.string() + ": holds results of an earlier run (" + name +
                                 "); use --force to replace them");
    }
    // Remember which directories this run creates: a run that fails removes
    // them again (if still empty), so bad input leaves no trace.
    // symlink_status: a link is the user's, wherever it points.
    for (fs::path p = outdir; !p.empty() && !fs::exists(fs::symlink_status(p, ec));
         p = p.parent_path()) {
        mCreated.push_back(p);
        if (p == p.parent_path()) break;
    }
    fs::create_directories(outdir, ec);
    if (ec) {
        removeCreatedDirectories();
        throw OutputError(outdir.string() + ": cannot create directory: " + ec.message());
    }
    mStaging = outdir / (".skelseg-staging-" + uniqueSuffix());
    fs::create_directory(mStaging, ec);
    if (ec) {
        const std::string problem = ec.message();
        mStaging.clear();
        removeCreatedDirectories();
        throw OutputError(outdir.string() +
                          ": cannot create a staging directory in it: " + problem);
    }
}

void OutputDirectory::removeCreatedDirectories() noexcept {
    std::error_code ec;
    // Deepest first; fs::remove() only removes empty directories.
    for (const auto& directory : mCreated) fs::remove(directory, ec);
    mCreated.clear();
}

OutputDirectory::~OutputDirectory() {
    discard();
}

fs::path OutputDirectory::stagingPath(const std::string& name) {
    // Writers run concurrently in the output flow graph: an unguarded
    // push_back here is a data race (it crashed PSB runs, docs/performance.md).
    const std::lock_guard<std::mutex> lock(mStagedMutex);
    if (std::find(mStaged.begin(), mStaged.end(), name) == mStaged.end()) mStaged.push_back(name);
    return mStaging / name;
}

void OutputDirectory::removeOnCommit(const std::string& name) {
    const std::lock_guard<std::mutex> lock(mStagedMutex);
    mObsolete.push_back(name);
}

void OutputDirectory::commit() {
    const std::lock_guard<std::mutex> lock(mStagedMutex);
    std::error_code ec;
    for (const auto& name : mObsolete)
        if (std::find(mStaged.begin(), mStaged.end(), name) == mStaged.end()) {
            fs::remove_all(mDirectory / name, ec);
            if (ec)
                throw OutputError((mDirectory / name).string() +
                                  ": cannot remove the earlier run's output: " + ec.message());
        }
    for (const auto& name : mStaged) {
        const fs::path from = mStaging / name;
        if (!fs::exists(from, ec)) continue;  // an optional output that was not produced
        // A staged directory (levels/) replaces the earlier run's whole:
        // rename(2) does not replace a non-empty directory.
        if (fs::is_directory(from, ec) && fs::is_directory(mDirectory / name, ec))
            fs::remove_all(mDirectory / name, ec);
        fs::rename(from, mDirectory / name, ec);
        if (ec)
            throw OutputError((mDirectory / name).string() +
                              ": cannot move into place: " + ec.message());
    }
    mCommitted = true;
    fs::remove_all(mStaging, ec);
}

void OutputDirectory::discard() noexcept {
    std::error_code ec;
    if (!mStaging.empty()) fs::remove_all(mStaging, ec);
    {
        const std::lock_guard<std::mutex> lock(mStagedMutex);
        mStaged.clear();
    }
    if (!mCommitted) removeCreatedDirectories();
}

namespace {

/// `inner` lies at or below `outer` (both made absolute, symlinks resolved
/// where they exist).
bool isWithin(const fs::path& inner, const fs::path& outer) {
    std::error_code ec;
    const fs::path a = fs::weakly_canonical(inner, ec), b = fs::weakly_canonical(outer, ec);
    auto ia = a.begin(), ib = b.begin();
    for (; ib != b.end(); ++ia, ++ib)
        if (ia == a.end() || *ia != *ib) return false;
    return true;
}

}  // namespace

void checkOutputDirectoryPath(const fs::path& outdir) {
    std::error_code ec;
    if (fs::is_symlink(fs::symlink_status(outdir, ec)) && !fs::exists(outdir, ec)) {
        const fs::path target = fs::read_symlink(outdir, ec);
        throw UsageError(outdir.string() + ": is a symbolic link to " + target.string() +
                         ", which does not exist");
    }
    if (fs::exists(outdir, ec) && !fs::is_directory(outdir, ec))
        throw UsageError(outdir.string() + ": exists and is not a directory");
}

std::string outputReplacing(const fs::path& file, const fs::path& outdir,
                            const std::vector<std::string>& outputNames) {
    for (const std::string& name : outputNames) {
        std::error_code ec;
        // equivalent() also catches a hard link to an output.
        if (fs::equivalent(file, outdir / name, ec) || isWithin(file, outdir / name)) return name;
    }
    return {};
}

void writeFileAtomically(const fs::path& path, const std::string& bytes) {
    const fs::path parent = path.has_parent_path() ? path.parent_path() : fs::path(".");
    const fs::path temp = parent / ("." + path.filename().string() + ".tmp-" + uniqueSuffix());
    {
        std::ofstream out(temp, std::ios::binary | std::ios::trunc);
        if (!out) throw OutputError(path.string() + ": cannot write: " + std::strerror(errno));
        out.write(bytes.data(), std::streamsize(bytes.size()));
        out.flush();
        if (!out) {
            std::error_code ec;
            fs::remove(temp, ec);
            throw OutputError(path.string() + ": write failed (disk full?)");
        }
    }
    std::error_code ec;
    fs::rename(temp, path, ec);
    if (ec) {
        fs::remove(temp, ec);
        throw OutputError(path.string() + ": cannot move into place: " + ec.message());
    }
}

}  // namespace skelseg
