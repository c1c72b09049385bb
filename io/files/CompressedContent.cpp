#include "io/files/CompressedContent.h"

#include "kernels/base/Error.h"

namespace skelseg {

namespace {

bool startsWith(std::string_view bytes, std::string_view signature) noexcept {
    return bytes.substr(0, signature.size()) == signature;
}

}  // namespace

std::string_view compressionFormatOf(std::string_view bytes) noexcept {
    using namespace std::string_view_literals;
    if (startsWith(bytes, "\x1f\x8b"sv)) return "gzip";
    // "BZh" alone could begin a line of text; the block size digit and the
    // magic of the first block (pi) or of an empty stream's end (sqrt(pi))
    // cannot.
    if (bytes.size() >= 10 && startsWith(bytes, "BZh"sv) && bytes[3] >= '1' && bytes[3] <= '9' &&
        (bytes.substr(4, 6) == "\x31\x41\x59\x26\x53\x59"sv ||
         bytes.substr(4, 6) == "\x17\x72\x45\x38\x50\x90"sv))
        return "bzip2";
    if (startsWith(bytes, "\xfd\x37\x7a\x58\x5a\x00"sv)) return "xz";
    if (startsWith(bytes, "\x28\xb5\x2f\xfd"sv)) return "zstd";
    if (startsWith(bytes, "PK\x03\x04"sv) || startsWith(bytes, "PK\x05\x06"sv)) return "zip";
    if (startsWith(bytes, "7z\xbc\xaf\x27\x1c"sv)) return "7-Zip";
    if (startsWith(bytes, "Rar!\x1a\x07"sv)) return "RAR";
    if (startsWith(bytes, "\x04\x22\x4d\x18"sv)) return "lz4";
    // A tar archive starts with the first member's name; its header's
    // format mark sits at byte 257.
    if (bytes.size() >= 262 && bytes.substr(257, 5) == "ustar"sv) return "tar";
    return {};
}

std::string compressedFileProblem(std::string_view how) {
    return "is a compressed file or archive (" + std::string(how) + "); unpack it first";
}

void refuseCompressedContent(const std::string& name, std::string_view bytes) {
    const std::string_view format = compressionFormatOf(bytes);
    if (format.empty()) return;
    const bool isArchive =
        format == "zip" || format == "7-Zip" || format == "RAR" || format == "tar";
    throw InputError(
        name, compressedFileProblem("its bytes are " + std::string(isArchive ? "a " : "") +
                                    std::string(format) + (isArchive ? " archive" : " data")));
}

}  // namespace skelseg
