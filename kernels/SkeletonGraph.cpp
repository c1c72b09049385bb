#include "kernels/SkeletonGraph.h"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <unordered_map>

#include "kernels/DisjointSets.h"
#include "kernels/SkeletonBridges.h"
#include "kernels/SkeletonForks.h"
#include "kernels/SkeletonGraphSearch.h"
#include "kernels/base/ParallelFor.h"

namespace skelseg {

namespace {

/// Whether any of the graph nodes `nodes` is a junction point (J_tau).
bool anyJunctionPoint(const SkeletonGraph& g, const std::vector<SkeletonPoint>& points,
                      const std::vector<std::uint32_t>& nodes) {
    return std::any_of(nodes.begin(), nodes.end(),
                       [&](std::uint32_t n) { return isJunctionPoint(points[g.point[n]]); });
}

void buildAdjacency(SkeletonGraph& g) {
    std::vector<std::vector<std::uint32_t>> lists(g.nodeCount());
    for (const auto& e : g.edges) lists[e[0]].push_back(e[1]), lists[e[1]].push_back(e[0]);
    g.offset.assign(std::size_t(g.nodeCount()) + 1, 0);
    g.neighbour.clear();
    for (std::uint32_t n = 0; n < g.nodeCount(); ++n) {
        std::sort(lists[n].begin(), lists[n].end());
        g.neighbour.insert(g.neighbour.end(), lists[n].begin(), lists[n].end());
        g.offset[std::size_t(n) + 1] = std::uint32_t(g.neighbour.size());
    }
}

/// Junction clusters (J_tau points and forks) and their regions, each
/// junction's rho_S, and the branch pieces outside the regions.
void contractJunctions(SkeletonGraph& g, const std::vector<SkeletonPoint>& points,
                       const SkeletonGraphOptions& options, const std::vector<std::uint8_t>& fork,
                       const std::vector<float>& forkBodyRhoS) {
    g.junctions.clear();
    // Junction clusters and their regions.
    auto isCore = [&](std::uint32_t n) { return isJunctionPoint(points[g.point[n]]) || fork[n]; };
    std::vector<std::uint32_t> cluster;
    const std::uint32_t clusters = labelComponents(g, isCore, cluster);
    std::vector<std::uint32_t> owner(g.nodeCount(),
                                     kNoJunction);  // cluster whose region took the node first
    DisjointSets merged(clusters);
    // Each cluster's cores and part radius (the median rho_S of its J_tau
    // points, or of its forks' body loops), for the merge test.
    std::vector<std::vector<std::uint32_t>> coresOf(clusters);
    std::vector<double> radiusOf(clusters, 0.0);
    std::vector<std::uint8_t> forksOnly(clusters, 1);
    for (std::uint32_t n = 0; n < g.nodeCount(); ++n)
        if (cluster[n] != kNoJunction) {
            coresOf[cluster[n]].push_back(n);
            if (!fork[n]) forksOnly[cluster[n]] = 0;
        }
    for (std::uint32_t c = 0; c < clusters; ++c) {
        std::vector<float> rho;
        for (std::uint32_t n : coresOf[c])
            rho.push_back(fork[n] ? forkBodyRhoS[n] : points[g.point[n]].rhoS);
        std::sort(rho.begin(), rho.end());
        if (!rho.empty()) radiusOf[c] = loopRadius(std::max(0.0, double(rho[rho.size() / 2])));
    }
    const auto oneJunction = [&](std::uint32_t a, std::uint32_t b) {
        // Forks come in spread clusters along a branching, and a junction
        // of forks is only as many branches as its clusters together leave.
        if (options.junctionMergeRadii <= 0.0 || forksOnly[a] || forksOnly[b]) return true;
        const double reach = options.junctionMergeRadii * std::max(radiusOf[a], radiusOf[b]);
        for (std::uint32_t u : coresOf[a])
            for (std::uint32_t v : coresOf[b]) {
                const double dx = g.coord[u].x - g.coord[v].x, dy = g.coord[u].y - g.coord[v].y,
                             dz = g.coord[u].z - g.coord[v].z;
                if (dx * dx + dy * dy + dz * dz <= reach * reach) return true;
            }
        return false;
    };
    std::vector<std::array<std::uint32_t, 2>> touching;  // node pairs of clusters kept apart
    {
        // Multi-source BFS from all cores at once, `regionRadius` steps.
        std::vector<std::uint32_t> depth(g.nodeCount(), kNoJunction), queue;
        for (std::uint32_t n = 0; n < g.nodeCount(); ++n)
            if (cluster[n] != kNoJunction) depth[n] = 0, owner[n] = cluster[n], queue.push_back(n);
        for (std::size_t h = 0; h < queue.size(); ++h) {
            const std::uint32_t n = queue[h];
            for (std::uint32_t e = g.offset[n]; e < g.offset[n + 1]; ++e) {
                const std::uint32_t m = g.neighbour[e];
                if (owner[m] != kNoJunction) {
                    if (owner[m] == owner[n]) continue;
                    if (oneJunction(owner[m], owner[n]))
                        merged.unite(owner[m], owner[n]);  // regions touch
                    else
                        touching.push_back({n, m});
                    continue;
                }
                if (int(depth[n]) >= options.regionRadius) continue;
                depth[m] = depth[n] + 1;
                owner[m] = owner[n];
                queue.push_back(m);
            }
        }
    }
    g.junctionOf.assign(g.nodeCount(), kNoJunction);
    std::vector<std::uint32_t> junctionOfRoot(clusters, kNoJunction);
    for (std::uint32_t n = 0; n < g.nodeCount(); ++n) {
        if (owner[n] == kNoJunction) continue;
        const std::uint32_t root = merged.find(owner[n]);
        if (junctionOfRoot[root] == kNoJunction) {
            junctionOfRoot[root] = std::uint32_t(g.junctions.size());
            g.junctions.emplace_back();
        }
        const std::uint32_t j = junctionOfRoot[root];
        g.junctionOf[n] = j;
        g.junctions[j].region.push_back(n);
        if (cluster[n] != kNoJunction) g.junctions[j].core.push_back(n);
    }
    g.junctionContacts.clear();
    for (const auto& [n, m] : touching) {
        std::uint32_t a = g.junctionOf[n], b = g.junctionOf[m], na = n, nb = m;
        if (a == b) continue;  // joined through a third cluster
        if (a > b) std::swap(a, b), std::swap(na, nb);
        if (std::none_of(g.junctionContacts.begin(), g.junctionContacts.end(),
                         [&](const JunctionContact& c) { return c.junction == a && c.other == b; }))
            g.junctionContacts.push_back({a, b, na, nb});
    }
    for (SkeletonJunction& j : g.junctions) {
        // A fork's own loop goes round one branch; the body's loop there is
        // its widest branch's (ForkSearch). Junctions with J_tau points keep
        // their median over those.
        const bool coreHasJunctionPoint = anyJunctionPoint(g, points, j.core);
        std::vector<std::pair<float, std::uint32_t>> byRho;
        for (std::uint32_t n : j.core)
            if (!fork[n])
                byRho.emplace_back(points[g.point[n]].rhoS, n);
            else if (!coreHasJunctionPoint)
                byRho.emplace_back(forkBodyRhoS[n], n);
        std::sort(byRho.begin(), byRho.end());
        if (byRho.empty()) continue;
        const auto& mid = byRho[byRho.size() / 2];
        j.rhoS =
            byRho.size() % 2 ? mid.first : 0.5f * (byRho[byRho.size() / 2 - 1].first + mid.first);
        j.representative = mid.second;
    }

    g.pieceCount = labelComponents(
        g, [&](std::uint32_t n) { return g.junctionOf[n] == kNoJunction; }, g.pieceOf);
}

}  // namespace

SkeletonGraph buildSkeletonGraph(const std::vector<SkeletonPoint>& points, const Dims& dims,
                                 const SkeletonGraphOptions& options, Interrupter& interrupter) {
    InterrupterScope scope(interrupter, "skeleton graph");
    SkeletonGraph g;
    std::unordered_map<std::uint32_t, std::uint32_t> nodeOfVoxel;
    const std::uint32_t nx = std::uint32_t(dims.x), ny = std::uint32_t(dims.y);
    for (std::uint32_t i = 0; i < points.size(); ++i) {
        if (!(points[i].rhoC >= options.tau)) continue;
        const std::uint32_t v = points[i].voxel;
        nodeOfVoxel.emplace(v, g.nodeCount());
        g.point.push_back(i);
        g.coord.push_back(Coord{int(v % nx), int((v / nx) % ny), int(v / (nx * ny))});
    }
    auto lookup = [&](int x, int y, int z) -> std::uint32_t {
        if (x < 0 || y < 0 || z < 0 || x >= dims.x || y >= dims.y || z >= dims.z)
            return kNoJunction;
        auto it =
            nodeOfVoxel.find(std::uint32_t(x) + nx * (std::uint32_t(y) + ny * std::uint32_t(z)));
        return it == nodeOfVoxel.end() ? kNoJunction : it->second;
    };
    // 26-adjacency edges (each once, i < j).
    for (std::uint32_t n = 0; n < g.nodeCount(); ++n) {
        const Coord c = g.coord[n];
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    if (!dx && !dy && !dz) continue;
                    const std::uint32_t m = lookup(c.x + dx, c.y + dy, c.z + dz);
                    if (m != kNoJunction && m > n) g.edges.push_back({n, m});
                }
    }
    buildAdjacency(g);

