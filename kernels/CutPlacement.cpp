#include "kernels/CutPlacement.h"

#include "kernels/DisjointSets.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace skelseg {

namespace {

/// One tight level of a branch walk (sigma >= sigmaMin): its best node.
struct TightLevel {
    std::uint32_t node = 0;
    std::uint32_t level = 0;
    float sigma = 0.0f;
    float rhoS = 0.0f;
};

/// Drops the tight levels that lie in no run of `consecutiveLevels`
/// consecutive tight levels: a single level that reaches sigmaMin is not
/// enough to be a loop round the part (§8.2), and near a branch's end the
/// best node of a level can lie on a thin protrusion (an ear past a head),
/// whose loop is a small fraction of the part's.
void keepRuns(std::vector<TightLevel>& tight, int consecutiveLevels) {
    const std::size_t needed = std::size_t(std::max(consecutiveLevels, 1));
    std::vector<TightLevel> kept;
    kept.reserve(tight.size());
    for (std::size_t begin = 0; begin < tight.size();) {
        std::size_t end = begin + 1;
        while (end < tight.size() && tight[end].level == tight[end - 1].level + 1) ++end;
        if (end - begin >= needed)
            kept.insert(kept.end(), tight.begin() + std::ptrdiff_t(begin),
                        tight.begin() + std::ptrdiff_t(end));
        begin = end;
    }
    tight.swap(kept);
}

/// What one branch walk found (walkBranch).
struct BranchWalk {
    /// The candidate node: the best node of the first level of the run of
    /// tight levels; kNoJunction when the branch has no such run.
    std::uint32_t candidate = kNoJunction;
    /// The candidate's BFS level from the junction region and its sigma.
    std::uint32_t level = 0;
    float sigma = 0.0f;
    /// The limb's circumference for the body test: the smallest rho_S of the
    /// tight levels up to windowEnd (limbCircumferenceLevels).
    float limbRhoS = 0.0f;
    /// The tight levels from the candidate to the walk's end (where the cut
    /// may move).
    std::vector<TightLevel> tight;
    /// The last level of the limb circumference window, and the walk's last level.
    std::uint32_t windowEnd = 0;
    std::uint32_t walkEnd = 0;
    /// No other junction's region next to the branch (a limb ends free).
    bool endsFree = true;
    /// Every level's best node, tight or not, in walk order.
    std::vector<TightLevel> levels;
    /// The nodes this walk marked taken.
    std::vector<std::uint32_t> visited;
    /// A branch with no candidate that reaches another junction's region is
    /// a passage: its middle level's best node with the smallest rho_S of its
    /// levels' best nodes (passage.node is kNoJunction otherwise).
    TightLevel passage{kNoJunction, 0, 0.0f, 0.0f};
    /// The first other junction whose region the branch reaches (kNoJunction
    /// where the branch ends free).
    std::uint32_t otherJunction = kNoJunction;
};

/// Walks one branch from junction j's region (the candidate and what the
/// cut placement needs of the branch). `taken` marks nodes already walked
/// from this junction.
BranchWalk walkBranch(const SkeletonGraph& g, const std::vector<SkeletonPoint>& points,
                      std::uint32_t junction, std::uint32_t piece, const CutOptions& options,
                      std::vector<std::uint8_t>& taken) {
    BranchWalk walk;
    std::vector<std::uint32_t> level;
    for (std::uint32_t n : g.junctions[junction].region)
        for (std::uint32_t e = g.offset[n]; e < g.offset[n + 1]; ++e) {
            const std::uint32_t m = g.neighbour[e];
            if (g.pieceOf[m] == piece && !taken[m])
                taken[m] = 1, level.push_back(m), walk.visited.push_back(m);
        }
    std::sort(level.begin(), level.end());
    std::uint32_t runStart = kNoJunction, runLength = 0, runStartLevel = 0;
    float runStartSigma = 0.0f;
    // Once the run is complete (found), the next `extraLevels` levels give
    // the limb's circumference; the walk goes on to the branch's end for the
    // tight levels where the cut may settle (settledLevel).
    bool found = false;
    std::uint32_t lastLevel = 0;
    float limbRhoS = 0.0f;
    std::vector<TightLevel> tight;
    const std::uint32_t extraLevels =
        limbCircumferenceLevels(g.junctions[junction].rhoS, options.consecutiveLevels);
    std::uint32_t depth = 1;
    bool endsFree = true;  // no other junction's region next to the branch
    for (; !level.empty(); ++depth) {
        // Best sigma on this level; ties by lowest node id (levels are sorted).
        std::uint32_t bestNode = level.front();
        float best = -1.0f;
        for (std::uint32_t n : level) {
            const float s = points[g.point[n]].sigma;
            if (s > best) best = s, bestNode = n;
        }
        const bool isTight = best >= float(options.sigmaMin);
        const float rhoS = points[g.point[bestNode]].rhoS;
        walk.levels.push_back({bestNode, depth, best, rhoS});
        if (found) {
            if (isTight) {
                if (depth <= lastLevel) limbRhoS = std::min(limbRhoS, rhoS);
                tight.push_back({bestNode, depth, best, rhoS});
            }
        } else if (isTight) {
            if (runLength == 0) {
                runStart = bestNode, runStartLevel = depth, runStartSigma = best;
                limbRhoS = rhoS;
                tight.clear();
            } else {
                limbRhoS = std::min(limbRhoS, rhoS);
            }
            tight.push_back({bestNode, depth, best, rhoS});
            if (++runLength >= std::uint32_t(options.consecutiveLevels)) {
                found = true;
                lastLevel = runStartLevel + extraLevels;
            }
        } else {
            runLength = 0;
        }
        std::vector<std::uint32_t> next;
        for (std::uint32_t n : level)
            for (std::uint32_t e = g.offset[n]; e < g.offset[n + 1]; ++e) {
                const std::uint32_t m = g.neighbour[e];
                if (g.junctionOf[m] != kNoJunction && g.junctionOf[m] != junction) {
                    endsFree = false;
                    if (walk.otherJunction == kNoJunction) walk.otherJunction = g.junctionOf[m];
                }
                if (g.pieceOf[m] == piece && !taken[m])
                    taken[m] = 1, next.push_back(m), walk.visited.push_back(m);
            }
        std::sort(next.begin(), next.end());
        level.swap(next);
    }
    if (!found) {
        if (!endsFree && !walk.levels.empty()) {
            walk.passage = walk.levels[walk.levels.size() / 2];
            for (const TightLevel& t : walk.levels)
                walk.passage.rhoS = std::min(walk.passage.rhoS, t.rhoS);
        }
        return walk;
    }
    walk.candidate = runStart;
    walk.level = runStartLevel;
    walk.sigma = runStartSigma;
    if (options.tightLevelsInRuns) {
        keepRuns(tight, options.consecutiveLevels);
        // The candidate's own run is kept, so tight is not empty.
        limbRhoS = tight.front().rhoS;
        for (const TightLevel& t : tight)
            if (t.level <= lastLevel) limbRhoS = std::min(limbRhoS, t.rhoS);
    }
    walk.limbRhoS = limbRhoS;
    walk.tight = std::move(tight);
    walk.windowEnd = lastLevel;
    walk.walkEnd = depth - 1;
    walk.endsFree = endsFree;
    return walk;
}

/// From tight level `start` on, the first tight level whose loop no longer
/// shrinks by more than `taper` over the next loop diameter (2 rho_S / pi
/// levels, at least `minLevels`): no tight loop in that reach is shorter
/// than (1 - taper) times its own. `start` itself when the walk ends before
/// a level can be judged (a limb that keeps tapering to its end).
std::size_t settledLevel(const std::vector<TightLevel>& tight, std::size_t start,
                         std::uint32_t walkEnd, double taper, int minLevels) {
    for (std::size_t i = start; i < tight.size(); ++i) {
        const std::uint32_t reach = std::max<std::uint32_t>(
            std::uint32_t(std::max(minLevels, 1)),
            std::uint32_t(std::ceil(2.0 * loopRadius(std::max(0.0, double(tight[i].rhoS))))));
        if (tight[i].level + reach > walkEnd) return start;
        float ahead = tight[i].rhoS;
        for (std::size_t k = i + 1; k < tight.size() && tight[k].level <= tight[i].level + reach;
             ++k)
            ahead = std::min(ahead, tight[k].rhoS);
        if (double(ahead) >= (1.0 - taper) * double(tight[i].rhoS)) return i;
    }
    return start;
}

/// How much the loop's length varies over one limb radius from `level`
/// (levels up to walkEnd): the coefficient of variation of the levels'
/// rho_S (standard deviation over mean; 0 for a straight tube).
double loopVariation(const std::vector<TightLevel>& levels, std::uint32_t level,
                     std::uint32_t walkEnd, float limbRhoS, int consecutiveLevels) {
    const std::uint32_t reach = std::max<std::uint32_t>(
        std::uint32_t(std::max(consecutiveLevels, 1)),
        std::uint32_t(std::ceil(loopRadius(std::max(0.0, double(limbRhoS))))));
    double sum = 0.0, sumSquares = 0.0;
    std::size_t count = 0;
    for (const TightLevel& t : levels)
        if (t.level >= level && t.level <= std::min(walkEnd, level + reach))
            sum += double(t.rhoS), sumSquares += double(t.rhoS) * double(t.rhoS), ++count;
    if (count < 2 || sum <= 0.0) return 0.0;
    const double mean = sum / double(count);
    return std::sqrt(std::max(0.0, sumSquares / double(count) - mean * mean)) / mean;
}

/// The body reference shared by junctions joined through passages: the
/// largest of their own references (bodyOf) over each group.
std::vector<float> sharedBodyReference(
    const std::vector<float>& bodyOf,
    const std::vector<std::pair<std::uint32_t, std::uint32_t>>& passageLinks) {
    DisjointSets groups(std::uint32_t(bodyOf.size()));
    for (const auto& [a, b] : passageLinks) groups.unite(a, b);
    std::vector<float> group(bodyOf.size(), 0.0f);
    for (std::uint32_t i = 0; i < bodyOf.size(); ++i) {
        float& largest = group[groups.find(i)];
        largest = std::max(largest, bodyOf[i]);
    }
    std::vector<float> shared(bodyOf.size());
    for (std::uint32_t i = 0; i < bodyOf.size(); ++i) shared[i] = group[groups.find(i)];
    return shared;
}

/// The rule of CutOptions::separatingCutsOnly. The loops of all cuts are
/// judged together (loopsSeparate, by SkeletonPoint index); a cut whose loop
/// separates nothing moves to the first tight level further along its walk
/// whose loop separates with the other cuts in place; where its walk reached
/// another junction without one, to the first such level of that junction's
/// one candidate that was not cut and lies on a branch that ends free (the
/// limb goes on past that junction: a handle joins it to the rest before
/// there, so no loop before the junction can cut it off); otherwise the cut
/// is dropped. Moving or dropping a cut can change what the others separate,
/// so the test repeats until every cut separates (each round moves a cut
/// outwards or drops one, so it ends). Per candidate: its tight levels, its
/// skeleton's end (kNoJunction: at another junction) and the junction its
/// walk reached.
void moveToSeparatingLoops(const SkeletonGraph& g, std::vector<CutCandidate>& candidates,
                           const std::vector<std::vector<TightLevel>>& tightOf,
                           const std::vector<std::uint32_t>& skeletonEndOf,
                           const std::vector<std::uint32_t>& otherJunctionOf,
                           const LoopSeparation& loopsSeparate) {
    std::vector<std::uint8_t> wasCut(candidates.size());
    for (std::size_t i = 0; i < candidates.size(); ++i) wasCut[i] = candidates[i].isCut ? 1 : 0;
    for (std::size_t round = 0; round <= candidates.size(); ++round) {
        std::vector<std::size_t> cuts;
        std::vector<std::uint32_t> loops;
        for (std::size_t i = 0; i < candidates.size(); ++i)
            if (candidates[i].isCut)
                cuts.push_back(i), loops.push_back(g.point[candidates[i].node]);
        const std::vector<std::uint8_t> separates = loopsSeparate(loops);
        std::size_t at = 0;
        while (at < cuts.size() && separates[at]) ++at;
        if (at == cuts.size()) return;
        const std::size_t i = cuts[at];
        CutCandidate& c = candidates[i];
        c.loopSeparates = false;
        // The first level of `tight` past `afterLevel` whose loop separates
        // with the other cuts in place.
        const auto firstSeparating = [&](const std::vector<TightLevel>& tight,
                                         std::uint32_t afterLevel) -> const TightLevel* {
            for (const TightLevel& t : tight) {
                if (t.level <= afterLevel) continue;
                loops[at] = g.point[t.node];
                if (loopsSeparate(loops)[at]) return &t;
            }
            return nullptr;
        };
        const TightLevel* to = firstSeparating(tightOf[i], c.level);
        if (!to && otherJunctionOf[i] != kNoJunction) {
            std::size_t limb = candidates.size(), freeCount = 0;
            for (std::size_t k = 0; k < candidates.size(); ++k)
                if (candidates[k].junction == otherJunctionOf[i] && !wasCut[k] &&
                    skeletonEndOf[k] != kNoJunction)
                    limb = k, ++freeCount;
            if (freeCount == 1) to = firstSeparating(tightOf[limb], 0);
        }
        if (!to) {
            c.isCut = false;
            continue;
        }
        c.movedToSeparate = true;
        c.exactRhoC = -1.0;
        c.node = to->node, c.level = to->level, c.sigma = to->sigma;
    }
}

}  // namespace

