#include "kernels/base/Volume.h"

#include <cmath>

namespace skelseg {

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

}  // namespace skelseg
