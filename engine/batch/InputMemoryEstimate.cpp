#include "engine/batch/InputMemoryEstimate.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "engine/SegmentInput.h"
#include "engine/Segmenter.h"
#include "io/volume/VolumeReader.h"

namespace fs = std::filesystem;

namespace skelseg {

namespace {

/// The words after `keyword` on the first line it starts, in the text header
/// (first 4 KiB) of an NRRD or binvox file ("sizes:" -> {"64", "64", "32"});
/// nullopt as for peekVolumeDims() or when no line starts with it.
std::optional<std::vector<std::string>> peekHeaderWords(const fs::path& file,
                                                        const std::string& keyword) {
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
    for (std::string line; std::getline(lines, line);) {
        if (format == VolumeFormat::Nrrd && line.empty()) break;  // end of the header
        std::istringstream words(line);
        std::string first;
        if (!(words >> first) || first != keyword) continue;
        std::vector<std::string> rest;
        for (std::string word; words >> word;) rest.push_back(word);
        return rest;
    }
    return std::nullopt;
}

}  // namespace

std::optional<Dims> peekVolumeDims(const fs::path& file) {
    const std::string keyword = volumeFormatFromPath(file) == VolumeFormat::Nrrd ? "sizes:" : "dim";
    std::optional<std::vector<std::string>> words = peekHeaderWords(file, keyword);
    if (!words || words->size() < 3) return std::nullopt;
    // A 4-D NRRD's axis of size 1 is no axis of the volume (io/volume/NrrdHeader.h).
    if (words->size() == 4)
        if (const auto one = std::find(words->begin(), words->end(), "1"); one != words->end())
            words->erase(one);
    long long extent[3] = {0, 0, 0};
    for (int axis = 0; axis < 3; ++axis) {
        std::istringstream number((*words)[std::size_t(axis)]);
        if (!(number >> extent[axis]) || extent[axis] < 1 || extent[axis] > 65536)
            return std::nullopt;
    }
    return Dims{int(extent[0]), int(extent[1]), int(extent[2])};
}

std::uint64_t estimateInputMemory(const fs::path& input, const SegmentCommandOptions& options,
                                  int threads) {
    std::error_code ec;
    const std::uint64_t fileBytes = fs::is_regular_file(input, ec) ? fs::file_size(input, ec) : 0;
    // The preview's picture and panels; its triangles are not known before
    // reading (segment counts them).
    const std::uint64_t preview = previewRunMemory(options.writePreview, 0, 0, threads);
    if (isMeshPath(input)) {
        const int side = options.resolution + 2;
        const Dims dims{side, side, side};
        return estimateSegmentationMemory(dims, dims.voxelCount() / 4, threads) +
               dims.voxelCount() * 12 + fileBytes * 4 +
               preview;  // as segment: level set, dense copy, nearest-triangle grid
    }
    std::optional<Dims> dims = peekVolumeDims(input);
    if (!dims) {
        const int side =
            std::max(1, int(std::ceil(std::cbrt(double(std::max<std::uint64_t>(fileBytes, 1))))));
        dims = Dims{side, side, side};
    }
    return estimateSegmentationMemory(*dims, dims->voxelCount() / 4, threads) + fileBytes + preview;
}

}  // namespace skelseg
