// skelseg: placing the part cuts (docs/algorithm.md §8; the RT07 baseline
// of §10).
//
// For every junction, walk out along each branch leaving its region. A
// "point" of the 2-3 voxel thick skeleton is one BFS level from the region;
// its sigma is the best sigma on that level. The candidate is the best point
// of the first level that starts a run of `consecutiveLevels` levels with
// sigma >= sigmaMin (a single high level in a corner fan is not enough).
// Where no run reaches sigmaMin, a run just below it (limbSigmaMargin) gives a
// candidate when the loops keep their length over one limb radius (a tube,
// not a block or a panel whose loops round its edges) on a branch that ends
// free; such a candidate that reads body is dropped unless a free-ending
// candidate at sigmaMin reads alike (a twin prong). A free branch with no
// run at all (a limb of about tau, whose C_tau holds only its base) gives
// its best level as such a candidate when the piece past that loop or past
// the branch's last loop reaches stubReach loop sizes (stubLimbs).
// Candidates whose circumference rho_S is similar to the junction's (body
// test) lie on the body and are dropped; a candidate's circumference is the
// smallest rho_S of the tight levels (sigma >= sigmaMin) from the candidate
// to one body radius further out (rho_S(j) / pi levels; past the last tight
// loop as long as the body's, which still goes round the body), because the first
// tight levels past a junction still wrap the part's base, whose loop is
// about as long as the body's (docs/algorithm.md §8.6, "limb circumference"); the body's
// circumference is the largest of the junction's rho_S and every candidate's first tight loop and
// limb circumference. A branch that reaches another junction without a run of tight levels is a
// passage, body too: it counts in the sibling test and, beside two body candidates, in the next
// rule, where it pushes off the body only candidates carrying less surface than itself. When more
// than two are similar, only the one carrying the most surface (largest exact rho_C) is dropped,
// ties broken by voxel index. A junction with one branch is where the body ends: it cuts nothing on
// a branch that reaches another junction, which judges that branch. Each remaining candidate's cut
// moves to the first tight level of that window whose loop is closer to the limb's circumference
// than to the body's (a loop as long as the body's still wraps the body); a cut past which the
// skeleton ends within half the loop's radius, and whose piece stays within the ball its loop spans
// (where the caller measures it), is a corner of a flat end and is dropped (isCornerOfTheBody,
// pieceReach); the loops Gamma of the remaining points are the cuts.
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
    /// too (then the "more than two" rule decides). Wider than the spread of
    /// one limb's measure between resolutions, so two alike limbs get one
    /// answer; narrower than the gap to a thinner branch beside a body passing
    /// through, so the body is not cut there (both bounds: docs/algorithm.md §8.6).
    double siblingTolerance = 0.25;
    /// The sibling must be alike both ways: within siblingTolerance of the
    /// thinner body member and that member within siblingTolerance of it
    /// (off: any candidate above (1 - siblingTolerance) times the thinner
    /// member is pulled in; docs/algorithm.md §8.6, "Siblings").
    bool siblingsBothWays = true;
    /// A cut moves further out along the limb while its loop still shrinks
    /// by more than this fraction over the next loop diameter (a limb's own
    /// taper is less; a skirt lying on a thigh shrinks faster).
    double limbTaper = 0.3;
    /// A cut past which the branch's skeleton ends within this many loop
    /// radii takes a corner of a flat end, not a limb (isCornerOfTheBody).
    double cornerLength = 0.5;
    /// ... and, where the caller measures the piece past the cut (placeCuts'
    /// pieceReach), only if the piece stays within this many times the
    /// loop's own size from the loop's centre: a corner is a cap inside the
    /// ball its loop spans, a fin or a limb sticks out of it
    /// (pieceReachPastLoop; docs/algorithm.md §8.6).
    double cornerReach = 1.16;
    /// A branch that reaches another junction without a run of tight levels
    /// is body at this junction: it counts in the "more than two" rule and
    /// in the sibling test (docs/algorithm.md §8.6, "Passages").
    bool passagesAreBody = true;
    /// Junctions joined through passages share one body reference, the
    /// largest of theirs: the body passes through all of them, and whether
    /// two junction regions a few voxels apart touch (one junction) or not
    /// (two, joined by a passage) depends on the resolution
    /// (docs/algorithm.md §8.6, "One body reference across passages").
    bool shareBodyAcrossPassages = true;
    /// Where no run reaches sigmaMin, a branch may give a candidate from a
    /// run of levels within limbSigmaMargin below it (the digitisation
    /// spread of a thin limb's sigma), but only where the loops are a
    /// tube's: the coefficient of variation of rho_S over one limb radius
    /// from the candidate is at most limbLoopVariation (a block's or a
    /// panel's loops round its edges and change), on a branch that ends
    /// free (a limb; docs/algorithm.md §8.7).
    bool relaxSigmaMinForLimbs = true;
    double limbSigmaMargin = 0.05;
    double limbLoopVariation = 0.065;
    /// The walk below sigmaMin only finds limbs: a candidate of that walk
    /// whose circumference reads body (similarity >= bodyRatio: a bulge of
    /// the body such as a hump) is dropped, as if the branch gave no
    /// candidate, so it cannot make the "more than two" rule cut the body;
    /// unless a candidate found at sigmaMin on a branch that ends free reads
    /// alike (within siblingTolerance: a tail's twin prongs)
    /// (docs/algorithm.md §8.8).
    bool belowSigmaMinOnlyLimbs = true;
    /// Beside two body candidates, a passage pushes off the body only the
    /// candidates that carry less surface than it (a plier's handles); one
    /// that carries more stays body, the passage being a short way between
    /// junctions inside the body (docs/algorithm.md §8.8).
    bool passageCutsOnlySmallerCandidates = true;
    /// Rule 3 reads a loop round a handle (exact rho_C infinite) as carrying
    /// no area to compare: such a passage pushes nothing off the body and
    /// such a body candidate stays body. For voxel models whose handles are
    /// not the shape's (a closed mesh's model with a higher genus than the
    /// mesh: surfaces that touch or pass through each other stayed joined),
    /// where the infinity is the artefact's; the engine sets it there
    /// (docs/algorithm.md §8.8).
    bool handleLoopsCarryNoArea = false;
    /// A junction with a single branch is where the body ends (a round end
    /// such as a mantle, whose loops fan out): nothing leaves it but that
    /// branch. Where the branch reaches another junction it is the body's
    /// way to the rest of the shape and is judged there, where the body
    /// passes through; the one-branch junction cuts nothing on it
    /// (docs/algorithm.md §8.9).
    bool oneBranchJunctionsEndTheBody = true;
    /// Where the body goes on through a junction (a body candidate or a
    /// passage leads, directly or through junctions where nothing was cut,
    /// to a junction where the plan without this rule cut a limb), a body
    /// candidate whose branch ends (free, or at a junction that leads to no
    /// limb) stays on the body only from this similarity up: a head or
    /// a tail read near bodyRatio is cut in every pose (docs/algorithm.md
    /// §8.14). 0, or anything up to bodyRatio: off.
    double endBodyRatio = 0.75;
    /// ... and only where the piece the candidate's loop cuts off reaches at
    /// least this many times the loop's size from its centre (pieceReach;
    /// a stump of the body's end, such as a hand's wrist, reaches about 1.4).
    double endReach = 1.75;
    /// A cut loop must separate what it cuts off: with every cut's band
    /// removed from the surface, the pieces on its two sides differ. A loop
    /// round a limb that a handle (genus > 0) joins to the rest again, with
    /// no other cut on the handle, cuts nothing off. Such a cut moves to the
    /// first loop further along its walk that separates; where the walk
    /// reaches another junction first, to that junction's one candidate on a
    /// branch that ends free (the limb going on past it); otherwise it is
    /// dropped (docs/algorithm.md §8.10).
    bool separatingCutsOnly = true;
    /// The limb circumference is read over one body radius from the
    /// candidate, and the body is the reference the body test compares with
    /// (the largest of the junction's median rho_S and the loops next to
    /// it), not the junction's median alone: where the median falls on a few
    /// thin core voxels the window would shrink to the run's three levels
    /// and read the limb's base instead of its girth. Junctions of two
    /// branches, where nothing branches off the body, keep their median
    /// (docs/algorithm.md §8.11).
    bool windowFromBodyReference = true;
    /// Every loop length the cut placement reads (the body test's limb
    /// circumference and body reference, the walk's tight levels, passages)
    /// is half the circumference of the surface round the point
    /// (surfaceHalfLoop), not rho_S: rho_S reads a share of it that depends
    /// on the part's radius and angle to the grid, so a limb and a body at
    /// different angles or sizes read a ratio that moves with pose and
    /// resolution (docs/algorithm.md §8.13).
    /// Off by default: at body_ratio 0.6 it moves one shared shape's neck
    /// across the threshold (docs/quality.md, "loops16").
    bool surfaceLoops = false;
    /// The walk's tight levels after the candidate (where the limb
    /// circumference, the cut's border and taper and a separating loop are
    /// read) are only those in a run of consecutiveLevels tight levels, as
    /// the candidate's own: a single level reaching sigmaMin near a branch's
    /// end can be a loop round a thin protrusion (an ear's tip past a head),
    /// a small fraction of the part's girth, which made the part read as thin
    /// as the protrusion and moved its cut there (docs/algorithm.md §8.13,
    /// "loops17").
    bool tightLevelsInRuns = false;
    /// A branch that ends free with no run of tight levels, even below
    /// sigmaMin, is a limb whose area is about tau when the piece past its
    /// best loop, or past the branch's last loop, reaches at least stubReach
    /// times that loop's size from its centre (pieceReach; a corner's piece
    /// is a cap within cornerReach, a stump of the body's end within
    /// endReach): C_tau holds only the limb's base, whose loops still wrap
    /// the body, so no loop there is tight. Its best loop is a candidate of
    /// the walk below sigmaMin (belowSigmaMin; docs/algorithm.md §8.12).
    bool stubLimbs = true;
    double stubReach = 1.75;
    /// ... where the junction's median rho_S is below this fraction of the
    /// body reference: only then does the median lie on thin core voxels
    /// rather than on the body (docs/algorithm.md §8.11).
    double thinJunctionMedian = 0.5;
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
    /// Not on the body, but the skeleton ends right past the cut
    /// (isCornerOfTheBody): a corner of a flat end, not cut.
    bool isCorner = false;
    bool isCut = false;
    /// Found by a run below sigmaMin (relaxSigmaMinForLimbs).
    bool belowSigmaMin = false;
    /// Found by the stub rule (stubLimbs): a limb of about tau with no run of
    /// tight levels, so its sigma is its best loop's, not a run's. Such a
    /// candidate is also belowSigmaMin.
    bool stubLimb = false;
    /// false: the loop first chosen for this cut separated nothing
    /// (separatingCutsOnly); the cut then moved (movedToSeparate) or was
    /// dropped (isCut false).
    bool loopSeparates = true;
    bool movedToSeparate = false;
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

