// skelseg: the list of inputs of a batch, their output names and shards.
//
// A manifest is a text file with one input path per line, or a *.csv whose
// header names a path column (path, input, file, ...; readCsvManifest in
// Manifest.cpp): that column's fields are read as lines are. Blank lines and
// lines whose first non-blank character is '#' are skipped (a '#' later in a
// line is part of the path: file names may hold one; a comment that names an
// existing shape, "#1.off" as `ls` lists it, is a warning); a first line
// that opens JSON ('[', '{', '["', '{"') makes the file no manifest;
// surrounding blanks are trimmed; a path in matching quotes ("my
// shapes/a.off", 'a.off') is the path inside them unless a file named with
// the quotes exists; relative paths
// are relative to the manifest's folder, so a manifest can travel with its
// data. A directory instead of a file, as the manifest or on one of its
// lines, means every supported input file directly in it (not its
// subfolders), by name; a listed directory without one is a warning. A line
// with a shell wildcard (* ? [...], glob(3)) that names no existing file
// means the supported files it matches (and those of the folders it
// matches), by name; a pattern matching none is a warning. A folder's or a
// pattern's files leave out what a batch wrote (the outputs of `segment` in
// a folder holding a done or pending marker): data/*/* beside OUTROOT
// data/res matched them on every run after the first.
//
// Each input gets an output name, the folder OUTROOT/<name>/: the file name
// without its extension. Inputs that share it get as many of their innermost
// folders in front (of the absolute path) as tell each apart from the others
// ("chairs-1", "tables-1"; "e2-a" beside "in-e1-a" and "e2-e1-a"), so the
// names do not depend on the order of the lines; names still equal (3.off
// and 3.obj, or cut to the same bytes) get a counter in manifest order
// ("3-2"), except that an input named by its file name alone keeps it before
// one whose folders made the same name (b-c.off keeps "b-c", a/b/c.off beside
// a-b/c.off takes "b-c-2"). A name that is one of the batch's own files in
// OUTROOT (summary.json, summary.csv, summary.shard-I-of-N.json/.csv) gets a
// counter too ("summary.json-2"), and no name is longer than the 255 bytes a
// folder name can have (a long parent folder's name is cut, then the name
// before a counter). The names depend only on the manifest, so every shard of
// a cluster job computes the same ones. Hidden files (".name") are not
// among a folder's shapes, as a shell's * leaves them out; a line longer
// than any path (PATH_MAX) makes the file no manifest.
//
// Shards: assignShards() splits the inputs into N shares of about equal total
// file size (largest first, each to the lightest shard so far; ties by
// manifest order). File size is the cost proxy that needs no reading: the
// work grows with the voxel count, which grows with the file for volumes and
// with the resolution (the same for all) for meshes. The split depends only on
// the manifest and the sizes, so independent processes agree on it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace skelseg {

struct ManifestEntry {
    std::filesystem::path input;  // as resolved (relative ones joined to the manifest's folder)
    std::string name;             // output folder name, unique in the manifest
    std::uint64_t fileBytes = 0;  // 0 when the file is missing
    bool exists = false;          // a regular file at read time
    /// A missing input's likely cause, for its failure (empty: none seen):
    /// ~ or $NAME in the line, or a path that is a file from the working
    /// directory but not from the manifest's folder.
    std::string missingNote;
    int line = 0;  // 1-based line in the manifest (0 when the manifest is a directory)
};

struct Manifest {
    std::filesystem::path source;
    std::vector<ManifestEntry> entries;  // in manifest order
    std::vector<std::string> warnings;   // duplicates dropped, one line each
    /// The folders lines named, with their line, in manifest order: their
    /// files are entries, the folders are not. (Folders a pattern matched
    /// are not among them: a pattern may match OUTROOT once it exists.)
    std::vector<std::pair<std::filesystem::path, int>> listedFolders;
};

/// True for the extensions `skelseg segment` reads (.nrrd .nhdr .binvox .vdb
/// .off .obj .stl .ply, any case).
bool isSupportedInputPath(const std::filesystem::path& path);

/// Reads a manifest file or lists a directory. An input listed twice (the
/// same file by any path) is kept once, with a warning. Missing files are
/// kept (exists = false): the batch records them as failed.
/// @throw InputError if `source` cannot be read, or lists no input at all.
Manifest readManifest(const std::filesystem::path& source);

/// Output names for `inputs` by the rule above (exposed for tests).
std::vector<std::string> uniqueOutputNames(const std::vector<std::filesystem::path>& inputs);

/// Shard of each input (0..shardCount-1), size-balanced and deterministic.
/// @throw UsageError if shardCount < 1.
std::vector<int> assignShards(const std::vector<std::uint64_t>& sizes, int shardCount);

/// One share of a batch: index in 0..count-1.
struct ShardSpec {
    int index = 0;
    int count = 1;
    /// "I/N" with 0 <= I < N. @throw UsageError otherwise.
    static ShardSpec parse(const std::string& text);
    std::string toString() const;  // "I/N"
    /// Summary file stem: "summary" for 0/1, "summary.shard-I-of-N" otherwise.
    std::string summaryStem() const;
};

/// The shard a cluster scheduler asks for, read through `environment`
/// (getenv in the CLI):
///   Slurm job arrays: SLURM_ARRAY_TASK_ID with SLURM_ARRAY_TASK_COUNT, or
///   with SLURM_ARRAY_TASK_MIN and _MAX (and _STEP): index = (ID - MIN) / STEP;
///   Kubernetes Indexed Jobs: JOB_COMPLETION_INDEX, with `shardsOption`
///   (--shards N) giving the count (the Job's completions).
/// Returns nullopt when neither is set. @throw UsageError for inconsistent
/// values (an index outside the count, a Slurm task id not on MIN + k * STEP,
/// JOB_COMPLETION_INDEX without --shards).
std::optional<ShardSpec> shardFromEnvironment(
    const std::function<const char*(const char*)>& environment, int shardsOption);

}  // namespace skelseg
