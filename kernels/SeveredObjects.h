// skelseg: a separation in the voxel model must not cut an object in two.
//
// The voxeliser's separations (io/mesh/ContactSeparation.h,
// SelfOverlapSeparation.h) clear groups of voxels to part surfaces that touch
// or cross. Each group is checked in the box around it (its genus must not
// grow, no cavity may appear), but a box cannot tell a seam between a leg and
// the body (still joined through the hip, far outside the box) from a seam
// through a thin limb (the foot is then cut loose). Both split the box; only
// the second splits the whole object.
//
// So after a separation stage, the objects of the whole mask are labelled
// once (kernels/ConnectedObjects.h). Every voxel a group cleared had all its
// 26-neighbours in one object before; a group whose neighbouring object voxels
// now lie in two or more objects is what cut them apart, and it is set back.
// Groups are visited in the order given and the objects a set-back group
// rejoins are merged as they go, so where two groups together cut a ring of
// voxels only the first is set back. The cost is one labelling per stage,
// whatever the number of groups.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

/// One group of voxels a separation set to 0: (x, y, z), 26-connected.
using ClearedGroup = std::vector<std::array<int, 3>>;

struct SeveredObjectsOptions {
    /// false: the labelling runs on the calling thread (same result).
    bool threaded = true;
    /// false: the mask is left as it is and only the groups that would be
    /// set back are reported (a stage that counts its cuts without undoing
    /// them).
    bool setBack = true;
};

/// Sets back to 1 the groups of `cleared` (voxels of `mask` that are now 0)
/// that cut an object of `mask` in two (see above) and returns, per group,
/// whether it was (or, with setBack off, would be) set back.
/// @throw InterruptedError.
std::vector<bool> rejoinSeveredObjects(MaskVolume& mask, const std::vector<ClearedGroup>& cleared,
                                       const SeveredObjectsOptions& options = {},
                                       Interrupter& interrupter = nullInterrupter());

}  // namespace skelseg