/// Whether a cut at BFS level `cutLevel` of a branch whose skeleton ends at
/// level `skeletonEnd` (kNoJunction: the branch reaches another junction)
/// takes a corner of the body rather than a limb: the skeleton goes on past
/// the cut for less than `cornerLength` loop radii (rho_S / pi). The skeleton
/// of a flat end forks into the end's corners, and a loop round one corner
/// prong, next to the prong's end, passes sigma and the body test like a
/// limb's; a limb's skeleton reaches on past its border (docs/algorithm.md
/// §8.6, "Corners of flat ends are not limbs").
bool isCornerOfTheBody(std::uint32_t cutLevel, std::uint32_t skeletonEnd, float cutRhoS,
                       double cornerLength);

/// The body test of one junction's candidates (baseRhoS and limbRhoS filled):
/// sets bodyRhoS (the largest of the junction's rho_S and every candidate's
/// baseRhoS and limbRhoS), similarity (limbRhoS against bodyRhoS) and onBody,
/// before the "more than two" rule. passageRhoS: the circumference of each
/// branch of the junction that is a passage to another junction (body with
/// no candidate); it counts among the body candidates of the sibling test.
/// bodyFloor: a lower bound of bodyRhoS (the body reference of the junctions
/// joined to this one through passages, CutOptions::shareBodyAcrossPassages).
void markBodyCandidates(float junctionRhoS, const CutOptions& options, CutCandidate* candidates,
                        std::size_t count, const std::vector<float>& passageRhoS = {},
                        float bodyFloor = 0.0f);

