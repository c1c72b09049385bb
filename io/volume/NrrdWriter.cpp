// Writing NRRD volumes: labels.nrrd and mask outputs (declared in NrrdIO.h).
#include <zlib.h>

#include <algorithm>
#include <vector>

#include <fmt/format.h>

#include "io/files/OutputDirectory.h"
#include "io/volume/NrrdHeader.h"
#include "io/volume/NrrdIO.h"
#include "kernels/base/Error.h"

namespace fs = std::filesystem;

namespace skelseg {

namespace {

std::string formatVector(const std::array<double, 3>& v) {
    // {} prints the shortest text that reads back as the same double.
    return fmt::format("({},{},{})", v[0], v[1], v[2]);
}

std::string headerText(const char* type, const Dims& dims, const VolumeGeometry& geometry,
                       bool multiByte) {
    std::string text = "NRRD0004\n";
    text += "# Complete NRRD file format specification at:\n";
    text += "# http://teem.sourceforge.net/nrrd/format.html\n";
    text += std::string("type: ") + type + "\n";
    text += "dimension: 3\n";
    text += geometry.spaceName.empty() ? std::string("space dimension: 3\n")
                                       : "space: " + geometry.spaceName + "\n";
    text += fmt::format("sizes: {} {} {}\n", dims.x, dims.y, dims.z);
    text += "space directions: " + formatVector(geometry.directions[0]) + " " +
            formatVector(geometry.directions[1]) + " " + formatVector(geometry.directions[2]) +
            "\n";
    text += "kinds: domain domain domain\n";
    if (multiByte) text += "endian: little\n";
    text += "encoding: gzip\n";
    text += "space origin: " + formatVector(geometry.origin) + "\n";
    text += "\n";
    return text;
}

/// Appends the gzip stream of `bytes` to `out`. Level 1: labels and masks
/// are long runs, which fast deflate already shrinks well, and output time
/// counts against the run's time budget.
void appendGzip(const std::string& file, const std::uint8_t* bytes, std::size_t size,
                std::string& out) {
    z_stream stream{};
    if (deflateInit2(&stream, 1, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
        throw OutputError(file + ": cannot initialise zlib");
    std::vector<std::uint8_t> chunk(std::size_t(1) << 18);
    std::size_t consumed = 0;
    int status = Z_OK;
    do {
        if (stream.avail_in == 0 && consumed < size) {
            const std::size_t piece = std::min<std::size_t>(size - consumed, 1u << 30);
            stream.next_in = const_cast<Bytef*>(bytes + consumed);
            stream.avail_in = uInt(piece);
            consumed += piece;
        }
        const int flush = (consumed == size && stream.avail_in == 0) ? Z_FINISH : Z_NO_FLUSH;
        stream.next_out = chunk.data();
        stream.avail_out = uInt(chunk.size());
        status = deflate(&stream, flush);
        if (status == Z_STREAM_ERROR) {
            deflateEnd(&stream);
            throw OutputError(file + ": gzip compression failed");
        }
        out.append(reinterpret_cast<const char*>(chunk.data()), chunk.size() - stream.avail_out);
    } while (status != Z_STREAM_END);
    deflateEnd(&stream);
}

}  // namespace

void writeNrrdLabels(const fs::path& file, const LabelVolume& labels) {
    std::string out = headerText("uint16", labels.dims(), labels.geometry, true);
    if (nrrd::hostIsBigEndian()) {
        std::vector<std::uint16_t> swapped(labels.values());
        for (auto& value : swapped) value = std::uint16_t((value >> 8) | (value << 8));
        appendGzip(file.string(), reinterpret_cast<const std::uint8_t*>(swapped.data()),
                   swapped.size() * 2, out);
    } else {
        appendGzip(file.string(), reinterpret_cast<const std::uint8_t*>(labels.data()),
                   labels.size() * 2, out);
    }
    writeFileAtomically(file, out);
}

void writeNrrdMask(const fs::path& file, const MaskVolume& mask) {
    std::string out = headerText("uint8", mask.dims(), mask.geometry, false);
    appendGzip(file.string(), mask.data(), mask.size(), out);
    writeFileAtomically(file, out);
}

}  // namespace skelseg