void markBodyCandidates(float junctionRhoS, const CutOptions& options, CutCandidate* candidates,
                        std::size_t count, const std::vector<float>& passageRhoS, float bodyFloor) {
    // The body passes through the junction, so the junction's loops are at
    // least as long as the body's; a tight loop next to the junction longer
    // than the junction's median rho_S shows that the median fell on a few
    // thin core voxels. bodyFloor: the reference of the junctions joined to
    // this one through passages.
    float body = std::max(junctionRhoS, bodyFloor);
    for (std::size_t i = 0; i < count; ++i)
        body = std::max({body, candidates[i].baseRhoS, candidates[i].limbRhoS});
    for (std::size_t i = 0; i < count; ++i) {
        CutCandidate& c = candidates[i];
        c.bodyRhoS = body;
        c.similarity = body > 0.0f ? 1.0f - std::fabs(body - c.limbRhoS) / body : 0.0f;
        c.onBody = c.similarity >= float(options.bodyRatio);
    }
    // Two candidates about equally thick get the same answer: when the
    // thinner of two body candidates has a sibling below the threshold that
    // is nearly as thick, the threshold cannot tell them apart, and the
    // "more than two" rule decides (placeCuts).
    // A passage to another junction is body as well (placeCuts).
    std::vector<float> body2 = passageRhoS;
    for (std::size_t i = 0; i < count; ++i)
        if (candidates[i].onBody) body2.push_back(candidates[i].limbRhoS);
    if (body2.size() != 2) return;
    const float thinner = std::min(body2[0], body2[1]);
    // Nearly as thick as the thinner member, and (siblingsBothWays) that
    // member nearly as thick as the candidate: a candidate much thicker than
    // the thinner member is no sibling of it (a passage along a limb's
    // forearm, beside the upper arm's candidate, is not its twin).
    const float siblingRatio = float(1.0 - options.siblingTolerance);
    for (std::size_t i = 0; i < count; ++i)
        if (CutCandidate& c = candidates[i];
            !c.onBody && c.limbRhoS >= siblingRatio * thinner &&
            (!options.siblingsBothWays || siblingRatio * c.limbRhoS <= thinner))
            c.onBody = true;
}

