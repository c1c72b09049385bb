#include "engine/SegmentReport.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "engine/LevelOutputs.h"
#include "engine/ResultReport.h"
#include "engine/SegmentSteps.h"

using json = nlohmann::json;

namespace skelseg {
namespace {

json budgetCalibrationJson(const BudgetChoice& budget) {
    const BudgetCalibration& c = budget.calibration;
    return {{"method", c.enabled ? "probe" : "cpu"},
            {"probe_wall_seconds", budget.probeSeconds},
            {"probe_cpu_seconds", c.probeCpuSeconds},
            {"probe_predicted_cpu_seconds", c.probePredictedCpuSeconds},
            {"probe_grid_voxels", budget.probeWork.gridVoxels},
            {"probe_object_voxels", budget.probeWork.objectVoxels},
            {"probe_boundary_voxels", budget.probeWork.boundaryVoxels},
            {"probe_candidates", budget.probeWork.candidates},
            {"wall_per_cpu_second", c.wallPerCpuSecond},
            {"clamped", c.clamped}};
}

}  // namespace

std::string previewSkippedWarning(double budgetSeconds) {
    return "preview.png skipped to fit --time-budget " +
           std::to_string(budgetSeconds).substr(0, 5) + " s";
}

void addVoxelAspect(json& input, const SegmentedShape& shape) {
    // The labels are on the input's grid (refineStep), whatever was segmented.
    const SegmentSource& source = *shape.input->source;
    const auto steps = voxelSteps(shape.result.labels.geometry);
    input["voxel_steps"] = {steps[0], steps[1], steps[2]};
    if (!source.cubicGrid) {
        input["cubic_voxels"] = nullptr;
        return;
    }
    const CubicGrid& grid = *source.cubicGrid;
    input["cubic_voxels"] = {{"grid", {grid.dims[0], grid.dims[1], grid.dims[2]}},
                             {"voxel_size", grid.geometry.voxelSize()},
                             {"scale", {grid.scale[0], grid.scale[1], grid.scale[2]}}};
}

json segmentReport(const SegmentCommandOptions& options, const SegmentedShape& shape,
                   const std::vector<StageTiming>& timings, const SegmentRunFigures& figures) {
    const SegmentSource& source = *shape.input->source;
    const SegmentationResult& result = shape.result;
    ResultReportContext context;
    context.input = {{"file", options.input.string()},
                     {"kind", source.isMesh() ? "mesh" : "volume"}};
    if (!source.isMesh()) addVoxelAspect(context.input, shape);
    if (source.isMesh()) {
        context.input["faces"] = source.mesh->faceCount;
        context.input["vertices"] = source.mesh->vertices.size();
        context.input["resolution"] = shape.input->resolution;
        context.input["mesh_closed"] = source.meshDiagnostics.closed;
        context.input["mesh_pieces"] = source.meshDiagnostics.pieces;
        context.input["mesh_boundary_edges"] = source.meshDiagnostics.boundaryEdges;
        context.input["mesh_degenerate_faces"] = source.meshDiagnostics.degenerateFaces;
        context.input["mesh_faces_turned"] =
            source.flippedFacesTurned ? source.flippedFacesTurned->turnedFaces : 0;
        context.input["mesh_fin_faces"] = source.withoutFins ? source.withoutFins->finFaces : 0;
        context.input["mesh_holes_capped"] =
            source.withHolesCapped ? source.withHolesCapped->holes : 0;
        context.input["mesh_genus"] = shape.input->meshGenus.genus;
        context.input["mesh_closed_pieces"] = shape.input->meshGenus.closedPieces;
        context.input["mesh_pieces_without_genus"] = shape.input->meshGenus.otherPieces;
        context.input["voxel_genus"] = shape.input->voxelGenus.genus;
        context.input["contacts_separated"] = shape.input->contacts.contacts;
        context.input["contact_voxels_cleared"] = shape.input->contacts.voxelsCleared;
        context.input["contacts_rejoined"] = shape.input->contacts.contactsRejoined;
        context.input["contact_patch_seams"] = options.contactPatchSeams;
        context.input["contacts_patch_seamed"] = shape.input->contacts.contactsPatchSeamed;
        context.input["grown_contact_seams"] = options.grownContactSeams;
        context.input["contacts_grown"] = shape.input->contacts.contactsGrown;
        context.input["self_overlap_clearance"] = options.selfOverlapClearance;
        context.input["self_overlaps_separated"] = shape.input->selfOverlaps.overlaps;
        context.input["self_overlaps_kept"] = shape.input->selfOverlaps.overlapsKept;
        context.input["self_overlaps_severing"] = shape.input->selfOverlaps.overlapsSevering;
        context.input["self_overlap_voxels"] = shape.input->selfOverlaps.overlapVoxels;
        context.input["self_overlap_voxels_cleared"] = shape.input->selfOverlaps.voxelsCleared;
        context.input["thin_part_fill"] = shape.input->thinPartFill;
        if (shape.input->thinPartFill != "not needed")
            context.input["thin_part_fill_voxel_genus"] = shape.input->thinPartGenus;
        context.input["thin_part_voxels_added"] = shape.input->thinParts.voxelsAdded;
        std::uint32_t faceSegments = 0;
        for (std::uint32_t l : shape.faceLabels) faceSegments = std::max(faceSegments, l + 1);
        context.faceSegments = faceSegments;
    }
    context.parameters = parametersFor(*shape.input, options.parameters);
    context.threads = figures.threads;
    context.stages = timings;
    context.wallSeconds = figures.wallSeconds;
    context.cpuSeconds = figures.cpuSeconds;
    context.estimatedMemoryBytes = shape.input->estimatedMemory;
    context.memoryLimitBytes = figures.memoryLimit;
    context.warnings = shape.input->warnings;
    context.warnings.insert(context.warnings.end(), result.warnings.begin(), result.warnings.end());
    // Printed by the surfaces writer; the report lists every warning of the run.
    if (figures.previewSkippedForBudget && shape.input->budget)
        context.warnings.push_back(previewSkippedWarning(shape.input->budget->budgetSeconds));
    json report = resultReport(result, context);
    // With the mesh's face nesting counts, which only the command has.
    report["levels"] = reportLevelsJson(result, shape.levels.nestedFaces);
    const double wall = figures.wallSeconds;
    if (const auto& budget = shape.input->budget) {
        report["time_budget"] = {
            {"budget_seconds", budget->budgetSeconds},
            {"probe_seconds", budget->probeSeconds},
            {"predicted_seconds", budget->predictedSeconds},
            {"predicted_cpu_seconds", budget->predictedCpuSeconds},
            {"seconds_left_after_probe", budget->secondsLeft},
            {"calibration", budgetCalibrationJson(*budget)},
            {"actual_seconds", wall},
            {"resolution", source.isMesh() ? json(budget->resolution) : json(nullptr)},
            {"requested_resolution", source.isMesh() ? json(options.resolution) : json(nullptr)},
            {"coarsening", budget->coarsening},
            {"coarsened", budget->coarsened},
            {"fits", budget->fits},
            {"safety_margin", budget->safetyMargin},
            {"preview_predicted_seconds", budget->previewSeconds},
            {"skipped",
             figures.previewSkippedForBudget ? json::array({"preview.png"}) : json::array()},
            {"chosen", describeBudgetChoice(*budget)}};
        if (budget->memoryCapResolution > 0)
            report["time_budget"]["memory_cap_resolution"] = budget->memoryCapResolution;
        if (budget->memoryCapCoarsening > 0)
            report["time_budget"]["memory_cap_coarsening"] = budget->memoryCapCoarsening;
    }
    if (figures.budgetRefinement) {
        const BudgetRefinement& refinement = *figures.budgetRefinement;
        json block = {{"tried", refinement.tried},
                      {"first_resolution",
                       source.isMesh() ? json(refinement.firstResolution) : json(nullptr)},
                      {"first_coarsening", refinement.firstCoarsening},
                      {"first_pass_seconds", refinement.firstPassSeconds}};
        if (refinement.tried) {
            const BudgetChoice& finer = refinement.choice;
            block["resolution"] = source.isMesh() ? json(finer.resolution) : json(nullptr);
            block["coarsening"] = finer.coarsening;
            block["predicted_seconds"] = finer.predictedSeconds;
            block["margin"] = finer.safetyMargin;
            block["deadline_seconds"] = refinement.deadlineSeconds;
            block["kept"] = refinement.kept;
            block["over_memory"] = refinement.overMemory;
            block["outcome"] =
                refinement.kept ? "finished by its deadline; its output is given"
                : refinement.overMemory
                    ? "needed more than --max-memory; the first pass's output is given"
                    : "stopped at its deadline; the first pass's output is given";
        } else {
            block["outcome"] = "not tried: " + refinement.reason;
        }
        report["time_budget"]["refinement"] = block;
    }
    return report;
}

std::string segmentReportJson(const SegmentCommandOptions& options, const SegmentedShape& shape,
                              const std::vector<StageTiming>& timings,
                              const SegmentRunFigures& figures) {
    return segmentReport(options, shape, timings, figures)
               .dump(2, ' ', false, nlohmann::json::error_handler_t::replace) +
           "\n";
}

}  // namespace skelseg
