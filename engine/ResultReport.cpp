#include "engine/ResultReport.h"

#include <cmath>

#include "engine/LevelOutputs.h"
#include "engine/Version.h"

using json = nlohmann::json;

namespace skelseg {

namespace {

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

void addCount(json& j, const char* key, std::uint64_t value) {
    j[key] = j[key].get<std::uint64_t>() + value;
}

const char* jointStatusName(JointStatus status) {
    switch (status) {
        case JointStatus::Cut:
            return "cut";
        case JointStatus::BelowThreshold:
            return "below_threshold";
        case JointStatus::LowSigma:
            return "low_sigma";
        case JointStatus::NearCut:
            return "near_cut";
        case JointStatus::Handle:
            return "handle";
    }
    return "unknown";
}

}  // namespace

json methodParameters(const SegmentationParameters& p) {
    const CutOptions& cut = p.cutRules;
    return {{"tau", p.tauListString()},
            {"sigma_min", p.sigmaMin},
            {"body_ratio", p.bodyRatio},
            {"mode", p.mode == CutMode::Junctions ? "junctions" : "junction-rule"},
            {"region_radius", p.regionRadius},
            {"bridge_gap", p.bridgeGap},
            {"consecutive_levels", p.consecutiveLevels},
            {"fork_junctions", p.forkJunctions},
            {"handles_on_genus_zero", p.handleFlagOnGenusZero},
            {"grow_regions_to_splits", p.growRegionsToSplits},
            {"junction_merge_radii", p.junctionMergeRadii},
            {"sibling_tolerance", cut.siblingTolerance},
            {"end_body_ratio", cut.endBodyRatio},
            {"siblings_both_ways", cut.siblingsBothWays},
            {"limb_taper", cut.limbTaper},
            {"corner_length", cut.cornerLength},
            {"corner_reach", cut.cornerReach},
            {"passages_are_body", cut.passagesAreBody},
            {"shared_body_reference", cut.shareBodyAcrossPassages},
            {"below_sigma_min_only_limbs", cut.belowSigmaMinOnlyLimbs},
            {"passage_cuts_only_smaller", cut.passageCutsOnlySmallerCandidates},
            {"one_branch_junctions_end_the_body", cut.oneBranchJunctionsEndTheBody},
            {"separating_cuts_only", cut.separatingCutsOnly},
            {"window_from_body_reference", cut.windowFromBodyReference},
            {"surface_loops", cut.surfaceLoops},
            {"tight_levels_in_runs", cut.tightLevelsInRuns},
            {"stub_limbs", cut.stubLimbs},
            {"limbs_below_sigma_min", cut.relaxSigmaMinForLimbs},
            {"limb_sigma_margin", cut.limbSigmaMargin},
            {"limb_loop_variation", cut.limbLoopVariation}};
}

json resultReport(const SegmentationResult& result, const ResultReportContext& context) {
    const SegmentationParameters& p = context.parameters;
    const VolumeGeometry& geometry = result.labels.geometry;
    json report;
    report["status"] = "ok";
    report["skelseg_version"] = versionString();
    report["skelseg_build"] = engineBuildId();
    report["input"] = context.input;
    const Dims d = result.labels.dims();
    report["grid"] = {{"size", {d.x, d.y, d.z}},
                      {"voxel_size", geometry.voxelSize()},
                      {"origin", toJson(geometry.origin)}};
    report["parameters"] = methodParameters(p);
    // Decided per input (engine/SegmentSteps.h, parametersFor), not asked for.
    report["parameters"]["handle_loops_carry_no_area"] = p.cutRules.handleLoopsCarryNoArea;
    report["parameters"].update({{"threads", context.threads},
                                 {"skeleton_search", skeletonSearchName(skeletonSearchToRun(p))},
                                 {"joints", p.joints}});
    if (p.joints) {
        const JointOptions& j = p.jointOptions;
        report["parameters"]["joint_options"] = {
            {"narrowing_ratio", j.narrowingRatio},
            {"bend_angle_degrees", j.bendAngleDegrees},
            {"min_segment_tau_fraction", j.minSegmentTauFraction},
            {"smoothing_scale", j.smoothingScale},
            {"side_window", j.sideWindow},
            {"side_median_window", j.sideMedianWindow},
            {"min_side_length", j.minSideLength},
            {"bend_window", j.bendWindow},
            {"min_cut_distance", j.minCutDistance},
            {"snap_distance", j.snapDistance}};
    }
    json counts = {{"object_voxels", 0},   {"boundary_voxels", 0},
                   {"candidates", 0},      {"curve_skeleton_points", 0},
                   {"skeleton_points", 0}, {"junction_voxels", 0},
                   {"cavities", 0},        {"cavity_voxels", 0},
                   {"tunnel_voxels", 0}};
    json work = {{"objects_voxels_examined", 0},
                 {"candidates_searched", 0},
                 {"candidates_measured", 0},
                 {"closure_rounds", 0},
                 {"dijkstra_searches", 0},
                 {"heap_pops", 0},
                 {"nodes_settled", 0},
                 {"path_cache_hits", 0},
                 {"rim_tests", 0},
                 {"component_growth_steps", 0},
                 {"sigma_evaluations", 0},
                 {"sigma_searches", 0},
                 {"repeated_feature_sets", 0},
                 {"coarse_candidates", 0},
                 {"coarse_candidates_measured", 0},
                 {"thin_wall_seeds", 0}};
    json objects = json::array(), junctions = json::array(), critical = json::array();
    json cuts = json::array(), jointCandidates = json::array();
    std::uint64_t jointCuts = 0;
    for (std::size_t o = 0; o < result.objects.size(); ++o) {
        const ObjectSegmentation& obj = result.objects[o];
        const SearchCounters& search = obj.measureStats.search;
        const SearchCounters& sigmaSearch = obj.measureStats.sigmaSearch;
        addCount(counts, "object_voxels", obj.voxelCount);
        addCount(counts, "boundary_voxels", obj.boundaryArea);
        addCount(counts, "candidates", obj.candidateStats.candidates);
        addCount(counts, "curve_skeleton_points", obj.curveSkeletonPoints);
        addCount(counts, "skeleton_points", obj.simplifiedSkeletonPoints);
        addCount(counts, "junction_voxels", obj.junctionVoxels);
        addCount(counts, "cavities", obj.cavities);
        addCount(counts, "cavity_voxels", obj.cavityVoxels);
        addCount(counts, "tunnel_voxels", obj.tunnelVoxels);
        addCount(work, "objects_voxels_examined", obj.candidateStats.objectVoxels);
        addCount(work, "candidates_searched", obj.candidateStats.candidates);
        addCount(work, "candidates_measured", obj.bandStats.candidatesMeasured);
        addCount(work, "closure_rounds", obj.bandStats.closureRounds);
        addCount(work, "coarse_candidates", obj.bandStats.coarseCandidates);
        addCount(work, "coarse_candidates_measured", obj.bandStats.coarseMeasured);
        addCount(work, "thin_wall_seeds", obj.bandStats.thinWallSeeds);
        addCount(work, "dijkstra_searches", search.searches);
        addCount(work, "heap_pops", search.heapPops + sigmaSearch.heapPops);
        addCount(work, "nodes_settled", search.nodesSettled + sigmaSearch.nodesSettled);
        addCount(work, "path_cache_hits", obj.measureStats.pathCacheHits);
        addCount(work, "rim_tests", obj.measureStats.rimTests);
        addCount(work, "component_growth_steps", obj.measureStats.componentGrowthSteps);
        addCount(work, "sigma_evaluations", obj.measureStats.sigmaEvaluations);
        addCount(work, "sigma_searches", sigmaSearch.searches);
        addCount(work, "repeated_feature_sets", obj.measureStats.repeatedFeatureSets);
        objects.push_back({{"index", o},
                           {"voxels", obj.voxelCount},
                           {"boundary_voxels", obj.boundaryArea},
                           {"boundary_components", obj.boundaryComponents},
                           {"cavities", obj.cavities},
                           {"cavity_voxels", obj.cavityVoxels},
                           {"tunnel_voxels", obj.tunnelVoxels},
                           {"genus", obj.genus},
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
                           {"skeleton_bridges_along_object", obj.skeletonBridgesAlongObject},
                           {"cuts", obj.cutLoops.size()},
                           {"segments", obj.labels}});
        json before = json::array();
        for (const SegmentMeasure& m : obj.segmentsBeforeMerge)
            before.push_back({{"core", m.core},
                              {"area", m.area},
                              {"measured", m.measured},
                              {"merged", m.merged}});
        objects.back()["segments_before_merge"] = std::move(before);
        for (const auto& j : obj.junctions)
            junctions.push_back(
                {{"object", o},
                 {"voxel", toJson(j.voxel)},
                 {"position", toJson(geometry.indexToWorld(j.voxel[0], j.voxel[1], j.voxel[2]))},
                 {"branches", j.branches},
                 {"cuts", j.cuts},
                 {"rho_s", j.rhoS},
                 {"core_voxels", j.coreVoxels},
                 {"fork_voxels", j.forkVoxels}});
        for (const auto& c : obj.criticalPoints)
            critical.push_back(
                {{"object", o},
                 {"voxel", toJson(c.voxel)},
                 {"position", toJson(geometry.indexToWorld(c.voxel[0], c.voxel[1], c.voxel[2]))},
                 {"junction", c.junction},
                 {"sigma", c.sigma},
                 {"rho_s", c.rhoS},
                 {"rho_c", areaJson(c.rhoC)},
                 {"limb_rho_s", c.limbRhoS},
                 {"body_similarity", c.similarity},
                 {"is_corner", c.isCorner},
                 {"below_sigma_min", c.belowSigmaMin},
                 {"stub_limb", c.stubLimb},
                 {"loop_separates", c.loopSeparates},
                 {"moved_to_separate", c.movedToSeparate},
                 {"is_cut", c.isCut}});
        for (const auto& c : obj.cuts) {
            jointCuts += c.kind == CutKind::Joint;
            cuts.push_back(
                {{"object", o},
                 {"kind", c.kind == CutKind::Joint ? "joint" : "junction"},
                 {"voxel", toJson(c.voxel)},
                 {"position", toJson(geometry.indexToWorld(c.voxel[0], c.voxel[1], c.voxel[2]))},
                 {"sigma", c.sigma},
                 {"rho_s", c.rhoS},
                 {"separates", c.separates}});
        }
        for (const auto& c : obj.jointCandidates)
            jointCandidates.push_back(
                {{"object", o},
                 {"kind", c.kind == JointKind::Bend ? "bend" : "narrowing"},
                 {"status", jointStatusName(c.status)},
                 {"voxel", toJson(c.voxel)},
                 {"position", toJson(geometry.indexToWorld(c.voxel[0], c.voxel[1], c.voxel[2]))},
                 {"ratio", c.ratio},
                 {"angle_degrees", c.angleDegrees},
                 {"radius", c.radius},
                 {"sigma", c.sigma}});
    }
    report["counts"] = counts;
    report["work"] = work;
    report["objects"] = objects;
    report["junctions"] = junctions;
    report["critical_points"] = critical;
    report["cuts"] = cuts;
    report["joint_cuts"] = jointCuts;
    if (p.joints) report["joint_candidates"] = jointCandidates;
    json segments = json::array();
    for (const auto& s : result.segments)
        segments.push_back({{"id", s.label},
                            {"object", s.object},
                            {"voxels", s.voxelCount},
                            {"boundary_area", s.boundaryArea}});
    report["segments"] = segments;
    report["segment_count"] = result.segments.size();
    report["levels"] = reportLevelsJson(result, {});
    report["islands"] = {{"count", result.islands.count},
                         {"voxels", result.islands.voxels},
                         {"noise_area", result.islands.noiseArea},
                         {"fragments", result.islands.fragments},
                         {"fragment_voxels", result.islands.fragmentVoxels}};
    if (context.faceSegments) report["face_segments"] = *context.faceSegments;
    json stages = json::array();
    double serialWall = 0.0;
    for (const auto& s : context.stages) {
        stages.push_back({{"name", s.name},
                          {"parallel", s.parallel},
                          {"wall_seconds", s.wallSeconds},
                          {"cpu_seconds", s.cpuSeconds},
                          {"calls", s.calls}});
        if (!s.parallel) serialWall += s.wallSeconds;
    }
    report["stages"] = stages;
    const double wall = context.wallSeconds;
    report["timing"] = {{"wall_seconds", wall},
                        {"cpu_seconds", context.cpuSeconds},
                        {"serial_stage_seconds", serialWall},
                        {"serial_share", wall > 0 ? serialWall / wall : 0.0}};
    report["memory"] = {{"peak_resident_bytes", peakResidentBytes()},
                        {"estimated_bytes", context.estimatedMemoryBytes},
                        {"limit_bytes", context.memoryLimitBytes}};
    report["warnings"] = context.warnings;
    return report;
}

}  // namespace skelseg
