// read_volume(), read_mesh(), read_seg(), face areas, score() and
// sequence_consensus(): the engine's readers, the benchmark measures and a
// pose sequence's consensus on numpy arrays.
#include <pybind11/stl.h>

#include <cmath>

#include "engine/SegmentOptions.h"
#include "engine/SegmentationScore.h"
#include "engine/SequenceConsensus.h"
#include "engine/python/Bindings.h"
#include "engine/python/CallerPolledInterrupter.h"
#include "engine/python/EngineCall.h"
#include "engine/python/ResultArrays.h"
#include "io/mesh/MeshIO.h"
#include "io/mesh/SegFile.h"
#include "io/volume/VolumeReader.h"

namespace py = pybind11;

namespace skelseg {

namespace {

TriangleMesh meshForAreas(const py::array_t<double>& vertices,
                          const py::array_t<std::int64_t>& faces,
                          const py::array_t<std::int64_t>& triangleFace) {
    if (vertices.ndim() != 2 || vertices.shape(1) != 3 || faces.ndim() != 2 || faces.shape(1) != 3)
        throw UsageError("face areas: vertices must be (V, 3) and faces (F, 3)");
    const auto v = vertices.unchecked<2>();
    const auto f = faces.unchecked<2>();
    TriangleMesh mesh;
    for (py::ssize_t i = 0; i < v.shape(0); ++i)
        mesh.vertices.push_back({v(i, 0), v(i, 1), v(i, 2)});
    for (py::ssize_t t = 0; t < f.shape(0); ++t) {
        std::array<std::uint32_t, 3> triangle{};
        for (int c = 0; c < 3; ++c) {
            if (f(t, c) < 0 || f(t, c) >= v.shape(0))
                throw UsageError("face areas: face " + std::to_string(t) + " uses vertex " +
                                 std::to_string(f(t, c)) + " of " + std::to_string(v.shape(0)));
            triangle[c] = std::uint32_t(f(t, c));
        }
        mesh.triangles.push_back(triangle);
    }
    if (triangleFace.size() == 0) {
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
            mesh.triangleFace.push_back(std::uint32_t(t));
    } else {
        if (triangleFace.ndim() != 1 || triangleFace.shape(0) != f.shape(0))
            throw UsageError("face areas: triangle_face must have one entry per row of faces");
        const auto tf = triangleFace.unchecked<1>();
        for (py::ssize_t t = 0; t < tf.shape(0); ++t) {
            if (tf(t) < 0 || tf(t) > std::int64_t(mesh.triangles.size()))
                throw UsageError("face areas: triangle_face " + std::to_string(tf(t)) +
                                 " is out of range");
            mesh.triangleFace.push_back(std::uint32_t(tf(t)));
        }
    }
    std::uint32_t faceCount = 0;
    for (std::uint32_t face : mesh.triangleFace) faceCount = std::max(faceCount, face + 1);
    mesh.faceCount = faceCount;
    return mesh;
}

std::vector<std::int64_t> labelVector(const py::array_t<std::int64_t>& labels, const char* what) {
    if (labels.ndim() != 1) throw UsageError(std::string(what) + " must be a 1-D array of labels");
    const auto view = labels.unchecked<1>();
    std::vector<std::int64_t> values(std::size_t(view.shape(0)));
    for (py::ssize_t i = 0; i < view.shape(0); ++i) values[std::size_t(i)] = view(i);
    return values;
}

py::dict scoreDict(const PartitionScore& score) {
    py::dict d;
    d["rand_index_error"] = score.randIndexError;
    d["hamming_distance"] = score.hammingDistance;
    d["missing_rate"] = score.missingRate;
    d["false_alarm_rate"] = score.falseAlarmRate;
    return d;
}

}  // namespace

py::tuple readVolumeArray(const std::string& path, const std::string& gridName,
                          const std::string& maxMemory, double timeLimitSeconds) {
    if (!(timeLimitSeconds >= 0) || !std::isfinite(timeLimitSeconds))
        throw UsageError("--time-limit must be a positive number of seconds");
    const std::uint64_t memoryLimit =
        maxMemory.empty() ? defaultMemoryLimit() : parseMemoryLimit(maxMemory);
    CallerPolledInterrupter interrupter(timeLimitSeconds);
    VolumeReadOptions options;
    options.gridName = gridName;
    // What the mask alone needs: reading is all this call does.
    options.guards.checkGrid = [&](const Dims& dims) {
        if (dims.voxelCount() > memoryLimit)
            throw MemoryLimitError(
                path + ": its grid of " + std::to_string(dims.x) + " x " + std::to_string(dims.y) +
                " x " + std::to_string(dims.z) + " voxels needs " + formatBytes(dims.voxelCount()) +
                ", over the limit of " + formatBytes(memoryLimit) + " (--max-memory)");
    };
    options.guards.memoryLimit = memoryLimit;
    options.guards.interrupter = &interrupter;
    MaskVolume mask;
    runEngineCall(
        [&] {
            mask = readVolume(path, options);
            // numpy's bool must be 0 or 1.
            for (std::uint8_t& value : mask.values()) value = value != 0;
        },
        interrupter, 0, py::none());
    const Dims d = mask.dims();
    const VolumeGeometry geometry = mask.geometry;
    py::tuple spacing(3);
    for (int a = 0; a < 3; ++a) {
        const auto& step = geometry.directions[a];
        spacing[a] = std::sqrt(step[0] * step[0] + step[1] * step[1] + step[2] * step[2]);
    }
    py::tuple origin = py::make_tuple(geometry.origin[0], geometry.origin[1], geometry.origin[2]);
    py::array_t<std::uint8_t> bytes =
        arrayOwning(std::move(mask.values()), {d.x, d.y, d.z}, {1, d.x, py::ssize_t(d.x) * d.y});
    return py::make_tuple(bytes.attr("view")("bool"), spacing, origin);
}

py::tuple readMeshArrays(const std::string& path) {
    TriangleMesh mesh;
    {
        py::gil_scoped_release release;
        mesh = readMesh(path);
    }
    const auto vertexCount = py::ssize_t(mesh.vertices.size());
    const auto triangleCount = py::ssize_t(mesh.triangles.size());
    std::vector<double> vertices;
    vertices.reserve(mesh.vertices.size() * 3);
    for (const auto& v : mesh.vertices) vertices.insert(vertices.end(), v.begin(), v.end());
    std::vector<std::int64_t> triangles, triangleFace;
    triangles.reserve(mesh.triangles.size() * 3);
    for (const auto& t : mesh.triangles) triangles.insert(triangles.end(), t.begin(), t.end());
    triangleFace.assign(mesh.triangleFace.begin(), mesh.triangleFace.end());
    return py::make_tuple(arrayOwning(std::move(vertices), {vertexCount, 3}),
                          arrayOwning(std::move(triangles), {triangleCount, 3}),
                          arrayOwning(std::move(triangleFace), {triangleCount}), mesh.faceCount);
}

py::array_t<std::int64_t> readSegArray(const std::string& path) {
    std::vector<std::int64_t> labels = readSeg(path);
    const auto count = py::ssize_t(labels.size());
    return arrayOwning(std::move(labels), {count});
}

py::array_t<double> faceAreaArray(const py::array_t<double>& vertices,
                                  const py::array_t<std::int64_t>& faces,
                                  const py::array_t<std::int64_t>& triangleFace) {
    std::vector<double> areas = faceAreas(meshForAreas(vertices, faces, triangleFace));
    const auto count = py::ssize_t(areas.size());
    return arrayOwning(std::move(areas), {count});
}

py::dict scoreLabels(const py::array_t<std::int64_t>& labels, const py::list& humans,
                     const py::object& faceAreas) {
    const std::vector<std::int64_t> candidate = labelVector(labels, "labels");
    std::vector<std::vector<std::int64_t>> references;
    for (const auto& human : humans)
        references.push_back(labelVector(human.cast<py::array_t<std::int64_t>>(), "human_labels"));
    std::vector<double> areas;
    const bool weighted = !faceAreas.is_none();
    if (weighted) {
        const auto array = faceAreas.cast<py::array_t<double>>();
        if (array.ndim() != 1) throw UsageError("face_areas must be a 1-D array");
        const auto view = array.unchecked<1>();
        for (py::ssize_t i = 0; i < view.shape(0); ++i) areas.push_back(view(i));
    }
    const ScoreSummary summary =
        scoreAgainstHumans(candidate, references, weighted ? &areas : nullptr,
                           weighted ? ScoreWeighting::Benchmark : ScoreWeighting::Faces);
    py::list perHuman;
    for (const auto& s : summary.perHuman) perHuman.append(scoreDict(s));
    py::dict out = scoreDict(summary.mean);
    out["per_human"] = perHuman;
    return out;
}

py::dict sequenceConsensusOf(const py::list& frames, const std::vector<bool>& trusted) {
    std::vector<std::vector<std::int64_t>> labels;
    for (const auto& frame : frames)
        labels.push_back(labelVector(frame.cast<py::array_t<std::int64_t>>(), "frame_labels"));
    const SequenceConsensus c = chooseSequenceConsensus(labels, trusted);
    const auto n = py::ssize_t(labels.size());
    py::dict out;
    out["reference"] = c.reference;
    out["modal_parts"] = c.modalParts;
    out["parts"] = c.parts;
    out["voted"] = c.voted;
    out["mean_error_to_others"] = c.meanErrorToOthers;
    out["pair_errors"] = arrayOwning(std::vector<double>(c.pairErrors), {n, n});
    out["mean_pair_error"] = c.meanPairError;
    return out;
}

}  // namespace skelseg
