// segment() and segment_mesh(): the engine on numpy arrays, off the GIL.
#include <pybind11/stl.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

#include "engine/LevelOutputs.h"
#include "engine/SegmentOptions.h"
#include "engine/SegmentReport.h"
#include "engine/SegmentSteps.h"
#include "engine/Stage.h"
#include "engine/UsableThreads.h"
#include "engine/python/ArrayMask.h"
#include "engine/python/Bindings.h"
#include "engine/python/EngineCall.h"
#include "engine/python/ResultArrays.h"
#include "io/files/TextFile.h"
#include "io/mesh/MeshCheck.h"

namespace py = pybind11;

namespace skelseg {

namespace {

// Names used in messages where the CLI names the input file.
const std::string kMaskName = "mask";
const std::string kMeshName = "mesh";

/// One call: its options, clocks and interrupter, and the CLI's steps from
/// the input to the result (engine/SegmentSteps.h).
struct CallRecord {
    explicit CallRecord(const CallOptions& callOptions)
        : options(callOptions.command),
          threads(usableThreads(options.threads)),
          inputOptions(segmentInputOptions(options, threads, wallStart)),
          interrupter(options.timeLimitSeconds) {
        inputOptions.preview = false;  // the module writes no preview.png
    }

    /// The mask, its segmentation and the face labels, as the CLI's graph
    /// makes them. The time budget counts from the start of the call.
    std::shared_ptr<SegmentedShape> segment(std::shared_ptr<SegmentSource> source) {
        std::shared_ptr<SegmentedShape> first = onePass(std::move(source), inputOptions);
        if (!first->input->budget || options.budgetPasses < 2) return first;
        // The CLI's finer pass (engine/TimeBudget.h BudgetRefinement), with
        // the result in memory instead of staged files.
        const bool mesh = first->input->source->isMesh();
        refinement = planFinerPass(*first->input->budget, mesh, options.resolution, timer.timings(),
                                   inputOptions.start);
        if (!refinement->tried) return first;
        // The input again: a mesh is whole in the first pass's source; a
        // volume's mask went into the first pass, which kept it as its fine mask.
        auto again = std::make_shared<SegmentSource>(*first->input->source);
        if (!mesh) again->volumeMask = first->input->fineMask;
        // Both clocks start with the call; time_limit when it comes first.
        const double userLimit = interrupter.timeLimit();
        if (userLimit > 0)
            refinement->deadlineSeconds = std::min(refinement->deadlineSeconds, userLimit);
        interrupter.setTimeLimit(refinement->deadlineSeconds);
        SegmentInputOptions finer = inputOptions;
        finer.budgetChoice = refinement->choice;
        finer.heldBytes = heldResultBytes(*first->input, inputOptions.levels);
        try {
            std::shared_ptr<SegmentedShape> second = onePass(std::move(again), finer);
            refinement->kept = true;
            return second;
        } catch (const InterruptedError& error) {
            if (error.reason() != InterruptedError::Reason::TimeLimit) throw;
        } catch (const MemoryLimitError&) {
            refinement->overMemory = true;
        }
        refinement->kept = false;
        interrupter.setTimeLimit(0.0);  // the call returns the first pass's result
        return first;
    }

    /// One pass from the input to the result, as the CLI's graph makes it.
    std::shared_ptr<SegmentedShape> onePass(std::shared_ptr<SegmentSource> source,
                                            const SegmentInputOptions& passOptions) {
        const auto quiet = [](const std::string&) {};  // warnings come back in the result
        auto mask = std::make_shared<SegmentMask>(
            maskSegmentSource(std::move(source), passOptions, timer, interrupter, quiet));
        interrupter.setTimeLimit(
            limitTimeToBudget(*mask, interrupter.timeLimit(), options.timeBudgetSeconds));
        auto shape =
            segmentMaskStep(std::move(mask), options.parameters, timer, interrupter, quiet);
        refineStep(*shape, timer, interrupter);
        completeStep(*shape, timer, interrupter);
        return shape;
    }

    /// The result as plain Python objects; `input` replaces report.json's
    /// description of the input file.
    py::dict finish(SegmentedShape& shape, const nlohmann::json& input) {
        SegmentRunFigures figures;
        figures.threads = threads;
        figures.memoryLimit = inputOptions.memoryLimit;
        figures.wallSeconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
        figures.cpuSeconds = processCpuSeconds() - cpuStart;
        figures.budgetRefinement = refinement;
        nlohmann::json report = segmentReport(options, shape, timer.timings(), figures);
        report["input"].erase("file");
        for (const auto& [key, value] : input.items()) report["input"][key] = value;
        SegmentationResult& result = shape.result;
        py::dict out;
        out["warnings"] = jsonToPython(report["warnings"]);
        out["report"] = jsonToPython(report);
        out["skeleton"] = skeletonArrays(result);
        out["cuts"] = cutArrays(result);
        // Every level, finest first; labels None: the top-level "labels".
        // Mesh inputs add each level's face labels (segmentation.seg's).
        const auto levelLoops =
            shape.levels.cutLoops.empty() ? levelCutLoops(result) : shape.levels.cutLoops;
        const bool mesh = shape.input->source->isMesh();
        const std::vector<std::vector<std::uint32_t>> singleLevelFaces = {shape.faceLabels};
        const auto& levelFaceLabels =
            shape.levels.faceLabels.empty() ? singleLevelFaces : shape.levels.faceLabels;
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
            if (mesh && k < levelFaceLabels.size()) {
                entry["face_labels"] = faceLabelArray(levelFaceLabels[k]);
            } else {
                entry["face_labels"] = py::none();
            }
            levels.append(entry);
        }
        out["levels"] = levels;
        out["labels"] = labelArray(std::move(result.labels));
        if (mesh) out["face_labels"] = faceLabelArray(shape.faceLabels);
        return out;
    }

