// skelseg: exact Euclidean feature transform (docs/algorithm.md §2).
//
// For every voxel, the linear index of a nearest "site" voxel (for skelseg:
// a boundary voxel) in exact Euclidean distance. Separable algorithm: one
// pass per axis, each pass computing the lower envelope of parabolas along
// every grid line (Felzenszwalb & Huttenlocher 2012; the feature-propagating
// form of Maurer et al. 2003). O(voxels) work, every line independent.
//
// Determinism: ties are resolved by the envelope construction, which depends
// only on the line's data, never on scheduling: any thread count gives the
// same result.
#pragma once

#include <cstdint>

#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// Marker for "no site anywhere in the volume".
constexpr std::uint32_t kNoFeature = 0xFFFFFFFFu;

struct FeatureTransformOptions {
    /// false runs every pass serially (identical output; for debugging and
    /// the determinism tests).
    bool threaded = true;
};

/// Returns FT with FT[i] = linear index of a site nearest to voxel i, or
/// kNoFeature when `sites` has no nonzero voxel. `sites` nonzero = site.
/// Throws InterruptedError when the interrupter asks to stop.
Volume<std::uint32_t> featureTransform(const MaskVolume& sites,
                                       const FeatureTransformOptions& options = {},
                                       Interrupter& interrupter = nullInterrupter());

/// Squared Euclidean distance between two voxels given by linear index.
inline std::int64_t squaredDistance(const Dims& dims, std::uint32_t a, std::uint32_t b) noexcept {
    const std::int64_t nx = dims.x, ny = dims.y;
    const std::int64_t ax = a % nx, ay = (a / nx) % ny, az = a / (nx * ny);
    const std::int64_t bx = b % nx, by = (b / nx) % ny, bz = b / (nx * ny);
    return (ax - bx) * (ax - bx) + (ay - by) * (ay - by) + (az - bz) * (az - bz);
}

}  // namespace skelseg
