#include "kernels/CutPlacement.h"

#include <algorithm>
#include <cmath>

namespace skelseg {

namespace {

/// Walks one branch from junction j's region; returns the candidate node or
/// kNoJunction. `taken` marks nodes already walked from this junction.
std::uint32_t walkBranch(const SkeletonGraph& g, const std::vector<SkeletonPoint>& points,
                         std::uint32_t junction, std::uint32_t piece, const CutOptions& options,
                         std::vector<std::uint8_t>& taken, std::uint32_t& levelOut,
                         float& sigmaOut) {
    std::vector<std::uint32_t> level;
    for (std::uint32_t n : g.junctions[junction].region)
        for (std::uint32_t e = g.offset[n]; e < g.offset[n + 1]; ++e) {
            const std::uint32_t m = g.neighbour[e];
            if (g.pieceOf[m] == piece && !taken[m]) taken[m] = 1, level.push_back(m);
        }
    std::sort(level.begin(), level.end());
    std::uint32_t runStart = kNoJunction, runLength = 0, runStartLevel = 0;
    float runStartSigma = 0.0f;
    for (std::uint32_t depth = 1; !level.empty(); ++depth) {
        // Best sigma on this level; ties by lowest node id (levels are sorted).
        std::uint32_t bestNode = level.front();
        float best = -1.0f;
        for (std::uint32_t n : level) {
            const float s = points[g.point[n]].sigma;
            if (s > best) best = s, bestNode = n;
        }
        if (best >= float(options.sigmaMin)) {
            if (runLength == 0) runStart = bestNode, runStartLevel = depth, runStartSigma = best;
            if (++runLength >= std::uint32_t(options.consecutiveLevels)) break;
        } else {
            runLength = 0;
        }
        std::vector<std::uint32_t> next;
        for (std::uint32_t n : level)
            for (std::uint32_t e = g.offset[n]; e < g.offset[n + 1]; ++e) {
                const std::uint32_t m = g.neighbour[e];
                if (g.pieceOf[m] == piece && !taken[m]) taken[m] = 1, next.push_back(m);
            }
        std::sort(next.begin(), next.end());
        level.swap(next);
    }
    if (runLength < std::uint32_t(options.consecutiveLevels)) return kNoJunction;
    levelOut = runStartLevel;
    sigmaOut = runStartSigma;
    return runStart;
}

}  // namespace

CutPlan placeCuts(const SkeletonGraph& g, const std::vector<SkeletonPoint>& points,
                  const CutOptions& options,
                  const std::function<double(std::uint32_t)>& exactRhoC) {
    CutPlan plan;
    plan.junctions.resize(g.junctions.size());
    for (std::uint32_t j = 0; j < g.junctions.size(); ++j) {
        const SkeletonJunction& junction = g.junctions[j];
        // Branches: pieces touching the region, in order of first contact.
        std::vector<std::uint32_t> branches;
        for (std::uint32_t n : junction.region)
            for (std::uint32_t e = g.offset[n]; e < g.offset[n + 1]; ++e) {
                const std::uint32_t piece = g.pieceOf[g.neighbour[e]];
                if (piece != kNoJunction &&
                    std::find(branches.begin(), branches.end(), piece) == branches.end())
                    branches.push_back(piece);
            }
        std::sort(branches.begin(), branches.end());
        plan.junctions[j].branches = std::uint32_t(branches.size());

        if (options.mode == CutMode::Junctions) {
            plan.cutNodes.push_back(junction.representative);
            plan.junctions[j].cuts = 1;
            continue;
        }

        std::vector<std::uint8_t> taken(g.nodeCount(), 0);
        const std::size_t first = plan.candidates.size();
        for (std::uint32_t piece : branches) {
            std::uint32_t level = 0;
            float sigma = 0.0f;
            const std::uint32_t node =
                walkBranch(g, points, j, piece, options, taken, level, sigma);
            if (node == kNoJunction) continue;
            CutCandidate c;
            c.junction = j;
            c.node = node;
            c.level = level;
            c.sigma = sigma;
            const float rhoJ = junction.rhoS, rhoQ = points[g.point[node]].rhoS;
            c.similarity = rhoJ > 0.0f ? 1.0f - std::fabs(rhoJ - rhoQ) / rhoJ : 0.0f;
            c.onBody = c.similarity >= float(options.bodyRatio);
            plan.candidates.push_back(c);
        }
        // Body passes through a junction at most once: drop at most two.
        std::vector<std::size_t> body;
        for (std::size_t i = first; i < plan.candidates.size(); ++i)
            if (plan.candidates[i].onBody) body.push_back(i);
        if (body.size() > 2) {
            std::size_t keepOnBody = body.front();
            double bestArea = -1.0;
            for (std::size_t i : body) {
                CutCandidate& c = plan.candidates[i];
                c.exactRhoC = exactRhoC(g.point[c.node]);
                const bool better = c.exactRhoC > bestArea ||
                                    (c.exactRhoC == bestArea &&
                                     points[g.point[c.node]].voxel <
                                         points[g.point[plan.candidates[keepOnBody].node]].voxel);
                if (better) bestArea = c.exactRhoC, keepOnBody = i;
            }
            for (std::size_t i : body) plan.candidates[i].onBody = i == keepOnBody;
        }
        for (std::size_t i = first; i < plan.candidates.size(); ++i) {
            CutCandidate& c = plan.candidates[i];
            c.isCut = !c.onBody;
            if (c.isCut) {
                plan.cutNodes.push_back(c.node);
                ++plan.junctions[j].cuts;
            }
        }
    }
    std::sort(plan.cutNodes.begin(), plan.cutNodes.end());
    plan.cutNodes.erase(std::unique(plan.cutNodes.begin(), plan.cutNodes.end()),
                        plan.cutNodes.end());
    return plan;
}

}  // namespace skelseg
