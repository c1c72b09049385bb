// The message of an expected exception, for tests that compare it whole.
#pragma once

#include <string>

namespace skelseg::test {

/// what() of the `ErrorType` that `call()` throws, or "" when it throws none
/// (another exception type passes through and fails the test).
template <typename ErrorType, typename Call>
std::string thrownMessage(Call&& call) {
    try {
        call();
    } catch (const ErrorType& error) {
        return error.what();
    }
    return "";
}

}  // namespace skelseg::test
