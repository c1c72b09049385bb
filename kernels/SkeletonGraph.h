// skelseg: the simplified skeleton as a graph of junctions and branches
// (docs/algorithm.md §6).
//
// Nodes are the points of C_tau (rho_C >= tau) with 26-adjacency. The
// skeleton is 2-3 voxels thick and junction voxels (J_tau, three or more
// robust rims) come in clusters, so junctions are contracted into regions:
// a region is a 26-connected cluster of J_tau voxels plus the C_tau voxels
// within `regionRadius` steps of it; clusters whose regions touch are one
// junction where their cores are within `junctionMergeRadii` part radii
// (two junctions in contact otherwise). Branches are the 26-connected pieces of C_tau outside the
// regions. Noise can break the skeleton into pieces; gaps of up to `bridgeGap`
// voxels, or up to the radius of the parts around both ends (rho_S / pi)
// where that is larger, between different connected parts of C_tau are
// bridged by one edge (the closest voxel pair, shortest bridges first), which
// the walks and branch pieces then follow. Given the object's voxels, parts
// still apart are then joined through the object (SkeletonGraphOptions).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "kernels/SkeletonMeasures.h"
#include "kernels/base/Interrupter.h"
#include "kernels/base/Volume.h"

namespace skelseg {

constexpr std::uint32_t kNoJunction = 0xFFFFFFFFu;

struct SkeletonJunction {
    std::vector<std::uint32_t> core;    // graph nodes in J_tau
    std::vector<std::uint32_t> region;  // core plus the C_tau nodes around it
    float rhoS = 0.0f;                  // median rho_S over the core
    std::uint32_t representative = 0;   // core node used for reports and RT07 cuts
};

/// Two junctions whose regions touch but whose cores lie too far apart to be
/// one junction (SkeletonGraphOptions::junctionMergeRadii): the body passes
/// from one to the other with no branch between them. `node` and `otherNode`
/// are the touching region nodes of `junction` and `other`.
struct JunctionContact {
    std::uint32_t junction = 0, other = 0;
    std::uint32_t node = 0, otherNode = 0;
};

struct SkeletonGraph {
    /// Index into the SkeletonPoint list of each node (C_tau), voxel order.
    std::vector<std::uint32_t> point;
    std::vector<Coord> coord;
    /// CSR adjacency (26-adjacency plus bridges).
    std::vector<std::uint32_t> offset, neighbour;
    /// Undirected edges (i < j), for output.
    std::vector<std::array<std::uint32_t, 2>> edges;
    std::uint32_t bridgeCount = 0;
    /// Of those, the bridges joined along the object (joinGroupsAlongObject).
    std::uint32_t bridgesAlongObject = 0;
    std::vector<SkeletonJunction> junctions;
    /// Junction whose region holds each node, or kNoJunction.
    std::vector<std::uint32_t> junctionOf;
    /// Branch piece of each node outside regions (kNoJunction inside regions).
    std::vector<std::uint32_t> pieceOf;
    std::uint32_t pieceCount = 0;
    /// Junctions whose regions touch but stay apart, each pair once.
    std::vector<JunctionContact> junctionContacts;

    std::uint32_t nodeCount() const noexcept { return std::uint32_t(point.size()); }
};

struct SkeletonGraphOptions {
    double tau = 0.0;
    int regionRadius = 3;
    /// Smallest reach of a bridge in voxels; 0 turns bridging off.
    double bridgeGap = 4.0;
    /// The object's voxels (same dims), or null. When given, parts of the
    /// object's skeleton still apart after the bridges within reach are
    /// joined too, each by its closest node pair whose straight segment stays
    /// inside the object (shortest first, a spanning forest): the skeleton
    /// of a connected object is connected, and a piece left floating is a
    /// limb whose skeleton broke near its base, whatever the gap's length.
    const MaskVolume* inside = nullptr;
    /// A node where three or more branches of C_tau leave a ball of twice
    /// the part's radius (loopRadius(rho_S)), with no J_tau point within one
    /// radius, is a junction core too (a fork): where many parts meet in a
    /// small place (an octopus's mouth) a point's few feature points rarely
    /// fall on three of them, so J_tau there comes and goes with the
    /// resolution, while the skeleton's branching does not
    /// (docs/algorithm.md §6, "Forks").
    bool forkJunctions = true;
    /// A junction's region also takes the start of a piece that carries two
    /// or more branches, up to where they separate (at most one part radius
    /// out): a fork within that radius of a J_tau point is left to the
    /// junction, so the junction's region must separate its branches
    /// (docs/algorithm.md §6, "A region reaches its branches' split").
    bool growRegionsToSplits = true;
    /// Two junction clusters whose regions touch are one junction only when
    /// their cores are within this many part radii (loopRadius of the
    /// larger cluster's rho_S) of each other; farther apart they stay two
    /// junctions in contact (SkeletonGraph::junctionContacts). The regions'
    /// `regionRadius` steps are a count of voxels, so whether two regions
    /// touch depends on the resolution; the cores' distance in part radii
    /// does not (docs/algorithm.md §6, "Junctions apart by their radii").
    /// 0 or less: every touching pair is one junction.
    double junctionMergeRadii = 0.8;
    /// false: the fork tests run on the calling thread (each node's test
    /// writes only its own flag, so the graph is the same either way).
    bool threaded = true;
};

/// The graph of C_tau (points with rho_C >= options.tau), its junctions,
/// forks and bridges.
/// @throw InterruptedError when `interrupter` asks to stop (polled between
/// the fork tests, which on a sheet of C_tau cost the square of its size).
SkeletonGraph buildSkeletonGraph(const std::vector<SkeletonPoint>& points, const Dims& dims,
                                 const SkeletonGraphOptions& options,
                                 Interrupter& interrupter = nullInterrupter());

/// The branches of junction `junction` of `g`: the pieces (pieceOf) of the
/// nodes next to its region, each once, in the order the region first
/// touches them.
std::vector<std::uint32_t> junctionBranches(const SkeletonGraph& g, std::uint32_t junction);

}  // namespace skelseg
