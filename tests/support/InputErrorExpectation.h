// The check every reader test makes of a refused file: an InputError whose
// message is one line, names the file and says what is wrong.
#pragma once

#include <functional>
#include <string>

namespace skelseg::test {

/// Expects `read` to throw an InputError whose one-line message contains
/// `file` and `keyword` (non-fatal gtest failures otherwise).
void expectInputError(const std::function<void()>& read, const std::string& file,
                      const std::string& keyword);

}  // namespace skelseg::test
