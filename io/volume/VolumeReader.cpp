#include "io/volume/VolumeReader.h"

#include "io/files/TextFile.h"
#include "io/volume/BinvoxIO.h"
#include "io/volume/NrrdIO.h"
#include "io/volume/VdbIO.h"
#include "kernels/base/Error.h"

namespace fs = std::filesystem;

namespace skelseg {

VolumeFormat volumeFormatFromPath(const fs::path& file) {
    const std::string extension = lowercase(file.extension().string());
    if (extension == ".nrrd" || extension == ".nhdr") return VolumeFormat::Nrrd;
    if (extension == ".binvox") return VolumeFormat::Binvox;
    if (extension == ".vdb") return VolumeFormat::Vdb;
    return VolumeFormat::Unknown;
}

MaskVolume readVolume(const fs::path& file, const VolumeReadOptions& options) {
    checkReadableFile(file);
    const VolumeFormat format = volumeFormatFromPath(file);
    if (!options.gridName.empty() && format != VolumeFormat::Vdb)
        throw UsageError(file.string() + ": a grid name applies only to OpenVDB (.vdb) input");
    switch (format) {
        case VolumeFormat::Nrrd:
            return readNrrdMask(file, options.guards);
        case VolumeFormat::Binvox:
            return readBinvox(file, options.guards);
        case VolumeFormat::Vdb:
            return readVdbMask(file, options.gridName, options.guards);
        case VolumeFormat::Unknown:
            break;
    }
    const std::string extension = file.extension().string();
    throw InputError(file.string(),
                     (extension.empty() ? std::string("has no file extension to tell the format")
                                        : "unknown volume format '" + extension + "'") +
                         " (supported: .nrrd, .nhdr, .binvox, .vdb)");
}

std::vector<fs::path> volumeInputFiles(const fs::path& file) {
    std::vector<fs::path> files{file};
    if (volumeFormatFromPath(file) == VolumeFormat::Nrrd)
        for (fs::path& dataFile : nrrdDetachedDataFiles(file)) files.push_back(std::move(dataFile));
    return files;
}

}  // namespace skelseg
