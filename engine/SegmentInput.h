// skelseg: the input of `skelseg segment`, read and made a mask.
//
// Two steps, two values, so the command's flow graph can pass them along:
//   readSegmentSource(): the file as it is, a mesh (.off .obj .stl .ply) or
//     a volume (.nrrd/.nhdr .binvox .vdb; its mask is read here);
//   maskSegmentSource(): a mesh voxelised at the requested resolution (the
//     grid is sized and its memory checked before any voxel is made), and for
//     every input the memory estimate of the segmentation against the limit.
//     With a time budget (--time-budget, engine/TimeBudget.h) it first probes
//     the work and chooses the mesh resolution or the volume coarsening; the
//     choice travels in the SegmentMask.
// Errors name the input file: InputError for a file that cannot be read,
// UsageError for a grid that cannot be made, MemoryLimitError for a run that
// would need more than the limit. checkInputFileSize() refuses a file larger
// than the limit before anything is read (readers load the whole file), and
// refuseVolumeGridOverMemory(), called by the volume readers before they
// allocate the mask, a grid that cannot fit.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/StageTimer.h"
#include "engine/TimeBudget.h"
#include "io/mesh/FlippedFaces.h"
#include "io/mesh/MeshCheck.h"
#include "io/mesh/MeshFins.h"
#include "io/mesh/MeshFinsAndHoles.h"
#include "io/mesh/MeshGenus.h"
#include "io/mesh/MeshHoles.h"
#include "io/mesh/MeshIO.h"
#include "io/mesh/MeshVoxelizer.h"
#include "kernels/CubicVoxels.h"
#include "kernels/VoxelGenus.h"
#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// The input file as read.
struct SegmentSource {
    std::filesystem::path file;
    std::optional<TriangleMesh> mesh;  // mesh inputs, as read (every face is labelled)
    /// Mesh inputs with flipped faces (io/mesh/FlippedFaces.h,
    /// checkSourceMesh): the mesh with them turned, which the fin and hole
    /// rules then read.
    std::optional<MeshWithFlippedFacesTurned> flippedFacesTurned;
    /// Mesh inputs closed but for fins (io/mesh/MeshFins.h, checkSourceMesh):
    /// the mesh without them, which is voxelised and whose genus is counted.
    std::optional<MeshWithoutFins> withoutFins;
    /// Mesh inputs closed but for small holes (io/mesh/MeshHoles.h,
    /// checkSourceMesh): the mesh with them capped, voxelised in its place.
    std::optional<MeshWithHolesCapped> withHolesCapped;
    /// Mesh inputs: closedness, pieces, of the mesh voxelised (voxelisedMesh()).
    MeshDiagnostics meshDiagnostics{};
    MaskVolume volumeMask;  // volume inputs: the mask as read (moves on)
    /// Volume inputs of anisotropic voxels (SegmentInputOptions::cubicVoxels):
    /// the cubic grid `volumeMask` was resampled to; the result goes back to
    /// the input's grid (refineStep).
    std::optional<CubicGrid> cubicGrid;
    bool isMesh() const noexcept { return mesh.has_value(); }
    /// The mesh the voxel model is made of: with its holes capped where it
    /// has been found closed so (after its fins were dropped, where both
    /// rules were needed), without its fins where it has been found closed
    /// without them, else as read with its flipped faces turned, if any.
    const TriangleMesh& voxelisedMesh() const {
        if (withHolesCapped) return withHolesCapped->mesh;
        if (withoutFins) return withoutFins->mesh;
        return flippedFacesTurned ? flippedFacesTurned->mesh : *mesh;
    }
};

/// Checks source.mesh (checkMesh) into source.meshDiagnostics; a mesh with
/// flipped faces gets source.flippedFacesTurned (withFlippedFacesTurned),
/// which the rules below then read; a mesh that is open only through fins (closedWithoutFins) gets
/// source.withoutFins, one open only through small holes (closedWithHolesCapped) gets
/// source.withHolesCapped, one open through both (closedWithoutFinsAndHoles)
/// gets both, and the diagnostics are then those of the mesh voxelised.
void checkSourceMesh(SegmentSource& source);

/// The input as the mask to segment.
struct SegmentMask {
    std::shared_ptr<const SegmentSource> source;
    MaskVolume mask;
    std::uint64_t estimatedMemory = 0;  // bytes: voxelising, segmenting, writing
    std::vector<std::string> warnings;  // about the input (mesh check, memory)
    /// The run fits --max-memory only without preview.png: it is skipped.
    bool previewOverMemory = false;
    // Mesh inputs: genus of the mesh and of its voxel model, contacts and
    // self-overlaps separated.
    MeshTopology meshGenus{};
    VoxelTopology voxelGenus{};
    ContactSeparation contacts{};
    SelfOverlapSeparation selfOverlaps{};
    ThinPartFill thinParts{};
    // The mesh piece of each object of `mask` (io/mesh/VoxelObjectPieces.h);
    // empty for volumes and single objects.
    std::vector<ObjectSource> objectSources;
    // "not needed" (voxel genus = mesh genus), "kept" or "rejected": the
    // thin-part fill tried when the voxel model has handles the mesh has not;
    // thinPartGenus is the voxel genus it gave.
    std::string thinPartFill = "not needed";
    std::int64_t thinPartGenus = 0;
    int resolution = 0;  // meshes: the voxelisation's resolution (the budget may lower it)
    // --time-budget: what it chose. A volume segmented `coarsening` times
    // coarser keeps its input mask in `fineMask` for the refinement.
    std::optional<BudgetChoice> budget;
    MaskVolume fineMask;
};

