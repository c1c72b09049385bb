#include "engine/batch/InputMemoryEstimate.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "engine/Segmenter.h"
#include "io/volume/VolumeReader.h"

namespace fs = std::filesystem;

namespace skelseg {

std::optional<Dims> peekVolumeDims(const fs::path& file) {
    const VolumeFormat format = volumeFormatFromPath(file);
    if (format != VolumeFormat::Nrrd && format != VolumeFormat::Binvox) return std::nullopt;
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) return std::nullopt;
    std::ifstream in(file, std::ios::binary);
    if (!in) return std::nullopt;
    std::string header(4096, '\0');
    in.read(header.data(), std::streamsize(header.size()));
    header.resize(std::size_t(in.gcount()));
    std::istringstream lines(header);
    const std::string keyword = format == VolumeFormat::Nrrd ? "sizes:" : "dim";
    for (std::string line; std::getline(lines, line);) {
        if (format == VolumeFormat::Nrrd && line.empty()) break;  // end of the header
        std::istringstream words(line);
        std::string first;
        long long a = 0, b = 0, c = 0;
        if (!(words >> first) || first != keyword || !(words >> a >> b >> c)) continue;
        if (a < 1 || b < 1 || c < 1 || a > 65536 || b > 65536 || c > 65536) return std::nullopt;
        return Dims{int(a), int(b), int(c)};
    }
    return std::nullopt;
}

std::uint64_t estimateInputMemory(const fs::path& input, const SegmentCommandOptions& options,
                                  int threads) {
    std::error_code ec;
    const std::uint64_t fileBytes = fs::is_regular_file(input, ec) ? fs::file_size(input, ec) : 0;
    if (isMeshPath(input)) {
        const int side = options.resolution + 2;
        const Dims dims{side, side, side};
        return estimateSegmentationMemory(dims, dims.voxelCount() / 4, threads) +
               dims.voxelCount() * 12 +
               fileBytes * 4;  // as segment: level set, dense copy, nearest-triangle grid
    }
    std::optional<Dims> dims = peekVolumeDims(input);
    if (!dims) {
        const int side =
            std::max(1, int(std::ceil(std::cbrt(double(std::max<std::uint64_t>(fileBytes, 1))))));
        dims = Dims{side, side, side};
    }
    return estimateSegmentationMemory(*dims, dims->voxelCount() / 4, threads) + fileBytes;
}

}  // namespace skelseg
