#include "io/volume/BinvoxIO.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "io/files/CompressedContent.h"
#include "io/files/ForeignContent.h"
#include "io/files/OutputDirectory.h"
#include "io/files/TextFile.h"
#include "io/files/TextTokenizer.h"
#include "kernels/base/Error.h"

namespace fs = std::filesystem;

namespace skelseg {

namespace {

struct BinvoxHeader {
    std::array<std::int64_t, 3> dim{};  // as listed: extents of x, z, y
    std::array<double, 3> translate{0.0, 0.0, 0.0};
    double scale = 1.0;
    std::size_t dataOffset = 0;
};

class BinvoxHeaderParser {
public:
    BinvoxHeaderParser(const std::string& name, const std::uint8_t* bytes, std::size_t size)
        : mName(name),
          mBytes(reinterpret_cast<const char*>(bytes), size),
          mSize(size),
          mLines(reinterpret_cast<const char*>(bytes), size) {}

    BinvoxHeader parse() {
        if (mSize == 0) fail("file is empty");
        refuseCompressedContent(mName, mBytes);  // before "wrong magic"
        const auto magic = splitWhitespace(nextLine());
        if (magic.empty() || magic[0] != "#binvox") {
            refuseForeignContent(mName, mBytes, "binvox");
            fail("not a binvox file: wrong magic " + quote(magic.empty() ? "" : magic[0]) +
                 ", expected '#binvox'");
        }
        if (magic.size() != 2 || (magic[1] != "1" && magic[1] != "2"))
            fail("unsupported binvox version " + quote(magic.size() > 1 ? magic[1] : "") +
                 " (supported: 1, 2)");
        bool hasDim = false, hasData = false;
        while (mLines.bytesLeft() > 0) {
            const auto tokens = splitWhitespace(nextLine());
            if (tokens.empty()) continue;
            const std::string& keyword = tokens[0];
            if (keyword == "data") {
                if (tokens.size() != 1) fail("malformed 'data' line");
                hasData = true;
                break;
            }
            if (keyword == "dim") {
                if (hasDim) fail("'dim' line appears twice");
                if (tokens.size() != 4) fail("'dim' line needs 3 sizes");
                for (int a = 0; a < 3; ++a) mHeader.dim[a] = parseInteger(tokens[a + 1]);
                hasDim = true;
            } else if (keyword == "translate") {
                if (tokens.size() != 4) fail("'translate' line needs 3 numbers");
                for (int a = 0; a < 3; ++a)
                    mHeader.translate[a] = parseReal("translate", tokens[a + 1]);
            } else if (keyword == "scale") {
                if (tokens.size() != 2) fail("'scale' line needs 1 number");
                mHeader.scale = parseReal("scale", tokens[1]);
                if (!(mHeader.scale > 0.0)) fail("scale " + quote(tokens[1]) + " is not positive");
            }
            // Other lines are skipped, as binvox's own reader does.
        }
        if (!hasDim) fail("missing 'dim' line in the header");
        if (!hasData) fail("missing 'data' line: the header never ends");
        mHeader.dataOffset = mSize - mLines.bytesLeft();
        return mHeader;
    }

private:
    [[noreturn]] void fail(const std::string& problem) const { throw InputError(mName, problem); }

    /// The next line without its "\n"; empty at the end of the bytes.
    std::string nextLine() {
        std::string_view line;
        mLines.nextLine(line, false);
        return std::string(line);
    }

    std::int64_t parseInteger(const std::string& text) const {
        std::int64_t value = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (error == std::errc::result_out_of_range)
            fail("size " + quote(text) + " is too large (overflows a 64-bit integer)");
        if (error != std::errc() || end != text.data() + text.size())
            fail("size " + quote(text) + " is not an integer");
        return value;
    }

    double parseReal(const char* what, const std::string& text) const {
        double value = 0.0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
            fail(std::string(what) + ": " + quote(text) + " is not a finite number");
        return value;
    }

