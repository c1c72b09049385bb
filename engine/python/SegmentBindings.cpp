// segment() and segment_mesh(): the engine on numpy arrays, off the GIL.
#include <pybind11/stl.h>
#include <tbb/info.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

#include "engine/LevelOutputs.h"
#include "engine/ResultReport.h"
#include "engine/SegmentCommand.h"
#include "engine/Stage.h"
#include "engine/python/ArrayMask.h"
#include "engine/python/Bindings.h"
#include "engine/python/EngineCall.h"
#include "engine/python/ResultArrays.h"
#include "io/mesh/FaceLabels.h"
#include "io/mesh/MeshCheck.h"
#include "io/mesh/MeshVoxelizer.h"

namespace py = pybind11;

namespace skelseg {

namespace {

// Names used in messages where the CLI names the input file.
const std::string kMaskName = "mask";
const std::string kMeshName = "mesh";

SegmentationParameters parametersFrom(const CallOptions& options) {
    SegmentationParameters p;
    std::vector<TauSpec> taus = parseTauList(options.tau);
    p.tau = taus.back();
    taus.pop_back();
    p.finerTaus = std::move(taus);
    p.sigmaMin = options.sigmaMin;
    p.bodyRatio = options.bodyRatio;
    p.joints = options.joints;
    if (options.mode == "junction-rule")
        p.mode = CutMode::JunctionRule;
    else if (options.mode == "junctions")
        p.mode = CutMode::Junctions;
    else
        throw UsageError("mode '" + options.mode + "' is not junction-rule or junctions");
    return p;
}

/// What every call measures and reports besides the engine's result.
struct CallRecord {
    explicit CallRecord(const CallOptions& options)
        : parameters(parametersFrom(options)),
          threads(options.threads > 0 ? options.threads : tbb::info::default_concurrency()),
          memoryLimit(options.maxMemoryBytes ? options.maxMemoryBytes : defaultMemoryLimit()),
          interrupter(options.timeLimitSeconds) {}

    int levels() const { return int(parameters.levelCount()); }

    void checkMemory(const std::string& name, std::uint64_t estimate, const std::string& detail) {
        estimatedMemory = std::max(estimatedMemory, estimate);
        if (estimate > memoryLimit)
            throw MemoryLimitError(name + ": needs about " + formatBytes(estimate) + detail +
                                   ", over the limit of " + formatBytes(memoryLimit) +
                                   " (max_memory)");
    }

    py::dict finish(SegmentationResult&& result, nlohmann::json input,
                    std::optional<std::uint32_t> faceSegments = std::nullopt,
                    const std::vector<std::vector<std::uint32_t>>* levelFaceLabels = nullptr) {
        for (const auto& w : result.warnings) warnings.push_back(w);
        ResultReportContext context;
        context.input = std::move(input);
        context.parameters = parameters;
        context.threads = threads;
        context.stages = timer.timings();
        context.wallSeconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
        context.cpuSeconds = processCpuSeconds() - cpuStart;
        context.estimatedMemoryBytes = estimatedMemory;
        context.memoryLimitBytes = memoryLimit;
        context.warnings = warnings;
        context.faceSegments = faceSegments;
        py::dict out;
        out["report"] = jsonToPython(resultReport(result, context));
        out["skeleton"] = skeletonArrays(result);
        out["cuts"] = cutArrays(result);
        out["warnings"] = py::cast(warnings);
        // Every level, finest first; labels None: the top-level "labels".
        // Mesh inputs add each level's face labels (segmentation.seg's).
        const auto levelLoops = levelCutLoops(result);
        py::list levels;
        for (std::size_t k = 0; k < result.levelCount(); ++k) {
            py::dict entry;
            entry["tau"] = result.levelTau(k).toString();
            entry["joints"] = result.levelIsJoints(k);
            entry["segments"] = result.levelSegments(k).size();
            py::list cuts;
            for (const auto& loop : levelLoops[k]) {
                std::vector<double> points;
                points.reserve(3 * loop.size());
                for (const auto& p : loop) points.insert(points.end(), p.begin(), p.end());
                cuts.append(arrayOwning(std::move(points), {py::ssize_t(loop.size()), 3}));
            }
            entry["cuts"] = cuts;
            if (k < result.finerLevels.size()) {
                SegmentationLevel& level = result.finerLevels[k];
                const auto segmentCount = py::ssize_t(level.segments.size());
                entry["labels"] = labelArray(std::move(level.labels));
                entry["parents"] =
                    level.parentLabel.empty()
                        ? py::object(py::none())
                        : py::object(arrayOwning(std::move(level.parentLabel), {segmentCount}));
            } else {
                entry["labels"] = py::none();
                entry["parents"] = py::none();
            }
            if (levelFaceLabels && k < levelFaceLabels->size()) {
                std::vector<std::int32_t> faces((*levelFaceLabels)[k].begin(),
                                                (*levelFaceLabels)[k].end());
                const auto faceCount = py::ssize_t(faces.size());
                entry["face_labels"] = arrayOwning(std::move(faces), {faceCount});
            } else {
                entry["face_labels"] = py::none();
            }
            levels.append(entry);
        }
        out["levels"] = levels;
        out["labels"] = labelArray(std::move(result.labels));
        return out;
    }

