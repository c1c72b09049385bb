// skelseg: `skelseg segment INPUT -o OUTDIR`, end to end.
//
// Input: a volume (.nrrd/.nhdr, .binvox, .vdb) or a closed triangle mesh
// (.off, .obj, .stl, .ply) voxelised at `resolution`. Output, staged and
// moved into OUTDIR only when everything succeeded (OutputDirectory):
//   labels.nrrd, labels.vdb, skeleton.ply, cuts.ply, segments.ply,
//   segments.glb, viewer.html, preview.png, report.json, and for meshes
//   segmentation.seg.
// The stages run as a oneTBB flow graph: read -> (memory check) -> segment ->
// the writers in parallel -> report -> commit.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/ProgressReporter.h"
#include "engine/Segmenter.h"

namespace skelseg {

struct SegmentCommandOptions {
    std::filesystem::path input;
    std::filesystem::path outdir;
    std::string gridName;  // .vdb: grid to read (default: the first)
    int resolution = 256;  // meshes: voxels along the longest side
    SegmentationParameters parameters;
    int threads = 0;                   // 0: all cores
    double timeLimitSeconds = 0;       // 0: none
    bool force = false;                // replace earlier results in OUTDIR
    std::uint64_t maxMemoryBytes = 0;  // 0: default share of physical memory
    bool writePreview = true;
    bool writeVdb = true;
};

/// Every file name a run may write into OUTDIR.
const std::vector<std::string>& segmentOutputNames();

/// Default memory cap: 75% of physical memory.
std::uint64_t defaultMemoryLimit();

/// Runs the command. Throws skelseg::Error subclasses (see kernels/base/Error.h).
/// Warnings go to `progress.message()`.
void runSegmentCommand(const SegmentCommandOptions& options, ProgressReporter& progress);

/// True if the file name has a mesh extension (.off .obj .stl .ply).
bool isMeshPath(const std::filesystem::path& path);

}  // namespace skelseg
