#include "kernels/base/Volume.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>

namespace skelseg {

namespace {

/// A number for a message: six significant digits.
std::string shortNumber(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

/// True for a finite double of at least the smallest normal magnitude.
bool isNormalMagnitude(double value) noexcept {
    return std::isfinite(value) && std::abs(value) >= DBL_MIN;
}

}  // namespace

Dims Dims::checked(std::int64_t nx, std::int64_t ny, std::int64_t nz, const std::string& file) {
    const std::int64_t extents[3] = {nx, ny, nz};
    for (int a = 0; a < 3; ++a) {
        if (extents[a] < 1)
            throw InputError(file, "grid size " + std::to_string(extents[a]) + " along axis " +
                                       std::to_string(a) + " is not positive");
        if (extents[a] > kMaxAxisExtent)
            throw InputError(file, "grid size " + std::to_string(extents[a]) + " along axis " +
                                       std::to_string(a) + " is over the limit of " +
                                       std::to_string(kMaxAxisExtent));
    }
    const std::uint64_t count = std::uint64_t(nx) * std::uint64_t(ny) * std::uint64_t(nz);
    if (count > kMaxVoxels)
        throw InputError(file, "grid of " + std::to_string(nx) + "x" + std::to_string(ny) + "x" +
                                   std::to_string(nz) + " voxels is over the limit of " +
                                   std::to_string(kMaxVoxels) + " voxels");
    return Dims{int(nx), int(ny), int(nz)};
}

double VolumeGeometry::voxelSize() const noexcept {
    double sum = 0.0;
    for (const auto& d : directions) sum += std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    return sum / 3.0;
}

VolumeGeometry VolumeGeometry::uniform(double voxelSize, std::array<double, 3> origin) noexcept {
    VolumeGeometry g;
    g.origin = origin;
    g.directions = {{{voxelSize, 0, 0}, {0, voxelSize, 0}, {0, 0, voxelSize}}};
    return g;
}

std::string VolumeGeometry::problemOver(const Dims& dims) const {
    std::array<double, 3> length{};
    std::array<std::array<double, 3>, 3> unit{};
    for (int axis = 0; axis < 3; ++axis) {
        const std::string step = "the voxel step along axis " + std::to_string(axis);
        const auto& d = directions[axis];
        length[axis] = std::hypot(d[0], d[1], d[2]);
        if (length[axis] == 0.0) return step + " is zero: the voxels have no volume";
        if (!std::isfinite(length[axis])) return step + " is not finite";
        if (length[axis] < DBL_MIN)
            return step + " (" + shortNumber(length[axis]) +
                   ") is a subnormal number: the voxels have no usable size";
        for (int c = 0; c < 3; ++c) unit[axis][c] = d[c] / length[axis];
    }
    // The volume of a voxel with unit steps: 1 for orthogonal steps, 0 for
    // parallel ones. Apart from the lengths, so that tiny or huge voxels are
    // not taken for flat ones.
    const auto& u = unit;
    const double shape = u[0][0] * (u[1][1] * u[2][2] - u[1][2] * u[2][1]) -
                         u[0][1] * (u[1][0] * u[2][2] - u[1][2] * u[2][0]) +
                         u[0][2] * (u[1][0] * u[2][1] - u[1][1] * u[2][0]);
    if (std::abs(shape) < kMinRelativeVoxelStep)
        return "the voxel steps are parallel or nearly so: the voxels have no volume";
    const double volume = length[0] * length[1] * length[2] * std::abs(shape);
    if (!isNormalMagnitude(volume))
        return "the voxel volume (" + shortNumber(length[0]) + " x " + shortNumber(length[1]) +
               " x " + shortNumber(length[2]) + ") is outside the range of doubles";
    const auto shortest = std::min_element(length.begin(), length.end());
    const int shortestAxis = int(shortest - length.begin());

    double largestCoordinate = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
        const int i = (corner & 1) ? dims.x - 1 : 0;
        const int j = (corner & 2) ? dims.y - 1 : 0;
        const int k = (corner & 4) ? dims.z - 1 : 0;
        const std::array<double, 3> world = indexToWorld(i, j, k);
        for (double coordinate : world) {
            if (!std::isfinite(coordinate))
                return "world coordinates overflow: voxel (" + std::to_string(i) + ", " +
                       std::to_string(j) + ", " + std::to_string(k) +
                       ") lies at a non-finite position";
            largestCoordinate = std::max(largestCoordinate, std::abs(coordinate));
        }
    }
    if (*shortest < kMinRelativeVoxelStep * largestCoordinate)
        return "world coordinates reach " + shortNumber(largestCoordinate) +
               ", where the voxel step along axis " + std::to_string(shortestAxis) + " (" +
               shortNumber(*shortest) +
               ") is below 2^-40 of them: neighbouring voxels would get nearly the same world "
               "coordinates";
    return {};
}

}  // namespace skelseg