    // Noise breaks the skeleton into parts; close ones are bridged.
    if (bridgeSkeletonParts(g, points, options, interrupter)) buildAdjacency(g);

    // Forks: where three or more branches of C_tau meet but no point's path
    // set goes round three parts (docs/algorithm.md §6, "Forks").
    std::vector<std::uint8_t> fork(g.nodeCount(), 0);
    std::vector<float> forkBodyRhoS(g.nodeCount(), 0.0f);
    if (options.forkJunctions && g.nodeCount()) {
        // One search per thread; a node's test reads the graph and writes its
        // own two slots only. Small ranges: a test costs its ball, a few
        // nodes on a limb and most of the sheet on a sheet of C_tau.
        tbb::enumerable_thread_specific<std::unique_ptr<ForkSearch>> searches;
        std::atomic<bool> stop{false};
        parallelForSmallRanges(
            g.nodeCount(),
            [&](std::uint32_t begin, std::uint32_t end) {
                if (stop.load(std::memory_order_relaxed)) return;
                if (interrupter.wasInterrupted(double(begin) / double(g.nodeCount()))) {
                    stop = true;
                    return;
                }
                std::unique_ptr<ForkSearch>& search = searches.local();
                if (!search) search = std::make_unique<ForkSearch>(g.nodeCount());
                for (std::uint32_t n = begin; n < end; ++n)
                    if (!isJunctionPoint(points[g.point[n]]))
                        fork[n] = search->countBranches(g, points, n, double(options.regionRadius),
                                                        forkBodyRhoS[n]) >= 3;
            },
            options.threaded, 16);
        if (stop) throwInterrupted(interrupter);
    }

