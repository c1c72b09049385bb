// skelseg: the functions of the extension module _skelseg.
//
// Module.cpp registers them; the package's __init__.py wraps them in the
// public, documented API (keyword arguments, result classes, warnings). The
// functions here take already-checked plain arguments and return plain
// Python objects (dicts of numpy arrays), which pickle, so results travel
// between Dask workers as they are.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/SegmentCommand.h"

namespace skelseg {

/// What every segmentation call takes: the options of `skelseg segment`
/// (parsed from the keywords by parseSegmentOptions(), engine/SegmentOptions.h)
/// and the progress callback.
struct CallOptions {
    SegmentCommandOptions command;
    pybind11::object progress;  // callable(stage, fraction) or None
};

/// Segments a 3-D array (any dtype numpy can give as bool, int, uint or
/// float; any strides). Returns {"labels", "skeleton", "cuts", "report",
/// "warnings", "levels"}; labels has the array's shape (Fortran order, axis 0 = x).
pybind11::dict segmentArray(const pybind11::array& mask, const std::array<double, 3>& spacing,
                            const CallOptions& options);

/// Voxelises and segments a triangle mesh given as arrays, as the CLI does
/// a mesh file (resolution, self-overlap clearance, contact patch seams and
/// the time budget from options.command): vertices (V, 3) float64, faces
/// (F, 3) int64 triangles, triangleFace (F,) the input face of each triangle
/// or empty (each triangle is a face). Returns the same keys as segmentArray
/// plus "face_labels" (int32, one per input face).
pybind11::dict segmentMeshArrays(const pybind11::array_t<double>& vertices,
                                 const pybind11::array_t<std::int64_t>& faces,
                                 const pybind11::array_t<std::int64_t>& triangleFace,
                                 const CallOptions& options);

/// Every option of `skelseg segment` as parseSegmentOptions() takes it: a
/// list of {"name": "--sigma-min", "keyword": "sigma_min", "flag": bool,
/// "default": text, "help": text}.
pybind11::list segmentOptionList();

/// `message` with the command line's option names (--max-memory) written as
/// the module's keywords (max_memory), for the module's exceptions.
std::string withKeywordNames(const std::string& message);

/// Reads a volume file's mask as a bool array, axis 0 = x (Fortran order),
/// and its voxel spacing. Returns (array, spacing, origin). maxMemory: a
/// --max-memory text, empty for the CLI's default; the grid's mask must fit
/// in it, and an OpenVDB parse may take no more. timeLimitSeconds: 0 for
/// none. The read runs as the engine's calls do (EngineCall.h): Ctrl-C and
/// the time limit stop an OpenVDB parse; the other readers finish first.
pybind11::tuple readVolumeArray(const std::string& path, const std::string& gridName,
                                const std::string& maxMemory, double timeLimitSeconds);

/// Reads a mesh file: (vertices (V, 3) float64, triangles (T, 3) int64,
/// triangle_face (T,) int64, face_count).
pybind11::tuple readMeshArrays(const std::string& path);

/// Reads a .seg or .seg.gz file: one int64 label per face.
pybind11::array_t<std::int64_t> readSegArray(const std::string& path);

/// Area of every input face; arguments as segmentMeshArrays.
pybind11::array_t<double> faceAreaArray(const pybind11::array_t<double>& vertices,
                                        const pybind11::array_t<std::int64_t>& faces,
                                        const pybind11::array_t<std::int64_t>& triangleFace);

/// Princeton benchmark measures of `labels` against each of `humans` and
/// their mean: {"mean": {...}, "per_human": [{...}, ...]}. faceAreas: None
/// (every face counts once) or one weight per face (weighted as the CLI's
/// `skelseg score`: Rand Index by faces, Hamming by area).
pybind11::dict scoreLabels(const pybind11::array_t<std::int64_t>& labels,
                           const pybind11::list& humans, const pybind11::object& faceAreas);

/// The consensus of a pose sequence's face labels (engine/SequenceConsensus.h):
/// {"reference", "modal_parts", "parts", "voted", "mean_error_to_others",
///  "pair_errors" (frames x frames), "mean_pair_error"}. `trusted`: per
/// frame, or empty for every frame (chooseSequenceConsensus).
pybind11::dict sequenceConsensusOf(const pybind11::list& frames, const std::vector<bool>& trusted);

}  // namespace skelseg
