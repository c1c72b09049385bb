// skelseg: the extension module _skelseg (the package's __init__.py is the
// documented API; this file registers the bindings and maps the engine's
// exceptions to Python's).
//
//   InputError, UsageError             -> ValueError      (bad input, bad parameter)
//   MemoryLimitError, std::bad_alloc   -> MemoryError
//   InterruptedError (time limit)      -> TimeoutError
//   InterruptedError (user interrupt)  -> KeyboardInterrupt
//   OutputError                        -> OSError
//   any other skelseg::Error           -> RuntimeError
// Messages are the engine's one-line what(), as the CLI prints them.
#include <pybind11/stl.h>

#include "engine/Version.h"
#include "engine/python/Bindings.h"
#include "kernels/base/Error.h"

namespace py = pybind11;
using namespace skelseg;

namespace {

void translateEngineErrors(std::exception_ptr error) {
    try {
        if (error) std::rethrow_exception(error);
    } catch (const InterruptedError& e) {
        PyErr_SetString(e.reason() == InterruptedError::Reason::TimeLimit ? PyExc_TimeoutError
                                                                          : PyExc_KeyboardInterrupt,
                        e.what());
    } catch (const MemoryLimitError& e) {
        PyErr_SetString(PyExc_MemoryError, e.what());
    } catch (const InputError& e) {
        PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const UsageError& e) {
        PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const OutputError& e) {
        PyErr_SetString(PyExc_OSError, e.what());
    } catch (const Error& e) {
        PyErr_SetString(PyExc_RuntimeError, e.what());
    }
}

CallOptions callOptions(std::string tau, double sigmaMin, double bodyRatio, std::string mode,
                        bool joints, int threads, double timeLimit, std::uint64_t maxMemory,
                        py::object progress) {
    CallOptions options;
    options.tau = std::move(tau);
    options.sigmaMin = sigmaMin;
    options.bodyRatio = bodyRatio;
    options.mode = std::move(mode);
    options.joints = joints;
    options.threads = threads;
    options.timeLimitSeconds = timeLimit;
    options.maxMemoryBytes = maxMemory;
    options.progress = std::move(progress);
    return options;
}

}  // namespace

PYBIND11_MODULE(_skelseg, m) {
    m.doc() = "skelseg's engine; use the package skelseg, which documents this API.";
    m.attr("version") = versionString();
    py::register_exception_translator(&translateEngineErrors);

    m.def(
        "segment_array",
        [](const py::array& mask, std::array<double, 3> spacing, std::string tau, double sigmaMin,
           double bodyRatio, std::string mode, bool joints, int threads, double timeLimit,
           std::uint64_t maxMemory, py::object progress) {
            return segmentArray(
                mask, spacing,
                callOptions(std::move(tau), sigmaMin, bodyRatio, std::move(mode), joints, threads,
                            timeLimit, maxMemory, std::move(progress)));
        },
        py::arg("mask"), py::arg("spacing"), py::arg("tau"), py::arg("sigma_min"),
        py::arg("body_ratio"), py::arg("mode"), py::arg("joints"), py::arg("threads"),
        py::arg("time_limit"), py::arg("max_memory"), py::arg("progress"));
    m.def(
        "segment_mesh",
        [](const py::array_t<double>& vertices, const py::array_t<std::int64_t>& faces,
           const py::array_t<std::int64_t>& triangleFace, int resolution, int selfOverlapClearance,
           std::string tau, double sigmaMin, double bodyRatio, std::string mode, bool joints,
           int threads, double timeLimit, std::uint64_t maxMemory, py::object progress) {
            return segmentMeshArrays(
                vertices, faces, triangleFace, resolution, selfOverlapClearance,
                callOptions(std::move(tau), sigmaMin, bodyRatio, std::move(mode), joints, threads,
                            timeLimit, maxMemory, std::move(progress)));
        },
        py::arg("vertices"), py::arg("faces"), py::arg("triangle_face"), py::arg("resolution"),
        py::arg("self_overlap_clearance"), py::arg("tau"), py::arg("sigma_min"),
        py::arg("body_ratio"), py::arg("mode"), py::arg("joints"), py::arg("threads"),
        py::arg("time_limit"), py::arg("max_memory"), py::arg("progress"));
    m.def("read_volume", &readVolumeArray, py::arg("path"), py::arg("grid"));
    m.def("read_mesh", &readMeshArrays, py::arg("path"));
    m.def("read_seg", &readSegArray, py::arg("path"));
    m.def("face_areas", &faceAreaArray, py::arg("vertices"), py::arg("faces"),
          py::arg("triangle_face"));
    m.def("score", &scoreLabels, py::arg("labels"), py::arg("humans"), py::arg("face_areas"));
}
