#include "engine/SegmentReport.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "engine/Version.h"

using json = nlohmann::json;

namespace skelseg {

namespace {

std::array<double, 3> voxelToWorld(const VolumeGeometry& g, const std::array<int, 3>& v) {
    return g.indexToWorld(v[0], v[1], v[2]);
}

json toJson(const std::array<double, 3>& p) {
    return json::array({p[0], p[1], p[2]});
}
json toJson(const std::array<int, 3>& p) {
    return json::array({p[0], p[1], p[2]});
}
/// JSON has no infinity: handle loops report null for rho_C.
json areaJson(double value) {
    return std::isfinite(value) ? json(value) : json(nullptr);
}

}  // namespace

std::string segmentReportJson(const SegmentCommandOptions& options, const SegmentedShape& shape,
                              const std::vector<StageTiming>& timings,
                              const SegmentRunFigures& figures) {
    const SegmentSource& source = *shape.input->source;
    const SegmentationResult& result = shape.result;
    json report;
    report["status"] = "ok";
    report["skelseg_version"] = versionString();
    report["input"] = {{"file", options.input.string()},
                       {"kind", source.isMesh() ? "mesh" : "volume"}};
    if (source.isMesh()) {
        report["input"]["faces"] = source.mesh->faceCount;
        report["input"]["vertices"] = source.mesh->vertices.size();
        report["input"]["resolution"] = shape.input->resolution;
        report["input"]["mesh_closed"] = source.meshDiagnostics.closed;
        report["input"]["mesh_pieces"] = source.meshDiagnostics.pieces;
        report["input"]["mesh_boundary_edges"] = source.meshDiagnostics.boundaryEdges;
        report["input"]["mesh_degenerate_faces"] = source.meshDiagnostics.degenerateFaces;
        report["input"]["mesh_genus"] = shape.input->meshGenus.genus;
        report["input"]["mesh_closed_pieces"] = shape.input->meshGenus.closedPieces;
        report["input"]["voxel_genus"] = shape.input->voxelGenus.genus;
        report["input"]["contacts_separated"] = shape.input->contacts.contacts;
        report["input"]["contact_voxels_cleared"] = shape.input->contacts.voxelsCleared;
    }
    const Dims d = result.labels.dims();
    report["grid"] = {{"size", {d.x, d.y, d.z}},
                      {"voxel_size", result.labels.geometry.voxelSize()},
                      {"origin", toJson(result.labels.geometry.origin)}};
    report["parameters"] = {
        {"tau", options.parameters.tau.toString()},
        {"sigma_min", options.parameters.sigmaMin},
        {"body_ratio", options.parameters.bodyRatio},
        {"mode", options.parameters.mode == CutMode::Junctions ? "junctions" : "junction-rule"},
        {"threads", figures.threads},
        {"region_radius", options.parameters.regionRadius},
        {"bridge_gap", options.parameters.bridgeGap},
        {"consecutive_levels", options.parameters.consecutiveLevels},
        {"skeleton_search", skeletonSearchName(options.parameters.skeletonSearch)}};
    json counts = {{"object_voxels", 0},         {"boundary_voxels", 0}, {"candidates", 0},
                   {"curve_skeleton_points", 0}, {"skeleton_points", 0}, {"junction_voxels", 0}};
    json work = {
        {"objects_voxels_examined", 0}, {"candidates_searched", 0}, {"candidates_measured", 0},
        {"closure_rounds", 0},          {"dijkstra_searches", 0},   {"heap_pops", 0},
        {"nodes_settled", 0},           {"path_cache_hits", 0},     {"rim_tests", 0},
        {"component_growth_steps", 0},  {"sigma_evaluations", 0},   {"sigma_searches", 0},
        {"repeated_feature_sets", 0}};
    json objects = json::array(), junctions = json::array(), critical = json::array();
    for (std::size_t o = 0; o < result.objects.size(); ++o) {
        const ObjectSegmentation& obj = result.objects[o];
        auto add = [](json& j, const char* key, std::uint64_t v) {
            j[key] = j[key].get<std::uint64_t>() + v;
        };
        add(counts, "object_voxels", obj.voxelCount);
        add(counts, "boundary_voxels", obj.boundaryArea);
        add(counts, "candidates", obj.candidateStats.candidates);
        add(counts, "curve_skeleton_points", obj.curveSkeletonPoints);
        add(counts, "skeleton_points", obj.simplifiedSkeletonPoints);
        add(counts, "junction_voxels", obj.junctionVoxels);
        add(work, "objects_voxels_examined", obj.candidateStats.objectVoxels);
        add(work, "candidates_searched", obj.candidateStats.candidates);
        add(work, "candidates_measured", obj.bandStats.candidatesMeasured);
        add(work, "closure_rounds", obj.bandStats.closureRounds);
        add(work, "dijkstra_searches", obj.measureStats.search.searches);
        add(work, "heap_pops",
            obj.measureStats.search.heapPops + obj.measureStats.sigmaSearch.heapPops);
        add(work, "nodes_settled",
            obj.measureStats.search.nodesSettled + obj.measureStats.sigmaSearch.nodesSettled);
        add(work, "path_cache_hits", obj.measureStats.pathCacheHits);
        add(work, "rim_tests", obj.measureStats.rimTests);
        add(work, "component_growth_steps", obj.measureStats.componentGrowthSteps);
        add(work, "sigma_evaluations", obj.measureStats.sigmaEvaluations);
        add(work, "sigma_searches", obj.measureStats.sigmaSearch.searches);
        add(work, "repeated_feature_sets", obj.measureStats.repeatedFeatureSets);
        objects.push_back({{"index", o},
                           {"voxels", obj.voxelCount},
                           {"boundary_voxels", obj.boundaryArea},
                           {"boundary_components", obj.boundaryComponents},
                           {"bbox_min", toJson(obj.bboxMin)},
                           {"bbox_max", toJson(obj.bboxMax)},
                           {"tau_area", obj.tauArea},
                           {"noise_area", obj.noiseArea},
                           {"candidates", obj.candidateStats.candidates},
                           {"curve_skeleton_points", obj.curveSkeletonPoints},
                           {"skeleton_points", obj.simplifiedSkeletonPoints},
                           {"junction_voxels", obj.junctionVoxels},
                           {"handle_points", obj.handlePoints},
                           {"skeleton_bridges", obj.skeletonBridges},
                           {"cuts", obj.cutLoops.size()},
                           {"segments", obj.labels}});
        for (const auto& j : obj.junctions)
            junctions.push_back(
                {{"object", o},
                 {"voxel", toJson(j.voxel)},
                 {"position", toJson(voxelToWorld(result.labels.geometry, j.voxel))},
                 {"branches", j.branches},
                 {"cuts", j.cuts},
                 {"rho_s", j.rhoS},
                 {"core_voxels", j.coreVoxels}});
        for (const auto& c : obj.criticalPoints)
            critical.push_back({{"object", o},
                                {"voxel", toJson(c.voxel)},
                                {"position", toJson(voxelToWorld(result.labels.geometry, c.voxel))},
                                {"junction", c.junction},
                                {"sigma", c.sigma},
                                {"rho_s", c.rhoS},
                                {"rho_c", areaJson(c.rhoC)},
                                {"body_similarity", c.similarity},
                                {"is_cut", c.isCut}});
    }
    report["counts"] = counts;
    report["work"] = work;
    report["objects"] = objects;
    report["junctions"] = junctions;
    report["critical_points"] = critical;
    json segments = json::array();
    for (const auto& s : result.segments)
        segments.push_back({{"id", s.label},
                            {"object", s.object},
                            {"voxels", s.voxelCount},
                            {"boundary_area", s.boundaryArea}});
    report["segments"] = segments;
    report["segment_count"] = result.segments.size();
    report["islands"] = {{"count", result.islands.count},
                         {"voxels", result.islands.voxels},
                         {"noise_area", result.islands.noiseArea}};
    if (source.isMesh()) {
        std::uint32_t faceSegments = 0;
        for (std::uint32_t l : shape.faceLabels) faceSegments = std::max(faceSegments, l + 1);
        report["face_segments"] = faceSegments;
    }
    json stages = json::array();
    double serialWall = 0.0;
    for (const auto& s : timings) {
        stages.push_back({{"name", s.name},
                          {"parallel", s.parallel},
                          {"wall_seconds", s.wallSeconds},
                          {"cpu_seconds", s.cpuSeconds},
                          {"calls", s.calls}});
        if (!s.parallel) serialWall += s.wallSeconds;
    }
    report["stages"] = stages;
    const double wall = figures.wallSeconds;
    report["timing"] = {{"wall_seconds", wall},
                        {"cpu_seconds", figures.cpuSeconds},
                        {"serial_stage_seconds", serialWall},
                        {"serial_share", wall > 0 ? serialWall / wall : 0.0}};
    report["memory"] = {{"peak_resident_bytes", peakResidentBytes()},
                        {"estimated_bytes", shape.input->estimatedMemory},
                        {"limit_bytes", figures.memoryLimit}};
    if (const auto& budget = shape.input->budget)
        report["time_budget"] = {
            {"budget_seconds", budget->budgetSeconds},
            {"probe_seconds", budget->probeSeconds},
            {"predicted_seconds", budget->predictedSeconds},
            {"actual_seconds", wall},
            {"resolution", source.isMesh() ? json(budget->resolution) : json(nullptr)},
            {"requested_resolution", source.isMesh() ? json(options.resolution) : json(nullptr)},
            {"coarsening", budget->coarsening},
            {"coarsened", budget->coarsened},
            {"fits", budget->fits},
            {"chosen", describeBudgetChoice(*budget)}};
    std::vector<std::string> warnings = shape.input->warnings;
    warnings.insert(warnings.end(), result.warnings.begin(), result.warnings.end());
    report["warnings"] = warnings;
    return report.dump(2) + "\n";
}

}  // namespace skelseg