bool isCornerOfTheBody(std::uint32_t cutLevel, std::uint32_t skeletonEnd, float cutRhoS,
                       double cornerLength) {
    if (skeletonEnd == kNoJunction) return false;
    return double(skeletonEnd - std::min(skeletonEnd, cutLevel)) <
           cornerLength * loopRadius(std::max(0.0, double(cutRhoS)));
}

std::uint32_t limbCircumferenceLevels(float junctionRhoS, int consecutiveLevels) {
    const double bodyRadius = loopRadius(std::max(0.0, double(junctionRhoS)));
    return std::max<std::uint32_t>(std::uint32_t(std::max(consecutiveLevels, 1)),
                                   std::uint32_t(std::ceil(bodyRadius)));
}

namespace {

/// placeCuts on the loop lengths it is given (points' and junctions' rhoS).
CutPlan placeCutsOn(const SkeletonGraph& g, const std::vector<SkeletonPoint>& points,
                    const CutOptions& options,
                    const std::function<double(std::uint32_t)>& exactRhoC,
                    const LoopSeparation& loopsSeparate, const PieceReach& pieceReach) {
    // Junctions joined by a passage lie on one body (the body passes through
    // both), and whether their regions touch and make one junction depends
    // on the resolution: a first plan measures each junction's body
    // reference (bodyOf) and the passages between junctions; where there are
    // such passages, a second plan decides with the largest reference of the
    // junctions so joined (docs/algorithm.md §8.6).
    std::vector<float> bodyOf(g.junctions.size(), 0.0f);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> passageLinks;
    // Each junction's branches, in piece order.
    std::vector<std::vector<std::uint32_t>> branchesOf(g.junctions.size());
    for (std::uint32_t j = 0; j < g.junctions.size(); ++j) {
        branchesOf[j] = junctionBranches(g, j);
        std::sort(branchesOf[j].begin(), branchesOf[j].end());
    }
    // Per junction, the junctions its uncut branches and passages lead to
    // (the body's ways on) in the last plan made, and in the plan the end
    // rule reads.
    std::vector<std::vector<std::uint32_t>> bodyLinksOf(g.junctions.size()), wayOnOf;
    // limbsLeave: per junction, whether a plan without the end rule cut a
    // limb there (the rule reads it, with wayOnOf); nullptr: the end rule is
    // off.
    const auto planWith = [&](const std::vector<float>& bodyFloor,
                              const std::vector<std::uint8_t>* limbsLeave) {
        CutPlan plan;
        passageLinks.clear();
        for (std::vector<std::uint32_t>& links : bodyLinksOf) links.clear();
        // Per candidate of the plan: its walk's tight levels, where its
        // skeleton ends (kNoJunction: at another junction) and the junction
        // its walk reached (for moveToSeparatingLoops).
        std::vector<std::vector<TightLevel>> tightOfPlan;
        std::vector<std::uint32_t> skeletonEndOfPlan, otherJunctionOfPlan;
        plan.junctions.resize(g.junctions.size());
        for (std::uint32_t j = 0; j < g.junctions.size(); ++j) {
            const SkeletonJunction& junction = g.junctions[j];
            const std::vector<std::uint32_t>& branches = branchesOf[j];
            plan.junctions[j].branches = std::uint32_t(branches.size());

            if (options.mode == CutMode::Junctions) {
                plan.cutNodes.push_back(junction.representative);
                plan.junctions[j].cuts = 1;
                continue;
            }

            std::vector<std::uint8_t> taken(g.nodeCount(), 0);
            const std::size_t first = plan.candidates.size();
            std::vector<std::vector<TightLevel>> tightOf;  // per candidate of this junction
            std::vector<std::uint32_t> walkEndOf, windowEndOf;
            std::vector<std::uint32_t> skeletonEndOf;  // kNoJunction: ends at another junction
            std::vector<std::uint32_t> otherJunctionOf;
            // Branches to another junction with no tight run: the body passes
            // there (too short a walk for the run of levels, counted in voxels).
            std::vector<TightLevel> passages;
            std::vector<float> passageRhoS;
            std::vector<std::uint32_t> passageTo;  // the junction each passage reaches
            for (std::uint32_t piece : branches) {
                BranchWalk walk = walkBranch(g, points, j, piece, options, taken);
                if (walk.candidate == kNoJunction && walk.passage.node != kNoJunction) {
                    if (walk.otherJunction != kNoJunction)
                        passageLinks.emplace_back(j, walk.otherJunction);
                    if (options.passagesAreBody) {
                        passages.push_back(walk.passage);
                        passageRhoS.push_back(walk.passage.rhoS);
                        passageTo.push_back(walk.otherJunction);
                    }
                    continue;
                }
                bool relaxed = false;
                if (walk.candidate == kNoJunction && options.relaxSigmaMinForLimbs) {
                    for (std::uint32_t n : walk.visited) taken[n] = 0;
                    CutOptions below = options;
                    below.sigmaMin = options.sigmaMin - options.limbSigmaMargin;
                    walk = walkBranch(g, points, j, piece, below, taken);
                    // A tube's loops keep their length over a limb radius; a
                    // block's or a panel's change (loops round its edges and
                    // corners), and a panel's sigma straddles sigmaMin too. A
                    // limb ends free; a run next to another junction is that
                    // junction's approach, where the window is cut short.
                    if (walk.candidate != kNoJunction &&
                        (!walk.endsFree ||
                         loopVariation(walk.levels, walk.level, walk.walkEnd, walk.limbRhoS,
                                       options.consecutiveLevels) > options.limbLoopVariation))
                        walk.candidate = kNoJunction;
                    relaxed = walk.candidate != kNoJunction;
                }
                // A limb whose area is about tau shows only its base in C_tau:
                // the branch ends where the piece below falls to tau, before
                // its loops leave the base and become tight. Its piece still
                // reaches far past the loop (a corner's is a cap within it).
                bool stub = false;
                if (walk.candidate == kNoJunction && options.stubLimbs && pieceReach &&
                    walk.otherJunction == kNoJunction && !walk.levels.empty()) {
                    std::size_t best = 0;
                    for (std::size_t k = 1; k < walk.levels.size(); ++k)
                        if (walk.levels[k].sigma > walk.levels[best].sigma) best = k;
                    const TightLevel at = walk.levels[best];
                    // Past the best loop the loops leave the base for the
                    // limb: the piece past the branch's last loop, the
                    // limb's own, may reach out as a part where the best
                    // loop's, still round the base, does not. Only these two
                    // are flooded (each flood costs as much as the piece it
                    // covers, and a body's end has many levels). The cut
                    // stays at the best loop; the move to the limb's border
                    // below reads the levels past it.
                    const TightLevel last = walk.levels.back();
                    const bool reaches =
                        pieceReach(at.node, j) >= options.stubReach ||
                        (last.node != at.node && pieceReach(last.node, j) >= options.stubReach);
                    if (reaches) {
                        walk.candidate = at.node;
                        walk.level = at.level;
                        walk.sigma = at.sigma;
                        walk.tight.assign(walk.levels.begin() + std::ptrdiff_t(best),
                                          walk.levels.end());
                        walk.limbRhoS = at.rhoS;
                        for (const TightLevel& t : walk.tight)
                            walk.limbRhoS = std::min(walk.limbRhoS, t.rhoS);
                        walk.windowEnd = walk.walkEnd = walk.levels.back().level;
                        relaxed = true;
                        stub = true;
                    }
                }
                if (walk.candidate == kNoJunction) continue;
                const std::uint32_t node = walk.candidate;
                tightOf.push_back(std::move(walk.tight));
                walkEndOf.push_back(walk.walkEnd);
                windowEndOf.push_back(walk.windowEnd);
                skeletonEndOf.push_back(walk.endsFree ? walk.walkEnd : kNoJunction);
                otherJunctionOf.push_back(walk.otherJunction);
                CutCandidate c;
                c.junction = j;
                c.node = node;
                c.level = walk.level;
                c.sigma = walk.sigma;
                c.baseRhoS = points[g.point[node]].rhoS;
                c.limbRhoS = walk.limbRhoS;
                c.belowSigmaMin = relaxed;
                c.stubLimb = stub;
                plan.candidates.push_back(c);
            }
            // A junction in contact with another (regions touching, cores
            // too far apart to be one junction) passes the body on to it with
            // no branch between: a passage of no length, at the contact.
            for (const JunctionContact& contact : g.junctionContacts) {
                if (contact.junction != j && contact.other != j) continue;
                const bool mine = contact.junction == j;
                const std::uint32_t node = mine ? contact.node : contact.otherNode;
                const std::uint32_t across = mine ? contact.otherNode : contact.node;
                passageLinks.emplace_back(j, mine ? contact.other : contact.junction);
                if (!options.passagesAreBody) continue;
                const SkeletonPoint& p = points[g.point[node]];
                passages.push_back(
                    {node, 0, p.sigma, std::min(p.rhoS, points[g.point[across]].rhoS)});
                passageRhoS.push_back(passages.back().rhoS);
                passageTo.push_back(mine ? contact.other : contact.junction);
            }
            markBodyCandidates(junction.rhoS, options, plan.candidates.data() + first,
                               plan.candidates.size() - first, passageRhoS, bodyFloor[j]);
            // A tight loop as long as the body's still goes round the body: the
            // limb starts after it, so its window does too (a chest before a
            // waist). The body's reference is the one just measured, not the
            // junction's median, which can fall on thin core voxels.
            // One body radius is the radius of the body the test compares
            // with where the junction's median lies on thin core voxels (well
            // under the body's loops). Where only two branches meet, nothing
            // branches off the body there: the junction's own median keeps
            // setting the window.
            const bool windowFromBody = options.windowFromBodyReference && branches.size() > 2;
            bool windowMoved = false;
            for (std::size_t i = first; i < plan.candidates.size(); ++i) {
                CutCandidate& c = plan.candidates[i];
                const std::vector<TightLevel>& tight = tightOf[i - first];
                const bool thinMedian =
                    windowFromBody &&
                    double(junction.rhoS) < options.thinJunctionMedian * double(c.bodyRhoS);
                const std::uint32_t bodyLevels = limbCircumferenceLevels(
                    thinMedian ? c.bodyRhoS : junction.rhoS, options.consecutiveLevels);
                std::uint32_t windowEnd = windowEndOf[i - first];
                if (thinMedian) windowEnd = std::max(windowEnd, c.level + bodyLevels);
                float limb = c.limbRhoS;
                for (const TightLevel& t : tight) {
                    if (t.level > windowEnd) break;
                    limb = std::min(limb, t.rhoS);
                    if (t.rhoS >= c.bodyRhoS) windowEnd = std::max(windowEnd, t.level + bodyLevels);
                }
                if (limb < c.limbRhoS) c.limbRhoS = limb, windowMoved = true;
            }
            if (windowMoved)
                markBodyCandidates(junction.rhoS, options, plan.candidates.data() + first,
                                   plan.candidates.size() - first, passageRhoS, bodyFloor[j]);
            // The walk below sigma_min is there for thin limbs whose sigma
            // straddles it; a loop there that reads body (a hump on the body)
            // is no limb's border, and counted as body it would make the "more
            // than two" rule cut the body.
            if (options.belowSigmaMinOnlyLimbs) {
                // A limb's twin found at sigma_min (a tail's two prongs) vouches
                // for it: a branch that ends free and reads alike.
                const auto hasFreeTwin = [&](std::size_t i) {
                    const float limb = plan.candidates[i].limbRhoS;
                    for (std::size_t k = first; k < plan.candidates.size(); ++k) {
                        const CutCandidate& t = plan.candidates[k];
                        if (k == i || t.belowSigmaMin || skeletonEndOf[k - first] == kNoJunction)
                            continue;
                        if (std::min(limb, t.limbRhoS) >=
                            float(1.0 - options.siblingTolerance) * std::max(limb, t.limbRhoS))
                            return true;
                    }
                    return false;
                };
                std::vector<std::uint8_t> drop(plan.candidates.size() - first, 0);
                for (std::size_t i = first; i < plan.candidates.size(); ++i) {
                    const CutCandidate& c = plan.candidates[i];
                    drop[i - first] = c.belowSigmaMin && c.similarity >= float(options.bodyRatio) &&
                                      !hasFreeTwin(i);
                }
                std::size_t kept = first;
                for (std::size_t i = first; i < plan.candidates.size(); ++i) {
                    const CutCandidate& c = plan.candidates[i];
                    if (drop[i - first]) continue;
                    if (kept != i) {
                        plan.candidates[kept] = c;
                        tightOf[kept - first] = std::move(tightOf[i - first]);
                        walkEndOf[kept - first] = walkEndOf[i - first];
                        windowEndOf[kept - first] = windowEndOf[i - first];
                        skeletonEndOf[kept - first] = skeletonEndOf[i - first];
                        otherJunctionOf[kept - first] = otherJunctionOf[i - first];
                    }
                    ++kept;
                }
                if (kept != plan.candidates.size()) {
                    plan.candidates.resize(kept);
                    tightOf.resize(kept - first);
                    walkEndOf.resize(kept - first);
                    windowEndOf.resize(kept - first);
                    skeletonEndOf.resize(kept - first);
                    otherJunctionOf.resize(kept - first);
                    markBodyCandidates(junction.rhoS, options, plan.candidates.data() + first,
                                       plan.candidates.size() - first, passageRhoS, bodyFloor[j]);
                }
            }
            bodyOf[j] = std::max(junction.rhoS, bodyFloor[j]);
            for (std::size_t i = first; i < plan.candidates.size(); ++i)
                bodyOf[j] = std::max(bodyOf[j], plan.candidates[i].bodyRhoS);
            // Body passes through a junction at most once: drop at most two.
            // Where two candidates are body, a passage is a third body member:
            // it has no loop to cut, so when it carries the most surface both
            // candidates are cut. A single body candidate beside passages (a
            // plate whose skeleton branches into several junctions) is left
            // alone: passages only stand in for the candidate a longer walk
            // would have given.
            // Where the model's handles are not the shape's, a loop round one
            // (rho_C infinite) has an area only the model gives it: such a
            // candidate stays body and such a passage pushes nothing off it,
            // and rule 3 compares the others.
            const auto roundAnArtefact = [&](std::uint32_t node) {
                return options.handleLoopsCarryNoArea && std::isinf(exactRhoC(g.point[node]));
            };
            std::vector<std::size_t> body;
            for (std::size_t i = first; i < plan.candidates.size(); ++i)
                if (plan.candidates[i].onBody && !roundAnArtefact(plan.candidates[i].node))
                    body.push_back(i);
            std::vector<TightLevel> comparedPassages;
            for (const TightLevel& p : passages)
                if (!roundAnArtefact(p.node)) comparedPassages.push_back(p);
            if (body.size() > 2 || (body.size() == 2 && !comparedPassages.empty())) {
                constexpr std::size_t kPassage = ~std::size_t(0);
                std::size_t keepOnBody = kPassage;
                double bestArea = -std::numeric_limits<double>::infinity();
                std::uint32_t bestVoxel = 0;
                const auto offer = [&](std::uint32_t node, double area, std::size_t index) {
                    const std::uint32_t voxel = points[g.point[node]].voxel;
                    if (area > bestArea || (area == bestArea && voxel < bestVoxel))
                        bestArea = area, bestVoxel = voxel, keepOnBody = index;
                };
                double passageArea = -std::numeric_limits<double>::infinity();
                for (const TightLevel& p : comparedPassages) {
                    const double area = exactRhoC(g.point[p.node]);
                    passageArea = std::max(passageArea, area);
                    offer(p.node, area, kPassage);
                }
                for (std::size_t i : body) {
                    CutCandidate& c = plan.candidates[i];
                    c.exactRhoC = exactRhoC(g.point[c.node]);
                    offer(c.node, c.exactRhoC, i);
                }
                // Beside two body candidates a passage stands in for the
                // candidate its walk was too short to give: it can push off the
                // body a candidate that carries less surface than itself (a
                // plier's handle), never one that carries more (a torso beside
                // a short way between junctions inside the body).
                for (std::size_t i : body)
                    plan.candidates[i].onBody =
                        i == keepOnBody ||
                        (options.passageCutsOnlySmallerCandidates && body.size() == 2 &&
                         plan.candidates[i].exactRhoC > passageArea);
            }
            // Where the body goes on through this junction (a body member
            // or a passage leads to a junction where limbs leave it), a
            // branch that ends here (free, or at a junction where no limb
            // leaves) and reaches past its loop as a part does (a stump a
            // little longer than a corner's cap is the body's own end) stays
            // on the body only when nearly as thick as the body: a head or a
            // tail about 0.6 of the body's girth reads either side of
            // bodyRatio from pose to pose (docs/algorithm.md §8.14). Loops
            // round the model's artefact handles show no way on. It reads
            // what the rule above left on the body: taking a branch off
            // first would leave that rule fewer members to compare (a tail's
            // two prongs beside the way on, one each side of
            // endBodyRatio), and a plan where the rule cannot act (no uncut
            // candidate below endBodyRatio) is not made at all.
            if (limbsLeave) {
                // A branch back to this junction (round a handle) leads on
                // to nothing new; one to a junction where nothing leaves the
                // body leads on where the body goes on from there (a hip
                // where only the tail's stub branches, between the chest
                // and the hind legs).
                const auto leadsOn = [&](std::uint32_t other) {
                    if (other == kNoJunction || other == j) return false;
                    std::vector<std::uint8_t> seen(g.junctions.size(), 0);
                    std::vector<std::uint32_t> open{other};
                    seen[j] = seen[other] = 1;
                    while (!open.empty()) {
                        const std::uint32_t k = open.back();
                        open.pop_back();
                        if ((*limbsLeave)[k]) return true;
                        for (const std::uint32_t next : wayOnOf[k])
                            if (!seen[next]) seen[next] = 1, open.push_back(next);
                    }
                    return false;
                };
                const auto goesOn = [&](std::size_t i) {
                    return skeletonEndOf[i - first] == kNoJunction &&
                           leadsOn(otherJunctionOf[i - first]);
                };
                // 0: no piece lies past the loop's plane (a head bent back
                // over its neck), so the reach tells nothing.
                const auto reachesAsAPart = [&](std::uint32_t node) {
                    if (!pieceReach) return true;
                    const double reach = pieceReach(node, j);
                    return reach == 0.0 || reach >= options.endReach;
                };
                bool bodyGoesOn = false;
                for (std::size_t k = 0; k < passages.size(); ++k)
                    bodyGoesOn |= leadsOn(passageTo[k]) && !roundAnArtefact(passages[k].node);
                for (std::size_t i = first; i < plan.candidates.size(); ++i)
                    if (const CutCandidate& c = plan.candidates[i];
                        c.onBody && goesOn(i) && !roundAnArtefact(c.node))
                        bodyGoesOn = true;
                if (bodyGoesOn)
                    for (std::size_t i = first; i < plan.candidates.size(); ++i)
                        if (CutCandidate& c = plan.candidates[i];
                            c.onBody && !goesOn(i) && c.similarity < float(options.endBodyRatio) &&
                            reachesAsAPart(c.node))
                            c.onBody = false;
            }
            // Nothing leaves a one-branch junction but its branch: the body
            // ends there, and a branch that reaches another junction is the
            // body's way on, judged at that junction (where a coarser
            // digitisation gives no junction at this end at all).
            if (options.oneBranchJunctionsEndTheBody && branches.size() == 1)
                for (std::size_t i = first; i < plan.candidates.size(); ++i)
                    if (skeletonEndOf[i - first] == kNoJunction) plan.candidates[i].onBody = true;
            for (std::size_t i = first; i < plan.candidates.size(); ++i) {
                CutCandidate& c = plan.candidates[i];
                c.isCut = !c.onBody;
                if (c.isCut) {
                    // The cut loop is the limb's border: the first tight level
                    // whose loop is closer to the limb's girth than to the
                    // body's (a loop as long as the body's still wraps the
                    // body, e.g. a skirt around a leg).
                    const float border = 0.5f * (c.bodyRhoS + c.limbRhoS);
                    const std::vector<TightLevel>& tight = tightOf[i - first];
                    std::size_t at = 0;
                    while (at < tight.size() && tight[at].rhoS > border) ++at;
                    // Something lying against the limb (a skirt on a thigh) keeps
                    // the loop longer than the limb's own and lets it shrink
                    // slowly; the limb's border is where the loop stops
                    // shrinking faster than a limb tapers.
                    if (at < tight.size())
                        at = settledLevel(tight, at, walkEndOf[i - first], options.limbTaper,
                                          options.consecutiveLevels);
                    if (at < tight.size()) {
                        const TightLevel& t = tight[at];
                        if (t.node != c.node) c.exactRhoC = -1.0;
                        c.node = t.node, c.level = t.level, c.sigma = t.sigma;
                    }
                    // Only a loop clearly shorter than the body's: where more than
                    // two candidates look like body (the flukes of a tail), the
                    // loops are the body's own and rule 3 decides.
                    // A short skeleton past the cut makes it a candidate corner;
                    // the piece's surface decides where the caller can flood it
                    // (the skeleton's end comes in whole levels and moves with
                    // the resolution on short flat parts such as fins).
                    c.isCorner =
                        c.similarity < float(options.bodyRatio) &&
                        isCornerOfTheBody(c.level, skeletonEndOf[i - first],
                                          points[g.point[c.node]].rhoS, options.cornerLength) &&
                        (!pieceReach || pieceReach(c.node, j) < options.cornerReach);
                    c.isCut = !c.isCorner;
                }
            }
            for (std::size_t i = first; i < plan.candidates.size(); ++i) {
                const CutCandidate& c = plan.candidates[i];
                const std::uint32_t other = otherJunctionOf[i - first];
                if (!c.isCut && skeletonEndOf[i - first] == kNoJunction && other != kNoJunction &&
                    !roundAnArtefact(c.node))
                    bodyLinksOf[j].push_back(other), bodyLinksOf[other].push_back(j);
            }
            for (std::size_t k = 0; k < passages.size(); ++k)
                if (passageTo[k] != kNoJunction && !roundAnArtefact(passages[k].node))
                    bodyLinksOf[j].push_back(passageTo[k]), bodyLinksOf[passageTo[k]].push_back(j);
            for (std::size_t i = first; i < plan.candidates.size(); ++i) {
                tightOfPlan.push_back(std::move(tightOf[i - first]));
                skeletonEndOfPlan.push_back(skeletonEndOf[i - first]);
                otherJunctionOfPlan.push_back(otherJunctionOf[i - first]);
            }
        }
        if (options.separatingCutsOnly && loopsSeparate)
            moveToSeparatingLoops(g, plan.candidates, tightOfPlan, skeletonEndOfPlan,
                                  otherJunctionOfPlan, loopsSeparate);
        for (const CutCandidate& c : plan.candidates)
            if (c.isCut) {
                plan.cutNodes.push_back(c.node);
                ++plan.junctions[c.junction].cuts;
            }
        std::sort(plan.cutNodes.begin(), plan.cutNodes.end());
        plan.cutNodes.erase(std::unique(plan.cutNodes.begin(), plan.cutNodes.end()),
                            plan.cutNodes.end());
        return plan;
    };
    std::vector<float> bodyFloor(g.junctions.size(), 0.0f);
    CutPlan plan = planWith(bodyFloor, nullptr);
    if (options.passagesAreBody && options.shareBodyAcrossPassages && !passageLinks.empty()) {
        bodyFloor = sharedBodyReference(bodyOf, passageLinks);
        plan = planWith(bodyFloor, nullptr);
    }
    // The end rule reads where the plan without it cut limbs: a junction
    // where limbs leave is where the body goes on. It can act only on an
    // uncut candidate below endBodyRatio, and only where some limb leaves.
    if (options.endBodyRatio > 0.0 && options.mode != CutMode::Junctions &&
        g.junctions.size() > 1) {
        std::vector<std::uint8_t> limbsLeave(g.junctions.size(), 0);
        for (std::uint32_t j = 0; j < g.junctions.size(); ++j)
            limbsLeave[j] = plan.junctions[j].cuts > 0;
        const bool canAct =
            std::find(limbsLeave.begin(), limbsLeave.end(), 1) != limbsLeave.end() &&
            std::any_of(plan.candidates.begin(), plan.candidates.end(), [&](const CutCandidate& c) {
                return !c.isCut && c.similarity < float(options.endBodyRatio);
            });
        if (canAct) {
            wayOnOf = bodyLinksOf;
            plan = planWith(bodyFloor, &limbsLeave);
        }
    }
    return plan;
}

}  // namespace

