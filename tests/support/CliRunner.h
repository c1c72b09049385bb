// Runs the skelseg executable as a child process, as a user would, and
// collects its exit code and output. Used by the robustness tests, which check
// what the CLI promises: exit codes, one-line errors, no partial outputs.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "tests/support/FileBytes.h"

namespace skelseg::test {

struct CliResult {
    /// Exit code, or -1 if the child was killed by a signal (see signal).
    int exitCode = -1;
    /// Signal that ended the child, 0 if it exited normally.
    int signal = 0;
    std::string out, err;
    double seconds = 0.0;

    /// The lines of `err` (without their newlines). A final line without a
    /// newline counts as a line.
    std::vector<std::string> errLines() const;
    /// "exit 2, stderr: ..." for assertion messages.
    std::string describe() const;
};

/// Runs skelsegBinary() with `arguments` (argv[1..]), waits for it and returns
/// what it did. The child's stdin is /dev/null. `whileRunning`, if given, is
/// called every 20 ms with the child's pid until the child ends (e.g. to send
/// it a signal). The child is killed (SIGKILL) after `timeout`.
CliResult runSkelseg(const std::vector<std::string>& arguments,
                     const std::function<void(pid_t)>& whileRunning = {},
                     std::chrono::seconds timeout = std::chrono::seconds(600));

/// As runSkelseg(), but `binary` runs as user `uid` and group `gid`, without
/// supplementary groups (through setpriv(1), util-linux): what a user without
/// root's rights sees, for tests that run as root. `binary` must be readable
/// and executable by that user (a copy in a TempDir made world-readable is).
CliResult runSkelsegAsUser(uid_t uid, gid_t gid, const std::filesystem::path& binary,
                           const std::vector<std::string>& arguments);

/// Names of the entries of `directory` (empty if it does not exist), sorted.
std::vector<std::string> directoryEntries(const std::filesystem::path& directory);

}  // namespace skelseg::test