    SegmentationParameters parameters;
    int threads;
    std::uint64_t memoryLimit;
    CallerPolledInterrupter interrupter;
    StageTimer timer;
    std::uint64_t estimatedMemory = 0;
    std::vector<std::string> warnings;
    std::chrono::steady_clock::time_point wallStart = std::chrono::steady_clock::now();
    double cpuStart = processCpuSeconds();
};

std::string dtypeName(const py::dtype& dtype) {
    return py::str(static_cast<const py::handle&>(dtype)).cast<std::string>();
}

ArrayView viewOf(const py::array& array) {
    if (array.ndim() != 3) {
        std::string shape;
        for (py::ssize_t a = 0; a < array.ndim(); ++a)
            shape += (a ? ", " : "") + std::to_string(array.shape(a));
        throw InputError(kMaskName, "must be a 3-D array, got " + std::to_string(array.ndim()) +
                                        "-D of shape (" + shape + (array.ndim() == 1 ? ",)" : ")"));
    }
    ArrayView view;
    view.data = static_cast<const std::uint8_t*>(array.data());
    for (int a = 0; a < 3; ++a) {
        view.shape[a] = array.shape(a);
        view.strides[a] = array.strides(a);
    }
    const py::dtype dtype = array.dtype();
    view.itemSize = int(dtype.itemsize());
    const char kind = dtype.kind();
    const bool integer = kind == 'b' || kind == 'i' || kind == 'u';
    const bool real =
        kind == 'f' && (view.itemSize == 2 || view.itemSize == 4 || view.itemSize == 8);
    if (!(integer &&
          (view.itemSize == 1 || view.itemSize == 2 || view.itemSize == 4 || view.itemSize == 8)) &&
        !real)
        throw py::type_error("mask: dtype " + dtypeName(dtype) +
                             " is not supported (bool, integers or floats; nonzero is object)");
    if (real && dtype.attr("isnative").cast<bool>() == false)
        throw py::type_error("mask: float dtype " + dtypeName(dtype) +
                             " is not in native byte order");
    if (real)
        view.element = view.itemSize == 2   ? MaskElement::Float16
                       : view.itemSize == 4 ? MaskElement::Float32
                                            : MaskElement::Float64;
    return view;
}

}  // namespace

py::dict segmentArray(const py::array& array, const std::array<double, 3>& spacing,
                      const CallOptions& options) {
    CallRecord call(options);
    const ArrayView view = viewOf(array);
    const Dims dims = Dims::checked(view.shape[0], view.shape[1], view.shape[2], kMaskName);
    for (double s : spacing)
        if (!(s > 0) || !std::isfinite(s))
            throw UsageError("spacing must be three positive finite numbers");

    SegmentationResult result;
    std::uint64_t objectVoxels = 0;
    runEngineCall(
        [&] {
            // Counting first costs a pass over the array; it is only needed
            // when the bound that counts every voxel as object is too high.
            if (estimateSegmentationMemory(dims, dims.voxelCount(), call.threads) >
                call.memoryLimit) {
                objectVoxels = countObjectVoxels(view, kMaskName);
                call.checkMemory(
                    kMaskName,
                    estimateSegmentationMemory(dims, objectVoxels, call.threads, call.levels()),
                    "");
            }
            MaskVolume mask = maskFromArray(view, kMaskName);
            mask.geometry.directions = {
                {{spacing[0], 0, 0}, {0, spacing[1], 0}, {0, 0, spacing[2]}}};
            objectVoxels = 0;
            for (std::uint8_t v : mask.values()) objectVoxels += v;
            call.estimatedMemory =
                estimateSegmentationMemory(dims, objectVoxels, call.threads, call.levels());
            result = segmentVolume(mask, call.parameters, call.interrupter, &call.timer);
        },
        call.interrupter, options.threads, options.progress);

    nlohmann::json input = {{"kind", "array"},
                            {"shape", {view.shape[0], view.shape[1], view.shape[2]}},
                            {"dtype", dtypeName(array.dtype())},
                            {"spacing", {spacing[0], spacing[1], spacing[2]}}};
    return call.finish(std::move(result), std::move(input));
}

TriangleMesh meshFromArrays(const py::array_t<double>& vertices,
                            const py::array_t<std::int64_t>& faces,
                            const py::array_t<std::int64_t>& triangleFace) {
    if (vertices.ndim() != 2 || vertices.shape(1) != 3)
        throw InputError(kMeshName, "vertices must be an array of shape (V, 3)");
    if (faces.ndim() != 2 || faces.shape(1) != 3)
        throw InputError(kMeshName, "faces must be an array of shape (F, 3) of vertex indices");
    if (faces.shape(0) == 0) throw InputError(kMeshName, "has no faces");
    const auto v = vertices.unchecked<2>();
    const auto f = faces.unchecked<2>();
    TriangleMesh mesh;
    mesh.vertices.resize(std::size_t(v.shape(0)));
    for (py::ssize_t i = 0; i < v.shape(0); ++i)
        for (int c = 0; c < 3; ++c) {
            const double value = v(i, c);
            if (!std::isfinite(value))
                throw InputError(kMeshName, "vertex " + std::to_string(i) +
                                                " has a coordinate that is not finite");
            mesh.vertices[std::size_t(i)][c] = value;
        }
    const auto vertexCount = std::int64_t(mesh.vertices.size());
    mesh.triangles.resize(std::size_t(f.shape(0)));
    mesh.triangleFace.resize(std::size_t(f.shape(0)));
    for (py::ssize_t t = 0; t < f.shape(0); ++t)
        for (int c = 0; c < 3; ++c) {
            const std::int64_t index = f(t, c);
            if (index < 0 || index >= vertexCount)
                throw InputError(kMeshName, "face " + std::to_string(t) + " uses vertex " +
                                                std::to_string(index) + " of " +
                                                std::to_string(vertexCount));
            mesh.triangles[std::size_t(t)][c] = std::uint32_t(index);
        }
    if (triangleFace.size() == 0) {
        for (std::size_t t = 0; t < mesh.triangleFace.size(); ++t)
            mesh.triangleFace[t] = std::uint32_t(t);
        mesh.faceCount = mesh.triangles.size();
        return mesh;
    }
    if (triangleFace.ndim() != 1 || triangleFace.shape(0) != faces.shape(0))
        throw InputError(kMeshName, "triangle_face must have one entry per row of faces");
    const auto tf = triangleFace.unchecked<1>();
    // As the readers make it: triangles of one face are consecutive, faces in order.
    for (py::ssize_t t = 0; t < tf.shape(0); ++t) {
        const std::int64_t previous = t ? tf(t - 1) : -1;
        if (tf(t) != previous && tf(t) != previous + 1)
            throw InputError(kMeshName, "triangle_face must start at 0 and rise by 0 or 1");
        mesh.triangleFace[std::size_t(t)] = std::uint32_t(tf(t));
    }
    mesh.faceCount = std::size_t(tf(tf.shape(0) - 1)) + 1;
    return mesh;
}

py::dict segmentMeshArrays(const py::array_t<double>& vertices,
                           const py::array_t<std::int64_t>& faces,
                           const py::array_t<std::int64_t>& triangleFace, int resolution,
                           int selfOverlapClearance, const CallOptions& options) {
    CallRecord call(options);
    const TriangleMesh mesh = meshFromArrays(vertices, faces, triangleFace);

    MeshDiagnostics diagnostics{};
    SegmentationResult result;
    std::vector<std::uint32_t> faceLabels;
    LevelOutputs levels;
    runEngineCall(
        [&] {
            // As the CLI: the voxeliser's refusals name the input.
            const auto named = [](const UsageError& error) {
                return UsageError(kMeshName + ": " + error.what());
            };
            MaskVolume mask;
            {
                InterrupterScope scope(call.interrupter, "voxelise");
                diagnostics = checkMesh(mesh);
                VoxelizeOptions vo;
                vo.resolution = resolution;
                vo.selfOverlapOptions.maxClearance = selfOverlapClearance;
                vo.meshIsClosed = diagnostics.closed;
                VoxelGrid grid;
                try {
                    grid = voxelGridFor(mesh, vo);
                } catch (const UsageError& error) {
                    throw named(error);
                }
                call.checkMemory(kMeshName,
                                 estimateSegmentationMemory(grid.dims, grid.dims.voxelCount() / 4,
                                                            call.threads) +
                                     grid.dims.voxelCount() * 8,
                                 " at resolution " + std::to_string(resolution));
                Stage t(call.timer, call.interrupter, "voxelise", true);
                try {
                    mask = voxelizeMesh(mesh, vo, call.interrupter);
                } catch (const UsageError& error) {
                    throw named(error);
                }
            }
            for (const auto& w : meshWarnings(diagnostics, kMeshName)) call.warnings.push_back(w);
            std::uint64_t objectVoxels = 0;
            for (std::uint8_t value : mask.values()) objectVoxels += value != 0;
            call.checkMemory(
                kMeshName,
                estimateSegmentationMemory(mask.dims(), objectVoxels, call.threads, call.levels()),
                "");
            result = segmentVolume(mask, call.parameters, call.interrupter, &call.timer);
            FaceLabelStatistics statistics;
            {
                Stage t(call.timer, call.interrupter, "face labels", true);
                faceLabels = labelFaces(mesh, result.labels, {}, call.interrupter, &statistics);
            }
            if (result.levelCount() > 1) {
                // As the CLI's levels/k/segmentation.seg: nested level to level.
                Stage t(call.timer, call.interrupter, "level face labels", true);
                labelLevelFaces(mesh, result, faceLabels, statistics.voxelLabels, levels,
                                call.interrupter);
            } else {
                levels.faceLabels = {faceLabels};
            }
        },
        call.interrupter, options.threads, options.progress);

    std::uint32_t faceSegments = 0;
    for (std::uint32_t l : faceLabels) faceSegments = std::max(faceSegments, l + 1);
    nlohmann::json input = {{"kind", "mesh"},
                            {"faces", mesh.faceCount},
                            {"vertices", mesh.vertices.size()},
                            {"resolution", resolution},
                            {"self_overlap_clearance", selfOverlapClearance},
                            {"mesh_closed", diagnostics.closed},
                            {"mesh_pieces", diagnostics.pieces},
                            {"mesh_boundary_edges", diagnostics.boundaryEdges},
                            {"mesh_degenerate_faces", diagnostics.degenerateFaces}};
    std::vector<std::int32_t> labels(faceLabels.begin(), faceLabels.end());
    const auto faceCount = py::ssize_t(labels.size());
    py::dict out =
        call.finish(std::move(result), std::move(input), faceSegments, &levels.faceLabels);
    out["face_labels"] = arrayOwning(std::move(labels), {faceCount});
    return out;
}

}  // namespace skelseg
