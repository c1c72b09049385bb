// skelseg: the boundary graph (docs/algorithm.md §1).
//
// Nodes are the boundary voxels of an object: object voxels with at least one
// face (6-)neighbour in the background; everything outside the grid counts as
// background. Edges join 26-adjacent boundary voxels, weighted by the
// Euclidean step length (1, sqrt 2, sqrt 3). Shortest paths on this graph
// stand in for surface geodesics. Stored as CSR with 32-bit ids; node ids are
// assigned brick by brick (8^3 voxel bricks in z, y, x order, voxels inside
// a brick in z, y, x order) for memory locality, so the graph is identical
// for any thread count.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "kernels/base/Interrupter.h"
#include "kernels/base/UninitialisedStorage.h"
#include "kernels/base/Volume.h"

namespace skelseg {

constexpr std::uint32_t kNoNode = 0xFFFFFFFFu;

struct BoundaryGraph {
    Dims dims;
    /// Linear voxel index of each node.
    std::vector<std::uint32_t> voxel;
    /// Voxel coordinates of each node (x, y, z).
    std::vector<Coord> coord;
    /// CSR adjacency: neighbours of node n are neighbour[offset[n] .. offset[n+1]).
    std::vector<std::uint32_t> offset;
    std::vector<std::uint32_t> neighbour;
    /// Euclidean length of each CSR edge.
    std::vector<float> weight;
    /// Node id of every voxel of the grid (kNoNode for non-boundary voxels).
    /// Grid-sized, so it is allocated unwritten and each slab of the
    /// numbering pass writes its own part (UninitialisedStorage.h).
    UninitialisedVector<std::uint32_t> nodeOfVoxel;
    /// Connected component (of the graph) of each node, numbered from 0 in
    /// order of smallest node id, and each component's node count.
    std::vector<std::uint32_t> component;
    std::vector<std::uint32_t> componentSize;

    std::uint32_t nodeCount() const noexcept { return std::uint32_t(voxel.size()); }
    std::size_t edgeCount() const noexcept { return neighbour.size(); }
    float euclidean(std::uint32_t a, std::uint32_t b) const noexcept {
        const float dx = float(coord[a].x - coord[b].x), dy = float(coord[a].y - coord[b].y),
                    dz = float(coord[a].z - coord[b].z);
        return std::sqrt(dx * dx + dy * dy + dz * dz);
    }
};

struct BoundaryGraphOptions {
    bool threaded = true;
};

/// Boundary voxels of `mask` as a mask volume (1 = boundary voxel).
MaskVolume boundaryVoxels(const MaskVolume& mask, const BoundaryGraphOptions& options = {});

/// The number of boundary voxels of `mask`, without a volume for them: what
/// the memory estimate of the outputs' surfaces needs (engine/SegmentInput.h).
std::uint64_t countBoundaryVoxels(const MaskVolume& mask, const BoundaryGraphOptions& options = {});

/// Builds the boundary graph of all objects in `mask` (nonzero = object).
/// Throws InterruptedError when asked to stop.
BoundaryGraph buildBoundaryGraph(const MaskVolume& mask, const BoundaryGraphOptions& options = {},
                                 Interrupter& interrupter = nullInterrupter());

}  // namespace skelseg
