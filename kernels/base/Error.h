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

#include <stdexcept>
#include <string>
#include <string_view>

namespace skelseg {

/// `text` with every ASCII control character (0x00-0x1f, 0x7f) written as a
/// C escape: "\n", "\r", "\t", otherwise "\x1b" (two lower-case hex digits).
/// Other bytes are kept, UTF-8 names stay readable; a backslash is kept too
/// (the escapes only need to be recognisable, not reversible).
inline std::string escapeControlCharacters(std::string_view text) {
    static constexpr char kHex[] = "0123456789abcdef";
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
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
            out += kHex[byte >> 4];
            out += kHex[byte & 0xf];
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
