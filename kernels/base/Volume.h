// skelseg: dense voxel volumes, the data layout every kernel works on.
//
// A Volume<T> is a dense nx*ny*nz array, x fastest: index = x + nx*(y + ny*z).
// 32-bit linear indices are used in the hot loops, so a volume holds at most
// kMaxVoxels voxels (checked by the readers and by Dims::checkedVoxelCount).
// VolumeGeometry maps voxel indices to world coordinates and back; readers
// fill it from the file and writers reproduce it, so outputs line up with
// inputs in any viewer.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/base/Error.h"
#include "kernels/base/HugePages.h"

namespace skelseg {

/// Largest number of voxels in one volume: linear indices must fit in uint32
/// with room for an "invalid" marker.
constexpr std::uint64_t kMaxVoxels = 0xFFFFFFF0ull;
/// Largest extent of one axis (documented cap, see docs/formats.md).
constexpr std::int64_t kMaxAxisExtent = 8192;

struct Dims {
    int x = 0, y = 0, z = 0;

    std::uint64_t voxelCount() const noexcept {
        return std::uint64_t(x) * std::uint64_t(y) * std::uint64_t(z);
    }
    bool operator==(const Dims& o) const noexcept { return x == o.x && y == o.y && z == o.z; }
    bool operator!=(const Dims& o) const noexcept { return !(*this == o); }
    /// Throws InputError(file, ...) unless every extent is in [1, kMaxAxisExtent]
    /// and the product is at most kMaxVoxels. Computed without overflow.
    static Dims checked(std::int64_t nx, std::int64_t ny, std::int64_t nz, const std::string& file);
};

/// World placement of a voxel grid: world = origin + directions * (i, j, k),
/// where directions' columns are the world vectors of one step along x, y, z.
struct VolumeGeometry {
    std::array<double, 3> origin{0.0, 0.0, 0.0};
    std::array<std::array<double, 3>, 3> directions{
        {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};  // [axis][component]
    /// Name of the world frame where the input file gives one (NRRD "space"),
    /// empty otherwise; writers repeat it.
    std::string spaceName;

    std::array<double, 3> indexToWorld(double i, double j, double k) const noexcept {
        std::array<double, 3> w = origin;
        for (int c = 0; c < 3; ++c)
            w[c] += directions[0][c] * i + directions[1][c] * j + directions[2][c] * k;
        return w;
    }
    /// Uniform voxel size (length of the x direction); exact for the isotropic
    /// grids skelseg makes, the mean step length otherwise.
    double voxelSize() const noexcept;
    static VolumeGeometry uniform(double voxelSize, std::array<double, 3> origin) noexcept;

    /// Empty when a grid of `dims` voxels placed by this geometry can be
    /// represented in doubles, otherwise the problem as one line for an
    /// InputError. Refused: a voxel step (a direction) that is zero,
    /// subnormal or not finite; steps so close to parallel that a voxel with
    /// unit steps would have a volume under kMinRelativeVoxelStep; a voxel
    /// volume that underflows or overflows doubles; a voxel centre whose world
    /// position is not finite; and world coordinates so large that a voxel
    /// step is below kMinRelativeVoxelStep of their magnitude, where
    /// neighbouring voxels would get nearly the same world coordinates.
    std::string problemOver(const Dims& dims) const;
};

/// Smallest voxel step relative to the largest world coordinate of a grid
/// (2^-40): world positions then keep 12 bits below one voxel step, and
/// neighbouring voxels stay distinct in every output written in doubles.
constexpr double kMinRelativeVoxelStep = 1.0 / 1099511627776.0;

template <typename T>
class Volume {
public:
    using ValueType = T;

    Volume() = default;
    /// Crop-sized volumes get huge pages (HugePages.h): their first touch is
    /// otherwise mostly page faults.
    explicit Volume(Dims dims, T fill = T()) : mDims(dims) {
        assignWithHugePages(mData, std::size_t(dims.voxelCount()), fill);
    }

    const Dims& dims() const noexcept { return mDims; }
    std::size_t size() const noexcept { return mData.size(); }
    bool empty() const noexcept { return mData.empty(); }

    std::size_t index(int x, int y, int z) const noexcept {
        return std::size_t(x) +
               std::size_t(mDims.x) * (std::size_t(y) + std::size_t(mDims.y) * std::size_t(z));
    }
    bool contains(int x, int y, int z) const noexcept {
        return x >= 0 && y >= 0 && z >= 0 && x < mDims.x && y < mDims.y && z < mDims.z;
    }
    T& operator()(int x, int y, int z) noexcept { return mData[index(x, y, z)]; }
    const T& operator()(int x, int y, int z) const noexcept { return mData[index(x, y, z)]; }
    T& operator[](std::size_t i) noexcept { return mData[i]; }
    const T& operator[](std::size_t i) const noexcept { return mData[i]; }

    T* data() noexcept { return mData.data(); }
    const T* data() const noexcept { return mData.data(); }
    std::vector<T>& values() noexcept { return mData; }
    const std::vector<T>& values() const noexcept { return mData; }

    VolumeGeometry geometry;

private:
    Dims mDims;
    std::vector<T> mData;
};

/// Binary object mask: nonzero = object voxel.
using MaskVolume = Volume<std::uint8_t>;
/// Segment labels: 0 = background, 1..K = segments.
using LabelVolume = Volume<std::uint16_t>;

/// Integer voxel coordinate.
struct Coord {
    int x = 0, y = 0, z = 0;
    bool operator==(const Coord& o) const noexcept { return x == o.x && y == o.y && z == o.z; }
};

}  // namespace skelseg
