#include "io/files/ForeignContent.h"

#include <cstdint>

#include "io/files/OffKeyword.h"
#include "io/files/TextFile.h"
#include "io/files/TextTokenizer.h"
#include "kernels/base/Error.h"

namespace skelseg {

namespace {

bool startsWith(std::string_view bytes, std::string_view prefix) noexcept {
    return bytes.substr(0, prefix.size()) == prefix;
}

/// "an OFF file", "a PLY file": the formats' names as the messages use them.
std::string fileOf(std::string_view format) {
    const bool vowel = format == "OFF" || format == "OBJ" || format == "STL" || format == "OpenVDB";
    return std::string(vowel ? "an " : "a ") + std::string(format) + " file";
}

/// The first token of the first line that holds one, '#' comments skipped
/// (OFF and OBJ both allow them before their first statement).
std::string_view firstStatementWord(std::string_view text) {
    TextTokenizer lines(text);
    std::string_view line;
    if (!lines.nextSignificantLine(line)) return {};
    return TextTokenizer(line).nextToken();
}

/// The triangle count of a binary STL whose size matches it (84 bytes, then
/// 50 a triangle: the STL reader's own test), 0 otherwise.
std::uint64_t binaryStlTriangles(std::string_view bytes) noexcept {
    if (bytes.size() < 134) return 0;
    const auto byte = [&](std::size_t i) { return std::uint64_t(std::uint8_t(bytes[i])); };
    const std::uint64_t triangles =
        byte(80) | (byte(81) << 8) | (byte(82) << 16) | (byte(83) << 24);
    return 84 + 50 * triangles == bytes.size() ? triangles : 0;
}

bool isObjStatement(std::string_view word) {
    for (std::string_view statement : {"v", "vt", "vn", "vp", "f", "o", "g", "mtllib", "usemtl"})
        if (word == statement) return true;
    return false;
}

/// Another format skelseg reads, recognised by how its files begin.
struct OtherFormat {
    std::string_view format;     // "PLY"
    std::string_view holds;      // "a PLY mesh"
    std::string_view extension;  // ".ply"
    std::string how;             // "its first line is 'ply'"
};

bool recognise(std::string_view content, std::string_view expected, OtherFormat& found) {
    using namespace std::string_view_literals;
    std::string_view text = content;
    while (!text.empty() && isSpace(text.front())) text.remove_prefix(1);
    const std::size_t lineEnd = text.find('\n');
    std::string_view firstLine = text.substr(0, lineEnd);
    if (!firstLine.empty() && firstLine.back() == '\r') firstLine.remove_suffix(1);
    auto is = [&](std::string_view format) { return format != expected; };

    if (is("NRRD") && startsWith(content, "NRRD000"))
        found = {"NRRD", "a NRRD volume", ".nrrd", "it starts with " + quote(firstLine)};
    else if (is("binvox") && startsWith(content, "#binvox"))
        found = {"binvox", "a binvox volume", ".binvox", "it starts with " + quote(firstLine)};
    else if (is("OpenVDB") && startsWith(content, "\x20\x42\x44\x56\0\0\0\0"sv))
        found = {"OpenVDB", "an OpenVDB volume", ".vdb", "it starts with OpenVDB's magic number"};
    else if (is("PLY") && (startsWith(content, "ply\n") || startsWith(content, "ply\r\n")))
        found = {"PLY", "a PLY mesh", ".ply", "its first line is 'ply'"};
    else if (const std::uint64_t triangles = binaryStlTriangles(content);
             is("STL") && triangles != 0)
        found = {"STL", "a binary STL mesh", ".stl",
                 "its size is that of the " + std::to_string(triangles) +
                     " triangles its header counts"};
    if (!found.format.empty()) return true;
    // The text formats: by their first word, after blank and comment lines.
    if (is("STL") && lowercase(text.substr(0, 5)) == "solid" &&
        lowercase(text.substr(0, 4096)).find("facet") != std::string::npos)
        found = {"STL", "an ASCII STL mesh", ".stl", "it starts with 'solid' and holds facets"};
    else if (const std::string_view word = firstStatementWord(text);
             is("OFF") && isOffKeyword(word))
        found = {"OFF", "an OFF mesh", ".off", "it starts with " + quote(word)};
    else if (is("OBJ") && isObjStatement(word))
        found = {"OBJ", "an OBJ mesh", ".obj", "it starts with the OBJ statement " + quote(word)};
    return !found.format.empty();
}

}  // namespace

std::string foreignContentProblem(std::string_view bytes, std::string_view expected) {
    const std::string_view content = bytes.substr(utf8BomLength(bytes));
    if (startsWith(content, "version https://git-lfs.github.com/spec/"))
        return "is a Git LFS pointer (a small text file naming the content by its hash), not "
               "the " +
               std::string(expected) + " data itself; fetch the content with 'git lfs pull'";
    // git-annex leaves such a path in place of an unlocked file's content.
    if (startsWith(content, "/annex/objects/"))
        return "is a git-annex pointer, not the " + std::string(expected) +
               " data itself; fetch the content with 'git annex get'";
    std::string_view text = content;
    while (!text.empty() && isSpace(text.front())) text.remove_prefix(1);
    const std::string head = lowercase(text.substr(0, 14));
    if (startsWith(head, "<!doctype html") || startsWith(head, "<html"))
        return "is an HTML page, not " + fileOf(expected) +
               " (a download that saved a web page instead of the file?); download the file "
               "itself";
    OtherFormat found;
    if (!recognise(content, expected, found)) return {};
    return "holds " + std::string(found.holds) + " (" + found.how + "), not " + fileOf(expected) +
           " as its name says; rename it to " + std::string(found.extension);
}

void refuseForeignContent(const std::string& name, std::string_view bytes,
                          std::string_view expected) {
    const std::string problem = foreignContentProblem(bytes, expected);
    if (!problem.empty()) throw InputError(name, problem);
}

}  // namespace skelseg
