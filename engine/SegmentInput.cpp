#include "engine/SegmentInput.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdio>

#include "engine/Segmenter.h"
#include "engine/Stage.h"
#include "io/files/CompressedContent.h"
#include "io/files/TextFile.h"
#include "io/mesh/MeshVoxelizer.h"
#include "io/render/PreviewRenderer.h"
#include "io/volume/VolumeReader.h"
#include "kernels/BoundaryGraph.h"

namespace fs = std::filesystem;

namespace skelseg {

bool isMeshPath(const fs::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".off" || ext == ".obj" || ext == ".stl" || ext == ".ply";
}

std::string unknownInputFormatProblem(const fs::path& file) {
    // The volume reader's own message lists the volume formats only, which
    // told the user of "part.obj.zip" or "part.stl.gz" that meshes are not
    // read at all; an archive is the commonest such input (test-model
    // collections ship them), so say what to do with it.
    const std::string extension = file.extension().string();
    const std::string lower = lowercase(extension);
    static const char* const kArchives[] = {".gz",  ".tgz", ".bz2", ".xz",  ".zst", ".lz4",
                                            ".zip", ".7z",  ".rar", ".tar", ".z"};
    const std::string supported =
        "skelseg reads .off, .obj, .stl and .ply meshes and .nrrd, .nhdr, .binvox and .vdb volumes";
    if (extension.empty()) return "has no file extension to tell the format (" + supported + ")";
    for (const char* archive : kArchives)
        if (lower == archive)
            return compressedFileProblem(quote(extension)) + " (" + supported + ")";
    return "unknown input format " + quote(extension) + " (" + supported + ")";
}

void checkInputFileSize(const fs::path& file, std::uint64_t memoryLimit) {
    // A detached NRRD header's data files are read into memory with it
    // (all of them before the volume is allocated).
    const std::vector<fs::path> files = volumeInputFiles(file);
    std::uint64_t totalBytes = 0;
    for (const fs::path& part : files) {
        std::error_code ec;
        const auto size = fs::is_regular_file(part, ec) ? fs::file_size(part, ec) : 0;
        // Files over kMaxInputFileBytes are bad input whatever the memory:
        // the reader refuses them.
        if (ec || size > kMaxInputFileBytes) return;
        totalBytes += size;
    }
    if (totalBytes > memoryLimit)
        throw MemoryLimitError(
            file.string() + ": reading the file" + (files.size() > 1 ? " and its data files" : "") +
            " needs at least " + formatBytes(totalBytes) + ", over the limit of " +
            formatBytes(memoryLimit) + " (--max-memory)");
}

void refuseVolumeGridOverMemory(const fs::path& file, const Dims& dims,
                                const SegmentInputOptions& options) {
    const std::uint64_t leastBytes =
        options.timeBudgetSeconds > 0
            ? dims.voxelCount()
            : estimateSegmentationMemory(dims, 0, options.threads, options.levels);
    if (leastBytes > options.memoryLimit)
        throw MemoryLimitError(file.string() + ": its grid of " + std::to_string(dims.x) + " x " +
                               std::to_string(dims.y) + " x " + std::to_string(dims.z) +
                               " voxels needs at least " + formatBytes(leastBytes) +
                               ", over the limit of " + formatBytes(options.memoryLimit) +
                               " (--max-memory)");
}

void makeVoxelsCubic(SegmentSource& source, const SegmentInputOptions& options, StageTimer& timer,
                     Interrupter& interrupter) {
    if (source.isMesh() || !options.cubicVoxels || source.cubicGrid ||
        !hasAnisotropicVoxels(source.volumeMask.geometry))
        return;
    const CubicGrid grid = cubicGridFor(source.volumeMask.dims(), source.volumeMask.geometry);
    if (grid.dims[0] > kMaxAxisExtent || grid.dims[1] > kMaxAxisExtent ||
        grid.dims[2] > kMaxAxisExtent || grid.voxelCount() > kMaxVoxels) {
        const auto steps = voxelSteps(grid.inputGeometry);
        throw InputError(source.file.string(),
                         fmt::format("voxels are anisotropic (steps {:g} x {:g} x {:g}): the "
                                     "cubic grid of {} x {} x {} voxels they need is over the "
                                     "limit of {} voxels or {} along an axis; "
                                     "--keep-voxel-aspect segments the file's own voxels",
                                     steps[0], steps[1], steps[2], grid.dims[0], grid.dims[1],
                                     grid.dims[2], kMaxVoxels, kMaxAxisExtent));
    }
    // The memory check of a grid read from a file, on the cubic grid; the
    // message says which grid, as the file's own grid fitted.
    try {
        refuseVolumeGridOverMemory(
            source.file, Dims{int(grid.dims[0]), int(grid.dims[1]), int(grid.dims[2])}, options);
    } catch (const MemoryLimitError& error) {
        throw MemoryLimitError(std::string(error.what()) +
                               "; that is the cubic grid of its anisotropic voxels, and "
                               "--keep-voxel-aspect segments the file's own voxels");
    }
    Stage stage(timer, interrupter, "cubic voxels", true);
    source.volumeMask = resampleToCubicVoxels(source.volumeMask, grid, {}, interrupter);
    source.cubicGrid = grid;
}

void checkSourceMesh(SegmentSource& source) {
    source.flippedFacesTurned.reset();
    source.withoutFins.reset();
    source.withHolesCapped.reset();
    source.meshDiagnostics = checkMesh(*source.mesh);
    // Turned first: a hole's border is chained along the windings of the
    // faces round it, and a flipped face there would break the chain.
    if (source.meshDiagnostics.misorientedEdges > 0) {
        source.flippedFacesTurned = withFlippedFacesTurned(*source.mesh);
        if (source.flippedFacesTurned)
            source.meshDiagnostics = source.flippedFacesTurned->diagnostics;
    }
    const TriangleMesh& read =
        source.flippedFacesTurned ? source.flippedFacesTurned->mesh : *source.mesh;
    // Only a mesh with a free border can have fins or holes; each search
    // costs a sort of its edges.
    const MeshDiagnostics& found = source.meshDiagnostics;
    if (found.closed || found.boundaryEdges == 0) return;
    const std::size_t unusedVertices = found.unusedVertices;
    source.withoutFins = closedWithoutFins(read);
    if (source.withoutFins) {
        source.meshDiagnostics = source.withoutFins->diagnostics;
    } else if ((source.withHolesCapped = closedWithHolesCapped(read))) {
        source.meshDiagnostics = source.withHolesCapped->diagnostics;
    } else if (auto both = closedWithoutFinsAndHoles(read)) {
        source.withoutFins = std::move(both->withoutFins);
        source.withHolesCapped = std::move(both->capped);
        source.meshDiagnostics = source.withHolesCapped->diagnostics;
    } else {
        return;
    }
    // A fin's own corners are used by the mesh as read, and the caps use
    // only border vertices: only the file's unused vertices are reported.
    source.meshDiagnostics.unusedVertices = unusedVertices;
}

SegmentSource readSegmentSource(const fs::path& file, const SegmentInputOptions& options,
                                StageTimer& timer, Interrupter& interrupter) {
    SegmentSource source;
    source.file = file;
    if (isMeshPath(file)) {
        {
            Stage stage(timer, interrupter, "read mesh", false);
            checkReadableFile(file);
            // As readVolume() refuses it for the other volume formats: a
            // --grid given with a mesh was ignored without a word.
            if (!options.gridName.empty())
                throw UsageError(file.string() +
                                 ": a grid name applies only to OpenVDB (.vdb) input");
            source.mesh = readMesh(file);
        }
        Stage stage(timer, interrupter, "check mesh", false);
        checkSourceMesh(source);
    } else {
        Stage stage(timer, interrupter, "read volume", false);
        if (volumeFormatFromPath(file) == VolumeFormat::Unknown) {
            checkReadableFile(file);
            throw InputError(file.string(), unknownInputFormatProblem(file));
        }
        VolumeReadOptions readOptions;
        readOptions.gridName = options.gridName;
        readOptions.guards.checkGrid = [&](const Dims& dims) {
            refuseVolumeGridOverMemory(file, dims, options);
        };
        readOptions.guards.memoryLimit = options.memoryLimit;
        readOptions.guards.interrupter = &interrupter;
        source.volumeMask = readVolume(file, readOptions);
    }
    makeVoxelsCubic(source, options, timer, interrupter);
    return source;
}

namespace {
/// Bytes a labelled grid voxel holds while the outputs are written: its
/// mask byte and a 16-bit label per level.
std::uint64_t labelledVoxelBytes(int levels) {
    return 1 + 2 * std::uint64_t(std::max(levels, 1));
}
}  // namespace

std::uint64_t previewRunMemory(bool preview, std::uint64_t triangles, std::uint64_t vertices,
                               int threads) {
    if (!preview) return 0;
    PreviewOptions options;
    options.threaded = threads > 1;
    return previewMemoryBytes(options, triangles, vertices, threads);
}

namespace {

/// meshBoundaryVoxels of a mesh whose axisProjectedArea is `projectedArea`.
std::uint64_t boundaryVoxelsOfArea(double projectedArea, int resolution) {
    return std::uint64_t(projectedArea * double(resolution) * double(resolution));
}

}  // namespace

std::uint64_t meshBoundaryVoxels(const TriangleMesh& mesh, int resolution) {
    return boundaryVoxelsOfArea(axisProjectedArea(mesh), resolution);
}

std::uint64_t meshRunMemory(const Dims& grid, int threads, bool meshIsClosed,
                            std::uint64_t boundaryVoxels) {
    return estimateSegmentationMemory(grid, grid.voxelCount() / 4, threads, 1, boundaryVoxels) +
           grid.voxelCount() * (meshIsClosed ? 13 : 12);  // level set, dense copy,
                                                          // nearest-triangle grid
}

int largestResolutionWithinMemory(const TriangleMesh& mesh, bool meshIsClosed,
                                  const SegmentInputOptions& options) {
    VoxelizeOptions voxelizeOptions;
    const double projectedArea = axisProjectedArea(mesh);
    const auto fits = [&](int resolution) {
        voxelizeOptions.resolution = resolution;
        return meshRunMemory(voxelGridFor(mesh, voxelizeOptions).dims, options.threads,
                             meshIsClosed, boundaryVoxelsOfArea(projectedArea, resolution)) +
                   options.heldBytes <=
               options.memoryLimit;
    };
    if (options.resolution < kSmallestBudgetResolution || !fits(kSmallestBudgetResolution))
        return 0;
    if (fits(options.resolution)) return options.resolution;
    // The estimate grows with the resolution: the last that fits, by bisection.
    int fitting = kSmallestBudgetResolution, over = options.resolution;
    while (over - fitting > 1) {
        const int middle = fitting + (over - fitting) / 2;
        (fits(middle) ? fitting : over) = middle;
    }
    return fitting;
}

std::uint64_t volumeRunMemory(const Dims& grid, std::uint64_t objectVoxels, const Dims& fine,
                              std::uint64_t fineBoundaryVoxels,
                              const SegmentInputOptions& options) {
    const bool coarsened = grid.voxelCount() < fine.voxelCount();
    const std::uint64_t perLabelledVoxel = labelledVoxelBytes(options.levels);
    const std::uint64_t segmenting =
        estimateSegmentationMemory(grid, objectVoxels, options.threads, options.levels,
                                   std::min(objectVoxels, fineBoundaryVoxels)) +
        (coarsened ? fine.voxelCount() : 0);
    const std::uint64_t writing =
        (fine.voxelCount() + (coarsened ? grid.voxelCount() : 0)) * perLabelledVoxel +
        fineBoundaryVoxels * kOutputBytesPerBoundaryVoxel +
        previewRunMemory(options.preview, 2 * fineBoundaryVoxels, fineBoundaryVoxels,
                         options.threads);
    return std::max(segmenting, writing);
}

std::uint64_t heldResultBytes(const Dims& grid, int levels, bool coarsened) {
    const std::uint64_t voxels = grid.voxelCount();
    return voxels * labelledVoxelBytes(levels) + (coarsened ? voxels / 8 : 0);
}

std::uint64_t heldResultBytes(const SegmentMask& pass, int levels) {
    const bool coarsened = pass.fineMask.dims().voxelCount() > 0;
    return heldResultBytes(coarsened ? pass.fineMask.dims() : pass.mask.dims(), levels, coarsened);
}

namespace {
std::uint64_t objectVoxelCount(const MaskVolume& mask) {
    std::uint64_t count = 0;
    for (std::uint8_t v : mask.values()) count += v != 0;
    return count;
}
}  // namespace

CoarseningMemoryCaps finestCoarseningsWithinMemory(const MaskVolume& mask,
                                                   std::uint64_t boundaryVoxels,
                                                   const SegmentInputOptions& options,
                                                   Interrupter& interrupter) {
    CoarseningMemoryCaps caps;
    // A run that fits only without preview.png skips it (maskSegmentSource):
    // the preview never makes a grid coarser.
    SegmentInputOptions withoutPreview = options;
    withoutPreview.preview = false;
    const std::uint64_t held = heldResultBytes(mask.dims(), options.levels, true);
    for (int factor : {1, 2, 4}) {
        throwIfInterrupted(interrupter);
        // The coarse grid's object voxels decide the rest of the estimate; the
        // grid alone is the larger part, so a grid that cannot fit is not
        // coarsened to count them.
        const Dims grid{(mask.dims().x + factor - 1) / factor,
                        (mask.dims().y + factor - 1) / factor,
                        (mask.dims().z + factor - 1) / factor};
        if (volumeRunMemory(grid, 0, mask.dims(), boundaryVoxels, withoutPreview) >
            options.memoryLimit)
            continue;
        // Not `factor == 1 ? mask : coarsenMask(...)`: that would copy the mask.
        const std::uint64_t objects =
            factor == 1 ? objectVoxelCount(mask) : objectVoxelCount(coarsenMask(mask, factor));
        const std::uint64_t bytes =
            volumeRunMemory(grid, objects, mask.dims(), boundaryVoxels, withoutPreview);
        if (caps.firstPass == 0 && bytes <= options.memoryLimit) caps.firstPass = factor;
        if (caps.finerPass == 0 && bytes + held <= options.memoryLimit) caps.finerPass = factor;
        // Coarser grids need less: once both caps are known, counting their
        // object voxels would only cost the budget's time.
        if (caps.finerPass != 0) break;
    }
    return caps;
}

namespace {

/// Voxelises the mesh in a stage named `stageName`; `fillThinParts` as in
/// VoxelizeOptions. `heldBytes` is memory the caller keeps alive meanwhile (a
/// first voxelisation), counted in the estimate checked against the limit.
/// `signedVoxels`: the mesh conversion, kept by the first voxelisation and
/// reused by the second (MeshVoxelizer.h).
MeshVoxelization voxelise(const SegmentSource& source, const SegmentInputOptions& options,
                          StageTimer& timer, Interrupter& interrupter,
                          std::uint64_t& estimatedMemory, bool fillThinParts, const char* stageName,
                          std::uint64_t heldBytes, SignedVoxelization& signedVoxels) {
    const TriangleMesh& mesh = source.voxelisedMesh();
    VoxelizeOptions voxelizeOptions;
    voxelizeOptions.resolution = options.resolution;
    voxelizeOptions.meshIsClosed = source.meshDiagnostics.closed;
    voxelizeOptions.fillThinParts = fillThinParts;
    voxelizeOptions.selfOverlapOptions.maxClearance = options.selfOverlapClearance;
    voxelizeOptions.contactOptions.patchSeams = options.contactPatchSeams;
    voxelizeOptions.contactOptions.grownSeams = options.grownContactSeams;
    // The voxeliser's refusals (a grid over the cap, a mesh collapsed to a
    // point) do not know the file: name it, as every error must.
    const auto nameTheFile = [&](const UsageError& error) {
        return UsageError(source.file.string() + ": " + error.what());
    };
    VoxelGrid grid;
    try {
        grid = voxelGridFor(mesh, voxelizeOptions);
    } catch (const UsageError& error) {
        throw nameTheFile(error);
    }
    // No face with area: no surface bounds anything. The voxeliser would make
    // a wire of voxels and label it one part; refuse it, as the mesh
    // counterpart of an empty volume.
    if (mesh.faceCount > 0 && source.meshDiagnostics.degenerateFaces >= mesh.faceCount)
        throw InputError(source.file.string(),
                         noFaceHasArea(mesh.faceCount) + ": the mesh has no surface to segment");
    // Every face in one plane: the voxeliser would make a sheet one voxel
    // thick, which no skeleton crosses, and label it one part.
    if (source.meshDiagnostics.flat)
        throw InputError(source.file.string(),
                         "the mesh is flat (every vertex of its faces lies in one plane): it "
                         "encloses no volume to segment");
    estimatedMemory = meshRunMemory(grid.dims, options.threads, false,
                                    meshBoundaryVoxels(mesh, options.resolution)) +
                      heldBytes + options.heldBytes;
    if (estimatedMemory > options.memoryLimit)
        throw MemoryLimitError(source.file.string() + ": needs about " +
                               formatBytes(estimatedMemory) + " at resolution " +
                               std::to_string(options.resolution) + ", over the limit of " +
                               formatBytes(options.memoryLimit) + " (--max-memory)");
    Stage stage(timer, interrupter, stageName, true);
    try {
        return voxelizeMeshWithContacts(mesh, voxelizeOptions, interrupter, &signedVoxels);
    } catch (const UsageError& error) {
        throw nameTheFile(error);
    }
}

/// A closed mesh whose voxel model has handles the mesh lacks: surfaces
/// closer than about a voxel (an ear lying on the head, a leg folded against
/// the body) or passing through each other stayed joined, and the skeleton
/// runs round the joint. The cuts near such a place can differ from pose to
/// pose, and no resolution is sure to remove it (docs/meshes.md, "Handles
/// the voxel model keeps"), so the user is told rather than left to find it
/// in report.json.
std::string extraHandlesWarning(const std::string& file, std::int64_t extra,
                                std::int64_t voxelGenus, std::int64_t meshGenus, int resolution) {
    return fmt::format(
        "{}: the voxel model at resolution {} has {} handle{} the mesh lacks (voxel genus {}, "
        "mesh genus {}): surfaces closer than a voxel or passing through each other stay "
        "joined there, and the parts near them may differ from pose to pose",
        file, resolution, extra, extra == 1 ? "" : "s", voxelGenus, meshGenus);
}

double secondsLeft(const SegmentInputOptions& options) {
    return options.timeBudgetSeconds -
           std::chrono::duration<double>(std::chrono::steady_clock::now() - options.start).count();
}

/// Under --time-budget, the caller's interrupter until the plan says a
/// choice fits, stopping the run once the budget is spent: the probe, and
/// the mask of a choice predicted over the budget, end at the budget as
/// --time-limit would, instead of finishing a voxelisation that the caller's
/// limit (limitTimeToBudget) only stops after.
class BudgetStop final : public Interrupter {
public:
    BudgetStop(Interrupter& inner, const SegmentInputOptions& options)
        : mInner(inner), mOptions(options) {}
    void start(const char* name) override { mInner.start(name); }
    void end() override { mInner.end(); }
    bool wasInterrupted(double fraction) override {
        if (mInner.wasInterrupted(fraction)) return true;
        if (!mActive.load(std::memory_order_relaxed) || secondsLeft(mOptions) > 0.0) return false;
        mSpent.store(true);
        return true;
    }
    InterruptedError::Reason reason() const override {
        return mSpent.load() ? InterruptedError::Reason::TimeLimit : mInner.reason();
    }
    /// A choice fits: from here on only the caller's interrupter stops the
    /// run (a late answer rather than none, docs/performance.md).
    void release() noexcept { mActive.store(false); }

private:
    Interrupter& mInner;
    const SegmentInputOptions& mOptions;
    std::atomic<bool> mActive{true}, mSpent{false};
};

/// Chooses the resolution (meshes) before voxelising; budget of the user,
/// not what is left after reading, in the choice's budgetSeconds.
BudgetChoice planMeshBudget(const SegmentSource& source, const SegmentInputOptions& options,
                            StageTimer& timer, Interrupter& interrupter) {
    Stage stage(timer, interrupter, "time budget probe", true);
    VoxelizeOptions voxelizeOptions;
    voxelizeOptions.resolution = options.resolution;
    voxelizeOptions.meshIsClosed = source.meshDiagnostics.closed;
    // Only what --max-memory allows is a choice; with none, the requested
    // resolution stays and its refusal names the limit.
    const int memoryCap = largestResolutionWithinMemory(source.voxelisedMesh(),
                                                        source.meshDiagnostics.closed, options);
    if (memoryCap > 0) voxelizeOptions.resolution = memoryCap;
    const ProbeCostModel probeModel = ProbeCostModel::fitted();
    BudgetChoice choice = planMeshRun(
        source.voxelisedMesh(), voxelizeOptions, secondsLeft(options), CostModel::fitted(),
        options.calibrateTimeBudget ? &probeModel : nullptr, interrupter);
    choice.budgetSeconds = options.timeBudgetSeconds;
    choice.memoryCapResolution = memoryCap < options.resolution ? memoryCap : 0;
    if (choice.memoryCapResolution > 0) choice.coarsened = true;
    // A finer pass runs beside the first pass's result: only what fits with
    // it (none above the first choice when nothing does).
    if (choice.fits && choice.coarsened) {
        SegmentInputOptions finer = options;
        voxelizeOptions.resolution = choice.resolution;
        finer.heldBytes += heldResultBytes(
            voxelGridFor(source.voxelisedMesh(), voxelizeOptions).dims, options.levels, false);
        const int finerCap = largestResolutionWithinMemory(source.voxelisedMesh(),
                                                           source.meshDiagnostics.closed, finer);
        if (finerCap < options.resolution)
            choice.finerMemoryCapResolution = std::max(finerCap, choice.resolution);
    }
    return choice;
}

/// Chooses the coarsening (volumes) and coarsens `result.mask`, keeping the
/// input mask for the refinement.
void planVolumeBudget(SegmentMask& result, std::uint64_t boundaryVoxels,
                      const SegmentInputOptions& options, StageTimer& timer,
                      Interrupter& interrupter) {
    Stage stage(timer, interrupter, "time budget probe", true);
    if (options.budgetChoice) {
        result.budget = options.budgetChoice;
    } else {
        // Only what --max-memory allows is a choice. With nothing, the
        // coarsest runs into the memory check, whose refusal names the least
        // a run of this volume needs.
        const CoarseningMemoryCaps caps =
            finestCoarseningsWithinMemory(result.mask, boundaryVoxels, options, interrupter);
        result.budget = planVolumeRun(result.mask, secondsLeft(options), CostModel::fitted(),
                                      caps.firstPass == 0 ? 4 : caps.firstPass, interrupter);
        result.budget->budgetSeconds = options.timeBudgetSeconds;
        result.budget->memoryCapCoarsening = caps.firstPass > 1 ? caps.firstPass : 0;
        // No finer pass where nothing fits beside the first pass's result.
        result.budget->finerMemoryCapCoarsening = caps.finerPass == 0  ? 8
                                                  : caps.finerPass > 1 ? caps.finerPass
                                                                       : 0;
    }
    if (result.budget->coarsening > 1) {
        result.fineMask = std::move(result.mask);
        result.mask = coarsenMask(result.fineMask, result.budget->coarsening);
    }
}

}  // namespace

SegmentMask maskSegmentSource(std::shared_ptr<SegmentSource> source,
                              const SegmentInputOptions& options, StageTimer& timer,
                              Interrupter& interrupter,
                              const std::function<void(const std::string&)>& warn) {
    SegmentMask result;
    BudgetStop budgetStop(interrupter, options);
    Interrupter& stop = options.timeBudgetSeconds > 0 ? budgetStop : interrupter;
    if (source->isMesh()) {
        SegmentInputOptions chosen = options;
        if (options.budgetChoice) {
            result.budget = options.budgetChoice;
            chosen.resolution = result.budget->resolution;
            budgetStop.release();
        } else if (options.timeBudgetSeconds > 0) {
            result.budget = planMeshBudget(*source, options, timer, stop);
            chosen.resolution = result.budget->resolution;
            if (result.budget->fits) budgetStop.release();
        }
        result.resolution = chosen.resolution;
        SignedVoxelization signedVoxels;
        MeshVoxelization voxelised = voxelise(*source, chosen, timer, stop, result.estimatedMemory,
                                              false, "voxelise", 0, signedVoxels);
        {
            Stage stage(timer, stop, "genus", true);
            result.meshGenus = meshTopology(source->voxelisedMesh());
            result.voxelGenus = voxelTopology(voxelised.mask, {}, stop);
        }
        // Handles the mesh does not have: parts thinner than a voxel (an ear)
        // may have come out perforated. Voxelise again with their middles
        // filled, and keep that model only if it has fewer handles: a fill
        // that changes no handle (joining a broken tip, which is an island
        // and no part anyway) would only change parts that were right
        // (docs/meshes.md, "Parts thinner than a voxel"). Meshes whose voxel
        // genus is right pay nothing.
        const bool fillThinParts = handlesTheMeshLacks(source->meshDiagnostics.closed,
                                                       result.meshGenus, result.voxelGenus) > 0;
        if (!fillThinParts) signedVoxels = SignedVoxelization{};  // free it before the skeleton
        if (fillThinParts) {
            std::uint64_t filledMemory = 0;
            MeshVoxelization filled = voxelise(*source, chosen, timer, stop, filledMemory, true,
                                               "voxelise with thin parts filled",
                                               voxelised.mask.dims().voxelCount(), signedVoxels);
            signedVoxels = SignedVoxelization{};
            result.estimatedMemory = std::max(result.estimatedMemory, filledMemory);
            VoxelTopology filledGenus;
            {
                Stage stage(timer, stop, "genus with thin parts filled", true);
                filledGenus = voxelTopology(filled.mask, {}, stop);
            }
            result.thinPartFill = filledGenus.genus < result.voxelGenus.genus ? "kept" : "rejected";
            result.thinPartGenus = filledGenus.genus;
            if (filledGenus.genus < result.voxelGenus.genus) {
                voxelised = std::move(filled);
                result.voxelGenus = filledGenus;
            }
        }
        result.mask = std::move(voxelised.mask);
        result.contacts = voxelised.contacts;
        result.selfOverlaps = voxelised.selfOverlaps;
        result.thinParts = voxelised.thinParts;
        result.objectSources = std::move(voxelised.objectSources);
        std::vector<std::string> warnings;
        if (source->flippedFacesTurned)
            warnings.push_back(
                flippedFacesWarning(source->file.string(), *source->flippedFacesTurned));
        if (source->withoutFins && source->withHolesCapped)
            warnings.push_back(finsAndHolesWarning(source->file.string(), *source->withoutFins,
                                                   *source->withHolesCapped));
        else if (source->withoutFins)
            warnings.push_back(finsWarning(source->file.string(), *source->withoutFins));
        else if (source->withHolesCapped)
            warnings.push_back(holesWarning(source->file.string(), *source->withHolesCapped));
        for (std::string& warning : meshWarnings(source->meshDiagnostics, source->file.string()))
            warnings.push_back(std::move(warning));
        const std::int64_t extraHandles = handlesTheMeshLacks(source->meshDiagnostics.closed,
                                                              result.meshGenus, result.voxelGenus);
        if (extraHandles > 0)
            warnings.push_back(extraHandlesWarning(source->file.string(), extraHandles,
                                                   result.voxelGenus.genus, result.meshGenus.genus,
                                                   chosen.resolution));
        for (const auto& w : warnings) {
            result.warnings.push_back(w);
            warn(w);
        }
    }
    // Volumes: the outputs' surfaces are drawn on the input's grid, however
    // coarse the grid segmented; their memory grows with its boundary.
    std::uint64_t inputBoundaryVoxels = 0;
    if (!source->isMesh()) {
        result.mask = std::move(source->volumeMask);
        inputBoundaryVoxels = countBoundaryVoxels(result.mask);
        if (options.budgetChoice || options.timeBudgetSeconds > 0) {
            planVolumeBudget(result, inputBoundaryVoxels, options, timer, stop);
            if (result.budget->fits) budgetStop.release();
        }
    }
    const Dims fine = source->isMesh() || result.fineMask.dims().voxelCount() == 0
                          ? result.mask.dims()
                          : result.fineMask.dims();
    SegmentInputOptions withoutPreview = options;
    withoutPreview.preview = false;
    const std::uint64_t objects = objectVoxelCount(result.mask);
    result.estimatedMemory = std::max(
        result.estimatedMemory,
        volumeRunMemory(result.mask.dims(), objects, fine, inputBoundaryVoxels, withoutPreview) +
            options.heldBytes);
    // Anisotropic voxels: the labels of every level on the input's grid, made
    // while the cubic grid's are still held.
    if (source->cubicGrid)
        result.estimatedMemory += source->cubicGrid->inputDims.voxelCount() * 2 *
                                  std::uint64_t(std::max(options.levels, 1));
    if (result.estimatedMemory > options.memoryLimit)
        throw MemoryLimitError(source->file.string() + ": needs about " +
                               formatBytes(result.estimatedMemory) + ", over the limit of " +
                               formatBytes(options.memoryLimit) + " (--max-memory)");
    if (options.preview) {
        // preview.png is drawn while the outputs are written: beside the
        // labels (and a volume's surfaces), not beside the segmentation's
        // workspaces. A run that fits only without it skips it.
        const std::uint64_t writing =
            source->isMesh()
                ? fine.voxelCount() * labelledVoxelBytes(options.levels) +
                      previewRunMemory(true, source->mesh->triangles.size(),
                                       source->mesh->vertices.size(), options.threads)
                : volumeRunMemory(result.mask.dims(), objects, fine, inputBoundaryVoxels, options);
        const std::uint64_t withPreview =
            std::max(result.estimatedMemory, writing + options.heldBytes);
        if (withPreview <= options.memoryLimit) {
            result.estimatedMemory = withPreview;
        } else {
            result.previewOverMemory = true;
            const std::string warning =
                source->file.string() + ": preview.png skipped to fit --max-memory (it needs " +
                formatBytes(withPreview - result.estimatedMemory) + " more)";
            result.warnings.push_back(warning);
            warn(warning);
        }
    }
    result.source = std::move(source);
    return result;
}

std::int64_t handlesTheMeshLacks(bool meshClosed, const MeshTopology& mesh,
                                 const VoxelTopology& voxels) {
    return meshClosed && mesh.otherPieces == 0
               ? std::max<std::int64_t>(0, voxels.genus - mesh.genus)
               : 0;
}

}  // namespace skelseg
