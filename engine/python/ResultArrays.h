// skelseg: engine results as numpy arrays and Python objects.
//
// Arrays take over the engine's vectors without copying where the layout
// allows (labels: the LabelVolume's own storage, x fastest, seen by numpy in
// Fortran order with the input's shape); the small per-point arrays are
// gathered once. Coordinates are world coordinates of the result's geometry,
// as skeleton.ply and cuts.ply hold them.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>
#include <vector>

#include "engine/Segmenter.h"

namespace skelseg {

/// Moves `values` into a numpy array of `shape` and byte `strides`
/// (empty: C order) that owns them.
template <typename T>
pybind11::array_t<T> arrayOwning(std::vector<T>&& values, std::vector<pybind11::ssize_t> shape,
                                 std::vector<pybind11::ssize_t> strides = {}) {
    auto* owner = new std::vector<T>(std::move(values));
    pybind11::capsule base(owner, [](void* p) { delete static_cast<std::vector<T>*>(p); });
    return strides.empty() ? pybind11::array_t<T>(shape, owner->data(), base)
                           : pybind11::array_t<T>(shape, strides, owner->data(), base);
}

/// The labels as a uint16 array of shape (nx, ny, nz), Fortran order; takes
/// the volume's storage.
pybind11::array_t<std::uint16_t> labelArray(LabelVolume&& labels);

/// {"points" (N, 3) float64, "voxels" (N, 3) int32, "edges" (M, 2) int64,
/// "rho_s" float32, "rho_c" float64 (inf for handle loops), "sigma" float32,
/// "junction" bool, "critical" bool, "object" int32}, all objects' skeletons
/// concatenated in object order (as skeleton.ply).
pybind11::dict skeletonArrays(const SegmentationResult& result);

/// The cut loops as a list of (K, 3) float64 arrays, in object order.
pybind11::list cutArrays(const SegmentationResult& result);

/// A JSON value as plain Python objects (dict, list, int, float, str, None).
pybind11::object jsonToPython(const nlohmann::json& value);

}  // namespace skelseg
