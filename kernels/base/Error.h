// skelseg: the exception hierarchy.
//
// Every failure the engine reports is one of these. The CLI maps each kind to
// one exit code (see README "Exit codes") and prints what() as a single line,
// so messages must name the file (where there is one) and the problem, and
// must not contain newlines. File names can hold any byte but '/' and NUL, a
// newline or an escape sequence included; every constructor therefore
// passes its message through escapeControlCharacters(), so that no name can
// break the one line or drive the terminal.
//
//   Error                 base; exit code 1 (internal error) when not more specific
//   ├─ UsageError         bad command line / parameter value           -> exit 2
//   ├─ InputError         unreadable or malformed input file           -> exit 2
//   ├─ OutputError        an output could not be written               -> exit 1
//   ├─ InterruptedError   time limit reached or user interrupt         -> exit 3
//   └─ MemoryLimitError   estimated memory over --max-memory           -> exit 4
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

namespace skelseg {

/// Length (2 to 4) and code point of the well-formed UTF-8 sequence that
/// starts `text`, or {0, 0} where none does (a lone byte of another encoding).
inline std::pair<std::size_t, char32_t> decodeUtf8Sequence(std::string_view text) {
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
    const unsigned char lead = byte(0);
    const std::size_t length = lead >= 0xf0 && lead <= 0xf4   ? 4
                               : lead >= 0xe0 && lead <= 0xef ? 3
                               : lead >= 0xc2 && lead <= 0xdf ? 2
                                                              : 0;
    if (length == 0 || text.size() < length) return {0, 0};
    char32_t code = lead & (0x7f >> length);
    for (std::size_t i = 1; i < length; ++i) {
        if ((byte(i) & 0xc0) != 0x80) return {0, 0};
        code = (code << 6) | (byte(i) & 0x3f);
    }
    const char32_t smallest = length == 2 ? 0x80 : length == 3 ? 0x800 : 0x10000;
    if (code < smallest || code > 0x10ffff || (code >= 0xd800 && code <= 0xdfff)) return {0, 0};
    return {length, code};
}

/// `text` with every control character written as an escape, so that it
/// prints on one line and cannot drive a terminal: the ASCII controls
/// (0x00-0x1f, 0x7f) as C escapes ("\n", "\r", "\t", otherwise "\x1b"); the
/// C1 controls and the line and paragraph separators in UTF-8 (U+0080 to
/// U+009F, U+2028, U+2029) as "\u0085"; a byte 0x80 to 0x9f outside UTF-8
/// (a C1 control to an 8-bit terminal) as "\x9b". Other bytes are kept, so
/// UTF-8 names and names in other encodings stay readable; a backslash is
/// kept too (the escapes only need to be recognisable, not reversible).
inline std::string escapeControlCharacters(std::string_view text) {
    static constexpr char kHex[] = "0123456789abcdef";
    const auto hex = [](std::string& out, unsigned value, int digits) {
        for (int shift = 4 * (digits - 1); shift >= 0; shift -= 4)
            out += kHex[(value >> shift) & 0xf];
    };
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size();) {
        const char c = text[i];
        const auto byte = static_cast<unsigned char>(c);
        if (byte >= 0x80) {
            const auto [length, code] = decodeUtf8Sequence(text.substr(i));
            if (length == 0) {
                if (byte <= 0x9f) {
                    out += "\\x";
                    hex(out, byte, 2);
                } else {
                    out += c;
                }
                ++i;
            } else if (code <= 0x9f || code == 0x2028 || code == 0x2029) {
                out += "\\u";
                hex(out, unsigned(code), 4);
                i += length;
            } else {
                out.append(text.substr(i, length));
                i += length;
            }
            continue;
        }
        ++i;
        if (byte >= 0x20 && byte != 0x7f) {
            out += c;
        } else if (c == '\n') {
            out += "\\n";
        } else if (c == '\r') {
            out += "\\r";
        } else if (c == '\t') {
            out += "\\t";
        } else {
            out += "\\x";
            hex(out, byte, 2);
        }
    }
    return out;
}

class Error : public std::runtime_error {
public:
    /// what() is `message` through escapeControlCharacters(): one line.
    explicit Error(const std::string& message)
        : std::runtime_error(escapeControlCharacters(message)) {}
    /// Process exit code the CLI uses for this kind of error.
    virtual int exitCode() const noexcept { return 1; }
};

class UsageError : public Error {
public:
    using Error::Error;
    int exitCode() const noexcept override { return 2; }
};

/// Bad input file. Construct with the file name and the problem; what() reads
/// "FILE: PROBLEM" (escaped as every Error's); file() and problem() are kept
/// as given.
class InputError : public Error {
public:
    InputError(const std::string& file, const std::string& problem)
        : Error(file + ": " + problem), mFile(file), mProblem(problem) {}
    const std::string& file() const noexcept { return mFile; }
    const std::string& problem() const noexcept { return mProblem; }
    int exitCode() const noexcept override { return 2; }

private:
    std::string mFile, mProblem;
};

class OutputError : public Error {
public:
    using Error::Error;
};

class InterruptedError : public Error {
public:
    enum class Reason { TimeLimit, UserInterrupt };
    InterruptedError(Reason reason, const std::string& message) : Error(message), mReason(reason) {}
    Reason reason() const noexcept { return mReason; }
    int exitCode() const noexcept override { return 3; }

private:
    Reason mReason;
};

class MemoryLimitError : public Error {
public:
    using Error::Error;
    int exitCode() const noexcept override { return 4; }
};

}  // namespace skelseg
