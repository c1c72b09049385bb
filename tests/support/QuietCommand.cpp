#include "tests/support/QuietCommand.h"

#include <sys/wait.h>

#include <cstdlib>

namespace skelseg::test {

int runQuietly(const std::string& commandLine) {
    const int status = std::system((commandLine + " > /dev/null 2>&1").c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace skelseg::test
