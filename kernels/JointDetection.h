// skelseg: joints inside parts, where the junction rule cannot cut
// (docs/algorithm.md, "Joints").
//
// People also split limbs where no skeleton junction is: at elbows, knees,
// wrists and necks. Along one branch of the simplified skeleton those places
// show as (a) a narrowing: the circumference rho_S has a clear local minimum
// between two wider stretches, or (b) a bend: the branch direction turns
// sharply. Each branch of the SkeletonGraph (a piece between junction
// regions and end points; pieces that meet at a junction with exactly two
// branches, which a sharp bend or a bulge of one limb can make, are one
// branch with that junction's region) becomes a profile along arc length: nodes are ordered by
// their distance inside the piece from one end of it, binned per voxel of
// arc length (the skeleton is 2-3 voxels thick), and each bin gives the
// median rho_S and the mean position. Every length below is in units of the
// local radius r = rho_S / pi (rho_S of a tube is half its circumference),
// so the same thresholds hold at any resolution and pose:
//   smoothing  Gaussian along arc length, width smoothingScale * r;
//   narrowing  a local minimum whose value, divided by the smaller of the
//              medians within sideMedianWindow * r on each side (the limb's
//              typical thickness there, which a flexed neighbouring joint
//              or an unresolved foot changes far less than its widest
//              point), is at most narrowingRatio, with at least
//              minSideLength * r of branch on each side (so end caps, where
//              rho_S falls to the tip, and noise wiggles are not joints);
//              its wider stretches are the maxima within sideWindow * r;
//   bend       a local maximum of the angle between the mean directions over
//              bendWindow * r before and after a point, at least
//              bendAngleDegrees (off by default: kNoBends).
// A candidate becomes a cut at the node with the best sigma within
// snapDistance * r of arc length (the smoothest loop there), when that sigma
// reaches sigmaMin and the node is at least minCutDistance * r away from
// every existing cut and every joint kept before it (narrowings first, the
// deepest first; then bends, the sharpest first), and, for a narrowing, when
// no such cut lies on the branch between its two wider stretches (the side
// maxima): that cut parts them already, and where it sits along a neck
// depends on the pose. Handle loops are never cut.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "kernels/SkeletonGraph.h"
#include "kernels/SkeletonMeasures.h"
#include "kernels/base/Interrupter.h"

namespace skelseg {

enum class JointKind : std::uint8_t { Narrowing, Bend };

/// A bend threshold no branch reaches: bends are off (the default, since a
/// bend exists only while its joint is flexed; docs/algorithm.md §14).
constexpr double kNoBends = 360.0;

struct JointOptions {
    double smoothingScale = 0.5;
    double narrowingRatio = 0.82;
    double sideWindow = 6.0;        // where the wider stretches (the side maxima) are sought
    double sideMedianWindow = 4.0;  // the ratio's reference: the median within this on each side
    double minSideLength = 1.5;
    double bendAngleDegrees = kNoBends;  // 30 is the measured choice when bends are wanted
    double bendWindow = 2.0;
    double minCutDistance = 2.0;
    double snapDistance = 0.5;
    double sigmaMin = 0.8;
    /// Segments of a run with joint cuts merge into a neighbour below this
    /// fraction of tau (the labelling's rule; kept here with the joint options).
    double minSegmentTauFraction = 0.25;
    /// Extrema weaker than these are not even reported as candidates.
    double reportRatio = 0.95;
    double reportAngleDegrees = 20.0;
};

/// One branch as a profile along arc length (samples in arc order).
struct BranchProfile {
    std::vector<double> arc;                      // arc length, voxels, increasing
    std::vector<double> rhoS;                     // circumference measure per sample
    std::vector<std::array<double, 3>> position;  // skeleton position per sample, voxels
};

/// An extremum of a profile: a narrowing (local minimum of rho_S) or a bend
/// (local maximum of the turning angle), with its measures. Only extrema at
/// least as strong as reportRatio / reportAngleDegrees are returned.
struct ProfileJoint {
    JointKind kind = JointKind::Narrowing;
    std::size_t sample = 0;
    double ratio = 1.0;          // smoothed minimum / smaller side median (narrowings)
    double angleDegrees = 0.0;   // turning angle (bends)
    double radius = 0.0;         // local radius at the sample, voxels
    bool passes = false;         // meets the thresholds and the side-length rule
    std::size_t wideBefore = 0;  // narrowings: the samples of the side maxima
    std::size_t wideAfter = 0;
};

/// The profile smoothed as detection sees it (rho_S and positions).
BranchProfile smoothProfile(const BranchProfile& profile, const JointOptions& options);

/// Extrema of one profile, in sample order (narrowings and bends mixed).
std::vector<ProfileJoint> findProfileJoints(const BranchProfile& profile,
                                            const JointOptions& options);

enum class JointStatus : std::uint8_t {
    Cut,             // kept: its loop becomes a cut
    BelowThreshold,  // reported for measurements only
    LowSigma,        // no node near it has sigma >= sigmaMin
    NearCut,         // too close to an existing cut or a stronger joint, or one parts its sides
    Handle,          // on a handle loop
};

struct JointCandidate {
    JointKind kind = JointKind::Narrowing;
    JointStatus status = JointStatus::BelowThreshold;
    std::uint32_t branch = 0;    // see jointBranches()
    std::uint32_t node = 0;      // skeleton graph node (the best-sigma node near the extremum)
    double arc = 0.0;            // arc length from the branch's first end, voxels
    double wideBeforeArc = 0.0;  // narrowings: arc lengths of the two wider stretches
    double wideAfterArc = 0.0;
    double ratio = 1.0;
    double angleDegrees = 0.0;
    double radius = 0.0;
    float sigma = -1.0f;
};

/// The branch of every skeleton graph node (kNoJunction for nodes of
/// junctions with three or more branches); `branchCount` receives the count.
std::vector<std::uint32_t> jointBranches(const SkeletonGraph& graph, std::uint32_t& branchCount);

/// The profile of one branch (nodes with nodeBranch == branch), with each
/// node's arc length (-1 for nodes of other branches) through `nodeArc`.
BranchProfile branchProfile(const SkeletonGraph& graph, const std::vector<SkeletonPoint>& points,
                            const std::vector<std::uint32_t>& nodeBranch, std::uint32_t branch,
                            std::vector<double>* nodeArc = nullptr);

/// Every reported candidate of every branch, in branch then sample order; those
/// with status Cut are the joint cuts. `existingCuts` are skeleton graph
/// nodes already cut (the junction rule's). Polls `interrupter` per piece.
std::vector<JointCandidate> detectJoints(const SkeletonGraph& graph,
                                         const std::vector<SkeletonPoint>& points,
                                         const std::vector<std::uint32_t>& existingCuts,
                                         const JointOptions& options,
                                         Interrupter& interrupter = nullInterrupter());

}  // namespace skelseg
