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
