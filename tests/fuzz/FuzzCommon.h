// Shared helpers for the libFuzzer targets in tests/fuzz/.
//
// Each target hands the fuzzer's bytes to one *FromMemory reader. A reader may
// reject its input only with skelseg::InputError, whose message must be one
// line starting with the file name. Any other exception escapes the target
// (libFuzzer reports it as a crash: "uncaught exception"), and so does a
// message that breaks the one-line rule or holds control characters
// (checked with __builtin_trap()).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "kernels/base/Error.h"

namespace skelseg::fuzz {

/// The name the targets pass to the readers; every message must start with it.
inline const std::string& inputName() {
    static const std::string name = "fuzz-input";
    return name;
}

/// Checks the contract of an InputError message: "NAME: PROBLEM", one line.
inline void checkMessage(const InputError& error) {
    const std::string what = error.what();
    if (what.rfind(inputName() + ": ", 0) != 0) __builtin_trap();
    // One line, and no control characters (a file's garbage bytes must not
    // reach the terminal: readers quote file content as printable ASCII).
    for (char c : what)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) __builtin_trap();
    if (error.problem().empty()) __builtin_trap();
}

/// Runs `read` and lets only InputError through (after checking its message).
template <typename Read>
void expectOnlyInputErrors(Read&& read) {
    try {
        read();
    } catch (const InputError& error) {
        checkMessage(error);
    }
}

}  // namespace skelseg::fuzz