CutPlan placeCuts(const SkeletonGraph& g, const std::vector<SkeletonPoint>& points,
                  const CutOptions& options, const std::function<double(std::uint32_t)>& exactRhoC,
                  const LoopSeparation& loopsSeparate, const PieceReach& pieceReach) {
    if (!options.surfaceLoops)
        return placeCutsOn(g, points, options, exactRhoC, loopsSeparate, pieceReach);
    // The same plan on the surface's half loops: every point's and every
    // junction's rho_S replaced by it. A junction's median is taken again
    // over its J_tau points (as SkeletonGraph does); a junction whose core
    // holds forks only keeps its own, the rho_S of its widest branch's
    // point.
    std::vector<SkeletonPoint> surface(points);
    for (SkeletonPoint& p : surface) p.rhoS = surfaceHalfLoop(p);
    SkeletonGraph graph = g;
    std::vector<float> loops;
    for (SkeletonJunction& j : graph.junctions) {
        loops.clear();
        for (std::uint32_t n : j.core)
            if (isJunctionPoint(points[g.point[n]])) loops.push_back(surface[g.point[n]].rhoS);
        if (loops.empty()) continue;
        std::sort(loops.begin(), loops.end());
        const std::size_t m = loops.size() / 2;
        j.rhoS = loops.size() % 2 ? loops[m] : 0.5f * (loops[m - 1] + loops[m]);
    }
    return placeCutsOn(graph, surface, options, exactRhoC, loopsSeparate, pieceReach);
}

}  // namespace skelseg
