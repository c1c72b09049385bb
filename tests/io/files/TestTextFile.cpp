// Tests for io/files/TextFile.h and io/files/TextTokenizer.h: the one copy of
// the text helpers every reader shares.
#include "io/files/TextFile.h"

#include <gtest/gtest.h>

#include <cerrno>
#include <fstream>
#include <string>
#include <vector>

#include "io/files/TextTokenizer.h"
#include "kernels/base/Error.h"
#include "tests/support/TempDir.h"

namespace skelseg {
namespace {

TEST(TextFile, QuoteShowsPrintableAsciiOnlyAndShortens) {
    EXPECT_EQ(quote("type"), "'type'");
    EXPECT_EQ(quote(""), "''");
    EXPECT_EQ(quote(std::string("a\x01\n\xff"
                                "b",
                                5)),
              "'a???b'");
    const std::string forty(40, 'x');
    EXPECT_EQ(quote(forty), "'" + forty + "'");
    EXPECT_EQ(quote(forty + "y"), "'" + forty + "...'");
}

TEST(TextFile, LowercaseTrimAndSplit) {
    EXPECT_EQ(lowercase(".OFF Binary_Little"), ".off binary_little");
    EXPECT_EQ(trim(" \t value  \r\n"), "value");
    EXPECT_EQ(trim(" \t\r\n"), "");
    EXPECT_EQ(splitWhitespace("  dim 2\t3\r\n 4 "),
              (std::vector<std::string>{"dim", "2", "3", "4"}));
    EXPECT_TRUE(splitWhitespace(" \n ").empty());
}

TEST(TextFile, DescribeErrnoStartsLowerCase) {
    EXPECT_EQ(describeErrno(EACCES), "permission denied");
    const std::string text = describeErrno(ENOENT);
    ASSERT_FALSE(text.empty());
    EXPECT_TRUE(text[0] < 'A' || text[0] > 'Z') << text;
}

TEST(TextFile, ReadFileBytesRefusesWhatIsNotAFile) {
    test::TempDir dir;
    const std::string content("a\0b\n", 4);
    std::ofstream(dir / "bytes.bin", std::ios::binary) << content;
    EXPECT_EQ(readFileBytes(dir / "bytes.bin"), content);
    try {
        readFileBytes(dir / "absent.off");
        FAIL() << "no error for a missing file";
    } catch (const InputError& error) {
        EXPECT_EQ(error.problem(), "no such file");
    }
    try {
        checkReadableFile(dir.path());
        FAIL() << "no error for a directory";
    } catch (const InputError& error) {
        EXPECT_EQ(error.problem(), "is a directory, not a file");
    }
}

TEST(TextFile, AFileNamedAsAFolderIsNotCalledMissing) {
    // "cube.off/" fails with ENOTDIR, which the library reports as not
    // found: "no such file" of a file the user can see.
    test::TempDir dir;
    std::ofstream(dir / "cube.off") << "OFF\n";
    for (const std::string slashes : {"/", "//"}) {
        try {
            checkReadableFile((dir / "cube.off").string() + slashes);
            FAIL() << "no error for a file named as a folder";
        } catch (const InputError& error) {
            EXPECT_EQ(error.problem(),
                      "names a file as a folder (a '/' ends the name); drop the '/'");
        }
    }
    try {
        checkReadableFile((dir / "absent.off").string() + "/");
        FAIL() << "no error for a missing file";
    } catch (const InputError& error) {
        EXPECT_EQ(error.problem(), "no such file");
    }
}

TEST(TextTokenizer, LinesCountNumbersAndStripComments) {
    const std::string text = "OFF # header\n\n  3 1 0\nlast";
    TextTokenizer lines(text);
    std::string_view line;
    ASSERT_TRUE(lines.nextSignificantLine(line));
    EXPECT_EQ(line, "OFF ");
    EXPECT_EQ(lines.lineNumber(), 1u);
    ASSERT_TRUE(lines.nextSignificantLine(line));
    EXPECT_EQ(line, "  3 1 0");
    EXPECT_EQ(lines.lineNumber(), 3u);
    EXPECT_EQ(lines.bytesLeft(), 4u);  // "last", the '\n' before it not counted
    ASSERT_TRUE(lines.nextLine(line, false));
    EXPECT_EQ(line, "last");
    EXPECT_EQ(lines.lineNumber(), 4u);
    EXPECT_EQ(lines.bytesLeft(), 0u);
    EXPECT_FALSE(lines.nextLine(line, false));
    EXPECT_EQ(lines.lineNumber(), 4u);
}

TEST(TextTokenizer, TrailingNewlineEndsTheText) {
    TextTokenizer lines(std::string_view("a\n"));
    std::string_view line;
    ASSERT_TRUE(lines.nextLine(line, false));
    EXPECT_EQ(line, "a");
    EXPECT_EQ(lines.bytesLeft(), 0u);
    EXPECT_FALSE(lines.nextLine(line, false));
    TextTokenizer blank(std::string_view("\nb"));
    ASSERT_TRUE(blank.nextLine(line, false));
    EXPECT_EQ(line, "");
    ASSERT_TRUE(blank.nextLine(line, false));
    EXPECT_EQ(line, "b");
    EXPECT_EQ(blank.lineNumber(), 2u);
}

TEST(TextTokenizer, TokensAcrossLinesAndAfterALine) {
    TextTokenizer tokens(std::string_view("solid name\n  facet normal\n\n1 2"));
    EXPECT_EQ(tokens.nextToken(), "solid");
    tokens.skipLine();
    EXPECT_EQ(tokens.nextToken(), "facet");
    EXPECT_EQ(tokens.lineNumber(), 2u);
    std::string_view line;
    ASSERT_TRUE(tokens.nextLine(line, false));
    EXPECT_EQ(line, " normal");
    EXPECT_EQ(tokens.nextToken(), "1");
    EXPECT_EQ(tokens.lineNumber(), 4u);
    EXPECT_EQ(tokens.nextToken(), "2");
    EXPECT_EQ(tokens.nextToken(), "");
}

TEST(TextTokenizer, NumbersAcceptALeadingPlusAndNothingElse) {
    std::int64_t integer = 0;
    EXPECT_TRUE(parseInteger("+42", integer));
    EXPECT_EQ(integer, 42);
    EXPECT_TRUE(parseInteger("-7", integer));
    EXPECT_EQ(integer, -7);
    EXPECT_FALSE(parseInteger("4x", integer));
    EXPECT_FALSE(parseInteger("+", integer));
    EXPECT_FALSE(parseInteger("", integer));
    double real = 0;
    EXPECT_TRUE(parseReal("+1.5e2", real));
    EXPECT_EQ(real, 150.0);
    EXPECT_FALSE(parseReal("1.5,", real));
}

}  // namespace
}  // namespace skelseg
