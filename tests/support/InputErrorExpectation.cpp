#include "tests/support/InputErrorExpectation.h"

#include <gtest/gtest.h>

#include "kernels/base/Error.h"

namespace skelseg::test {

void expectInputError(const std::function<void()>& read, const std::string& file,
                      const std::string& keyword) {
    try {
        read();
        ADD_FAILURE() << "no InputError for " << file << " (expected '" << keyword << "')";
    } catch (const InputError& error) {
        const std::string message = error.what();
        EXPECT_NE(message.find(file), std::string::npos) << message;
        EXPECT_NE(message.find(keyword), std::string::npos)
            << "expected '" << keyword << "' in: " << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
}

}  // namespace skelseg::test
