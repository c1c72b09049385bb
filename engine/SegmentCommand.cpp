#include "engine/SegmentCommand.h"

#include <tbb/flow_graph.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "engine/SegmentViews.h"
#include "engine/Version.h"
#include "io/files/OutputDirectory.h"
#include "io/mesh/FaceLabels.h"
#include "io/mesh/MeshCheck.h"
#include "io/mesh/MeshGenus.h"
#include "io/mesh/MeshIO.h"
#include "io/mesh/MeshVoxelizer.h"
#include "io/mesh/SegFile.h"
#include "io/render/PlyWriter.h"
#include "io/render/PreviewRenderer.h"
#include "io/render/SegmentSurfaces.h"
#include "io/volume/NrrdIO.h"
#include "io/volume/VdbIO.h"
#include "io/volume/VolumeReader.h"
#include "kernels/VoxelGenus.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace skelseg {

const std::vector<std::string>& segmentOutputNames() {
    static const std::vector<std::string> names = {
        "labels.nrrd", "labels.vdb",  "skeleton.ply",     "cuts.ply",     "segments.ply",
        "preview.png", "report.json", "segmentation.seg", "segments.glb", "viewer.html"};
    return names;
}

std::uint64_t defaultMemoryLimit() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), pageSize = ::sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || pageSize <= 0) return std::uint64_t(8) << 30;
    return std::uint64_t(pages) * std::uint64_t(pageSize) / 4 * 3;
}

bool isMeshPath(const fs::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".off" || ext == ".obj" || ext == ".stl" || ext == ".ply";
}

namespace {

std::string formatBytes(std::uint64_t bytes) {
    // A unit that shows the number: "--max-memory 1M" must not read "0.00 GB".
    char buffer[64];
    if (bytes >= 1000000000)
        std::snprintf(buffer, sizeof buffer, "%.2f GB", double(bytes) / 1e9);
    else if (bytes >= 1000000)
        std::snprintf(buffer, sizeof buffer, "%.2f MB", double(bytes) / 1e6);
    else if (bytes >= 1000)
        std::snprintf(buffer, sizeof buffer, "%.2f KB", double(bytes) / 1e3);
    else
        std::snprintf(buffer, sizeof buffer, "%llu bytes", static_cast<unsigned long long>(bytes));
    return buffer;
}

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

/// The lines under viewer.html's title.
std::vector<std::string> viewerFacts(const SegmentCommandOptions& options,
                                     const SegmentationResult& result) {
    const Dims d = result.labels.dims();
    std::vector<std::string> facts = {
        std::to_string(result.segments.size()) + " parts",
        "tau " + options.parameters.tau.toString(),
        "grid " + std::to_string(d.x) + " x " + std::to_string(d.y) + " x " + std::to_string(d.z)};
    if (!options.gridName.empty()) facts.push_back("grid name " + options.gridName);
    return facts;
}

}  // namespace