    contractJunctions(g, points, options, fork, forkBodyRhoS);
    // A fork is three branches; a junction of forks alone whose region
    // leaves fewer (a short branch swallowed by the region) is no junction.
    bool dissolved = false;
    for (const SkeletonJunction& j : g.junctions) {
        if (anyJunctionPoint(g, points, j.core)) continue;
        std::vector<std::uint32_t> branches;
        for (std::uint32_t n : j.region)
            for (std::uint32_t e = g.offset[n]; e < g.offset[n + 1]; ++e)
                if (const std::uint32_t piece = g.pieceOf[g.neighbour[e]];
                    piece != kNoJunction &&
                    std::find(branches.begin(), branches.end(), piece) == branches.end())
                    branches.push_back(piece);
        if (branches.size() >= 3) continue;
        for (std::uint32_t n : j.core) fork[n] = 0;
        dissolved = true;
    }
    if (dissolved) contractJunctions(g, points, options, fork, forkBodyRhoS);
    if (options.growRegionsToSplits) growRegionsToBranchSplits(g, options);
    return g;
}

std::vector<std::uint32_t> junctionBranches(const SkeletonGraph& g, std::uint32_t junction) {
    std::vector<std::uint32_t> branches;
    for (std::uint32_t n : g.junctions[junction].region)
        for (std::uint32_t e = g.offset[n]; e < g.offset[n + 1]; ++e) {
            const std::uint32_t piece = g.pieceOf[g.neighbour[e]];
            if (piece != kNoJunction &&
                std::find(branches.begin(), branches.end(), piece) == branches.end())
                branches.push_back(piece);
        }
    return branches;
}

}  // namespace skelseg
