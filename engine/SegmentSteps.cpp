#include "engine/SegmentSteps.h"

#include "engine/ResultOnInputGrid.h"
#include "engine/Stage.h"
#include "io/mesh/FaceLabels.h"

namespace skelseg {

SegmentInputOptions segmentInputOptions(const SegmentCommandOptions& options, int threads,
                                        std::chrono::steady_clock::time_point start) {
    SegmentInputOptions inputOptions;
    inputOptions.gridName = options.gridName;
    inputOptions.resolution = options.resolution;
    inputOptions.selfOverlapClearance = options.selfOverlapClearance;
    inputOptions.contactPatchSeams = options.contactPatchSeams;
    inputOptions.grownContactSeams = options.grownContactSeams;
    inputOptions.cubicVoxels = !options.keepVoxelAspect;
    inputOptions.threads = threads;
    inputOptions.levels = int(options.parameters.levelCount());
    inputOptions.preview = options.writePreview;
    inputOptions.timeBudgetSeconds = options.timeBudgetSeconds;
    inputOptions.calibrateTimeBudget = options.calibrateTimeBudget;
    if (options.timeBudgetSeconds > 0) inputOptions.budgetChoice = options.budgetChoice;
    inputOptions.start = start;
    inputOptions.memoryLimit =
        options.maxMemoryBytes ? options.maxMemoryBytes : defaultMemoryLimit();
    return inputOptions;
}

double limitTimeToBudget(const SegmentMask& mask, double currentLimit, double budgetAsTimeLimit) {
    if (!mask.budget || mask.budget->fits) return currentLimit;
    return currentLimit <= 0 || currentLimit > budgetAsTimeLimit ? budgetAsTimeLimit : currentLimit;
}

SegmentationParameters parametersFor(const SegmentMask& input,
                                     const SegmentationParameters& requested) {
    SegmentationParameters run = requested;
    run.objectSources = input.objectSources;
    run.closeNarrowTunnels =
        requested.closeNarrowTunnels && !(input.source && input.source->isMesh());
    // Loops round a handle the mesh lacks have an infinite area only in the
    // voxel model: touching or interpenetrating surfaces stayed joined.
    run.cutRules.handleLoopsCarryNoArea =
        requested.artefactHandlesCarryNoArea && input.source && input.source->isMesh() &&
        handlesTheMeshLacks(input.source->meshDiagnostics.closed, input.meshGenus,
                            input.voxelGenus) > 0;
    return run;
}

namespace {

/// What a mesh's voxel model did to its pieces: fragments left out
/// (kernels/Islands.h), and more objects than the mesh has pieces (a closed
/// box 1000 x 0.001 x 0.001 gave 7 segments at 48 without a word).
std::vector<std::string> voxelObjectWarnings(const SegmentMask& input,
                                             const SegmentationResult& result,
                                             const std::string& file) {
    std::vector<std::string> warnings;
    const std::string resolution = std::to_string(input.resolution);
    const IslandSummary& islands = result.islands;
    if (islands.fragments > 0)
        warnings.push_back(file + ": " + std::to_string(islands.fragments) +
                           (islands.fragments == 1 ? " piece" : " pieces") +
                           " of the voxel model (" + std::to_string(islands.fragmentVoxels) +
                           " voxels) broke off parts thinner than a voxel at resolution " +
                           resolution +
                           "; too small to be parts, their faces take the label of the "
                           "nearest part");
    if (!input.source || !input.source->isMesh()) return warnings;
    const MeshDiagnostics& mesh = input.source->meshDiagnostics;
    if (mesh.closed && result.objects.size() > mesh.pieces)
        warnings.push_back(file + ": the voxel model at resolution " + resolution + " has " +
                           std::to_string(result.objects.size()) + " objects, the mesh " +
                           std::to_string(mesh.pieces) + (mesh.pieces == 1 ? " piece" : " pieces") +
                           ": parts thinner than a voxel broke apart and are segmented apart (a "
                           "higher --resolution may keep them whole)");
    return warnings;
}

}  // namespace

std::shared_ptr<SegmentedShape> segmentMaskStep(
    std::shared_ptr<const SegmentMask> input, const SegmentationParameters& parameters,
    StageTimer& timer, Interrupter& interrupter,
    const std::function<void(const std::string&)>& warn) {
    auto shape = std::make_shared<SegmentedShape>();
    try {
        shape->result =
            segmentVolume(input->mask, parametersFor(*input, parameters), interrupter, &timer);
    } catch (const InputError& error) {
        // A problem of the input found while segmenting it (more segments
        // than a label volume holds): named here, where the input is known.
        if (!error.file().empty()) throw;
        throw InputError(input->source->file.string(), error.problem());
    }
    // The kernels do not know the file: a batch printed "the volume holds no
    // object voxels" once per empty input, naming none.
    const std::string file = input->source ? input->source->file.string() : std::string();
    for (auto& w : shape->result.warnings) {
        if (!file.empty()) w = file + ": " + w;
        warn(w);
    }
    for (std::string& warning : voxelObjectWarnings(*input, shape->result, file)) {
        warn(warning);
        shape->result.warnings.push_back(std::move(warning));
    }
    shape->input = std::move(input);
    return shape;
}

void refineStep(SegmentedShape& shape, StageTimer& timer, Interrupter& interrupter) {
    const SegmentMask& input = *shape.input;
    if (input.budget && input.budget->coarsening > 1) {
        Stage stage(timer, interrupter, "refine labels", true);
        refineSegmentationResult(shape.result, input.fineMask, input.budget->coarsening);
    }
    if (input.source->cubicGrid) {
        Stage stage(timer, interrupter, "labels on the input grid", true);
        cubicResultOnInputGrid(shape.result, *input.source->cubicGrid, interrupter);
    }
}

void completeStep(SegmentedShape& shape, StageTimer& timer, Interrupter& interrupter) {
    const SegmentSource& source = *shape.input->source;
    if (source.isMesh()) {
        FaceLabelStatistics statistics;
        {
            Stage stage(timer, interrupter, "face labels", true);
            shape.faceLabels =
                labelFaces(*source.mesh, shape.result.labels, {}, interrupter, &statistics);
        }
        shape.voxelLabelOfFaceLabel = std::move(statistics.voxelLabels);
        if (shape.result.levelCount() > 1) {
            Stage stage(timer, interrupter, "level face labels", true);
            labelLevelFaces(*source.mesh, shape.result, shape.faceLabels,
                            shape.voxelLabelOfFaceLabel, shape.levels, interrupter);
        }
    }
    if (shape.result.levelCount() > 1) shape.levels.cutLoops = levelCutLoops(shape.result);
}

}  // namespace skelseg
