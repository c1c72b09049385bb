// skelseg: the done marker of one batch input, OUTROOT/<name>/done.json.
//
// The batch writes it after `segment` has committed the outputs, through a
// temporary file and rename(2), so a folder holding it holds complete
// outputs. It records what the outputs were made from: the input's size and
// CRC-32 (zlib's; a change detector, not a security hash), the skelseg
// version and the options that change the outputs (not --threads, --quiet,
// --time-limit or --max-memory: the outputs are the same for any of those). A
// re-run skips an input whose marker matches all three and redoes it
// otherwise; before redoing, the marker is removed first, so a run killed
// while redoing leaves no marker behind.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "engine/SegmentCommand.h"

namespace skelseg {

inline constexpr const char* kDoneMarkerName = "done.json";

struct InputFingerprint {
    std::uint64_t bytes = 0;
    std::uint32_t crc32 = 0;
    bool operator==(const InputFingerprint& other) const {
        return bytes == other.bytes && crc32 == other.crc32;
    }
};

/// Size and CRC-32 of a file, read in 1 MiB blocks.
/// @throw InputError naming the file if it is not a readable regular file
///        (checkReadableFile(): a FIFO or a device is refused before it is
///        opened, which would block or read forever) or cannot be read.
InputFingerprint fingerprintFile(const std::filesystem::path& file);

/// The options that change a run's outputs, as canonical JSON text (keys
/// sorted), for the marker and for comparing with it.
std::string outputAffectingOptions(const SegmentCommandOptions& options);

struct DoneMarker {
    std::string skelsegVersion;
    std::filesystem::path input;
    InputFingerprint fingerprint;
    std::string options;     // outputAffectingOptions()
    std::string finishedAt;  // UTC, ISO 8601
    std::string run;         // host:pid of the batch that wrote it
    std::uint64_t parts = 0;
    double wallSeconds = 0.0, cpuSeconds = 0.0;
    std::uint64_t peakMemoryBytes = 0;

    /// True if outputs made under this marker are what a run with
    /// `fingerprint`, `options` and this skelseg would make.
    bool matches(const InputFingerprint& current, const std::string& currentOptions) const;
};

/// The marker in `directory`, or nullopt if there is none or it cannot be
/// parsed (a marker that cannot be trusted means "not done").
std::optional<DoneMarker> readDoneMarker(const std::filesystem::path& directory);

/// Writes the marker atomically. @throw OutputError.
void writeDoneMarker(const std::filesystem::path& directory, const DoneMarker& marker);

/// Removes the marker if present. @throw OutputError if it exists and cannot be removed.
void removeDoneMarker(const std::filesystem::path& directory);

/// Current UTC time as "2026-11-30T05:41:07Z".
std::string utcTimestamp();

/// "host:pid", naming this process in markers and summaries.
std::string runIdentity();

}  // namespace skelseg
