#include "io/files/TextFile.h"

#include <cerrno>
#include <cstdio>
#include <fstream>
#include <system_error>

#include "io/files/CompressedContent.h"
#include "kernels/base/Error.h"

namespace fs = std::filesystem;

namespace skelseg {

std::string describeErrno(int errorNumber) {
    if (errorNumber == EACCES || errorNumber == EPERM) return "permission denied";
    std::string text = std::generic_category().message(errorNumber);
    if (!text.empty() && text[0] >= 'A' && text[0] <= 'Z') text[0] = char(text[0] - 'A' + 'a');
    return text;
}

void checkReadableFile(const fs::path& file) {
    const std::string name = file.string();
    std::error_code ec;
    const fs::file_status status = fs::status(file, ec);
    if (status.type() == fs::file_type::not_found) {
        // "cube.off/" (a shell's completion after a folder's name, a script
        // joining a folder and a name) fails with ENOTDIR, which the library
        // reports as not found: "no such file" of a file the user can see.
        std::string withoutSlash = name;
        while (withoutSlash.size() > 1 && withoutSlash.back() == '/') withoutSlash.pop_back();
        std::error_code ignored;
        if (withoutSlash.size() != name.size() && fs::exists(withoutSlash, ignored) &&
            !fs::is_directory(withoutSlash, ignored))
            throw InputError(name, "names a file as a folder (a '/' ends the name); drop the '/'");
        throw InputError(name, "no such file");
    }
    if (ec) throw InputError(name, "cannot be read: " + describeErrno(ec.value()));
    if (status.type() == fs::file_type::directory)
        throw InputError(name, "is a directory, not a file");
    if (status.type() != fs::file_type::regular) throw InputError(name, "is not a regular file");
    // Permissions are only known for sure by trying (ACLs, root, read-only mounts).
    std::ifstream probe(file, std::ios::binary);
    if (!probe) throw InputError(name, "cannot be read: " + describeErrno(errno));
}

std::string readFileBytes(const fs::path& file) {
    checkReadableFile(file);
    const std::string name = file.string();
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(file, ec);
    if (ec) throw InputError(name, "cannot be read: " + describeErrno(ec.value()));
    if (size > kMaxInputFileBytes)
        throw InputError(name,
                         "file is " + std::to_string(size) + " bytes, over the limit of 16 GiB");
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError(name, "cannot be read: " + describeErrno(errno));
    std::string bytes(std::size_t(size), '\0');
    in.read(bytes.data(), std::streamsize(size));
    if (std::uintmax_t(in.gcount()) != size)
        throw InputError(name, "read failed after " + std::to_string(in.gcount()) + " of " +
                                   std::to_string(size) + " bytes (file changed while reading?)");
    return bytes;
}

std::string quote(std::string_view text) {
    std::string shown;
    for (char c : text.substr(0, 40)) {
        const auto byte = static_cast<unsigned char>(c);
        shown += (byte >= 0x20 && byte < 0x7f) ? c : '?';
    }
    if (text.size() > 40) shown += "...";
    return "'" + shown + "'";
}

std::string lowercase(std::string_view text) {
    std::string out(text);
    for (char& c : out)
        if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
    return out;
}

std::string_view trim(std::string_view text) noexcept {
    while (!text.empty() && isSpace(text.front())) text.remove_prefix(1);
    while (!text.empty() && isSpace(text.back())) text.remove_suffix(1);
    return text;
}

std::vector<std::string> splitWhitespace(std::string_view text) {
    std::vector<std::string> tokens;
    std::size_t i = 0;
    while (i < text.size()) {
        while (i < text.size() && isSpace(text[i])) ++i;
        const std::size_t start = i;
        while (i < text.size() && !isSpace(text[i])) ++i;
        if (i > start) tokens.emplace_back(text.substr(start, i - start));
    }
    return tokens;
}

std::size_t textContentStart(const std::string& name, std::string_view text) {
    // A compressed file holds any byte, a lone carriage return among them.
    refuseCompressedContent(name, text);
    if (text.size() >= 2 &&
        ((text[0] == '\xFF' && text[1] == '\xFE') || (text[0] == '\xFE' && text[1] == '\xFF')))
        throw InputError(name,
                         "is UTF-16 text (it starts with a UTF-16 byte order mark); "
                         "save it as UTF-8");
    const std::size_t bom = utf8BomLength(text);
    // Only the first line end is judged: a binary PLY body or a binary STL
    // header may hold any byte, but after a text header's first '\n'.
    const std::string_view content = text.substr(bom);
    const std::size_t cr = content.find('\r');
    if (cr != std::string_view::npos && cr < content.find('\n') &&
        (cr + 1 == content.size() || content[cr + 1] != '\n'))
        throw InputError(name,
                         "ends its lines with a carriage return alone (classic Mac OS text); "
                         "save it with LF or CRLF line ends");
    return bom;
}

std::string formatBytes(std::uint64_t bytes) {
    // A unit that shows the number: "--max-memory 1M" must not read "0.00 GB".
    char buffer[64];
    if (bytes >= 1000000000)
        std::snprintf(buffer, sizeof buffer, "%.2f GB", double(bytes) / 1e9);
    else if (bytes >= 1000000)
        std::snprintf(buffer, sizeof buffer, "%.2f MB", double(bytes) / 1e6);
    else if (bytes >= 1000)
        std::snprintf(buffer, sizeof buffer, "%.2f KB", double(bytes) / 1e3);
    else
        std::snprintf(buffer, sizeof buffer, "%llu bytes", static_cast<unsigned long long>(bytes));
    return buffer;
}

}  // namespace skelseg
