// skelseg: placing the part cuts (docs/algorithm.md §8; the RT07 baseline
// of §10).
//
// For every junction, walk out along each branch leaving its region. A
// "point" of the 2-3 voxel thick skeleton is one BFS level from the region;
// its sigma is the best sigma on that level. The candidate is the best point
// of the first level that starts a run of `consecutiveLevels` levels with
// sigma >= sigmaMin (a single high level in a corner fan is not enough).
// Candidates whose circumference rho_S is similar to the junction's (body
// test) lie on the body and are dropped; a candidate's circumference is the
// smallest rho_S of the tight levels (sigma >= sigmaMin) from the candidate
// to one body radius further out (rho_S(j) / pi levels), because the first
// tight levels past a junction still wrap the part's base, whose loop is
// about as long as the body's (docs/algorithm.md §8.6, "limb circumference"); the body's
// circumference is the largest of the junction's rho_S and every candidate's first tight loop and
// limb circumference. When more than two are similar, only the one carrying the most surface
// (largest exact rho_C) is dropped, ties broken by voxel index. Each remaining candidate's cut
// moves to the first tight level of that window whose loop is closer to the limb's circumference
// than to the body's (a loop as long as the body's still wraps the body); a cut that takes less
// area than a short limb would is a cap or corner of the body and is dropped (isCapOfTheBody);
// the loops Gamma of the remaining points are the cuts.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "kernels/SkeletonGraph.h"
#include "kernels/SkeletonMeasures.h"

namespace skelseg {

enum class CutMode {
    JunctionRule,  // docs/algorithm.md §8 (default)
    Junctions,     // RT07 (§10): the junctions' own path sets are the cuts
};

struct CutOptions {
    double sigmaMin = 0.8;
    double bodyRatio = 0.6;
    int consecutiveLevels = 3;
    /// A candidate below bodyRatio whose limb circumference is within this
    /// fraction of the thinner of two body candidates counts as body-similar
    /// too (then the "more than two" rule decides).
    double siblingTolerance = 0.1;
    /// A cut moves further out along the limb while its loop still shrinks
    /// by more than this fraction over the next loop diameter (a limb's own
    /// taper is less; a skirt lying on a thigh shrinks faster).
    double limbTaper = 0.3;
    /// A cut that takes less area than this many discs of its loop (pi r^2,
    /// r = rho_S / pi) takes a cap or corner of the body, not a limb: between
    /// a hemisphere (2) and a limb one radius long (4).
    double capArea = 3.0;
    CutMode mode = CutMode::JunctionRule;
};

/// One candidate found on a branch (a "critical point").
struct CutCandidate {
    std::uint32_t junction = 0;
    std::uint32_t node = 0;   // skeleton graph node
    std::uint32_t level = 0;  // BFS level from the junction region
    float sigma = 0.0f;
    float similarity = 0.0f;
    float baseRhoS = 0.0f;    // rho_S where sigma first holds (around the part's base)
    float limbRhoS = 0.0f;    // the circumference the body test compared
    float bodyRhoS = 0.0f;    // ... against this body circumference
    double exactRhoC = -1.0;  // filled where the tie rule needed it
    bool onBody = false;
    /// Not on the body, but the loop cuts off less than CutOptions::capArea
    /// discs (isCapOfTheBody): a corner or cap of the body, not cut.
    bool isCap = false;
    bool isCut = false;
};

struct JunctionReport {
    std::uint32_t branches = 0;
    std::uint32_t cuts = 0;
};

struct CutPlan {
    std::vector<CutCandidate> candidates;
    std::vector<JunctionReport> junctions;
    /// Skeleton graph nodes whose Gamma is a cut, deduplicated, ascending.
    std::vector<std::uint32_t> cutNodes;
};

/// How many levels past a candidate the body test looks for the limb's
/// circumference: one body radius (rho_S of a round loop is pi r), at least
/// consecutiveLevels.
std::uint32_t limbCircumferenceLevels(float junctionRhoS, int consecutiveLevels);

/// Whether a cut loop of rho_S `cutRhoS` that cuts off `cutOffArea` (rho_C,
/// in voxel faces) takes a cap or corner of the body rather than a limb: the
/// area is less than `capArea` discs of the loop, pi r^2 with r = rho_S / pi.
/// A hemisphere on the loop is 2 discs, a limb reaching one radius past the
/// cut 4. The skeleton of a flat or oblique end forks into its corners, and
/// a loop round one corner prong passes sigma and the body test like a
/// limb's (docs/algorithm.md §8.6, "Caps and corners are not limbs").
bool isCapOfTheBody(double cutOffArea, float cutRhoS, double capArea);

/// The body test of one junction's candidates (baseRhoS and limbRhoS filled):
/// sets bodyRhoS (the largest of the junction's rho_S and every candidate's
/// baseRhoS and limbRhoS), similarity (limbRhoS against bodyRhoS) and onBody,
/// before the "more than two" rule.
void markBodyCandidates(float junctionRhoS, const CutOptions& options, CutCandidate* candidates,
                        std::size_t count);

/// exactRhoC(pointIndex) returns the exact rho_C of a SkeletonPoint (only
/// called for the "more than two qualify" rule and for cuts whose bounded
/// rho_C cannot tell a cap from a limb).
CutPlan placeCuts(const SkeletonGraph& graph, const std::vector<SkeletonPoint>& points,
                  const CutOptions& options, const std::function<double(std::uint32_t)>& exactRhoC);

}  // namespace skelseg
