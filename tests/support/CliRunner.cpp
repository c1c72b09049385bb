#include "tests/support/CliRunner.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "tests/support/TempDir.h"
#include "tests/support/TestPaths.h"

extern char** environ;

namespace skelseg::test {

std::vector<std::string> CliResult::errLines() const {
    std::vector<std::string> lines;
    std::istringstream in(err);
    std::string line;
    while (std::getline(in, line)) lines.push_back(line);
    return lines;
}

std::string CliResult::describe() const {
    std::string text =
        signal ? "killed by signal " + std::to_string(signal) : "exit " + std::to_string(exitCode);
    return text + ", stderr: [" + err + "], stdout: [" + out.substr(0, 2000) + "]";
}

std::vector<std::string> directoryEntries(const std::filesystem::path& directory) {
    std::vector<std::string> names;
    std::error_code ec;
    if (!std::filesystem::is_directory(directory, ec)) return names;
    for (const auto& entry : std::filesystem::directory_iterator(directory, ec))
        names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

namespace {

/// Runs `command` (argv[0] a path, or with `searchPath` a name looked up in
/// PATH) as runSkelseg() describes.
CliResult runChild(const std::vector<std::string>& command, bool searchPath,
                   const std::function<void(pid_t)>& whileRunning, std::chrono::seconds timeout) {
    TempDir capture;
    const std::string outPath = (capture / "stdout").string(),
                      errPath = (capture / "stderr").string();
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, outPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    posix_spawn_file_actions_addopen(&actions, 2, errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);

    std::vector<char*> argv;
    for (const auto& a : command) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);

    // The child starts with default signal handling (a test runner may have
    // SIGINT ignored, which the child would otherwise inherit).
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    sigset_t defaults, none;
    sigemptyset(&defaults);
    sigaddset(&defaults, SIGINT);
    sigaddset(&defaults, SIGTERM);
    sigemptyset(&none);
    posix_spawnattr_setsigdefault(&attributes, &defaults);
    posix_spawnattr_setsigmask(&attributes, &none);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);

    const auto start = std::chrono::steady_clock::now();
    pid_t pid = 0;
    const int spawned = (searchPath ? posix_spawnp : posix_spawn)(
        &pid, command.front().c_str(), &actions, &attributes, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    if (spawned != 0) throw std::runtime_error("cannot start " + command.front());

    int status = 0;
    for (;;) {
        const pid_t done = ::waitpid(pid, &status, WNOHANG);
        if (done == pid) break;
        if (done < 0) throw std::runtime_error("waitpid failed");
        if (std::chrono::steady_clock::now() - start > timeout) {
            ::kill(pid, SIGKILL);
            ::waitpid(pid, &status, 0);
            break;
        }
        if (whileRunning) whileRunning(pid);
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    CliResult result;
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (WIFEXITED(status)) result.exitCode = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) result.signal = WTERMSIG(status);
    result.out = fileBytes(outPath);
    result.err = fileBytes(errPath);
    return result;
}

}  // namespace

CliResult runSkelseg(const std::vector<std::string>& arguments,
                     const std::function<void(pid_t)>& whileRunning, std::chrono::seconds timeout) {
    std::vector<std::string> command = {skelsegBinary()};
    command.insert(command.end(), arguments.begin(), arguments.end());
    return runChild(command, false, whileRunning, timeout);
}

CliResult runSkelsegAsUser(uid_t uid, gid_t gid, const std::filesystem::path& binary,
                           const std::vector<std::string>& arguments) {
    std::vector<std::string> command = {"setpriv",
                                        "--reuid=" + std::to_string(uid),
                                        "--regid=" + std::to_string(gid),
                                        "--clear-groups",
                                        "--",
                                        binary.string()};
    command.insert(command.end(), arguments.begin(), arguments.end());
    return runChild(command, true, {}, std::chrono::seconds(600));
}

}  // namespace skelseg::test
