// skelseg: step 7 of contact separation (ContactSeparation.h), the seams of
// ContactSeparationOptions::patchSeams (--contact-patch-seams, off by
// default). A contact kept by the box check is usually one whose pairs were
// missed at its rim, so its seam stops short and punches a hole (an ear lying
// on a head).
// The pairs found still tell the two surfaces apart: their triangles are split
// into the contact's two sides by a vote (triangles within patchGrowth of each
// other along the mesh count for one side, the two triangles of a pair for
// two, so a few links across a crease are outvoted; a contact with over a
// tenth of its pairs on one side is left), and each side is grown along the
// mesh by patchGrowth into a patch, which reaches the rim the pairs missed.
// For every object voxel within patchReach of both patches, f = (depth in side
// 0's solid) - (depth in side 1's), signed distances to each patch, is 0 on
// the middle surface between them and changes by at most 2 sqrt(3) between
// 26-neighbours; so clearing the voxels with |f| <= 2 sqrt(3) on one side
// parts the two sides wherever both patches are near, however the voxels'
// nearest triangles fall. Voxels inside both solids are left (a crease where
// the surfaces join: there the middle surface runs through the solid). Tried
// in turn: into the side with more such voxels (a head rather than the thin
// ear lying on it), into the other, and |f| <= sqrt(3) on both sides. The box
// check cannot judge it (a whole contact closes the loop outside any box), so
// a seam is kept only where the whole model's genus drops and no object or
// cavity is added (kernels/VoxelGenus.h): one whole-model count per seam
// tried, and none once the genus is 0.
#pragma once

#include <cstdint>
#include <mutex>
#include <utility>
#include <vector>

#include "io/mesh/ContactSeparation.h"
#include "io/mesh/ContactSurfaceGraph.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// The seams of step 7 for one contact kept: its triangles are split into the
/// contact's two sides, each side grown along the mesh into a patch, and the
/// object voxels near both patches are placed by their signed distances to
/// the two patches (see above). Keeps references to `graph` and `mask`;
/// seams() reads the mask as it is when called.
class PatchSeamFinder {
public:
    PatchSeamFinder(const SurfaceGraph& graph, const MaskVolume& mask,
                    const ContactSeparationOptions& options);

    /// Up to three seams (voxel indices) in the order to try: into the side
    /// with more voxels near both patches (a head rather than the thin ear
    /// lying on it), into the other, half into each; none where the sides
    /// cannot be told apart (a piece not oriented, or over a tenth of the
    /// pairs with both triangles on one side).
    std::vector<std::vector<std::uint32_t>> seams(
        const std::vector<std::pair<std::int32_t, std::int32_t>>& pairs,
        const std::vector<std::uint32_t>& voxels) const;

private:
    /// The triangles within mGrowth along the mesh of the contact's
    /// triangles, each with its side (0, 1). Seeds joined along the mesh
    /// within mGrowth tend to one side, the two triangles of a pair to two.
    bool sidesOf(const std::vector<std::pair<std::int32_t, std::int32_t>>& pairs,
                 std::vector<std::pair<std::uint32_t, int>>& patch) const;
    /// The triangles with corner v (built on first use).
    const std::vector<std::uint32_t>& trianglesAt(std::uint32_t v) const;
    /// Signed distance of p to triangle t: positive inside the solid.
    double signedDistance(std::uint32_t t, const vec3::Vec3& p) const;
    /// The seams of seams(), from the patch's triangles and sides.
    std::vector<std::vector<std::uint32_t>> seamsAround(
        const std::vector<std::pair<std::uint32_t, int>>& patch,
        const std::vector<std::uint32_t>& voxels) const;

    const SurfaceGraph& mGraph;
    const MaskVolume& mMask;
    double mGrowth, mReach;
    mutable std::once_flag mIncidenceBuilt;
    mutable std::vector<std::vector<std::uint32_t>> mIncidence;
};

}  // namespace skelseg