    static py::array_t<std::int32_t> faceLabelArray(const std::vector<std::uint32_t>& labels) {
        std::vector<std::int32_t> faces(labels.begin(), labels.end());
        const auto faceCount = py::ssize_t(faces.size());
        return arrayOwning(std::move(faces), {faceCount});
    }

    SegmentCommandOptions options;
    std::chrono::steady_clock::time_point wallStart = std::chrono::steady_clock::now();
    double cpuStart = processCpuSeconds();
    int threads;
    SegmentInputOptions inputOptions;
    CallerPolledInterrupter interrupter;
    StageTimer timer;
    std::optional<BudgetRefinement> refinement;  // time_budget's finer pass
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
    // The rule of the volume files' headers: a voxel volume that underflows
    // or world positions that overflow are refused, not segmented.
    VolumeGeometry geometry;
    geometry.directions = {{{spacing[0], 0, 0}, {0, spacing[1], 0}, {0, 0, spacing[2]}}};
    if (const std::string problem = geometry.problemOver(dims); !problem.empty())
        throw UsageError("spacing: " + problem);

    std::shared_ptr<SegmentedShape> shape;
    runEngineCall(
        [&] {
            // The array is converted before the CLI's memory check (which
            // counts the mask's object voxels): refuse first what cannot fit.
            // Counting costs a pass over the array; it is only needed when
            // the bound that counts every voxel as object is too high.
            // Under a time budget, which may coarsen the volume to fit, only
            // the mask itself must fit (the CLI's refuseVolumeGridOverMemory).
            const SegmentInputOptions& in = call.inputOptions;
            if (in.timeBudgetSeconds > 0) {
                if (dims.voxelCount() > in.memoryLimit)
                    throw MemoryLimitError(kMaskName + ": its mask needs " +
                                           formatBytes(dims.voxelCount()) + ", over the limit of " +
                                           formatBytes(in.memoryLimit) + " (--max-memory)");
            } else if (estimateSegmentationMemory(dims, dims.voxelCount(), in.threads) >
                       in.memoryLimit) {
                const std::uint64_t estimate = estimateSegmentationMemory(
                    dims, countObjectVoxels(view, kMaskName), in.threads, in.levels);
                if (estimate > in.memoryLimit)
                    throw MemoryLimitError(kMaskName + ": needs about " + formatBytes(estimate) +
                                           ", over the limit of " + formatBytes(in.memoryLimit) +
                                           " (--max-memory)");
            }
            auto source = std::make_shared<SegmentSource>();
            source->file = kMaskName;
            source->volumeMask = maskFromArray(view, kMaskName);
            source->volumeMask.geometry = geometry;
            // Anisotropic spacing: cubic voxels, as the CLI reads a file.
            makeVoxelsCubic(*source, call.inputOptions, call.timer, call.interrupter);
            shape = call.segment(std::move(source));
        },
        call.interrupter, call.options.threads, options.progress);

    nlohmann::json input = {{"kind", "array"},
                            {"shape", {view.shape[0], view.shape[1], view.shape[2]}},
                            {"dtype", dtypeName(array.dtype())},
                            {"spacing", {spacing[0], spacing[1], spacing[2]}}};
    addVoxelAspect(input, *shape);
    return call.finish(*shape, input);
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
                           const py::array_t<std::int64_t>& triangleFace,
                           const CallOptions& options) {
    CallRecord call(options);
    auto source = std::make_shared<SegmentSource>();
    source->file = kMeshName;
    source->mesh = meshFromArrays(vertices, faces, triangleFace);
    std::shared_ptr<SegmentedShape> shape;
    runEngineCall(
        [&] {
            {
                Stage stage(call.timer, call.interrupter, "check mesh", false);
                checkSourceMesh(*source);
            }
            shape = call.segment(std::move(source));
        },
        call.interrupter, call.options.threads, options.progress);
    return call.finish(*shape, {{"kind", "mesh"}});
}

py::list segmentOptionList() {
    py::list list;
    for (const SegmentOptionDescription& d : segmentOptionDescriptions()) {
        std::string keyword = d.name.substr(2);
        std::replace(keyword.begin(), keyword.end(), '-', '_');
        py::dict entry;
        entry["name"] = d.name;
        entry["keyword"] = keyword;
        entry["flag"] = d.flag;
        entry["default"] = d.defaultText;
        entry["help"] = d.help;
        list.append(entry);
    }
    return list;
}

std::string withKeywordNames(const std::string& message) {
    static const std::vector<SegmentOptionDescription> options = segmentOptionDescriptions();
    std::string out;
    for (std::size_t i = 0; i < message.size();) {
        const bool starts = message.compare(i, 2, "--") == 0 &&
                            (i == 0 || !std::isalnum(static_cast<unsigned char>(message[i - 1])));
        std::size_t end = i + 2;
        while (starts && end < message.size() &&
               (std::islower(static_cast<unsigned char>(message[end])) || message[end] == '-'))
            ++end;
        const std::string name = message.substr(i, end - i);
        const bool known = starts && std::any_of(options.begin(), options.end(),
                                                 [&](const auto& o) { return o.name == name; });
        if (!known) {
            out += message[i++];
            continue;
        }
        std::string keyword = name.substr(2);
        std::replace(keyword.begin(), keyword.end(), '-', '_');
        out += keyword;
        i = end;
    }
    return out;
}

}  // namespace skelseg