void runSegmentCommand(const SegmentCommandOptions& options, ProgressReporter& progress) {
    const auto wallStart = std::chrono::steady_clock::now();
    const double cpuStart = processCpuSeconds();
    const int threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
    tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism,
                                    std::size_t(threads));
    const std::uint64_t memoryLimit =
        options.maxMemoryBytes ? options.maxMemoryBytes : defaultMemoryLimit();

    // Never replace the input: with --force, an input stored in OUTDIR under
    // an output name (a labels.nrrd fed back in) would be overwritten.
    for (const auto& name : segmentOutputNames()) {
        std::error_code ec;
        if (fs::equivalent(options.input, options.outdir / name, ec))
            throw UsageError(options.input.string() + ": the input is " + name +
                             " in the output directory and would be overwritten; choose another "
                             "output directory");
    }
    // Readers load the whole file: a file larger than the memory limit is
    // refused before anything is read (the finer estimates follow below).
    {
        std::error_code ec;
        const auto fileSize =
            fs::is_regular_file(options.input, ec) ? fs::file_size(options.input, ec) : 0;
        // (Files over kMaxInputFileBytes are bad input whatever the memory: the reader refuses
        // them.)
        if (!ec && fileSize > memoryLimit && fileSize <= kMaxInputFileBytes)
            throw MemoryLimitError(options.input.string() + ": reading the file needs at least " +
                                   formatBytes(fileSize) + ", over the limit of " +
                                   formatBytes(memoryLimit) + " (--max-memory)");
    }
    // Refuse to clobber earlier results before doing any work.
    OutputDirectory out(options.outdir, options.force, segmentOutputNames());
    StageTimer timer;
    const bool meshInput = isMeshPath(options.input);

    std::optional<TriangleMesh> mesh;
    MeshDiagnostics meshDiagnostics{};
    // Mesh input: genus of the mesh and of its voxel model, contacts separated.
    MeshTopology meshGenus{};
    VoxelTopology voxelGenus{};
    ContactSeparation contacts{};
    MaskVolume mask;
    SegmentationResult result;
    std::vector<std::string> warnings;
    std::vector<std::uint32_t> faceLabels;
    std::uint64_t estimatedMemory = 0;
    auto warn = [&](const std::string& w) {
        warnings.push_back(w);
        progress.message("skelseg: warning: " + w);
    };

    // Each stage is a continue_node; writers depend on the segmentation and
    // run concurrently. Exceptions cancel the graph and surface from
    // wait_for_all().
    tbb::flow::graph graph;
    using Node = tbb::flow::continue_node<tbb::flow::continue_msg>;
    using Msg = tbb::flow::continue_msg;

    Node read(graph, [&](Msg) {
        InterrupterScope scope(progress, "reading input");
        if (meshInput) {
            {
                auto t = timer.stage("read mesh", false);
                checkReadableFile(options.input);
                mesh = readMesh(options.input);
            }
            meshDiagnostics = checkMesh(*mesh);
            VoxelizeOptions vo;
            vo.resolution = options.resolution;
            vo.meshIsClosed = meshDiagnostics.closed;
            // The voxeliser's refusals (a grid over the cap, a mesh collapsed
            // to a point) do not know the file: name it, as every error must.
            const auto nameTheFile = [&](const UsageError& error) {
                return UsageError(options.input.string() + ": " + error.what());
            };
            VoxelGrid grid;
            try {
                grid = voxelGridFor(*mesh, vo);
            } catch (const UsageError& error) {
                throw nameTheFile(error);
            }
            estimatedMemory =
                estimateSegmentationMemory(grid.dims, grid.dims.voxelCount() / 4, threads) +
                grid.dims.voxelCount() * 12;  // level set, dense copy, nearest-triangle grid
            if (estimatedMemory > memoryLimit)
                throw MemoryLimitError(options.input.string() + ": needs about " +
                                       formatBytes(estimatedMemory) + " at resolution " +
                                       std::to_string(options.resolution) + ", over the limit of " +
                                       formatBytes(memoryLimit) + " (--max-memory)");
            auto t = timer.stage("voxelise", true);
            try {
                MeshVoxelization voxelised = voxelizeMeshWithContacts(*mesh, vo, progress);
                mask = std::move(voxelised.mask);
                contacts = voxelised.contacts;
            } catch (const UsageError& error) {
                throw nameTheFile(error);
            }
            meshGenus = meshTopology(*mesh);
            voxelGenus = voxelTopology(mask, {}, progress);
            // Warned only now: a mesh that is refused costs one line, the error.
            for (const auto& w : meshWarnings(meshDiagnostics, options.input.string())) warn(w);
        } else {
            auto t = timer.stage("read volume", false);
            VolumeReadOptions ro;
            ro.gridName = options.gridName;
            mask = readVolume(options.input, ro);
        }
        std::uint64_t objectVoxels = 0;
        for (std::uint8_t v : mask.values()) objectVoxels += v != 0;
        estimatedMemory = std::max(estimatedMemory,
                                   estimateSegmentationMemory(mask.dims(), objectVoxels, threads));
        if (estimatedMemory > memoryLimit)
            throw MemoryLimitError(options.input.string() + ": needs about " +
                                   formatBytes(estimatedMemory) + ", over the limit of " +
                                   formatBytes(memoryLimit) + " (--max-memory)");
    });
    Node segment(graph, [&](Msg) {
        result = segmentVolume(mask, options.parameters, progress, &timer);
        for (const auto& w : result.warnings) warn(w);
        if (meshInput) {
            auto t = timer.stage("face labels", true);
            InterrupterScope scope(progress, "face labels");
            faceLabels = labelFaces(*mesh, result.labels, {}, progress);
        }
    });

    const VolumeGeometry* geometry = nullptr;
    std::vector<std::vector<std::array<double, 3>>> cutLoops;
    std::vector<SkeletonPointRecord> skeletonPoints;
    std::vector<std::array<std::uint32_t, 2>> skeletonEdges;
    Node gather(graph, [&](Msg) {
        geometry = &result.labels.geometry;
        for (const auto& object : result.objects) {
            const std::uint32_t base = std::uint32_t(skeletonPoints.size());
            for (const auto& v : object.skeleton) {
                SkeletonPointRecord r;
                r.position = voxelToWorld(*geometry, v.voxel);
                r.rhoS = v.rhoS;
                r.rhoC = std::isfinite(v.rhoC) ? float(v.rhoC) : float(object.boundaryArea);
                r.sigma = v.sigma;
                r.junction = v.junction;
                r.critical = v.critical;
                skeletonPoints.push_back(r);
            }
            for (const auto& e : object.skeletonEdges)
                skeletonEdges.push_back({e[0] + base, e[1] + base});
            for (const auto& loop : object.cutLoops) {
                std::vector<std::array<double, 3>> world;
                for (const auto& v : loop) world.push_back(voxelToWorld(*geometry, v));
                cutLoops.push_back(std::move(world));
            }
        }
    });
    Node writeNrrd(graph, [&](Msg) {
        auto t = timer.stage("write labels.nrrd", false);
        writeNrrdLabels(out.stagingPath("labels.nrrd"), result.labels);
    });
    Node writeVdb(graph, [&](Msg) {
        if (!options.writeVdb) return;
        auto t = timer.stage("write labels.vdb", false);
        writeVdbLabels(out.stagingPath("labels.vdb"), result.labels);
    });
    Node writeSkeleton(graph, [&](Msg) {
        auto t = timer.stage("write skeleton.ply, cuts.ply", false);
        writeSkeletonPly(out.stagingPath("skeleton.ply"), skeletonPoints, skeletonEdges);
        writeCutsPly(out.stagingPath("cuts.ply"), cutLoops);
    });
    Node writeSurfaces(graph, [&](Msg) {
        auto t = timer.stage("segment surfaces and preview", true);
        InterrupterScope scope(progress, "segment surfaces and preview");
        PreviewScene scene;
        if (meshInput) {
            std::vector<std::uint32_t> triangleLabels(mesh->triangles.size());
            for (std::size_t i = 0; i < triangleLabels.size(); ++i)
                triangleLabels[i] = faceLabels[mesh->triangleFace[i]];
            writeColouredMeshPly(out.stagingPath("segments.ply"), mesh->vertices, mesh->triangles,
                                 triangleLabels);
            writeSeg(out.stagingPath("segmentation.seg"), faceLabels);
            scene.vertices = mesh->vertices;
            scene.triangles = mesh->triangles;
            scene.triangleLabels.resize(triangleLabels.size());
            for (std::size_t i = 0; i < triangleLabels.size(); ++i)
                scene.triangleLabels[i] = triangleLabels[i] + 1;
        } else {
            // A few smoothing passes take the voxel terraces off the picture
            // and the meshes; the surfaces stay within a voxel of the labels.
            SegmentSurfaceOptions so;
            so.smoothingIterations = 10;
            LabelledSurface surface = extractSegmentSurfaces(result.labels, so, progress);
            std::vector<std::uint32_t> zeroBased(surface.triangleLabels.size());
            for (std::size_t i = 0; i < zeroBased.size(); ++i)
                zeroBased[i] = surface.triangleLabels[i] - 1;
            writeColouredMeshPly(out.stagingPath("segments.ply"), surface.vertices,
                                 surface.triangles, zeroBased);
            scene.vertices = std::move(surface.vertices);
            scene.triangles = std::move(surface.triangles);
            scene.triangleLabels = std::move(surface.triangleLabels);
        }
        auto views = timer.stage("write segments.glb, viewer.html", true);
        writeSegmentViews(
            out, {&result, &scene.vertices, &scene.triangles, &scene.triangleLabels,
                  &skeletonPoints, &skeletonEdges, &cutLoops, options.input.filename().string(),
                  viewerFacts(options, result), options.parameters.tau.toString()});
        if (!options.writePreview) return;
        for (const auto& p : skeletonPoints) scene.skeletonPoints.push_back(p.position);
        scene.skeletonEdges = skeletonEdges;
        scene.cutLoops = cutLoops;
        scene.title =
            options.input.filename().string() +
            "   parts: " + std::to_string(result.segments.size()) +
            "   tau: " + options.parameters.tau.toString() +
            (options.parameters.mode == CutMode::Junctions ? "   mode: junctions (RT07)" : "");
        PreviewOptions po;  // default: the longest side of the shape points up
        renderPreviewPng(out.stagingPath("preview.png"), scene, po);
    });

    tbb::flow::make_edge(read, segment);
    tbb::flow::make_edge(segment, gather);
    tbb::flow::make_edge(gather, writeNrrd);
    tbb::flow::make_edge(gather, writeVdb);
    tbb::flow::make_edge(gather, writeSkeleton);
    tbb::flow::make_edge(gather, writeSurfaces);
    read.try_put(Msg());
    graph.wait_for_all();
    throwIfInterrupted(progress);

    // The report comes last: it holds the timings of everything above.
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
    json report;
    report["status"] = "ok";
    report["skelseg_version"] = versionString();
    report["input"] = {{"file", options.input.string()}, {"kind", meshInput ? "mesh" : "volume"}};
    if (meshInput) {
        report["input"]["faces"] = mesh->faceCount;
        report["input"]["vertices"] = mesh->vertices.size();
        report["input"]["resolution"] = options.resolution;
        report["input"]["mesh_closed"] = meshDiagnostics.closed;
        report["input"]["mesh_pieces"] = meshDiagnostics.pieces;
        report["input"]["mesh_boundary_edges"] = meshDiagnostics.boundaryEdges;
        report["input"]["mesh_degenerate_faces"] = meshDiagnostics.degenerateFaces;
        report["input"]["mesh_genus"] = meshGenus.genus;
        report["input"]["mesh_closed_pieces"] = meshGenus.closedPieces;
        report["input"]["voxel_genus"] = voxelGenus.genus;
        report["input"]["contacts_separated"] = contacts.contacts;
        report["input"]["contact_voxels_cleared"] = contacts.voxelsCleared;
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
        {"threads", threads},
        {"region_radius", options.parameters.regionRadius},
        {"bridge_gap", options.parameters.bridgeGap},
        {"consecutive_levels", options.parameters.consecutiveLevels}};
    json counts = {{"object_voxels", 0},         {"boundary_voxels", 0}, {"candidates", 0},
                   {"curve_skeleton_points", 0}, {"skeleton_points", 0}, {"junction_voxels", 0}};
    json work = {{"objects_voxels_examined", 0},
                 {"candidates_searched", 0},
                 {"dijkstra_searches", 0},
                 {"heap_pops", 0},
                 {"nodes_settled", 0},
                 {"path_cache_hits", 0},
                 {"rim_tests", 0},
                 {"component_growth_steps", 0},
                 {"sigma_evaluations", 0},
                 {"sigma_searches", 0},
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
    if (meshInput) {
        std::uint32_t faceSegments = 0;
        for (std::uint32_t l : faceLabels) faceSegments = std::max(faceSegments, l + 1);
        report["face_segments"] = faceSegments;
    }
    json stages = json::array();
    double serialWall = 0.0, stageWall = 0.0;
    for (const auto& s : timer.timings()) {
        stages.push_back({{"name", s.name},
                          {"parallel", s.parallel},
                          {"wall_seconds", s.wallSeconds},
                          {"cpu_seconds", s.cpuSeconds},
                          {"calls", s.calls}});
        stageWall += s.wallSeconds;
        if (!s.parallel) serialWall += s.wallSeconds;
    }
    report["stages"] = stages;
    report["timing"] = {{"wall_seconds", wall},
                        {"cpu_seconds", processCpuSeconds() - cpuStart},
                        {"serial_stage_seconds", serialWall},
                        {"serial_share", wall > 0 ? serialWall / wall : 0.0}};
    report["memory"] = {{"peak_resident_bytes", peakResidentBytes()},
                        {"estimated_bytes", estimatedMemory},
                        {"limit_bytes", memoryLimit}};
    report["warnings"] = warnings;
    writeFileAtomically(out.stagingPath("report.json"), report.dump(2) + "\n");
    throwIfInterrupted(progress);
    out.commit();
}

}  // namespace skelseg
