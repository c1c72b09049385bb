#include "io/volume/VolumeReader.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

#include "io/volume/BinvoxIO.h"
#include "io/volume/NrrdIO.h"
#include "io/volume/VdbIO.h"
#include "kernels/base/Error.h"

namespace fs = std::filesystem;

namespace skelseg {

namespace {

/// errno as a message that fits after "cannot be read: " (strerror starts with
/// a capital letter; our messages do not).
std::string describeErrno(int errorNumber) {
    if (errorNumber == EACCES || errorNumber == EPERM) return "permission denied";
    std::string text = std::generic_category().message(errorNumber);
    if (!text.empty()) text[0] = char(std::tolower(static_cast<unsigned char>(text[0])));
    return text;
}

std::string lowercaseExtension(const fs::path& file) {
    std::string extension = file.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return extension;
}

}  // namespace

VolumeFormat volumeFormatFromPath(const fs::path& file) {
    const std::string extension = lowercaseExtension(file);
    if (extension == ".nrrd" || extension == ".nhdr") return VolumeFormat::Nrrd;
    if (extension == ".binvox") return VolumeFormat::Binvox;
    if (extension == ".vdb") return VolumeFormat::Vdb;
    return VolumeFormat::Unknown;
}

void checkReadableFile(const fs::path& file) {
    const std::string name = file.string();
    std::error_code ec;
    const fs::file_status status = fs::status(file, ec);
    if (status.type() == fs::file_type::not_found) throw InputError(name, "no such file");
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

MaskVolume readVolume(const fs::path& file, const VolumeReadOptions& options) {
    checkReadableFile(file);
    const VolumeFormat format = volumeFormatFromPath(file);
    if (!options.gridName.empty() && format != VolumeFormat::Vdb)
        throw UsageError(file.string() + ": a grid name applies only to OpenVDB (.vdb) input");
    switch (format) {
        case VolumeFormat::Nrrd:
            return readNrrdMask(file);
        case VolumeFormat::Binvox:
            return readBinvox(file);
        case VolumeFormat::Vdb:
            return readVdbMask(file, options.gridName);
        case VolumeFormat::Unknown:
            break;
    }
    const std::string extension = file.extension().string();
    throw InputError(file.string(),
                     (extension.empty() ? std::string("has no file extension to tell the format")
                                        : "unknown volume format '" + extension + "'") +
                         " (supported: .nrrd, .nhdr, .binvox, .vdb)");
}

}  // namespace skelseg
