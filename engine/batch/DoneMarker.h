// skelseg: the done marker of one batch input, OUTROOT/<name>/done.json.
//
// The batch writes it after `segment` has committed the outputs, through a
// temporary file and rename(2), so a folder holding it holds complete
// outputs. It records what the outputs were made from: the input's path
// (as the manifest gave it, and absolute), size and CRC-32 (zlib's; a change
// detector, not a security hash) of every file reading it reads (a detached
// NRRD header and its data file), the skelseg version and build
// (engineBuildId(): another build may cut elsewhere) and the options that
// change the outputs (not --threads, --quiet, --time-limit or --max-memory:
// the outputs are the same for any of those). A re-run skips an input whose
// marker matches size, CRC, version, build and options, and redoes it
// otherwise.
//
// The pending marker, OUTROOT/<name>/.pending.json, has the same format and
// says "the batch is making this folder for this input". The batch writes it
// before it segments an input and removes done.json after it, so a run
// killed while (re)doing an input leaves no done.json but a record that the
// folder's outputs are the batch's (engine/batch/OutputFolderClaim.h);
// done.json replaces it when the input is done.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "engine/SegmentCommand.h"

namespace skelseg {

inline constexpr const char* kDoneMarkerName = "done.json";
inline constexpr const char* kPendingMarkerName = ".pending.json";

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

/// Total size and CRC-32 of every file reading `input` reads, in order
/// (volumeInputFiles(): the file itself, and a detached NRRD header's data
/// file), so that new data behind an unchanged header is a changed input.
/// For any other input it equals fingerprintFile(input).
/// @throw InputError as fingerprintFile() for the first file that cannot be read.
InputFingerprint fingerprintInput(const std::filesystem::path& input);

/// The options that change a run's outputs, as canonical JSON text (keys
/// sorted), for the marker and for comparing with it.
std::string outputAffectingOptions(const SegmentCommandOptions& options);

struct DoneMarker {
    std::string skelsegVersion;
    std::string skelsegBuild;             // engineBuildId(); empty in markers that predate it
    std::filesystem::path input;          // as the manifest gave it
    std::filesystem::path absoluteInput;  // absolute; empty in markers that predate it
    InputFingerprint fingerprint;
    std::string options;     // outputAffectingOptions()
    std::string finishedAt;  // UTC, ISO 8601
    std::string run;         // host:pid of the batch that wrote it
    std::uint64_t parts = 0;
    double wallSeconds = 0.0, cpuSeconds = 0.0;
    std::uint64_t peakMemoryBytes = 0;

    /// True if outputs made under this marker are what a run with
    /// `fingerprint`, `options` and this build of skelseg would make.
    bool matches(const InputFingerprint& current, const std::string& currentOptions) const;
    /// True if the marker was written for the file `path` names: the same
    /// path (the manifest's or, from any working directory, the absolute
    /// one), or a path to the same file.
    bool isOf(const std::filesystem::path& path) const;
};

/// The marker `fileName` in `directory`, or nullopt if there is none or it
/// cannot be parsed (a marker that cannot be trusted means "not done").
std::optional<DoneMarker> readDoneMarker(const std::filesystem::path& directory,
                                         const char* fileName = kDoneMarkerName);

/// Writes the marker `fileName` atomically. @throw OutputError.
void writeDoneMarker(const std::filesystem::path& directory, const DoneMarker& marker,
                     const char* fileName = kDoneMarkerName);

/// Removes the marker `fileName` if present. @throw OutputError if it exists
/// and cannot be removed.
void removeDoneMarker(const std::filesystem::path& directory,
                      const char* fileName = kDoneMarkerName);

/// Current UTC time as "2026-11-30T05:41:07Z".
std::string utcTimestamp();

/// "host:pid", naming this process in markers and summaries.
std::string runIdentity();

}  // namespace skelseg
