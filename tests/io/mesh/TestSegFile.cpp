#include "io/mesh/SegFile.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "kernels/base/Error.h"
#include "tests/support/FileBytes.h"
#include "tests/support/TempDir.h"
#include "tests/support/TestPaths.h"

namespace skelseg {
namespace {

using test::fileBytes;
using test::TempDir;

std::vector<std::int64_t> segFromText(const std::string& text,
                                      const std::string& name = "test.seg") {
    return readSegFromMemory(name, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

/// The message of the InputError that reading `text` throws; a test failure
/// when it is accepted.
std::string segErrorMessage(const std::string& text) {
    try {
        segFromText(text, "bad.seg");
    } catch (const InputError& error) {
        EXPECT_EQ(std::string(error.what()).rfind("bad.seg: ", 0), 0u) << error.what();
        return error.what();
    }
    ADD_FAILURE() << "accepted: " << text;
    return {};
}

TEST(SegFile, ParsesOneIntegerPerLine) {
    EXPECT_EQ(segFromText("3\n1\n-2\n+4\n"), (std::vector<std::int64_t>{3, 1, -2, 4}));
    EXPECT_EQ(segFromText("0\r\n5\r\n\r\n"),
              (std::vector<std::int64_t>{0, 5}));                 // CRLF, blank trailing line
    EXPECT_EQ(segFromText("7"), (std::vector<std::int64_t>{7}));  // no final newline
    EXPECT_EQ(segFromText("  8  \n"), (std::vector<std::int64_t>{8}));
}

TEST(SegFile, RejectsMalformedFilesWithTheLineNumber) {
    EXPECT_NE(segErrorMessage("1\nabc\n").find("line 2 is not an integer"), std::string::npos);
    EXPECT_NE(segErrorMessage("1\n2\n1.5\n").find("line 3"), std::string::npos);
    EXPECT_NE(segErrorMessage("1 2\n").find("line 1"), std::string::npos);
    EXPECT_NE(segErrorMessage("1\n\n2\n").find("line 2 is blank"), std::string::npos);
    EXPECT_NE(segErrorMessage("99999999999999999999\n").find("line 1"), std::string::npos);
    EXPECT_NE(segErrorMessage("").find("no labels"), std::string::npos);
    EXPECT_NE(segErrorMessage("\n\n").find("no labels"), std::string::npos);
    EXPECT_NE(segErrorMessage(std::string("\x1f\x8b\x08\x00garbage", 11)).find("gzip"),
              std::string::npos);
}

TEST(SegFile, WritesAndReadsPlainAndGzip) {
    TempDir dir;
    const std::vector<std::uint32_t> labels = {0, 1, 1, 2, 0, 4000000000u};
    writeSeg(dir / "a.seg", labels);
    writeSeg(dir / "a.seg.gz", labels);
    const std::vector<std::int64_t> expected(labels.begin(), labels.end());
    EXPECT_EQ(readSeg(dir / "a.seg"), expected);
    EXPECT_EQ(readSeg(dir / "a.seg.gz"), expected);
    EXPECT_EQ(fileBytes(dir / "a.seg"), "0\n1\n1\n2\n0\n4000000000\n");
    const std::string gz = fileBytes(dir / "a.seg.gz");
    ASSERT_GE(gz.size(), 2u);
    EXPECT_EQ(std::uint8_t(gz[0]), 0x1f);  // really gzip
    EXPECT_EQ(std::uint8_t(gz[1]), 0x8b);
    // Gzip detected by content, whatever the name; two members concatenated read as one.
    EXPECT_EQ(segFromText(gz, "no-extension"), expected);
    std::vector<std::int64_t> twice = expected;
    twice.insert(twice.end(), expected.begin(), expected.end());
    EXPECT_EQ(segFromText(gz + gz), twice);
    // Truncated gzip data is an error, not a short label list.
    try {
        segFromText(gz.substr(0, gz.size() - 10), "cut.seg.gz");
        ADD_FAILURE() << "truncated gzip accepted";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("cut.seg.gz"), std::string::npos);
    }
    EXPECT_THROW(readSeg(dir / "missing.seg"), InputError);
    // No temporary files are left behind.
    int files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir.path())) (void)entry, ++files;
    EXPECT_EQ(files, 2);
}

TEST(SegFile, ReadsPrincetonHumanSegmentations) {
    if (!test::hasSharedData())
        GTEST_SKIP() << "shared data folder " << test::sharedDataDir() << " is absent";
    const auto path = test::sharedDataDir() / "psb" / "seg" / "1" / "1_0.seg.gz";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent";
    const auto labels = readSeg(path);
    EXPECT_GT(labels.size(), 1000u);
    for (std::int64_t label : labels) ASSERT_GE(label, 0);
}

}  // namespace
}  // namespace skelseg
