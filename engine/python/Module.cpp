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
// Messages are the engine's one-line what(), as the CLI prints them, with
// the CLI's option names written as the keywords (--max-memory: max_memory).
#include <pybind11/stl.h>

#include "engine/SegmentOptions.h"
#include "engine/Version.h"
#include "engine/python/Bindings.h"
#include "engine/python/EngineCall.h"
#include "kernels/base/Error.h"

namespace py = pybind11;
using namespace skelseg;

namespace {

/// Raises `type` with the engine's message. A file name may hold bytes that
/// are not UTF-8 (`read_volume(b"caf\xe9.nrrd")`); PyErr_SetString decodes
/// strictly, and such a message became a ValueError without any text. They
/// are shown as \xe9, as Python's own messages show undecodable bytes.
void raise(PyObject* type, const char* what) {
    const std::string message = withKeywordNames(what);
    PyObject* text =
        PyUnicode_DecodeUTF8(message.data(), Py_ssize_t(message.size()), "backslashreplace");
    if (text == nullptr) return;  // the decoding error is raised instead
    PyErr_SetObject(type, text);
    Py_DECREF(text);
}

void translateEngineErrors(std::exception_ptr error) {
    try {
        if (error) std::rethrow_exception(error);
    } catch (const InterruptedError& e) {
        raise(e.reason() == InterruptedError::Reason::TimeLimit ? PyExc_TimeoutError
                                                                : PyExc_KeyboardInterrupt,
              e.what());
    } catch (const MemoryLimitError& e) {
        raise(PyExc_MemoryError, e.what());
    } catch (const InputError& e) {
        raise(PyExc_ValueError, e.what());
    } catch (const UsageError& e) {
        raise(PyExc_ValueError, e.what());
    } catch (const OutputError& e) {
        raise(PyExc_OSError, e.what());
    } catch (const Error& e) {
        raise(PyExc_RuntimeError, e.what());
    }
}

CallOptions callOptions(const std::vector<std::string>& arguments, py::object progress) {
    CallOptions options;
    options.command = parseSegmentOptions(arguments);
    options.progress = std::move(progress);
    return options;
}

}  // namespace

PYBIND11_MODULE(_skelseg, m) {
    m.doc() = "skelseg's engine; use the package skelseg, which documents this API.";
    m.attr("version") = versionString();
    py::register_exception_translator(&translateEngineErrors);
    // Daemon threads may be inside the engine when the program ends.
    py::module_::import("atexit").attr("register")(py::cpp_function(&stopEngineCallsForExit));

    m.def(
        "segment_array",
        [](const py::array& mask, std::array<double, 3> spacing,
           const std::vector<std::string>& arguments, py::object progress) {
            return segmentArray(mask, spacing, callOptions(arguments, std::move(progress)));
        },
        py::arg("mask"), py::arg("spacing"), py::arg("arguments"), py::arg("progress"));
    m.def(
        "segment_mesh",
        [](const py::array_t<double>& vertices, const py::array_t<std::int64_t>& faces,
           const py::array_t<std::int64_t>& triangleFace, const std::vector<std::string>& arguments,
           py::object progress) {
            return segmentMeshArrays(vertices, faces, triangleFace,
                                     callOptions(arguments, std::move(progress)));
        },
        py::arg("vertices"), py::arg("faces"), py::arg("triangle_face"), py::arg("arguments"),
        py::arg("progress"));
    m.def("segment_options", &segmentOptionList);
    m.def("read_volume", &readVolumeArray, py::arg("path"), py::arg("grid"), py::arg("max_memory"),
          py::arg("time_limit"));
    m.def("read_mesh", &readMeshArrays, py::arg("path"));
    m.def("read_seg", &readSegArray, py::arg("path"));
    m.def("face_areas", &faceAreaArray, py::arg("vertices"), py::arg("faces"),
          py::arg("triangle_face"));
    m.def("score", &scoreLabels, py::arg("labels"), py::arg("humans"), py::arg("face_areas"));
    m.def("sequence_consensus", &sequenceConsensusOf, py::arg("frames"), py::arg("trusted"));
}
