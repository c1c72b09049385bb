#include "engine/batch/DoneMarker.h"

#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <ctime>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "engine/ResultReport.h"
#include "engine/Version.h"
#include "io/files/OutputDirectory.h"
#include "io/files/TextFile.h"
#include "io/volume/VolumeReader.h"
#include "kernels/base/Error.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace skelseg {

namespace {

/// Adds the bytes of `file` to `fingerprint`, whose crc32 runs on.
void addFileToFingerprint(const fs::path& file, InputFingerprint& fingerprint) {
    checkReadableFile(file);
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError(file.string(), "cannot be read: " + describeErrno(errno));
    uLong crc = fingerprint.crc32;
    std::vector<char> block(std::size_t(1) << 20);
    while (in) {
        in.read(block.data(), std::streamsize(block.size()));
        const auto got = in.gcount();
        if (got <= 0) break;
        crc = ::crc32(crc, reinterpret_cast<const Bytef*>(block.data()), uInt(got));
        fingerprint.bytes += std::uint64_t(got);
    }
    if (in.bad()) throw InputError(file.string(), "read error");
    fingerprint.crc32 = std::uint32_t(crc);
}

}  // namespace

InputFingerprint fingerprintFile(const fs::path& file) {
    InputFingerprint fingerprint;
    addFileToFingerprint(file, fingerprint);
    return fingerprint;
}

InputFingerprint fingerprintInput(const fs::path& input) {
    InputFingerprint fingerprint;
    for (const fs::path& file : volumeInputFiles(input)) addFileToFingerprint(file, fingerprint);
    return fingerprint;
}

std::string outputAffectingOptions(const SegmentCommandOptions& options) {
    const SegmentationParameters& p = options.parameters;
    // nlohmann::json objects keep keys sorted: the text is canonical.
    json j = methodParameters(p);
    j.update({{"noise_area_min", p.noiseAreaMin},
              {"noise_area_fraction", p.noiseAreaFraction},
              {"min_object_voxels", p.minObjectVoxels},
              {"resolution", options.resolution},
              {"grid", options.gridName},
              {"preview", options.writePreview},
              {"vdb", options.writeVdb}});
    // Only when set: markers written before the option existed still match
    // a run with its default, which gives the same outputs.
    if (options.selfOverlapClearance != SegmentCommandOptions{}.selfOverlapClearance)
        j["self_overlap_clearance"] = options.selfOverlapClearance;
    if (options.contactPatchSeams) j["contact_patch_seams"] = true;
    if (!options.grownContactSeams) j["grown_contact_seams"] = false;
    if (!p.artefactHandlesCarryNoArea) j["keep_handle_areas"] = true;
    if (options.keepVoxelAspect) j["keep_voxel_aspect"] = true;
    return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

bool DoneMarker::matches(const InputFingerprint& current, const std::string& currentOptions) const {
    return skelsegVersion == versionString() && skelsegBuild == engineBuildId() &&
           fingerprint == current && options == currentOptions;
}

bool DoneMarker::isOf(const fs::path& path) const {
    if (input.lexically_normal() == path.lexically_normal()) return true;
    std::error_code ec;
    const fs::path absolutePath = fs::absolute(path, ec).lexically_normal();
    if (!absoluteInput.empty() && !ec && absoluteInput.lexically_normal() == absolutePath)
        return true;
    // A relative path of the marker's is read from this working directory,
    // which may not be the batch's that wrote it: the absolute one first.
    const fs::path recorded = absoluteInput.empty() ? input : absoluteInput;
    return fs::equivalent(recorded, path, ec) && !ec;
}

std::optional<DoneMarker> readDoneMarker(const fs::path& directory, const char* fileName) {
    std::ifstream in(directory / fileName, std::ios::binary);
    if (!in) return std::nullopt;
    try {
        const json j = json::parse(in);
        DoneMarker marker;
        marker.skelsegVersion = j.at("skelseg_version").get<std::string>();
        marker.skelsegBuild = j.value("skelseg_build", std::string());
        marker.input = j.at("input").at("path").get<std::string>();
        marker.absoluteInput = j.at("input").value("absolute_path", std::string());
        marker.fingerprint.bytes = j.at("input").at("bytes").get<std::uint64_t>();
        marker.fingerprint.crc32 =
            std::uint32_t(std::stoul(j.at("input").at("crc32").get<std::string>(), nullptr, 16));
        marker.options = j.at("options").dump();
        marker.finishedAt = j.at("finished_at").get<std::string>();
        marker.run = j.at("run").get<std::string>();
        marker.parts = j.at("parts").get<std::uint64_t>();
        marker.wallSeconds = j.at("wall_seconds").get<double>();
        marker.cpuSeconds = j.at("cpu_seconds").get<double>();
        marker.peakMemoryBytes = j.at("peak_memory_bytes").get<std::uint64_t>();
        return marker;
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

void writeDoneMarker(const fs::path& directory, const DoneMarker& marker, const char* fileName) {
    char crc[16];
    std::snprintf(crc, sizeof crc, "%08x", marker.fingerprint.crc32);
    json j = {
        {"skelseg_version", marker.skelsegVersion},
        {"skelseg_build", marker.skelsegBuild},
        {"input",
         {{"path", marker.input.string()}, {"bytes", marker.fingerprint.bytes}, {"crc32", crc}}},
        {"options", json::parse(marker.options)},
        {"finished_at", marker.finishedAt},
        {"run", marker.run},
        {"parts", marker.parts},
        {"wall_seconds", marker.wallSeconds},
        {"cpu_seconds", marker.cpuSeconds},
        {"peak_memory_bytes", marker.peakMemoryBytes}};
    if (!marker.absoluteInput.empty()) j["input"]["absolute_path"] = marker.absoluteInput.string();
    writeFileAtomically(directory / fileName,
                        j.dump(2, ' ', false, json::error_handler_t::replace) + "\n");
}

void removeDoneMarker(const fs::path& directory, const char* fileName) {
    std::error_code ec;
    fs::remove(directory / fileName, ec);
    if (ec) throw OutputError((directory / fileName).string() + ": cannot remove: " + ec.message());
}

std::string utcTimestamp() {
    const std::time_t now = std::time(nullptr);
    std::tm utc{};
    ::gmtime_r(&now, &utc);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
    return text;
}

std::string runIdentity() {
    char host[256] = {};
    if (::gethostname(host, sizeof host - 1) != 0) std::strcpy(host, "unknown");
    return std::string(host) + ":" + std::to_string(::getpid());
}

}  // namespace skelseg
