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

#include <array>
#include <cstdint>
#include <functional>
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

// Fragments: where a closed mesh's piece is thinner than a voxel across a
// whole section (a claw, a whisker, the tip of a tail), the voxel model
// breaks there, and the part beyond is an object of its own: one more
// segment at this resolution or pose, none at the next (held-out cats and
// lion at 192: 1500 to 2400 voxels beside 650,000). Only a mesh can tell
// such an object from a shape of its own: the voxeliser records which piece
// of the mesh each object voxelises (ObjectSource), and an object that is
// not the largest of its piece, and whose boundary area is below the area
// a part of that piece needs (tau of the piece's largest object: it could
// be no part of it), is a fragment. Fragments are treated as islands: no
// segment, label 0, and the mesh's faces there take the label of the
// nearest part. A larger object broken off a piece (a limb beyond a neck
// thinner than a voxel) stays an object of its own, as before.

/// The mesh piece a voxel object comes from, named by one of its voxels.
struct ObjectSource {
    std::array<int, 3> voxel{};  // any voxel of the object
    std::uint32_t piece = 0;     // the mesh piece most of its surface voxels are nearest to
};

struct Fragments {
    /// Per object id: 1 when the object is a fragment.
    std::vector<std::uint8_t> isFragment;
    std::uint64_t count = 0;
    std::uint64_t voxels = 0;
};

/// The fragments among the objects of `found` not marked in `skip` (the
/// islands): per piece of `sources`, the objects other than the one of the
/// largest boundary area (ties: the lower id) whose area is below
/// `partArea(largest area)`. Objects no source names are never fragments.
Fragments findFragments(const ConnectedObjects& found,
                        const std::vector<std::uint64_t>& boundaryAreas,
                        const std::vector<ObjectSource>& sources,
                        const std::vector<std::uint8_t>& skip,
                        const std::function<double(double)>& partArea);

}  // namespace skelseg
