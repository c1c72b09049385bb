#include "kernels/CubicVoxels.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

#include "kernels/base/ParallelFor.h"

namespace skelseg {

namespace {

/// floor((2 * index + 1) * to / (2 * from)): the cell of the other grid that
/// holds the centre of cell `index`, when an axis of `from` cells is split
/// into `to` cells. Integer arithmetic, so that the two directions are exact
/// inverses (CubicVoxels.h).
int cellHoldingCentre(std::int64_t index, std::int64_t from, std::int64_t to) noexcept {
    const std::int64_t cell = ((2 * index + 1) * to) / (2 * from);
    return int(std::clamp<std::int64_t>(cell, 0, to - 1));
}

}  // namespace

std::array<double, 3> voxelSteps(const VolumeGeometry& geometry) {
    std::array<double, 3> steps{};
    for (int a = 0; a < 3; ++a) {
        const auto& d = geometry.directions[std::size_t(a)];
        steps[std::size_t(a)] = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
    return steps;
}

bool hasAnisotropicVoxels(const VolumeGeometry& geometry) {
    const auto steps = voxelSteps(geometry);
    const auto [shortest, longest] = std::minmax_element(steps.begin(), steps.end());
    return *longest > *shortest * (1.0 + kCubicVoxelTolerance);
}

std::array<int, 3> CubicGrid::inputVoxelOf(const std::array<int, 3>& v) const noexcept {
    const std::array<std::int64_t, 3> input{inputDims.x, inputDims.y, inputDims.z};
    std::array<int, 3> result{};
    for (std::size_t a = 0; a < 3; ++a) result[a] = cellHoldingCentre(v[a], dims[a], input[a]);
    return result;
}

std::array<int, 3> CubicGrid::cubicVoxelOf(const std::array<int, 3>& v) const noexcept {
    const std::array<std::int64_t, 3> input{inputDims.x, inputDims.y, inputDims.z};
    std::array<int, 3> result{};
    for (std::size_t a = 0; a < 3; ++a) result[a] = cellHoldingCentre(v[a], input[a], dims[a]);
    return result;
}

CubicGrid cubicGridFor(const Dims& dims, const VolumeGeometry& geometry) {
    CubicGrid grid;
    grid.inputDims = dims;
    grid.inputGeometry = geometry;
    const auto steps = voxelSteps(geometry);
    const double shortest = *std::min_element(steps.begin(), steps.end());
    const std::array<std::int64_t, 3> input{dims.x, dims.y, dims.z};
    std::array<double, 3> firstCentre{};
    grid.geometry = geometry;
    for (std::size_t a = 0; a < 3; ++a) {
        // Capped far above any grid Dims::checked accepts, so that a step a
        // billion times the shortest cannot overflow the rounding.
        const double voxels = std::min(double(input[a]) * steps[a] / shortest, 1e15);
        grid.dims[a] = std::max<std::int64_t>(input[a], std::llround(voxels));
        grid.scale[a] = double(grid.dims[a]) / double(input[a]);
        // The centre of cubic voxel 0, in input indices: half a cubic voxel
        // past the input grid's first cell boundary.
        firstCentre[a] = 0.5 / grid.scale[a] - 0.5;
        for (double& c : grid.geometry.directions[a]) c /= grid.scale[a];
    }
    grid.geometry.origin = geometry.indexToWorld(firstCentre[0], firstCentre[1], firstCentre[2]);
    return grid;
}

namespace {

/// Each voxel of a `dims` grid takes the value of the voxel `sourceOf(v)`
/// of `source`. The map is separable (each axis by itself), so a row's
/// source row is found once and its x columns once for the whole grid.
template <typename T, typename SourceOf>
Volume<T> gatherVoxels(const Volume<T>& source, const Dims& dims, const SourceOf& sourceOf,
                       bool threaded, Interrupter& interrupter) {
    Volume<T> out(dims, T());
    std::vector<int> sourceX(std::size_t(dims.x));
    for (int x = 0; x < dims.x; ++x) sourceX[std::size_t(x)] = sourceOf({x, 0, 0})[0];
    std::atomic<bool> stop{false};
    parallelForEach(
        dims.z,
        [&](int z) {
            if (stop.load(std::memory_order_relaxed)) return;
            if (interrupter.wasInterrupted()) {
                stop = true;
                return;
            }
            for (int y = 0; y < dims.y; ++y) {
                const auto row = sourceOf({0, y, z});
                const T* from = &source(0, row[1], row[2]);
                T* to = &out(0, y, z);
                for (int x = 0; x < dims.x; ++x) to[x] = from[sourceX[std::size_t(x)]];
            }
        },
        threaded);
    if (stop) throwInterrupted(interrupter);
    return out;
}

}  // namespace

MaskVolume resampleToCubicVoxels(const MaskVolume& mask, const CubicGrid& grid,
                                 const CubicVoxelOptions& options, Interrupter& interrupter) {
    const Dims dims{int(grid.dims[0]), int(grid.dims[1]), int(grid.dims[2])};
    MaskVolume cubic = gatherVoxels(
        mask, dims, [&](const std::array<int, 3>& v) { return grid.inputVoxelOf(v); },
        options.threaded, interrupter);
    cubic.geometry = grid.geometry;
    return cubic;
}

LabelVolume labelsOnInputGrid(const LabelVolume& cubic, const CubicGrid& grid,
                              const CubicVoxelOptions& options, Interrupter& interrupter) {
    LabelVolume labels = gatherVoxels(
        cubic, grid.inputDims, [&](const std::array<int, 3>& v) { return grid.cubicVoxelOf(v); },
        options.threaded, interrupter);
    labels.geometry = grid.inputGeometry;
    return labels;
}

}  // namespace skelseg
