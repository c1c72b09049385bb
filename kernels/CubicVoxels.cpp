#include "kernels/CubicVoxels.h"

#include <algorithm>
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

MaskVolume resampleToCubicVoxels(const MaskVolume& mask, const CubicGrid& grid,
                                 const CubicVoxelOptions& options, Interrupter& interrupter) {
    const Dims out{int(grid.dims[0]), int(grid.dims[1]), int(grid.dims[2])};
    MaskVolume cubic(out, 0);
    cubic.geometry = grid.geometry;
    // The input column of every cubic x, once: the inner loop is then a gather.
    std::vector<int> inputX(std::size_t(out.x));
    for (int x = 0; x < out.x; ++x) inputX[std::size_t(x)] = grid.inputVoxelOf({x, 0, 0})[0];
    parallelForEach(
        out.z,
        [&](int z) {
            if (interrupter.wasInterrupted()) return;
            for (int y = 0; y < out.y; ++y) {
                const auto source = grid.inputVoxelOf({0, y, z});
                const std::uint8_t* row = &mask(0, source[1], source[2]);
                std::uint8_t* target = &cubic(0, y, z);
                for (int x = 0; x < out.x; ++x) target[x] = row[inputX[std::size_t(x)]];
            }
        },
        options.threaded);
    throwIfInterrupted(interrupter);
    return cubic;
}

LabelVolume labelsOnInputGrid(const LabelVolume& cubic, const CubicGrid& grid,
                              const CubicVoxelOptions& options, Interrupter& interrupter) {
    const Dims in = grid.inputDims;
    LabelVolume labels(in, 0);
    labels.geometry = grid.inputGeometry;
    std::vector<int> cubicX(std::size_t(in.x));
    for (int x = 0; x < in.x; ++x) cubicX[std::size_t(x)] = grid.cubicVoxelOf({x, 0, 0})[0];
    parallelForEach(
        in.z,
        [&](int z) {
            if (interrupter.wasInterrupted()) return;
            for (int y = 0; y < in.y; ++y) {
                const auto source = grid.cubicVoxelOf({0, y, z});
                const std::uint16_t* row = &cubic(0, source[1], source[2]);
                std::uint16_t* target = &labels(0, y, z);
                for (int x = 0; x < in.x; ++x) target[x] = row[cubicX[std::size_t(x)]];
            }
        },
        options.threaded);
    throwIfInterrupted(interrupter);
    return labels;
}

}  // namespace skelseg