    const std::string& mName;
    std::string_view mBytes;
    std::size_t mSize;
    TextTokenizer mLines;
    BinvoxHeader mHeader;
};

/// Walks voxels in binvox order (y fastest, then z, then x) and yields our
/// x-fastest linear index for each.
class BinvoxOrder {
public:
    explicit BinvoxOrder(const Dims& dims) : mDims(dims) {}
    std::size_t index() const noexcept {
        return std::size_t(mX) +
               std::size_t(mDims.x) * (std::size_t(mY) + std::size_t(mDims.y) * std::size_t(mZ));
    }
    void advance() noexcept {
        if (++mY < mDims.y) return;
        mY = 0;
        if (++mZ < mDims.z) return;
        mZ = 0;
        ++mX;
    }
    /// Jumps to binvox linear index `position`.
    void seek(std::uint64_t position) noexcept {
        const std::uint64_t perSlab = std::uint64_t(mDims.y) * std::uint64_t(mDims.z);
        mX = int(position / perSlab);
        mZ = int((position % perSlab) / std::uint64_t(mDims.y));
        mY = int(position % std::uint64_t(mDims.y));
    }

private:
    Dims mDims;
    int mX = 0, mY = 0, mZ = 0;
};

}  // namespace

MaskVolume readBinvoxFromMemory(const std::string& name, const std::uint8_t* bytes,
                                std::size_t size, const VolumeReadGuards& guards) {
    const BinvoxHeader header = BinvoxHeaderParser(name, bytes, size).parse();
    // "dim d0 d1 d2" are the extents of binvox x, z, y; ours are x, y, z.
    const Dims dims = Dims::checked(header.dim[0], header.dim[2], header.dim[1], name);
    const double voxelSize =
        header.scale / double(std::max({header.dim[0], header.dim[1], header.dim[2]}));
    const VolumeGeometry geometry = VolumeGeometry::uniform(
        voxelSize, {header.translate[0] + 0.5 * voxelSize, header.translate[1] + 0.5 * voxelSize,
                    header.translate[2] + 0.5 * voxelSize});
    const std::string problem = geometry.problemOver(dims);
    if (!problem.empty()) throw InputError(name, problem);
    const std::uint64_t voxelCount = dims.voxelCount();
    const std::uint8_t* data = bytes + header.dataOffset;
    const std::size_t dataSize = size - header.dataOffset;
    // Each pair covers at most 255 voxels: reject impossible files before allocating.
    if (std::uint64_t(dataSize / 2) * 255 < voxelCount)
        throw InputError(name, "data is too short: " + std::to_string(dataSize) +
                                   " bytes of runs cannot cover " + std::to_string(voxelCount) +
                                   " voxels");
    if (guards.checkGrid) guards.checkGrid(dims);

    MaskVolume mask(dims);
    BinvoxOrder order(dims);
    std::uint64_t position = 0;
    std::size_t offset = 0;
    while (position < voxelCount) {
        if (offset + 2 > dataSize)
            throw InputError(name, "data is too short: runs cover " + std::to_string(position) +
                                       " of " + std::to_string(voxelCount) + " voxels" +
                                       (offset < dataSize ? " (truncated run)" : ""));
        const std::uint8_t value = data[offset];
        const std::uint8_t count = data[offset + 1];  // 0 is a no-op run, as in binvox's reader
        if (position + count > voxelCount)
            throw InputError(name, "run at data byte " + std::to_string(offset) +
                                       " overflows the " + std::to_string(voxelCount) +
                                       " voxels of the grid");
        if (value != 0) {
            for (unsigned i = 0; i < count; ++i) {
                mask[order.index()] = 1;
                order.advance();
            }
        }
        position += count;
        if (value == 0) order.seek(position);
        offset += 2;
    }
    if (offset != dataSize)
        throw InputError(name, "data is too long: " + std::to_string(dataSize - offset) +
                                   " bytes of trailing data after the last voxel");

    mask.geometry = geometry;
    return mask;
}

MaskVolume readBinvox(const fs::path& file, const VolumeReadGuards& guards) {
    const std::string bytes = readFileBytes(file);
    return readBinvoxFromMemory(file.string(), reinterpret_cast<const std::uint8_t*>(bytes.data()),
                                bytes.size(), guards);
}

void writeBinvox(const fs::path& file, const MaskVolume& mask) {
    const Dims& dims = mask.dims();
    const double voxelSize = mask.geometry.voxelSize();
    const int largest = std::max({dims.x, dims.y, dims.z});
    const auto& origin = mask.geometry.origin;
    std::string out = "#binvox 1\n";
    out += fmt::format("dim {} {} {}\n", dims.x, dims.z, dims.y);
    out += fmt::format("translate {} {} {}\n", origin[0] - 0.5 * voxelSize,
                       origin[1] - 0.5 * voxelSize, origin[2] - 0.5 * voxelSize);
    out += fmt::format("scale {}\n", voxelSize * largest);
    out += "data\n";

    std::uint8_t runValue = 0;
    unsigned runLength = 0;
    const auto flush = [&] {
        if (runLength == 0) return;
        out += char(runValue);
        out += char(runLength);
        runLength = 0;
    };
    for (int x = 0; x < dims.x; ++x)
        for (int z = 0; z < dims.z; ++z)
            for (int y = 0; y < dims.y; ++y) {
                const std::uint8_t value = mask(x, y, z) != 0 ? 1 : 0;
                if (value != runValue || runLength == 255) {
                    flush();
                    runValue = value;
                }
                ++runLength;
            }
    flush();
    writeFileAtomically(file, out);
}

}  // namespace skelseg
