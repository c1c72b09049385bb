// skelseg: reading input files whole, and the small text helpers every reader
// shares.
//
// Every reader (NRRD, binvox, OpenVDB, the four mesh formats, .seg) loads its
// file with readFileBytes() and parses the bytes in memory, so the same code
// is fuzzed. The text helpers exist once, here, so that every reader quotes
// garbage input the same way in its one-line error messages.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace skelseg {

/// Largest input file readFileBytes() accepts. A bound, so that a wrong path
/// (a disk image, a device) fails at once instead of filling memory.
constexpr std::uint64_t kMaxInputFileBytes = std::uint64_t(16) << 30;  // 16 GiB

/// Throws the InputError a reader would for a path that does not name a
/// readable regular file ("no such file", "is a directory, not a file", "is not
/// a regular file", "cannot be read: permission denied"); returns otherwise.
void checkReadableFile(const std::filesystem::path& file);

/// The whole content of `file`, after checkReadableFile().
/// @throw InputError as checkReadableFile(), for files over kMaxInputFileBytes
///        and for read errors.
std::string readFileBytes(const std::filesystem::path& file);

/// errno as a message that fits after "cannot be read: " ("permission denied",
/// otherwise the system's text starting with a lower-case letter).
std::string describeErrno(int errorNumber);

/// `text` in single quotes for a one-line message: printable ASCII only (any
/// other byte shows as '?'), shortened to 40 characters and "..." (garbage
/// input can hold anything, and it must not reach the terminal raw).
std::string quote(std::string_view text);

/// "1.50 GB", "12.00 MB", "512 bytes": a unit that shows the number.
std::string formatBytes(std::uint64_t bytes);

/// ASCII lower case (file extensions, keywords).
std::string lowercase(std::string_view text);

/// True for ' ', '\t', '\r', '\v', '\f': whitespace inside one line.
constexpr bool isBlank(char c) noexcept {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/// isBlank() or '\n' (the C locale's isspace).
constexpr bool isSpace(char c) noexcept {
    return isBlank(c) || c == '\n';
}

/// Length of a UTF-8 byte order mark at the start of `text` (3 or 0). Editors
/// on Windows write one; the text readers skip it, so that it neither hides
/// the first statement nor fails the magic-word check.
constexpr std::size_t utf8BomLength(std::string_view text) noexcept {
    return text.size() >= 3 && text[0] == '\xEF' && text[1] == '\xBB' && text[2] == '\xBF' ? 3 : 0;
}

/// Where the content of the text file `name` starts: after a UTF-8 byte order
/// mark (utf8BomLength()). @throw InputError(name, ...) when it is compressed
/// data or an archive (refuseCompressedContent()); when it starts with a
/// UTF-16 byte order mark (FF FE or FE FF): Windows PowerShell's `>` and Notepad's
/// "Unicode" write such files, whose every other byte is NUL, and each reader
/// refused them for a different wrong reason ("the mesh has no faces"); and
/// when its first line ends in a carriage return alone (classic Mac OS text),
/// which the line-based readers would take for one long line.
std::size_t textContentStart(const std::string& name, std::string_view text);

/// `text` without leading and trailing whitespace (a view into `text`).
std::string_view trim(std::string_view text) noexcept;

/// The whitespace-separated tokens of `text`.
std::vector<std::string> splitWhitespace(std::string_view text);

}  // namespace skelseg
