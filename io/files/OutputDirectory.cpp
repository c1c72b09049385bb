#include "io/files/OutputDirectory.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <climits>
#include <fstream>
#include <system_error>
#include <utility>

#include "io/files/TextFile.h"
#include "kernels/base/Error.h"

namespace fs = std::filesystem;

namespace skelseg {

namespace {
constexpr char kStagingPrefix[] = ".skelseg-staging-";

std::string uniqueSuffix() {
    static std::atomic<unsigned> counter{0};
    return std::to_string(::getpid()) + "-" + std::to_string(counter++);
}

void writeOwnerRecord(const fs::path& staging, std::error_code& ec);
}  // namespace

namespace {

/// The PID of a staging directory's name ".skelseg-staging-PID-N", or -1
/// when the name is not of that form.
long stagingNamePid(const std::string& fileName) {
    if (fileName.rfind(kStagingPrefix, 0) != 0) return -1;
    const std::string rest = fileName.substr(sizeof(kStagingPrefix) - 1);
    const std::size_t dash = rest.find('-');
    const auto isNumber = [](const std::string& text) {
        return !text.empty() && text.size() <= 9 &&
               std::all_of(text.begin(), text.end(),
                           [](unsigned char c) { return std::isdigit(c) != 0; });
    };
    if (dash == std::string::npos || !isNumber(rest.substr(0, dash)) ||
        !isNumber(rest.substr(dash + 1)))
        return -1;
    return std::stol(rest.substr(0, dash));
}

std::string hostName() {
    char name[HOST_NAME_MAX + 1] = {};
    if (::gethostname(name, sizeof(name) - 1) != 0) return "unknown";
    return name;
}

}  // namespace

bool isStagingDirectoryName(const std::string& fileName) {
    return stagingNamePid(fileName) >= 0;
}

std::string stagingOwnerRecord(long pid) {
    return hostName() + " " + std::to_string(pid) + "\n";
}

bool isLiveProcess(long pid) {
    if (pid <= 0) return false;
    // EPERM: it exists, but belongs to another user.
    return ::kill(pid_t(pid), 0) == 0 || errno == EPERM;
}

bool isLeftoverStagingDirectory(const fs::path& path) {
    const long namePid = stagingNamePid(path.filename().string());
    std::error_code ec;
    if (namePid < 0 || !fs::is_directory(fs::symlink_status(path, ec))) return false;
    if (fs::is_empty(path, ec) && !ec) return !isLiveProcess(namePid);
    std::ifstream record(path / kStagingOwnerFileName);
    std::string host;
    long pid = -1;
    if (!(record >> host >> pid) || pid <= 0) return false;  // not ours: a user's folder
    return host != hostName() || !isLiveProcess(pid);
}

namespace {

void writeOwnerRecord(const fs::path& staging, std::error_code& ec) {
    const std::string record = stagingOwnerRecord(long(::getpid()));
    const int fd = ::open((staging / kStagingOwnerFileName).c_str(),
                          O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 || ::write(fd, record.data(), record.size()) != ssize_t(record.size()))
        ec.assign(errno != 0 ? errno : EIO, std::generic_category());
    if (fd >= 0) ::close(fd);
}

}  // namespace

namespace {

/// Throws UsageError naming what no run writes, if `outdir / name` holds any.
void refuseForeignEntry(const fs::path& outdir, const std::string& name,
                        const OutputLayout& layout) {
    const auto foreign = foreignEntry(outdir, name, layout);
    if (!foreign) return;
    const std::string advice = "; move it away or choose another output directory";
    if (*foreign == outdir / name) {
        const bool isFile =
            std::find(layout.files.begin(), layout.files.end(), name) != layout.files.end();
        throw UsageError(foreign->string() + ": not written by skelseg (skelseg writes a " +
                         (isFile ? "file" : "folder") + " of this name), and a run in " +
                         outdir.string() + " replaces it" + advice);
    }
    throw UsageError(foreign->string() + ": not written by skelseg, but inside " + name +
                     "/, which a run in " + outdir.string() + " replaces" + advice);
}

}  // namespace

void checkEarlierOutputs(const fs::path& outdir, const OutputLayout& layout, bool force) {
    const std::vector<std::string> names = layout.names();
    // What is the user's first, so that no message calls it an earlier result.
    for (const auto& name : names) refuseForeignEntry(outdir, name, layout);
    if (force) return;
    std::error_code ec;
    for (const auto& name : names)
        if (fs::exists(fs::symlink_status(outdir / name, ec)))
            throw UsageError(outdir.string() + ": holds results of an earlier run (" + name +
                             "); use --force to replace them");
}

OutputDirectory::OutputDirectory(const fs::path& outdir, bool force, OutputLayout layout,
                                 std::shared_ptr<const DirectoryLock> heldLock)
    : mDirectory(outdir), mLayout(std::move(layout)), mLock(std::move(heldLock)) {
    std::error_code ec;
    checkOutputDirectoryPath(outdir);
    auto refuseEarlierResults = [&] { checkEarlierOutputs(outdir, mLayout, force); };
    refuseEarlierResults();
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
        throw OutputError(outdir.string() +
                          ": cannot create directory: " + describeErrno(ec.value()));
    }
    try {
        if (!mLock) {
            try {
                mLock = std::make_shared<const DirectoryLock>(outdir);
            } catch (const UsageError&) {
                // The other run may have created OUTDIR a moment ago: it is
                // not ours to remove.
                mCreated.clear();
                throw;
            }
        }
        if (mLock->isHeld()) {
            // A run that committed between the check above and the lock.
            refuseEarlierResults();
            // Locked: no live run stages here, so these are a killed run's.
            std::vector<fs::path> leftovers;
            for (const auto& item : fs::directory_iterator(outdir, ec))
                if (isLeftoverStagingDirectory(item.path())) leftovers.push_back(item.path());
            for (const auto& leftover : leftovers) fs::remove_all(leftover, ec);
        }
        mStaging = outdir / (std::string(kStagingPrefix) + uniqueSuffix());
        fs::create_directory(mStaging, ec);
        // The record is what lets a later run tell this directory, once a
        // killed run's, from a user's folder of the same name.
        if (!ec) writeOwnerRecord(mStaging, ec);
        if (ec) {
            const std::string problem = describeErrno(ec.value());
            fs::remove_all(mStaging, ec);
            mStaging.clear();
            throw OutputError(outdir.string() +
                              ": cannot create a staging directory in it: " + problem);
        }
    } catch (...) {
        mLock.reset();
        removeCreatedDirectories();
        throw;
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

std::string OutputDirectory::withFinalPaths(std::string message) const {
    if (mStaging.empty()) return message;
    // Messages come escaped (kernels/base/Error.h), and so must the paths.
    const std::string staging = escapeControlCharacters(mStaging.string() + "/"),
                      final = escapeControlCharacters(mDirectory.string() + "/");
    for (std::size_t at = message.find(staging); at != std::string::npos;
         at = message.find(staging, at + final.size()))
        message.replace(at, staging.size(), final);
    return message;
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
    // The earlier run's outputs are moved aside into the staging directory,
    // not removed, until every new one is in place: a commit that fails half
    // way moves them back, and OUTDIR holds the earlier run's outputs whole
    // (rename(2) would drop a replaced file at once, and cannot replace a
    // non-empty directory such as levels/ at all).
    const fs::path aside = mStaging / ".replaced";
    std::vector<std::string> movedAside, movedIn;
    const auto rollBack = [&]() noexcept {
        std::error_code ignored;
        for (auto it = movedIn.rbegin(); it != movedIn.rend(); ++it)
            fs::remove_all(mDirectory / *it, ignored);
        for (const auto& name : movedAside) fs::rename(aside / name, mDirectory / name, ignored);
    };
    const auto moveAside = [&](const std::string& name, const char* what) {
        std::error_code error;
        if (!fs::exists(fs::symlink_status(mDirectory / name, error))) return;
        error.clear();
        if (movedAside.empty()) fs::create_directory(aside, error);
        if (!error) fs::rename(mDirectory / name, aside / name, error);
        if (error) {
            const std::string problem = describeErrno(error.value());
            rollBack();
            throw OutputError((mDirectory / name).string() + ": cannot " + what + ": " + problem);
        }
        movedAside.push_back(name);
    };
    // Checked again here: a run takes minutes, and a file put into levels/
    // meanwhile would go with it.
    for (const auto& name : mObsolete) refuseForeignEntry(mDirectory, name, mLayout);
    for (const auto& name : mStaged)
        if (fs::exists(mStaging / name, ec)) refuseForeignEntry(mDirectory, name, mLayout);
    for (const auto& name : mObsolete)
        if (std::find(mStaged.begin(), mStaged.end(), name) == mStaged.end())
            moveAside(name, "remove the earlier run's output");
    for (const auto& name : mStaged) {
        const fs::path from = mStaging / name;
        if (!fs::exists(from, ec)) continue;  // an optional output that was not produced
        moveAside(name, "replace the earlier run's output");
        fs::rename(from, mDirectory / name, ec);
        if (ec) {
            const std::string problem = describeErrno(ec.value());
            rollBack();
            throw OutputError((mDirectory / name).string() +
                              ": cannot move into place: " + problem);
        }
        movedIn.push_back(name);
    }
    mCommitted = true;
    fs::remove_all(mStaging, ec);
}

namespace {
/// Where setAside() keeps the first attempt's files, inside the staging
/// directory: no output name starts with a dot, so none can clash.
constexpr char kSetAsideName[] = ".set-aside";

/// Renames each of `names` that exists in `from` to `to`; OutputError
/// naming the file and `what` on failure.
void moveEach(const std::vector<std::string>& names, const fs::path& from, const fs::path& to,
              const char* what) {
    std::error_code ec;
    for (const auto& name : names) {
        if (!fs::exists(fs::symlink_status(from / name, ec))) continue;
        fs::rename(from / name, to / name, ec);
        if (ec)
            throw OutputError((from / name).string() + ": cannot " + what + ": " +
                              describeErrno(ec.value()));
    }
}
}  // namespace

void OutputDirectory::setAside() {
    const std::lock_guard<std::mutex> lock(mStagedMutex);
    const fs::path kept = mStaging / kSetAsideName;
    std::error_code ec;
    fs::remove_all(kept, ec);
    fs::create_directory(kept, ec);
    if (ec)
        throw OutputError(kept.string() +
                          ": cannot create directory: " + describeErrno(ec.value()));
    moveEach(mStaged, mStaging, kept, "set aside");
    mSetAsideStaged = std::move(mStaged);
    mStaged.clear();
    mSetAsideObsolete = mObsolete;
    mHasSetAside = true;
}

void OutputDirectory::restoreSetAside() {
    const std::lock_guard<std::mutex> lock(mStagedMutex);
    if (!mHasSetAside) return;
    const fs::path kept = mStaging / kSetAsideName;
    std::error_code ec;
    for (const auto& name : mStaged) fs::remove_all(mStaging / name, ec);
    moveEach(mSetAsideStaged, kept, mStaging, "put back");
    mStaged = std::move(mSetAsideStaged);
    mObsolete = std::move(mSetAsideObsolete);
    mSetAsideStaged.clear();
    mSetAsideObsolete.clear();
    mHasSetAside = false;
    fs::remove_all(kept, ec);
}

void OutputDirectory::dropSetAside() noexcept {
    const std::lock_guard<std::mutex> lock(mStagedMutex);
    std::error_code ec;
    fs::remove_all(mStaging / kSetAsideName, ec);
    mSetAsideStaged.clear();
    mSetAsideObsolete.clear();
    mHasSetAside = false;
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
    std::error_code ecInner, ecOuter;
    const fs::path a = fs::weakly_canonical(inner, ecInner),
                   b = fs::weakly_canonical(outer, ecOuter);
    // A path the system cannot resolve (over PATH_MAX) is empty: within everything.
    if (ecInner || ecOuter) return false;
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
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) throw OutputError(path.string() + ": cannot write: " + describeErrno(errno));
    // The system's own reason, not a guess: a full disk, a quota, an I/O error.
    int error = 0;
    for (std::size_t done = 0; done < bytes.size();) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            error = errno;
            break;
        }
        done += std::size_t(n);
    }
    // Network file systems report a failed write only here.
    if (::close(fd) != 0 && error == 0 && errno != EINTR) error = errno;
    std::error_code ec;
    if (error != 0) {
        fs::remove(temp, ec);
        throw OutputError(path.string() + ": cannot write: " + describeErrno(error));
    }
    fs::rename(temp, path, ec);
    if (ec) {
        const std::string problem = describeErrno(ec.value());
        fs::remove(temp, ec);
        throw OutputError(path.string() + ": cannot move into place: " + problem);
    }
}

}  // namespace skelseg