/// Whether the loops of a set of cuts (their SkeletonPoint indices) each
/// separate the surface with all of them cut: one entry per cut, 1 or 0
/// (separatingLoops in kernels/SurfaceLabelling.h).
using LoopSeparation = std::function<std::vector<std::uint8_t>(const std::vector<std::uint32_t>&)>;

/// pieceReach(cutNode, junction): how far the piece that the loop of skeleton
/// graph node `cutNode` cuts off, on the side away from junction `junction`
/// (an index into graph.junctions), reaches from the loop's centre, over the
/// loop's own size (pieceReachPastLoop, CutPieceReach.h). Only asked for the
/// cuts the skeleton's levels take for corners (isCornerOfTheBody); a reach
/// of cornerReach or more makes such a cut a cut again.
using PieceReach = std::function<double(std::uint32_t cutNode, std::uint32_t junction)>;

/// exactRhoC(pointIndex) returns the exact rho_C of a SkeletonPoint (only
/// called for the "more than two qualify" rule). loopsSeparate answers for
/// separatingCutsOnly; empty, or with the rule off, every loop is taken to
/// separate. Without pieceReach the corner rule reads only the skeleton's
/// levels past the cut.
CutPlan placeCuts(const SkeletonGraph& graph, const std::vector<SkeletonPoint>& points,
                  const CutOptions& options, const std::function<double(std::uint32_t)>& exactRhoC,
                  const LoopSeparation& loopsSeparate = {}, const PieceReach& pieceReach = {});

}  // namespace skelseg
