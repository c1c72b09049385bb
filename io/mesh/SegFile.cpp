#include "io/mesh/SegFile.h"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <string_view>

#include "io/files/OutputDirectory.h"
#include "io/files/TextFile.h"
#include "io/files/TextTokenizer.h"
#include "kernels/base/Error.h"

namespace skelseg {

namespace {

/// Decompressed text larger than this is refused (a corrupt or hostile
/// gzip stream can expand a thousandfold).
constexpr std::size_t kMaxTextBytes = std::size_t(1) << 30;

bool isGzip(const std::uint8_t* data, std::size_t size) {
    return size >= 2 && data[0] == 0x1f && data[1] == 0x8b;
}

std::string inflateGzip(const std::string& name, const std::uint8_t* data, std::size_t size) {
    std::string text;
    z_stream stream{};
    // 15 + 16: gzip wrapper only.
    if (inflateInit2(&stream, 15 + 16) != Z_OK)
        throw InputError(name, "cannot start gzip decompression");
    stream.next_in = const_cast<Bytef*>(data);
    std::size_t consumed = 0;
    char buffer[1 << 16];
    for (;;) {
        // avail_in is 32-bit: feed huge inputs in pieces.
        if (stream.avail_in == 0 && consumed < size) {
            const std::size_t piece = std::min<std::size_t>(size - consumed, 1u << 30);
            stream.next_in = const_cast<Bytef*>(data + consumed);
            stream.avail_in = uInt(piece);
            consumed += piece;
        }
        stream.next_out = reinterpret_cast<Bytef*>(buffer);
        stream.avail_out = sizeof buffer;
        const int status = inflate(&stream, Z_NO_FLUSH);
        text.append(buffer, sizeof buffer - stream.avail_out);
        if (text.size() > kMaxTextBytes) {
            inflateEnd(&stream);
            throw InputError(name, "decompresses to more than 1 GiB");
        }
        if (status == Z_STREAM_END) {
            // Concatenated gzip members (as `cat a.gz b.gz` makes) continue.
            if (stream.avail_in == 0 && consumed == size) break;
            if (inflateReset(&stream) != Z_OK) break;
            continue;
        }
        if (status == Z_BUF_ERROR && stream.avail_in == 0 && consumed == size) {
            inflateEnd(&stream);
            throw InputError(name, "gzip data ends early (truncated file)");
        }
        if (status != Z_OK && status != Z_BUF_ERROR) {
            const std::string reason = stream.msg ? stream.msg : "corrupt data";
            inflateEnd(&stream);
            throw InputError(name, "bad gzip data: " + reason);
        }
    }
    inflateEnd(&stream);
    return text;
}

std::string gzipCompress(const std::string& text, const std::filesystem::path& path) {
    z_stream stream{};
    if (deflateInit2(&stream, Z_DEFAULT_COMPRESSION, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) !=
        Z_OK)
        throw OutputError(path.string() + ": cannot start gzip compression");
    std::string out;
    out.resize(deflateBound(&stream, uLong(text.size())));
    stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(text.data()));
    stream.avail_in = uInt(text.size());
    stream.next_out = reinterpret_cast<Bytef*>(out.data());
    stream.avail_out = uInt(out.size());
    const int status = deflate(&stream, Z_FINISH);
    out.resize(out.size() - stream.avail_out);
    deflateEnd(&stream);
    if (status != Z_STREAM_END) throw OutputError(path.string() + ": gzip compression failed");
    return out;
}

std::vector<std::int64_t> parseLabels(const std::string& name, std::string_view text) {
    text.remove_prefix(textContentStart(name, text));
    std::vector<std::int64_t> labels;
    labels.reserve(text.size() / 2);
    TextTokenizer lines(text);
    std::string_view line;
    std::size_t blankLine = 0;  // first blank line seen, 0 if none
    while (lines.nextLine(line, false)) {
        line = trim(line);
        if (line.empty()) {
            if (blankLine == 0) blankLine = lines.lineNumber();
            continue;
        }
        if (blankLine != 0)
            throw InputError(name, "line " + std::to_string(blankLine) +
                                       " is blank (one label per face expected)");
        std::int64_t value = 0;
        if (!parseInteger(line, value))
            throw InputError(name, "line " + std::to_string(lines.lineNumber()) +
                                       " is not an integer label: " + quote(line));
        labels.push_back(value);
    }
    if (labels.empty()) throw InputError(name, "no labels (empty segmentation file)");
    labels.shrink_to_fit();
    return labels;
}

}  // namespace

std::vector<std::int64_t> readSegFromMemory(const std::string& name, const std::uint8_t* data,
                                            std::size_t size) {
    if (data == nullptr) size = 0;
    if (isGzip(data, size)) {
        const std::string text = inflateGzip(name, data, size);
        return parseLabels(name, text);
    }
    if (size > kMaxTextBytes) throw InputError(name, "is larger than 1 GiB");
    return parseLabels(name, std::string_view(reinterpret_cast<const char*>(data), size));
}

std::vector<std::int64_t> readSeg(const std::filesystem::path& path) {
    // readFileBytes refuses directories, FIFOs and devices before opening them.
    const std::string bytes = readFileBytes(path);
    return readSegFromMemory(path.string(), reinterpret_cast<const std::uint8_t*>(bytes.data()),
                             bytes.size());
}

void writeSeg(const std::filesystem::path& path, const std::vector<std::uint32_t>& labels) {
    std::string text;
    text.reserve(labels.size() * 3);
    char buffer[16];
    for (std::uint32_t label : labels) {
        const auto result = std::to_chars(buffer, buffer + sizeof buffer, label);
        text.append(buffer, result.ptr);
        text += '\n';
    }
    const std::string extension = path.extension().string();
    const bool compress = extension == ".gz" || extension == ".GZ";
    writeFileAtomically(path, compress ? gzipCompress(text, path) : text);
}

}  // namespace skelseg
