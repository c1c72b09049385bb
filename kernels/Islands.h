// skelseg: islands, the objects of a volume too small to be parts (issue 12).
//
// A voxelised mesh can hold, beside the shape, objects of a few voxels: where
// a part of the mesh is thinner than a voxel (the ears of elephantgallop at
// resolution 192), only the voxels whose centres happen to fall inside it are
// solid, and they scatter into islands of 1 to 10 voxels. Segmented as
// objects of their own, each island would be one more segment and, for a
// mesh, take the faces around it.
//
// The rule: an object is an island when its boundary area (its 6-boundary
// voxels, the nodes its boundary graph would have) is below `noiseArea`, which
// the engine sets to the noise area of the largest object: the area below
// which a component cut off by a skeleton loop counts as noise inside that
// object (SkeletonMeasures.h). A piece the shape itself would ignore as
// surface noise is no part either. The largest object (by boundary area; ties
// to the lower id) is never an island, so a volume always keeps its shape.
// Islands get no segment: their voxels keep label 0, and a mesh's faces near
// them take the label of the nearest real part (FaceLabels.h, steps 2 and 4).
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/ConnectedObjects.h"
#include "kernels/base/Volume.h"

namespace skelseg {

struct IslandOptions {
    bool threaded = true;
};

/// Boundary area of every object of `objects` (found in `mask`): the number
/// of its voxels with a face neighbour in the background or outside the grid.
/// Indexed by object id. Identical for any thread count.
std::vector<std::uint64_t> objectBoundaryAreas(const MaskVolume& mask,
                                               const ConnectedObjects& objects,
                                               const IslandOptions& options = {});

/// The object with the largest boundary area (ties: the lower id); 0 for an
/// empty list.
std::uint32_t largestObject(const std::vector<std::uint64_t>& boundaryAreas);

struct Islands {
    /// Per object id: 1 when the object is an island.
    std::vector<std::uint8_t> isIsland;
    std::uint64_t count = 0;
    std::uint64_t voxels = 0;  // object voxels of all islands together
};

/// Marks every object whose boundary area is below `noiseArea` as an island,
/// except the largest object.
Islands findIslands(const std::vector<ObjectExtent>& objects,
                    const std::vector<std::uint64_t>& boundaryAreas, double noiseArea);

}  // namespace skelseg
