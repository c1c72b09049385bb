// Tests for io/files/CompressedContent.h: compressed files and archives told
// by their first bytes, and the text readers' first look refusing them.
#include "io/files/CompressedContent.h"

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "io/files/TextFile.h"
#include "kernels/base/Error.h"

namespace skelseg {
namespace {

/// The first bytes each compressor or archiver writes, followed by a lone
/// carriage return (which the text readers took for classic Mac OS line
/// ends) and a line of text.
std::vector<std::pair<std::string, std::string>> signedContents() {
    const std::string tail("\x03\r\x7f OFF\n", 9);
    std::string tar(512, '\0');
    tar.replace(0, 8, "cube.off");
    tar.replace(257, 6, std::string("ustar\0", 6));
    return {
        {"gzip", std::string("\x1f\x8b\x08\x00", 4) + tail},
        {"bzip2", "BZh91AY&SY" + tail},
        {"bzip2", std::string("BZh9\x17\x72\x45\x38\x50\x90", 10) + tail},  // an empty stream
        {"xz", std::string("\xfd\x37\x7a\x58\x5a\x00", 6) + tail},
        {"zstd", std::string("\x28\xb5\x2f\xfd", 4) + tail},
        {"zip", std::string("PK\x03\x04\x14\x00", 6) + tail},
        {"zip", std::string("PK\x05\x06\x00\x00", 6)},  // an empty archive
        {"7-Zip", std::string("7z\xbc\xaf\x27\x1c", 6) + tail},
        {"RAR", std::string("Rar!\x1a\x07\x00", 7) + tail},
        {"lz4", std::string("\x04\x22\x4d\x18", 4) + tail},
        {"tar", tar},
    };
}

TEST(CompressedContent, SignaturesOfCompressorsAndArchivesAreRecognised) {
    for (const auto& [format, bytes] : signedContents())
        EXPECT_EQ(compressionFormatOf(bytes), format) << format;
}

TEST(CompressedContent, TextThatStartsLikeASignatureIsNoArchive) {
    // Every format skelseg reads, and text that shares a signature's first
    // letters: "BZh" and "PK" begin words.
    for (const std::string text :
         {std::string("OFF\n8 6 12\n"), std::string("ply\nformat ascii 1.0\n"),
          std::string("solid cube\n"), std::string("NRRD0004\n"), std::string("#binvox 1\n"),
          std::string("BZh9 is a word\n"), std::string("PK 3 4\n"), std::string("\x1f"),
          std::string(), std::string(300, ' ')})
        EXPECT_EQ(compressionFormatOf(text), "") << text;
}

TEST(CompressedContent, TextReadersSayUnpackItBeforeJudgingLineEnds) {
    // A gzipped OFF file under its own name was "ends its lines with a
    // carriage return alone (classic Mac OS text)": advice that cannot help.
    for (const auto& [format, bytes] : signedContents()) {
        try {
            textContentStart("cube.off", bytes);
            ADD_FAILURE() << format << " content was taken for text";
        } catch (const InputError& error) {
            const std::string article =
                format == "zip" || format == "7-Zip" || format == "RAR" || format == "tar"
                    ? "a " + format + " archive"
                    : format + " data";
            EXPECT_EQ(std::string(error.what()),
                      "cube.off: is a compressed file or archive (its bytes are " + article +
                          "); unpack it first");
        }
    }
}

TEST(CompressedContent, ProblemReadsAsTheExtensionCheckGivesIt) {
    EXPECT_EQ(compressedFileProblem("'.gz'"),
              "is a compressed file or archive ('.gz'); unpack it first");
    EXPECT_NO_THROW(refuseCompressedContent("cube.off", "OFF\n"));
}

}  // namespace
}  // namespace skelseg