struct SegmentInputOptions {
    std::string gridName;  // .vdb: grid to read (default: the first)
    int resolution = 256;  // meshes: voxels along the longest side
    // Meshes: widest clearing of a place where the mesh passes through itself
    // (SelfOverlapOptions::maxClearance; 2: no wider retry).
    int selfOverlapClearance = 4;
    // Meshes: seams between the two mesh patches of a contact the box check
    // keeps (ContactSeparationOptions::patchSeams).
    bool contactPatchSeams = false;
    bool grownContactSeams = true;  // ContactSeparationOptions::grownSeams
    /// Volumes of anisotropic voxels: segment them resampled to cubic voxels
    /// (kernels/CubicVoxels.h); false: in the file's own voxels.
    bool cubicVoxels = true;
    int threads = 1;  // for the memory estimate (per-thread workspaces)
    int levels = 1;   // for the memory estimate (hierarchy runs: --tau list)
    std::uint64_t memoryLimit = 0;
    double timeBudgetSeconds = 0;     // 0: none; counted from `start`
    bool calibrateTimeBudget = true;  // meshes: engine/BudgetCalibration.h
    /// Set: take this choice instead of probing and planning one (the finer
    /// pass of a budget run, engine/TimeBudget.h BudgetRefinement).
    std::optional<BudgetChoice> budgetChoice;
    /// Memory the caller keeps alive during this run, counted in the memory
    /// check: the first pass's result while the finer pass of a budget run
    /// runs (heldResultBytes).
    std::uint64_t heldBytes = 0;
    /// The run renders preview.png: its memory is counted in the writing
    /// phase (previewRunMemory). A run that fits --max-memory only without
    /// it skips it (SegmentMask::previewOverMemory); the memory caps of a
    /// budget never count it.
    bool preview = false;
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
};

/// What rendering preview.png holds for a scene of `triangles` triangles and
/// `vertices` vertices on `threads` threads (previewMemoryBytes at the
/// default picture size); 0 when `preview` is false.
std::uint64_t previewRunMemory(bool preview, std::uint64_t triangles, std::uint64_t vertices,
                               int threads);

/// The memory a mesh run on a grid of `grid` voxels is estimated to need
/// (segmentation, level set, dense copy, nearest-triangle grid), the
/// estimate checked against --max-memory before voxelising.
/// `meshIsClosed`: also the first voxelisation's mask, which a closed mesh
/// whose voxel genus comes out too high holds while a second voxelisation
/// fills its thin parts (what a budget's choice must leave room for).
/// `boundaryVoxels`: meshBoundaryVoxels() of the mesh at the grid's
/// resolution (estimateSegmentationMemory).
std::uint64_t meshRunMemory(const Dims& grid, int threads, bool meshIsClosed = false,
                            std::uint64_t boundaryVoxels = 0);

/// About how many boundary voxels `mesh` has at `resolution`: its
/// axisProjectedArea() times the resolution squared (a bound: a boundary
/// voxel may expose several faces).
std::uint64_t meshBoundaryVoxels(const TriangleMesh& mesh, int resolution);

/// The largest resolution up to options.resolution whose meshRunMemory, plus
/// options.heldBytes, fits options.memoryLimit; 0 when not even
/// kSmallestBudgetResolution fits. What --time-budget may choose from: the
/// first pass, and with the first pass's result held, the finer pass.
int largestResolutionWithinMemory(const TriangleMesh& mesh, bool meshIsClosed,
                                  const SegmentInputOptions& options);

/// Bytes the outputs hold per boundary voxel of the input's grid while they
/// are written (the segment surfaces, their simplification for display,
/// segments.glb and viewer.html): measured 720 to 880 on four volumes at
/// 400, rounded up (docs/performance.md, "What the writers hold").
constexpr std::uint64_t kOutputBytesPerBoundaryVoxel = 1000;

/// The memory a volume run is estimated to need, the estimate checked
/// against --max-memory: the larger of its two phases. Segmenting: the
/// segmentation of its grid `grid` holding `objectVoxels`, and when that
/// grid is the input `fine` coarsened (by --time-budget) the input mask kept
/// beside it. Writing: the input's mask and labels (one label volume per
/// level; the coarse grid's too when coarsened) and the outputs' surfaces,
/// kOutputBytesPerBoundaryVoxel per boundary voxel of the input
/// (`fineBoundaryVoxels`; 0 for meshes, whose voxelisation's estimate
/// covers their outputs), and with options.preview the preview of a surface
/// of two triangles per boundary voxel.
std::uint64_t volumeRunMemory(const Dims& grid, std::uint64_t objectVoxels, const Dims& fine,
                              std::uint64_t fineBoundaryVoxels, const SegmentInputOptions& options);

