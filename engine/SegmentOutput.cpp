#include "engine/SegmentOutput.h"

#include <cmath>
#include <optional>

#include "engine/SegmentViews.h"
#include "engine/Stage.h"
#include "io/mesh/SegFile.h"
#include "io/render/PreviewRenderer.h"
#include "io/render/SegmentSurfaces.h"
#include "io/volume/NrrdIO.h"
#include "io/volume/VdbIO.h"

namespace skelseg {

namespace {

/// The lines under viewer.html's title.
std::vector<std::string> viewerFacts(const SegmentCommandOptions& options,
                                     const SegmentationResult& result) {
    const Dims d = result.labels.dims();
    std::vector<std::string> facts = {
        std::to_string(result.segments.size()) + " parts",
        "tau " + options.parameters.tauListString(),
        "grid " + std::to_string(d.x) + " x " + std::to_string(d.y) + " x " + std::to_string(d.z)};
    if (!options.gridName.empty()) facts.push_back("grid name " + options.gridName);
    return facts;
}

}  // namespace

WorldGeometry gatherWorldGeometry(const SegmentationResult& result) {
    WorldGeometry world;
    const VolumeGeometry& geometry = result.labels.geometry;
    auto toWorld = [&](const std::array<int, 3>& v) {
        return geometry.indexToWorld(v[0], v[1], v[2]);
    };
    for (const auto& object : result.objects) {
        const std::uint32_t base = std::uint32_t(world.skeletonPoints.size());
        for (const auto& v : object.skeleton) {
            SkeletonPointRecord r;
            r.position = toWorld(v.voxel);
            r.rhoS = v.rhoS;
            r.rhoC = std::isfinite(v.rhoC) ? float(v.rhoC) : float(object.boundaryArea);
            r.sigma = v.sigma;
            r.junction = v.junction;
            r.critical = v.critical;
            world.skeletonPoints.push_back(r);
        }
        for (const auto& e : object.skeletonEdges)
            world.skeletonEdges.push_back({e[0] + base, e[1] + base});
        for (const auto& loop : object.cutLoops) {
            std::vector<std::array<double, 3>> points;
            for (const auto& v : loop) points.push_back(toWorld(v));
            world.cutLoops.push_back(std::move(points));
        }
    }
    return world;
}

void writeLabelNrrd(OutputDirectory& out, const SegmentedShape& shape, StageTimer& timer,
                    Interrupter& interrupter) {
    Stage stage(timer, interrupter, "write labels.nrrd", false);
    writeNrrdLabels(out.stagingPath("labels.nrrd"), shape.result.labels);
}

void writeLabelVdb(OutputDirectory& out, const SegmentedShape& shape, StageTimer& timer,
                   Interrupter& interrupter) {
    Stage stage(timer, interrupter, "write labels.vdb", false);
    // maskShape() warned; an earlier run's labels.vdb would not match.
    if (!vdbCanHoldVoxelVolume(shape.result.labels.dims(), shape.result.labels.geometry)) {
        out.removeOnCommit("labels.vdb");
        return;
    }
    writeVdbLabels(out.stagingPath("labels.vdb"), shape.result.labels);
}

void writeSkeletonAndCuts(OutputDirectory& out, const SegmentedShape& shape, StageTimer& timer,
                          Interrupter& interrupter) {
    Stage stage(timer, interrupter, "write skeleton.ply, cuts.ply", false);
    writeSkeletonPly(out.stagingPath("skeleton.ply"), shape.world.skeletonPoints,
                     shape.world.skeletonEdges);
    writeCutsPly(out.stagingPath("cuts.ply"), shape.world.cutLoops);
}

void writeLevels(OutputDirectory& out, const SegmentedShape& shape, StageTimer& timer,
                 Interrupter& interrupter) {
    const SegmentationResult& result = shape.result;
    if (result.levelCount() < 2) return;
    Stage stage(timer, interrupter, "write levels, hierarchy.json", false);
    const bool isMesh = shape.input->source->isMesh();
    const std::filesystem::path root = out.stagingPath("levels");
    for (std::size_t k = 0; k < result.levelCount(); ++k) {
        const std::filesystem::path directory = root / std::to_string(k);
        std::error_code ec;
        std::filesystem::create_directories(directory, ec);
        if (ec)
            throw OutputError(directory.string() + ": cannot create directory: " + ec.message());
        writeNrrdLabels(directory / "labels.nrrd", result.levelLabels(k));
        writeCutsPly(directory / "cuts.ply", shape.levels.cutLoops[k]);
        if (isMesh) writeSeg(directory / "segmentation.seg", shape.levels.faceLabels[k]);
        throwIfInterrupted(interrupter);
    }
    writeFileAtomically(out.stagingPath("hierarchy.json"),
                        hierarchyJson(result, shape.levels, isMesh));
}

void writeSurfacesAndPreview(OutputDirectory& out, const SegmentedShape& shape,
                             const SegmentCommandOptions& options, bool writePreview,
                             StageTimer& timer, Interrupter& interrupter) {
    Stage stage(timer, interrupter, "segment surfaces and preview", true);
    const SegmentSource& source = *shape.input->source;
    const SegmentationResult& result = shape.result;
    PreviewScene scene;
    if (source.isMesh()) {
        const TriangleMesh& mesh = *source.mesh;
        // Face labels are 0-based (segmentation.seg); segments.ply, like the
        // preview and segments.glb, shows face label i as segment label i + 1
        // (label 0 would read as unlabelled and be drawn grey).
        std::vector<std::uint32_t> triangleLabels(mesh.triangles.size());
        for (std::size_t i = 0; i < triangleLabels.size(); ++i)
            triangleLabels[i] = shape.faceLabels[mesh.triangleFace[i]] + 1;
        writeColouredMeshPly(out.stagingPath("segments.ply"), mesh.vertices, mesh.triangles,
                             triangleLabels);
        writeSeg(out.stagingPath("segmentation.seg"), shape.faceLabels);
        scene.vertices = mesh.vertices;
        scene.triangles = mesh.triangles;
        scene.triangleLabels = std::move(triangleLabels);
    } else {
        // A few smoothing passes take the voxel terraces off the picture
        // and the meshes; the surfaces stay within a voxel of the labels.
        SegmentSurfaceOptions surfaceOptions;
        surfaceOptions.smoothingIterations = 10;
        LabelledSurface surface =
            extractSegmentSurfaces(result.labels, surfaceOptions, interrupter);
        // The surfaces carry the labels of labels.nrrd (1..K), which is what
        // segments.ply's `segment` holds.
        writeColouredMeshPly(out.stagingPath("segments.ply"), surface.vertices, surface.triangles,
                             surface.triangleLabels);
        scene.vertices = std::move(surface.vertices);
        scene.triangles = std::move(surface.triangles);
        scene.triangleLabels = std::move(surface.triangleLabels);
    }
    // Hierarchy runs: every level on the one surface, labelled as labels.nrrd.
    std::vector<std::vector<std::uint32_t>> levelLabels;
    if (result.levelCount() > 1) {
        if (source.isMesh()) {
            const TriangleMesh& mesh = *source.mesh;
            levelLabels.resize(shape.levels.faceVoxelLabels.size());
            for (std::size_t k = 0; k < levelLabels.size(); ++k)
                for (std::uint32_t face : mesh.triangleFace)
                    levelLabels[k].push_back(shape.levels.faceVoxelLabels[k][face]);
        } else {
            levelLabels =
                levelTriangleLabels(result, scene.vertices, scene.triangles, scene.triangleLabels);
        }
    }
    {
        // Inside the surfaces stage (whose time includes it), as its own too.
        Stage views(timer, interrupter, "write segments.glb, viewer.html", true);
        SegmentViewInputs inputs{&result,
                                 &scene.vertices,
                                 &scene.triangles,
                                 &scene.triangleLabels,
                                 &shape.world.skeletonPoints,
                                 &shape.world.skeletonEdges,
                                 &shape.world.cutLoops,
                                 options.input.filename().string(),
                                 viewerFacts(options, result),
                                 options.parameters.tau.toString(),
                                 {},
                                 nullptr};
        if (result.levelCount() > 1) {
            inputs.levelTriangleLabels = levelLabels;
            inputs.levelCutLoops = &shape.levels.cutLoops;
        }
        writeSegmentViews(out, inputs);
    }
    if (!writePreview) return;
    for (const auto& p : shape.world.skeletonPoints) scene.skeletonPoints.push_back(p.position);
    scene.skeletonEdges = shape.world.skeletonEdges;
    scene.cutLoops = shape.world.cutLoops;
    const std::optional<BudgetChoice>& budget = shape.input->budget;
    scene.title =
        options.input.filename().string() + "   parts: " + std::to_string(result.segments.size()) +
        "   tau: " + options.parameters.tau.toString() +
        (budget && budget->coarsened
             ? "   coarsened for --time-budget: " + describeBudgetChoice(*budget)
             : std::string()) +
        (options.parameters.mode == CutMode::Junctions ? "   mode: junctions (RT07)" : "");
    PreviewOptions previewOptions;  // default: the longest side of the shape points up
    renderPreviewPng(out.stagingPath("preview.png"), scene, previewOptions);
    if (!options.writeLevelPreviews || levelLabels.empty()) return;
    // levels/k/preview.png: the same views of each level. Mesh faces take
    // their segmentation.seg label + 1, as in the top-level preview.
    for (std::size_t k = 0; k < levelLabels.size(); ++k) {
        if (source.isMesh()) {
            const TriangleMesh& mesh = *source.mesh;
            for (std::size_t t = 0; t < scene.triangleLabels.size(); ++t)
                scene.triangleLabels[t] = shape.levels.faceLabels[k][mesh.triangleFace[t]] + 1;
        } else {
            scene.triangleLabels = levelLabels[k];
        }
        scene.cutLoops = shape.levels.cutLoops[k];
        scene.title = options.input.filename().string() + "   level " + std::to_string(k) +
                      "   parts: " + std::to_string(result.levelSegments(k).size()) +
                      "   tau: " + result.levelTau(k).toString() +
                      (result.levelIsJoints(k) ? " + joints" : "");
        const std::filesystem::path directory = out.stagingPath("levels") / std::to_string(k);
        std::error_code ec;
        std::filesystem::create_directories(directory, ec);  // writeLevels may be first
        if (!std::filesystem::is_directory(directory))
            throw OutputError(directory.string() + ": cannot create directory: " + ec.message());
        renderPreviewPng(directory / "preview.png", scene, previewOptions);
        throwIfInterrupted(interrupter);
    }
}

}  // namespace skelseg
