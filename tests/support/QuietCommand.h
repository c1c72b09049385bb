// Runs a shell command line with its output discarded, for scene tests that
// drive the skelseg executable and look only at the files it writes.
#pragma once

#include <string>

namespace skelseg::test {

/// The command's exit code (-1 when it did not exit normally, e.g. killed
/// by a signal); stdout and stderr go to /dev/null.
int runQuietly(const std::string& commandLine);

}  // namespace skelseg::test