/// What a finished pass whose labels are on a grid of `grid` voxels keeps in
/// memory: its mask and, per level, its labels. A coarsened volume's result
/// holds those on the input's grid (plus the coarse mask, at most 1/8 of
/// it, which this counts too); a mesh's on the grid it was voxelised on.
std::uint64_t heldResultBytes(const Dims& grid, int levels, bool coarsened);
/// The same for the result of the pass that segmented `pass`.
std::uint64_t heldResultBytes(const SegmentMask& pass, int levels);

/// The finest coarsenings of a volume --max-memory allows (1, 2 or 4; 0 when
/// not even 4 fits; `boundaryVoxels` its boundary voxels): `firstPass` by volumeRunMemory,
/// `finerPass` with the result of a coarsened first pass held beside it (heldResultBytes). What
/// --time-budget may choose from, as largestResolutionWithinMemory for meshes.
struct CoarseningMemoryCaps {
    int firstPass = 0;
    int finerPass = 0;
};
CoarseningMemoryCaps finestCoarseningsWithinMemory(const MaskVolume& mask,
                                                   std::uint64_t boundaryVoxels,
                                                   const SegmentInputOptions& options,
                                                   Interrupter& interrupter = nullInterrupter());

/// @throw MemoryLimitError when `file`, with the data files of a detached
/// NRRD header, is larger than `memoryLimit` (and each small enough for the
/// readers, which refuse larger files themselves).
void checkInputFileSize(const std::filesystem::path& file, std::uint64_t memoryLimit);

/// @throw MemoryLimitError naming `file` when even the least a run could need
/// for a volume of `dims` is over options.memoryLimit: its mask, and without
/// a time budget (which may coarsen the volume after reading) the
/// segmentation of an empty grid of that size. readSegmentSource() gives it
/// to the volume readers as VolumeReadGuards::checkGrid (io/volume/ReadGuards.h), so a
/// compressed, run-length or OpenVDB file of a few megabytes that holds
/// billions of voxels is refused before they are allocated, and a grid the
/// reader refuses as bad input keeps the exit code of bad input.
void refuseVolumeGridOverMemory(const std::filesystem::path& file, const Dims& dims,
                                const SegmentInputOptions& options);

/// A volume of anisotropic voxels (hasAnisotropicVoxels) resampled to cubic
/// ones in place (stage "cubic voxels"): source.volumeMask becomes the cubic
/// mask and source.cubicGrid says how. Nothing for meshes, cubic voxels,
/// options.cubicVoxels false or a source already resampled. @throw
/// InputError for a cubic grid over kMaxAxisExtent or kMaxVoxels,
/// MemoryLimitError for one over options.memoryLimit, InterruptedError.
void makeVoxelsCubic(SegmentSource& source, const SegmentInputOptions& options, StageTimer& timer,
                     Interrupter& interrupter);

/// Reads a mesh (by extension, isMeshPath()) or a volume; times stage
/// "read mesh" or "read volume"; then makeVoxelsCubic(). @throw InputError, and MemoryLimitError
/// from refuseVolumeGridOverMemory().
SegmentSource readSegmentSource(const std::filesystem::path& file,
                                const SegmentInputOptions& options, StageTimer& timer,
                                Interrupter& interrupter);

/// How many handles the voxel model of a closed mesh has beyond the mesh's
/// own (0 for an open mesh, which has no genus to compare, and for a mesh
/// with a piece whose genus could not be counted, MeshTopology::otherPieces:
/// its handles are unknown, and taking them as none would call real ones
/// the voxel model's): touching or interpenetrating surfaces stayed joined. It decides the
/// thin-part fill, the warning and the cut rule for loops round handles (SegmentSteps.h,
/// parametersFor).
std::int64_t handlesTheMeshLacks(bool meshClosed, const MeshTopology& mesh,
                                 const VoxelTopology& voxels);

/// The mask of `source` (stage "voxelise" for meshes) after the memory
/// checks; a volume's mask moves out of `source` (no copy of the grid). `warn` hears the mesh
/// warnings as soon as the mesh is voxelised (a mesh that is refused costs one line, the error);
/// they are also kept in the result. @throw UsageError, MemoryLimitError, InterruptedError.
SegmentMask maskSegmentSource(std::shared_ptr<SegmentSource> source,
                              const SegmentInputOptions& options, StageTimer& timer,
                              Interrupter& interrupter,
                              const std::function<void(const std::string&)>& warn);

/// The problem with an input whose extension is neither a mesh's nor a
/// volume's (a ".zip" or ".gz" is called an archive to unpack), naming both
/// kinds of formats.
std::string unknownInputFormatProblem(const std::filesystem::path& file);

/// True if the file name has a mesh extension (.off .obj .stl .ply).
bool isMeshPath(const std::filesystem::path& path);

}  // namespace skelseg
