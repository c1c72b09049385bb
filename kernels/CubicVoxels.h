// skelseg: a volume of anisotropic voxels resampled to cubic ones, and the
// labels brought back to its own grid.
//
// Every measure of the method counts voxels: rho_S is a loop length in voxel
// steps, sigma a ratio of path lengths on the voxel boundary, tau an area in
// boundary voxels. On a scan whose slices lie 2.5 times farther apart than
// its pixels, a round limb across the slices is an ellipse of aspect 2.5 in
// voxels, and a limb along them is 2.5 times shorter than it is: the parts
// would be those of the shape stretched to cubes. So the engine segments a
// grid of cubic voxels instead and writes the labels on the input's grid
// (docs/formats.md, "Anisotropic voxels").
//
// The cubic grid: the voxel size is the input's shortest step h, and axis a
// gets n'_a = round(n_a * step_a / h) voxels (at least n_a), so that each
// axis is scaled by s_a = n'_a / n_a >= 1 and spans the input's extent
// exactly. A cubic voxel takes the value of the input voxel its centre lies
// in (nearest neighbour). With s_a >= 1 on every axis that is exactly
// invertible: the cubic voxel that contains an input voxel's centre lies in
// that input voxel, so the input mask is the cubic mask sampled at the input
// centres, and every input object voxel finds an object voxel there to take
// its label from.
#pragma once

#include <array>
#include <cstdint>

#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// Voxels whose longest step is at most this much longer than their shortest
/// count as cubic: a step that differs by 1% changes no measure by more than
/// the grid's own digitisation, and headers often round spacings that much.
constexpr double kCubicVoxelTolerance = 0.01;

/// The length of each voxel step (the columns of `geometry.directions`).
std::array<double, 3> voxelSteps(const VolumeGeometry& geometry);

/// Whether the longest step of `geometry` exceeds its shortest by more than
/// kCubicVoxelTolerance.
bool hasAnisotropicVoxels(const VolumeGeometry& geometry);

/// A grid of cubic voxels over an input grid of anisotropic ones.
struct CubicGrid {
    Dims inputDims;
    VolumeGeometry inputGeometry;
    /// Voxels of the cubic grid per axis; as 64-bit numbers, since they may
    /// exceed what a Volume holds (Dims::checked refuses them).
    std::array<std::int64_t, 3> dims{};
    /// n'_a / n_a: cubic voxels per input voxel along each axis (>= 1).
    std::array<double, 3> scale{1.0, 1.0, 1.0};
    /// World placement of the cubic grid: the same world box as the input's,
    /// each step the input's divided by `scale` (its direction kept).
    VolumeGeometry geometry;

    /// The input voxel whose cell holds the centre of cubic voxel `v`
    /// (clamped to the input grid).
    std::array<int, 3> inputVoxelOf(const std::array<int, 3>& v) const noexcept;
    /// The cubic voxel whose cell holds the centre of input voxel `v`.
    std::array<int, 3> cubicVoxelOf(const std::array<int, 3>& v) const noexcept;
    std::uint64_t voxelCount() const noexcept {
        return std::uint64_t(dims[0]) * std::uint64_t(dims[1]) * std::uint64_t(dims[2]);
    }
};

/// The cubic grid over an input grid of `dims` voxels placed by `geometry`.
CubicGrid cubicGridFor(const Dims& dims, const VolumeGeometry& geometry);

struct CubicVoxelOptions {
    bool threaded = true;  // slabs of z in parallel (the same result either way)
};

/// `mask` (on grid.inputDims) resampled to the cubic grid: each cubic voxel
/// the value of the input voxel its centre lies in. `grid.dims` must be
/// valid Dims. @throw InterruptedError.
MaskVolume resampleToCubicVoxels(const MaskVolume& mask, const CubicGrid& grid,
                                 const CubicVoxelOptions& options = {},
                                 Interrupter& interrupter = nullInterrupter());

/// Labels on the input grid: each input voxel takes the label of the cubic
/// voxel that holds its centre. Geometry: grid.inputGeometry.
/// @throw InterruptedError.
LabelVolume labelsOnInputGrid(const LabelVolume& cubic, const CubicGrid& grid,
                              const CubicVoxelOptions& options = {},
                              Interrupter& interrupter = nullInterrupter());

}  // namespace skelseg
