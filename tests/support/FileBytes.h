// Whole-file reads and writes for tests that compare outputs byte for byte
// or write malformed inputs.
#pragma once

#include <filesystem>
#include <string>

namespace skelseg::test {

/// The whole content of a file (empty string if it cannot be read).
std::string fileBytes(const std::filesystem::path& file);

/// Writes `bytes` to `file` (creating or truncating it).
/// @throw std::runtime_error when the file cannot be written, which fails the test.
void writeBytes(const std::filesystem::path& file, const std::string& bytes);

}  // namespace skelseg::test
