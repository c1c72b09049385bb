#include "kernels/base/Error.h"

#include <gtest/gtest.h>

#include <string>

namespace skelseg {
namespace {

TEST(EscapeControlCharacters, WritesControlCharactersAsCEscapes) {
    EXPECT_EQ(escapeControlCharacters("a\nb\rc\td"), "a\\nb\\rc\\td");
    EXPECT_EQ(escapeControlCharacters("\x1b[31mred"), "\\x1b[31mred");
    EXPECT_EQ(escapeControlCharacters(std::string("nul\0x", 5)), "nul\\x00x");
    EXPECT_EQ(escapeControlCharacters("\x01\x1f\x7f"), "\\x01\\x1f\\x7f");
}

TEST(EscapeControlCharacters, KeepsPrintableAsciiUtf8AndBackslashes) {
    const std::string kept = "dir/caf\xC3\xA9 (1) #2 \\n.off";
    EXPECT_EQ(escapeControlCharacters(kept), kept);
    EXPECT_EQ(escapeControlCharacters("caf\xE9.off"), "caf\xE9.off");  // not UTF-8: kept
    EXPECT_EQ(escapeControlCharacters(""), "");
}

// A C1 control is a terminal escape too: CSI (U+009B) starts a sequence as
// ESC [ does, NEL (U+0085) and the separators break lines in some terminals.
TEST(EscapeControlCharacters, WritesC1ControlsAndLineSeparatorsAsEscapes) {
    EXPECT_EQ(escapeControlCharacters("a\xC2\x9B"
                                      "31mred"),
              "a\\u009b31mred");
    EXPECT_EQ(escapeControlCharacters("x\xC2\x85y\xE2\x80\xA8z\xE2\x80\xA9"),
              "x\\u0085y\\u2028z\\u2029");
    // The same bytes alone, to an 8-bit terminal: escaped as bytes.
    EXPECT_EQ(escapeControlCharacters("a\x9B"
                                      "31m\x85"),
              "a\\x9b31m\\x85");
    // Neighbours of those code points are printable and kept.
    const std::string kept = "\xC2\xA0\xE2\x80\xA7\xE2\x80\xAA\xF0\x9F\x98\x80";
    EXPECT_EQ(escapeControlCharacters(kept), kept);
    // An overlong or truncated sequence is no UTF-8: its bytes from 0x80 to
    // 0x9f are escaped, the others kept.
    EXPECT_EQ(escapeControlCharacters("\xC1\x9B"), "\xC1\\x9b");
    EXPECT_EQ(escapeControlCharacters("\xE2\x80"), "\xE2\\x80");
}

TEST(Error, EveryKindEscapesItsMessage) {
    const std::string name = "bad\nname\x1b.off";
    const std::string shown = "bad\\nname\\x1b.off";
    EXPECT_EQ(std::string(Error(name).what()), shown);
    EXPECT_EQ(std::string(UsageError(name + ": unknown").what()), shown + ": unknown");
    EXPECT_EQ(std::string(OutputError(name).what()), shown);
    EXPECT_EQ(std::string(MemoryLimitError(name).what()), shown);
    EXPECT_EQ(
        std::string(InterruptedError(InterruptedError::Reason::TimeLimit, name + ": time").what()),
        shown + ": time");
}

TEST(Error, InputErrorEscapesWhatButKeepsItsFileAndProblemAsGiven) {
    const InputError error("frame\r\n1.off", "line 2:\tbad");
    EXPECT_EQ(std::string(error.what()), "frame\\r\\n1.off: line 2:\\tbad");
    EXPECT_EQ(error.file(), "frame\r\n1.off");
    EXPECT_EQ(error.problem(), "line 2:\tbad");
    EXPECT_EQ(error.exitCode(), 2);
}

}  // namespace
}  // namespace skelseg
