#include "kernels/SkeletonGraph.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <unordered_map>

namespace skelseg {

namespace {

struct UnionFind {
    std::vector<std::uint32_t> parent;
    explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
    std::uint32_t find(std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    void unite(std::uint32_t a, std::uint32_t b) {
        a = find(a), b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

/// Whether any of the graph nodes `nodes` is a junction point (J_tau).
bool anyJunctionPoint(const SkeletonGraph& g, const std::vector<SkeletonPoint>& points,
                      const std::vector<std::uint32_t>& nodes) {
    return std::any_of(nodes.begin(), nodes.end(),
                       [&](std::uint32_t n) { return isJunctionPoint(points[g.point[n]]); });
}

/// Connected components of the nodes with include(n), following `adjacency`;
/// numbered by smallest node. Returns the count; label kNoJunction elsewhere.
template <typename Include>
std::uint32_t labelComponents(const SkeletonGraph& g, const Include& include,
                              std::vector<std::uint32_t>& label) {
    label.assign(g.nodeCount(), kNoJunction);
    std::uint32_t count = 0;
    std::vector<std::uint32_t> queue;
    for (std::uint32_t seed = 0; seed < g.nodeCount(); ++seed) {
        if (!include(seed) || label[seed] != kNoJunction) continue;
        queue.assign(1, seed);
        label[seed] = count;
        for (std::size_t h = 0; h < queue.size(); ++h)
            for (std::uint32_t e = g.offset[queue[h]]; e < g.offset[queue[h] + 1]; ++e) {
                const std::uint32_t m = g.neighbour[e];
                if (include(m) && label[m] == kNoJunction) label[m] = count, queue.push_back(m);
            }
        ++count;
    }
    return count;
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

/// Whether the straight segment between voxels a and b stays in `inside`
/// (sampled every half voxel, each sample's nearest voxel).
bool segmentInside(const Coord& a, const Coord& b, const MaskVolume& inside) {
    const double dx = b.x - a.x, dy = b.y - a.y, dz = b.z - a.z;
    const int steps = std::max(1, int(std::ceil(2.0 * std::sqrt(dx * dx + dy * dy + dz * dz))));
    for (int s = 0; s <= steps; ++s) {
        const double t = double(s) / steps;
        const int x = int(std::lround(a.x + t * dx)), y = int(std::lround(a.y + t * dy)),
                  z = int(std::lround(a.z + t * dz));
        if (!inside.contains(x, y, z) || !inside(x, y, z)) return false;
    }
    return true;
}

/// Joins the parts of g that `joined` still keeps apart: for every node and
/// every other part, the nearest node there is a candidate; candidates are
/// taken shortest first, and one whose segment leaves the object is skipped.
void bridgeThroughObject(SkeletonGraph& g, const std::vector<std::uint32_t>& part,
                         UnionFind& joined, const MaskVolume& inside) {
    const std::uint32_t n = g.nodeCount();
    std::vector<std::uint32_t> group(n);
    std::map<std::uint32_t, std::uint32_t> groupIndex;
    for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t root = joined.find(part[i]);
        group[i] = groupIndex.emplace(root, std::uint32_t(groupIndex.size())).first->second;
    }
    const std::uint32_t groups = std::uint32_t(groupIndex.size());
    std::vector<std::tuple<double, std::uint32_t, std::uint32_t>> candidates;
    std::vector<std::pair<double, std::uint32_t>> nearest(groups);
    for (std::uint32_t a = 0; a < n; ++a) {
        std::fill(nearest.begin(), nearest.end(), std::make_pair(HUGE_VAL, kNoJunction));
        for (std::uint32_t b = 0; b < n; ++b) {
            if (group[b] == group[a]) continue;
            const double dx = g.coord[b].x - g.coord[a].x, dy = g.coord[b].y - g.coord[a].y,
                         dz = g.coord[b].z - g.coord[a].z;
            const double d2 = dx * dx + dy * dy + dz * dz;
            if (std::make_pair(d2, b) < nearest[group[b]]) nearest[group[b]] = {d2, b};
        }
        for (std::uint32_t k = 0; k < groups; ++k)
            if (nearest[k].second != kNoJunction && group[a] < k)
                candidates.emplace_back(nearest[k].first, a, nearest[k].second);
            else if (nearest[k].second != kNoJunction && k < group[a])
                candidates.emplace_back(nearest[k].first, nearest[k].second, a);
    }
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    UnionFind groupsJoined(groups);
    for (const auto& [d2, a, b] : candidates) {
        if (groupsJoined.find(group[a]) == groupsJoined.find(group[b])) continue;
        if (!segmentInside(g.coord[a], g.coord[b], inside)) continue;
        groupsJoined.unite(group[a], group[b]);
        g.edges.push_back({std::min(a, b), std::max(a, b)});
        ++g.bridgeCount;
    }
}

/// Distances along the skeleton graph's edges (Euclidean edge lengths,
/// bridges included) from seed nodes, up to `reach`, over the nodes with
/// allowed(n). Kept across calls: reset() clears only what the last search
/// touched.
struct BoundedDistances {
    std::vector<double> distance;
    std::vector<std::uint32_t> touched;  // nodes with a finite distance
    std::vector<std::pair<double, std::uint32_t>> heap;
    explicit BoundedDistances(std::size_t n) : distance(n, HUGE_VAL) {}

    void reset() {
        for (std::uint32_t n : touched) distance[n] = HUGE_VAL;
        touched.clear();
        heap.clear();
    }
    bool reached(std::uint32_t n) const { return distance[n] != HUGE_VAL; }
    /// Offers node m at distance d; false (ignored) beyond reach or when not
    /// shorter. A taken offer is pushed onto the heap's end.
    bool offer(std::uint32_t m, double d, double reach) {
        if (d > reach || d >= distance[m]) return false;
        if (distance[m] == HUGE_VAL) touched.push_back(m);
        distance[m] = d;
        heap.push_back({d, m});
        return true;
    }
    /// Offers m at its edge length from n.
    bool offerFrom(const SkeletonGraph& g, std::uint32_t n, double dn, std::uint32_t m,
                   double reach) {
        const double dx = g.coord[m].x - g.coord[n].x, dy = g.coord[m].y - g.coord[n].y,
                     dz = g.coord[m].z - g.coord[n].z;
        return offer(m, dn + std::sqrt(dx * dx + dy * dy + dz * dz), reach);
    }
    /// Dijkstra from the offered seeds.
    template <class Allowed>
    void run(const SkeletonGraph& g, double reach, const Allowed& allowed) {
        auto later = [](const auto& a, const auto& b) { return a > b; };
        std::make_heap(heap.begin(), heap.end(), later);
        while (!heap.empty()) {
            std::pop_heap(heap.begin(), heap.end(), later);
            const auto [d, n] = heap.back();
            heap.pop_back();
            if (d > distance[n]) continue;
            for (std::uint32_t e = g.offset[n]; e < g.offset[n + 1]; ++e)
                if (const std::uint32_t m = g.neighbour[e];
                    allowed(m) && offerFrom(g, n, d, m, reach))
                    std::push_heap(heap.begin(), heap.end(), later);
        }
    }
};

/// The connected parts of the shell (radius, reach] of a BoundedDistances
/// search, over the nodes with allowed(n). A part counts as a branch when it
/// reaches past 1.5 radius or leaves the ball (a neighbour with allowed(n)
/// and no distance): a branch, not a bump of the thick skeleton. Calls
/// visit(node) for each node of a part, then part(seed, counts) once per
/// part. `mark` holds each shell node's part (its seed) and must be
/// kNoJunction on the touched nodes at the start; the caller clears it.
template <class Allowed, class Visit, class Part>
void forEachShellPart(const SkeletonGraph& g, const BoundedDistances& ball, double radius,
                      std::vector<std::uint32_t>& mark, std::vector<std::uint32_t>& queue,
                      const Allowed& allowed, const Visit& visit, const Part& part) {
    const double reach = 2.0 * radius;
    for (std::uint32_t seed : ball.touched) {
        if (ball.distance[seed] <= radius || mark[seed] != kNoJunction) continue;
        mark[seed] = seed;
        queue.assign(1, seed);
        double farthest = 0.0;
        bool leavesBall = false;
        for (std::size_t h = 0; h < queue.size(); ++h) {
            const std::uint32_t n = queue[h];
            farthest = std::max(farthest, ball.distance[n]);
            visit(n);
            for (std::uint32_t e = g.offset[n]; e < g.offset[n + 1]; ++e) {
                const std::uint32_t m = g.neighbour[e];
                if (!allowed(m)) continue;
                if (!ball.reached(m)) leavesBall = true;
                if (ball.distance[m] > radius && ball.distance[m] <= reach &&
                    mark[m] == kNoJunction)
                    mark[m] = seed, queue.push_back(m);
            }
        }
        part(seed, farthest > 1.5 * radius || leavesBall);
    }
}

/// Fork test at node s: the nodes within 2R of s along the graph's edges,
/// R = the radius of the part at s (loopRadius(rho_S)), at least
/// `minimumRadius`. The shell (R, 2R] falls into one connected part per
/// branch leaving the ball (forEachShellPart), and a bridge from the inner
/// ball to beyond 2R is a branch too. s is a fork with three or more
/// branches, unless a J_tau point lies within R of it (the junction test
/// already marks that branching). `bodyRhoS` gets the largest of the
/// branches' median rho_S: the loop of the body through the fork.
struct ForkSearch {
    BoundedDistances ball;
    std::vector<std::uint32_t> piece, queue;
    std::vector<float> rho;  // rho_S along one shell part
    explicit ForkSearch(std::size_t n) : ball(n), piece(n, kNoJunction) {}

    std::uint32_t countBranches(const SkeletonGraph& g, const std::vector<SkeletonPoint>& points,
                                std::uint32_t s, double minimumRadius, float& bodyRhoS) {
        const double radius = std::max(minimumRadius, loopRadius(double(points[g.point[s]].rhoS)));
        const double reach = 2.0 * radius;
        for (std::uint32_t n : ball.touched) piece[n] = kNoJunction;
        ball.reset();
        ball.offer(s, 0.0, reach);
        const auto anyNode = [](std::uint32_t) { return true; };
        ball.run(g, reach, anyNode);
        // A junction point within reach already marks this branching.
        for (std::uint32_t n : ball.touched)
            if (ball.distance[n] <= radius && isJunctionPoint(points[g.point[n]])) return 0;
        std::uint32_t branches = 0;
        bodyRhoS = 0.0f;
        // Edges from a node to beyond the reach are bridges (no 26-step
        // leaves the ball from inside it). One from the inner ball (a limb's
        // skeleton that broke near its base, bridged here) is a branch.
        for (std::uint32_t n : ball.touched)
            if (ball.distance[n] <= radius)
                for (std::uint32_t e = g.offset[n]; e < g.offset[n + 1]; ++e)
                    if (const std::uint32_t far = g.neighbour[e]; !ball.reached(far)) {
                        ++branches;
                        bodyRhoS = std::max(bodyRhoS, points[g.point[far]].rhoS);
                    }
        rho.clear();
        forEachShellPart(
            g, ball, radius, piece, queue, anyNode,
            [&](std::uint32_t n) { rho.push_back(points[g.point[n]].rhoS); },
            [&](std::uint32_t, bool isBranch) {
                if (isBranch) {
                    ++branches;
                    std::nth_element(rho.begin(), rho.begin() + rho.size() / 2, rho.end());
                    bodyRhoS = std::max(bodyRhoS, rho[rho.size() / 2]);
                }
                rho.clear();
            });
        return branches;
    }
};

/// Grows junction regions up to where their branches separate (docs/algorithm.md
/// §6, "A region reaches its branches' split"). A fork within one part radius R
/// (loopRadius of the junction's rho_S) of a J_tau point is no junction of its
/// own, because that junction marks the branching; but its region reaches only
/// `regionRadius` steps, and two limbs whose thick skeletons touch just outside
/// it leave as one piece, which the walk of §8.1 takes as one branch. So for
/// each piece touching a region: the piece's nodes at distance (R, 2R] from the
/// region (within the piece) fall into shell parts, counted as in ForkSearch;
/// when two or more count, the region takes the piece's breadth-first levels
/// from the region one at a time, up to distance R, until what is left of the
/// piece holds the counted parts in separate pieces; the bits left with none
/// of them join the region too.
void growRegionsToBranchSplits(SkeletonGraph& g, const SkeletonGraphOptions& options) {
    const std::uint32_t n = g.nodeCount();
    BoundedDistances ball(n);
    std::vector<std::uint32_t> mark(n, kNoJunction), component(n, kNoJunction);
    std::vector<std::uint8_t> levelled(n, 0);  // taken by the region, or its next level
    std::vector<std::uint32_t> pieces, counted, queue, taken, front, next, flooded;
    for (std::uint32_t j = 0; j < g.junctions.size(); ++j) {
        const double radius =
            std::max(double(options.regionRadius), loopRadius(double(g.junctions[j].rhoS)));
        const double reach = 2.0 * radius;
        pieces.clear();
        for (std::uint32_t r : g.junctions[j].region)
            for (std::uint32_t e = g.offset[r]; e < g.offset[r + 1]; ++e)
                if (const std::uint32_t p = g.pieceOf[g.neighbour[e]];
                    p != kNoJunction && std::find(pieces.begin(), pieces.end(), p) == pieces.end())
                    pieces.push_back(p);
        std::sort(pieces.begin(), pieces.end());
        bool grownHere = false;
        for (std::uint32_t p : pieces) {
            const auto inPiece = [&](std::uint32_t m) { return g.pieceOf[m] == p; };
            // Labels c's part of the piece's nodes the region has not taken.
            const auto floodRest = [&](std::uint32_t c) {
                component[c] = c;
                flooded.push_back(c);
                queue.assign(1, c);
                for (std::size_t h = 0; h < queue.size(); ++h)
                    for (std::uint32_t e = g.offset[queue[h]]; e < g.offset[queue[h] + 1]; ++e)
                        if (const std::uint32_t m = g.neighbour[e];
                            inPiece(m) && !levelled[m] && component[m] == kNoJunction)
                            component[m] = c, queue.push_back(m), flooded.push_back(m);
            };
            // Distances within the piece from the region, bounded by 2R.
            ball.reset();
            for (std::uint32_t r : g.junctions[j].region)
                for (std::uint32_t e = g.offset[r]; e < g.offset[r + 1]; ++e)
                    if (const std::uint32_t m = g.neighbour[e]; inPiece(m))
                        ball.offerFrom(g, r, 0.0, m, reach);
            ball.run(g, reach, inPiece);
            counted.clear();
            forEachShellPart(
                g, ball, radius, mark, queue, inPiece, [](std::uint32_t) {},
                [&](std::uint32_t seed, bool isBranch) {
                    if (isBranch) counted.push_back(seed);
                });
            taken.clear();  // nodes the region would take
            bool separated = false;
            if (counted.size() >= 2) {
                // Breadth-first levels from the region within the piece.
                front.clear();
                for (std::uint32_t r : g.junctions[j].region)
                    for (std::uint32_t e = g.offset[r]; e < g.offset[r + 1]; ++e)
                        if (const std::uint32_t m = g.neighbour[e]; inPiece(m) && !levelled[m])
                            levelled[m] = 1, front.push_back(m);
                flooded.clear();
                while (!front.empty() && !separated) {
                    if (std::any_of(front.begin(), front.end(),
                                    [&](std::uint32_t m) { return ball.distance[m] > radius; }))
                        break;
                    taken.insert(taken.end(), front.begin(), front.end());
                    // Pieces of what is left; separated when no two counted
                    // parts share one.
                    for (std::uint32_t m : flooded) component[m] = kNoJunction;
                    flooded.clear();
                    std::size_t seeds = 0;
                    for (std::uint32_t c : counted) {
                        if (component[c] != kNoJunction) break;
                        ++seeds;
                        floodRest(c);
                    }
                    separated = seeds == counted.size();
                    next.clear();
                    for (std::uint32_t m0 : front)
                        for (std::uint32_t e = g.offset[m0]; e < g.offset[m0 + 1]; ++e)
                            if (const std::uint32_t m = g.neighbour[e]; inPiece(m) && !levelled[m])
                                levelled[m] = 1, next.push_back(m);
                    front.swap(next);
                }
                if (separated) {
                    // Bits of the ball cut off from every counted part join the
                    // region as well (they are not branches).
                    for (std::uint32_t m : ball.touched)
                        if (!levelled[m] && component[m] == kNoJunction) taken.push_back(m);
                }
                for (std::uint32_t m : ball.touched) levelled[m] = 0;
                for (std::uint32_t m : front) levelled[m] = 0;
                for (std::uint32_t m : flooded) component[m] = kNoJunction;
            }
            for (std::uint32_t m : ball.touched) mark[m] = kNoJunction;
            if (!separated) continue;
            for (std::uint32_t m : taken) {
                g.junctionOf[m] = j;
                g.junctions[j].region.push_back(m);
            }
            grownHere = true;
        }
        if (!grownHere) continue;
        // Later junctions see the pieces as they are now.
        std::sort(g.junctions[j].region.begin(), g.junctions[j].region.end());
        g.pieceCount = labelComponents(
            g, [&](std::uint32_t m) { return g.junctionOf[m] == kNoJunction; }, g.pieceOf);
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
    UnionFind merged(clusters);
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
                    merged.unite(owner[m], owner[n]);  // regions touch
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
                                 const SkeletonGraphOptions& options) {
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

    // Bridges between different connected parts closer than bridgeGap.
    std::vector<std::uint32_t> part;
    const std::uint32_t parts = labelComponents(
        g, [](std::uint32_t) { return true; }, part);
    if (parts > 1 && options.bridgeGap >= 1.0) {
        // A node reaches bridgeGap voxels, or the radius of the part around
        // it (loopRadius) where that is larger: a gap
        // shorter than the part's radius lies inside the part at any
        // resolution. A pair needs the reach of both nodes.
        std::vector<double> reach(g.nodeCount());
        double maxReach = 0.0;
        for (std::uint32_t n = 0; n < g.nodeCount(); ++n) {
            reach[n] = std::max(options.bridgeGap, loopRadius(double(points[g.point[n]].rhoS)));
            maxReach = std::max(maxReach, reach[n]);
        }
        // Sweep along x: only nodes within maxReach in x can pair.
        std::vector<std::uint32_t> byX(g.nodeCount());
        for (std::uint32_t n = 0; n < g.nodeCount(); ++n) byX[n] = n;
        std::sort(byX.begin(), byX.end(), [&](std::uint32_t a, std::uint32_t b) {
            return std::make_pair(g.coord[a].x, a) < std::make_pair(g.coord[b].x, b);
        });
        // Closest pair per pair of parts; std::map keeps the order deterministic.
        std::map<std::pair<std::uint32_t, std::uint32_t>,
                 std::tuple<double, std::uint32_t, std::uint32_t>>
            best;
        for (std::size_t i = 0; i < byX.size(); ++i) {
            const std::uint32_t a = byX[i];
            const Coord ca = g.coord[a];
            for (std::size_t k = i + 1; k < byX.size(); ++k) {
                const std::uint32_t b = byX[k];
                const Coord cb = g.coord[b];
                if (double(cb.x - ca.x) > maxReach) break;
                if (part[a] == part[b]) continue;
                const double dx = cb.x - ca.x, dy = cb.y - ca.y, dz = cb.z - ca.z;
                const double d2 = dx * dx + dy * dy + dz * dz;
                const double gap = std::min(reach[a], reach[b]);
                if (d2 > gap * gap) continue;
                const std::uint32_t n = part[a] < part[b] ? a : b, m = part[a] < part[b] ? b : a;
                const auto key = std::make_pair(part[n], part[m]);
                const auto candidate = std::make_tuple(d2, n, m);
                auto it = best.find(key);
                if (it == best.end() || candidate < it->second) best[key] = candidate;
            }
        }
        // Join parts with the shortest bridges first (a spanning forest), so
        // that a piece is not tied to everything within reach.
        std::vector<std::tuple<double, std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t>>
            order;
        for (const auto& [key, value] : best)
            order.emplace_back(std::get<0>(value), std::get<1>(value), std::get<2>(value),
                               key.first, key.second);
        std::sort(order.begin(), order.end());
        UnionFind joined(parts);
        std::uint32_t apart = parts;
        for (const auto& [d2, n, m, pa, pb] : order) {
            if (joined.find(pa) == joined.find(pb)) continue;
            joined.unite(pa, pb);
            --apart;
            g.edges.push_back({std::min(n, m), std::max(n, m)});
            ++g.bridgeCount;
        }
        if (apart > 1 && options.inside) bridgeThroughObject(g, part, joined, *options.inside);
        if (g.bridgeCount) buildAdjacency(g);
    }

    // Forks: where three or more branches of C_tau meet but no point's path
    // set goes round three parts (docs/algorithm.md §6, "Forks").
    std::vector<std::uint8_t> fork(g.nodeCount(), 0);
    std::vector<float> forkBodyRhoS(g.nodeCount(), 0.0f);
    if (options.forkJunctions && g.nodeCount()) {
        ForkSearch search(g.nodeCount());
        for (std::uint32_t n = 0; n < g.nodeCount(); ++n)
            if (!isJunctionPoint(points[g.point[n]]))
                fork[n] = search.countBranches(g, points, n, double(options.regionRadius),
                                               forkBodyRhoS[n]) >= 3;
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

}  // namespace skelseg
