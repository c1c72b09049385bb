// Tests for io/files/ForeignContent.h: files that are not the format their
// name says (Git LFS and git-annex pointers, HTML pages, a shape of another
// format), and every reader saying so instead of giving its own wrong reason.
#include "io/files/ForeignContent.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "io/mesh/MeshIO.h"
#include "io/volume/BinvoxIO.h"
#include "io/volume/NrrdIO.h"
#include "io/volume/VdbIO.h"
#include "kernels/base/Error.h"

namespace skelseg {
namespace {

const std::string kLfsPointer =
    "version https://git-lfs.github.com/spec/v1\n"
    "oid sha256:4d7a214614ab2935c943f9e0ff69d22eadbb8f32b1258daaa5e2ca24d17e2393\n"
    "size 12345\n";
const std::string kHtmlPage =
    "\n<!DOCTYPE html>\n<html><head><title>404 Not Found</title></head></html>\n";

/// A small valid file of each format, with the format's name in messages.
struct Sample {
    std::string format;
    std::string extension;
    std::string bytes;
};

std::string binaryStlOfOneTriangle() {
    std::string bytes(80, 'x');  // a header that says nothing
    bytes += std::string("\x01\0\0\0", 4);
    bytes += std::string(50, '\0');
    return bytes;
}

std::vector<Sample> samples() {
    return {
        {"OFF", ".off", "# a tetrahedron\nOFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n"},
        {"OBJ", ".obj", "# exported\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"},
        {"PLY", ".ply", "ply\r\nformat ascii 1.0\r\nend_header\r\n"},
        {"STL", ".stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"},
        {"STL", ".stl", binaryStlOfOneTriangle()},
        {"NRRD", ".nrrd", "NRRD0004\ntype: uint8\n"},
        {"binvox", ".binvox", "#binvox 1\ndim 1 1 1\ndata\n"},
        {"OpenVDB", ".vdb", std::string("\x20\x42\x44\x56\0\0\0\0\xdc\0\0\0", 12)},
    };
}

const std::vector<std::string> kFormats = {"OFF", "OBJ", "STL", "PLY", "NRRD", "binvox", "OpenVDB"};

TEST(ForeignContent, PointersAndWebPagesAreNamedWhateverTheExtension) {
    for (const std::string& expected : kFormats) {
        EXPECT_EQ(foreignContentProblem(kLfsPointer, expected),
                  "is a Git LFS pointer (a small text file naming the content by its hash), not "
                  "the " +
                      expected + " data itself; fetch the content with 'git lfs pull'");
        EXPECT_EQ(foreignContentProblem("/annex/objects/SHA256E-s1--ab.off\n", expected),
                  "is a git-annex pointer, not the " + expected +
                      " data itself; fetch the content with 'git annex get'");
        EXPECT_NE(foreignContentProblem(kHtmlPage, expected).find("is an HTML page"),
                  std::string::npos)
            << expected;
    }
}

TEST(ForeignContent, AnotherFormatIsNamedWithItsExtension) {
    for (const Sample& sample : samples())
        for (const std::string& expected : kFormats) {
            const std::string problem = foreignContentProblem(sample.bytes, expected);
            if (expected == sample.format) {
                // A reader's own format is never foreign to it.
                EXPECT_EQ(problem, "") << sample.format;
                continue;
            }
            EXPECT_EQ(problem.substr(0, 6), "holds ") << sample.format << " as " << expected;
            EXPECT_NE(problem.find(" as its name says; rename it to " + sample.extension),
                      std::string::npos)
                << problem;
        }
}

TEST(ForeignContent, OrdinaryBrokenFilesAreNotTakenForAnotherFormat) {
    for (const std::string text :
         {std::string(), std::string("hello world\n"), std::string("OFFICE party\n"),
          std::string("solid but no triangles\n"), std::string("{\"message\":\"Not Found\"}"),
          std::string("ply is a word\n"), std::string(200, '\0'), std::string("version 2\n")})
        for (const std::string& expected : kFormats)
            EXPECT_EQ(foreignContentProblem(text, expected), "") << text << " as " << expected;
}

/// The message each reader gives `bytes` read as `extension`.
std::string readerMessage(const std::string& extension, const std::string& bytes) {
    const std::string name = "shape" + extension;
    const auto* data = reinterpret_cast<const std::uint8_t*>(bytes.data());
    try {
        if (extension == ".nrrd")
            readNrrdMaskFromMemory(name, data, bytes.size());
        else if (extension == ".binvox")
            readBinvoxFromMemory(name, data, bytes.size());
        else if (extension == ".vdb")
            readVdbMaskFromMemory(name, data, bytes.size());
        else
            readMeshFromMemory(name, meshFormatFromPath(name), data, bytes.size());
    } catch (const InputError& error) {
        return error.what();
    }
    return "read without an error";
}

TEST(ForeignContent, EveryReaderSaysWhatTheFileIs) {
    // Before: an OBJ reader skips what it does not know ("the mesh has no
    // faces"); the STL reader took text for a binary STL ("binary STL header
    // says 845429046 triangles ..."); the others said "wrong magic".
    for (const std::string extension :
         {".off", ".obj", ".stl", ".ply", ".nrrd", ".binvox", ".vdb"}) {
        EXPECT_NE(readerMessage(extension, kLfsPointer).find("is a Git LFS pointer"),
                  std::string::npos)
            << extension << ": " << readerMessage(extension, kLfsPointer);
        EXPECT_NE(readerMessage(extension, kHtmlPage).find("is an HTML page"), std::string::npos)
            << extension << ": " << readerMessage(extension, kHtmlPage);
        for (const Sample& sample : samples()) {
            if (sample.extension == extension) continue;
            const std::string message = readerMessage(extension, sample.bytes);
            EXPECT_NE(message.find("rename it to " + sample.extension), std::string::npos)
                << sample.format << " as " << extension << ": " << message;
        }
    }
}

}  // namespace
}  // namespace skelseg
