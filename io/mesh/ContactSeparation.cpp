#include "io/mesh/ContactSeparation.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <mutex>
#include <numeric>
#include <queue>
#include <unordered_map>
#include <utility>

#include "io/mesh/MeshCheck.h"
#include "io/mesh/MeshOrientation.h"
#include "io/mesh/Vec3Arithmetic.h"
#include "kernels/SeveredObjects.h"
#include "kernels/VoxelGenus.h"
#include "kernels/base/ParallelFor.h"

namespace skelseg {

namespace {

using vec3::dot;
using vec3::sub;
using vec3::Vec3;

double distance(const Vec3& a, const Vec3& b) {
    return std::sqrt(dot(sub(a, b), sub(a, b)));
}
Vec3 along(const Vec3& a, const Vec3& d, double t) {
    return {a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]};
}

/// Point of triangle (a, b, c) nearest to p (Ericson, Real-Time Collision
/// Detection, 5.1.5: the Voronoi region of p decides vertex, edge or face).
Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const Vec3 bp = sub(p, b);
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return along(a, ab, d1 / (d1 - d3));
    const Vec3 cp = sub(p, c);
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return along(a, ac, d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return along(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const double denominator = va + vb + vc;
    if (!(denominator > 0)) return a;  // degenerate triangle
    const double v = vb / denominator, w = vc / denominator;
    return {a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w,
            a[2] + ab[2] * v + ac[2] * w};
}

struct CandidatePair {
    std::uint32_t a, b;     // voxel indices
    std::int32_t ta, tb;    // nearest triangles, ta < tb
    double depthA, depthB;  // signed depth of each voxel centre (negative: outside)
    double spaceDistance;   // |pa - pb|
    Vec3 pa, pb;            // surface points (index space), pa on ta
};

/// The mesh as a graph over canonical vertices, in voxel index space.
struct SurfaceGraph {
    std::vector<Vec3> points;                             // per vertex
    std::vector<std::array<std::uint32_t, 3>> triangles;  // canonical corners
    std::vector<std::uint32_t> piece;                     // per triangle
    /// Per triangle: +1 when its normal (right hand rule) points out of the
    /// solid, -1 when in, 0 when its piece is not consistently oriented.
    std::vector<std::int8_t> orientation;
    std::vector<std::uint32_t> firstNeighbour, neighbours;  // CSR

    bool adjacent(std::uint32_t u, std::uint32_t v) const {
        return std::binary_search(neighbours.begin() + firstNeighbour[u],
                                  neighbours.begin() + firstNeighbour[u + 1], v);
    }

    /// True when pa (on triangle ta) and pb (on tb) are joined by a path
    /// along mesh edges no longer than `limit`.
    bool nearOnMesh(std::int32_t ta, const Vec3& pa, std::int32_t tb, const Vec3& pb,
                    double limit) const {
        const auto& A = triangles[std::size_t(ta)];
        const auto& B = triangles[std::size_t(tb)];
        for (std::uint32_t u : A)
            for (std::uint32_t v : B)
                if (u == v || adjacent(u, v)) return true;
        std::unordered_map<std::uint32_t, double> settled, best;
        using Entry = std::pair<double, std::uint32_t>;
        std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
        for (std::uint32_t u : A) {
            const double d = distance(pa, points[u]);
            auto [it, inserted] = best.emplace(u, d);
            if (inserted || d < it->second) {
                it->second = d;
                queue.emplace(d, u);
            }
        }
        while (!queue.empty()) {
            const auto [d, u] = queue.top();
            queue.pop();
            if (d > limit) return false;
            if (!settled.emplace(u, d).second) continue;
            for (std::uint32_t v : B)
                if (u == v && d + distance(points[v], pb) <= limit) return true;
            for (std::uint32_t n = firstNeighbour[u]; n < firstNeighbour[u + 1]; ++n) {
                const std::uint32_t v = neighbours[n];
                if (settled.count(v)) continue;
                const double candidate = d + distance(points[u], points[v]);
                if (candidate > limit) continue;
                auto [it, inserted] = best.emplace(v, candidate);
                if (inserted || candidate < it->second) {
                    it->second = candidate;
                    queue.emplace(candidate, v);
                }
            }
        }
        return false;
    }
};

SurfaceGraph buildSurfaceGraph(const TriangleMesh& mesh, const VolumeGeometry& geometry) {
    SurfaceGraph graph;
    const std::vector<std::uint32_t> canonical = canonicalVertices(mesh);
    const double inverseVoxel = 1.0 / geometry.voxelSize();
    graph.points.resize(mesh.vertices.size());
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
        for (std::size_t c = 0; c < 3; ++c)
            graph.points[v][c] = (mesh.vertices[v][c] - geometry.origin[c]) * inverseVoxel;
    std::vector<std::uint32_t> parent(mesh.vertices.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    edges.reserve(mesh.triangles.size() * 6);
    graph.triangles.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) {
        const std::array<std::uint32_t, 3> c{canonical[t[0]], canonical[t[1]], canonical[t[2]]};
        graph.triangles.push_back(c);
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t u = c[k], v = c[(k + 1) % 3];
            if (u == v) continue;
            edges.emplace_back(u, v);
            edges.emplace_back(v, u);
            const std::uint32_t ru = find(u), rv = find(v);
            if (ru != rv) parent[std::max(ru, rv)] = std::min(ru, rv);
        }
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    graph.firstNeighbour.assign(mesh.vertices.size() + 1, 0);
    for (const auto& e : edges) ++graph.firstNeighbour[e.first + 1];
    std::partial_sum(graph.firstNeighbour.begin(), graph.firstNeighbour.end(),
                     graph.firstNeighbour.begin());
    graph.neighbours.reserve(edges.size());
    for (const auto& e : edges) graph.neighbours.push_back(e.second);
    graph.piece.reserve(graph.triangles.size());
    for (const auto& c : graph.triangles) graph.piece.push_back(find(c[0]));

    graph.orientation = triangleOrientation(graph.triangles, graph.points, graph.piece);
    return graph;
}

/// The seams of step 7 for one contact kept: its triangles are split into the
/// contact's two sides, each side grown along the mesh into a patch, and the
/// object voxels near both patches are placed by their signed distances to
/// the two patches (see seamsAround).
class PatchSeamFinder {
public:
    PatchSeamFinder(const SurfaceGraph& graph, const MaskVolume& mask,
                    const ContactSeparationOptions& options)
        : mGraph(graph), mMask(mask), mGrowth(options.patchGrowth), mReach(options.patchReach) {}

    /// Up to three seams (voxel indices) in the order to try: into the side
    /// with more voxels near both patches (a head rather than the thin ear
    /// lying on it), into the other, half into each; none where the sides
    /// cannot be told apart (a piece not oriented, or over a tenth of the
    /// pairs with both triangles on one side).
    std::vector<std::vector<std::uint32_t>> seams(
        const std::vector<std::pair<std::int32_t, std::int32_t>>& pairs,
        const std::vector<std::uint32_t>& voxels) const {
        std::vector<std::pair<std::uint32_t, int>> patch;  // (triangle, side), by triangle
        if (!sidesOf(pairs, patch)) return {};
        return seamsAround(patch, voxels);
    }

private:
    /// The triangles within mGrowth along the mesh of the contact's
    /// triangles, each with its side (0, 1). Seeds joined along the mesh
    /// within mGrowth tend to one side, the two triangles of a pair to two.
    bool sidesOf(const std::vector<std::pair<std::int32_t, std::int32_t>>& pairs,
                 std::vector<std::pair<std::uint32_t, int>>& patch) const {
        std::vector<std::uint32_t> seeds;
        for (const auto& [ta, tb] : pairs) {
            seeds.push_back(std::uint32_t(ta));
            seeds.push_back(std::uint32_t(tb));
        }
        std::sort(seeds.begin(), seeds.end());
        seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
        for (std::uint32_t t : seeds)
            if (mGraph.orientation[t] == 0) return false;
        auto seedOf = [&](std::int32_t t) {
            return std::uint32_t(std::lower_bound(seeds.begin(), seeds.end(), std::uint32_t(t)) -
                                 seeds.begin());
        };
        // Links between seeds: +1 for each mesh edge where the growths of
        // two seeds meet within mGrowth (same side), -1 for each pair
        // (opposite sides).
        std::unordered_map<std::uint64_t, std::int64_t> link;
        auto addLink = [&](std::uint32_t s, std::uint32_t t, std::int64_t weight) {
            if (s == t) return;
            link[(std::uint64_t(std::min(s, t)) << 32) | std::max(s, t)] += weight;
        };
        struct Reached {
            double distance;
            std::uint32_t seed;
            bool settled;
        };
        std::unordered_map<std::uint32_t, Reached> reached;
        using Entry = std::pair<double, std::uint32_t>;
        std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
        for (std::uint32_t s = 0; s < seeds.size(); ++s)
            for (std::uint32_t v : mGraph.triangles[seeds[s]]) {
                const auto [it, inserted] = reached.emplace(v, Reached{0.0, s, false});
                if (inserted)
                    queue.emplace(0.0, v);
                else
                    addLink(it->second.seed, s, 1);
            }
        while (!queue.empty()) {
            const auto [d, u] = queue.top();
            queue.pop();
            Reached& at = reached.at(u);
            if (at.settled || d > at.distance) continue;
            at.settled = true;
            const std::uint32_t seed = at.seed;
            for (std::uint32_t n = mGraph.firstNeighbour[u]; n < mGraph.firstNeighbour[u + 1];
                 ++n) {
                const std::uint32_t v = mGraph.neighbours[n];
                const double next = d + distance(mGraph.points[u], mGraph.points[v]);
                const auto it = reached.find(v);
                if (it != reached.end() && it->second.settled &&
                    next + it->second.distance <= mGrowth)
                    addLink(seed, it->second.seed, 1);
                if (next > mGrowth) continue;
                if (it == reached.end()) {
                    reached.emplace(v, Reached{next, seed, false});
                    queue.emplace(next, v);
                } else if (!it->second.settled && next < it->second.distance) {
                    it->second = Reached{next, seed, false};
                    queue.emplace(next, v);
                }
            }
        }
        for (const auto& [ta, tb] : pairs) addLink(seedOf(ta), seedOf(tb), -1);
        std::vector<std::vector<std::pair<std::uint32_t, std::int64_t>>> links(seeds.size());
        for (const auto& [key, weight] : link) {
            if (weight == 0) continue;
            const auto s = std::uint32_t(key >> 32), t = std::uint32_t(key & 0xffffffffu);
            links[s].emplace_back(t, weight);
            links[t].emplace_back(s, weight);
        }
        for (auto& list : links) std::sort(list.begin(), list.end());
        // Sides by vote, breadth first: a seed takes the side its sides'
        // links to the seeds already placed favour. A few links across a
        // crease (the contact reaching the fold where the two surfaces meet)
        // are outvoted instead of joining the two sides.
        std::vector<int> sideOfSeed(seeds.size(), -1);
        for (std::uint32_t start = 0; start < seeds.size(); ++start) {
            if (sideOfSeed[start] >= 0) continue;
            sideOfSeed[start] = 0;
            std::queue<std::uint32_t> next;
            next.push(start);
            while (!next.empty()) {
                const std::uint32_t s = next.front();
                next.pop();
                for (const auto& [t, weight] : links[s]) {
                    if (sideOfSeed[t] >= 0) continue;
                    std::int64_t vote = 0;  // > 0: side 0
                    for (const auto& [u, w] : links[t])
                        if (sideOfSeed[u] >= 0) vote += sideOfSeed[u] == 0 ? w : -w;
                    sideOfSeed[t] = vote >= 0 ? 0 : 1;
                    next.push(t);
                }
            }
        }
        std::size_t crossing = 0;
        for (const auto& [ta, tb] : pairs)
            crossing += sideOfSeed[seedOf(ta)] == sideOfSeed[seedOf(tb)];
        if (crossing * 10 > pairs.size()) return false;
        // Each triangle touched by the growth takes the side of its nearest
        // reached corner (ties: side 0); the seeds keep their own.
        std::unordered_map<std::uint32_t, std::pair<double, int>> nearest;
        for (std::uint32_t s = 0; s < seeds.size(); ++s) nearest[seeds[s]] = {-1.0, sideOfSeed[s]};
        for (const auto& [v, r] : reached) {
            if (!r.settled) continue;
            const int sideOfV = sideOfSeed[r.seed];
            for (std::size_t t : trianglesAt(v)) {
                const auto [it, inserted] =
                    nearest.emplace(std::uint32_t(t), std::make_pair(r.distance, sideOfV));
                if (!inserted && std::make_pair(r.distance, sideOfV) < it->second)
                    it->second = {r.distance, sideOfV};
            }
        }
        patch.clear();
        for (const auto& [t, entry] : nearest) patch.emplace_back(t, entry.second);
        std::sort(patch.begin(), patch.end());
        return true;
    }

    const std::vector<std::uint32_t>& trianglesAt(std::uint32_t v) const {
        std::call_once(mIncidenceBuilt, [this] {
            mIncidence.assign(mGraph.points.size(), {});
            for (std::uint32_t t = 0; t < mGraph.triangles.size(); ++t)
                for (std::uint32_t u : mGraph.triangles[t])
                    if (mIncidence[u].empty() || mIncidence[u].back() != t)
                        mIncidence[u].push_back(t);
        });
        return mIncidence[v];
    }

    /// Signed distance of p to triangle t: positive inside the solid.
    double signedDistance(std::uint32_t t, const Vec3& p) const {
        const auto& c = mGraph.triangles[t];
        const Vec3& a = mGraph.points[c[0]];
        const Vec3 q = closestPointOnTriangle(p, a, mGraph.points[c[1]], mGraph.points[c[2]]);
        const Vec3 e1 = sub(mGraph.points[c[1]], a), e2 = sub(mGraph.points[c[2]], a);
        const Vec3 normal{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                          e1[0] * e2[1] - e1[1] * e2[0]};
        const double length = distance(p, q);
        return mGraph.orientation[t] * dot(normal, sub(p, q)) > 0 ? -length : length;
    }

    std::vector<std::vector<std::uint32_t>> seamsAround(
        const std::vector<std::pair<std::uint32_t, int>>& patch,
        const std::vector<std::uint32_t>& voxels) const {
        const Dims d = mMask.dims();
        const int margin = int(std::ceil(mReach)) + 1;
        std::array<int, 3> lo{d.x, d.y, d.z}, hi{-1, -1, -1};
        const std::array<int, 3> dims{d.x, d.y, d.z};
        for (std::uint32_t i : voxels) {
            const std::array<int, 3> c{int(i % std::uint32_t(d.x)),
                                       int(i / std::uint32_t(d.x) % std::uint32_t(d.y)),
                                       int(i / (std::uint32_t(d.x) * std::uint32_t(d.y)))};
            for (int k = 0; k < 3; ++k) {
                lo[k] = std::min(lo[k], c[k]);
                hi[k] = std::max(hi[k], c[k]);
            }
        }
        std::array<int, 3> size{}, cells{};
        constexpr int kCell = 2;
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::max(0, lo[k] - margin);
            hi[k] = std::min(dims[k] - 1, hi[k] + margin);
            size[k] = hi[k] - lo[k] + 1;
            cells[k] = (size[k] + kCell - 1) / kCell;
        }
        // Patch triangles by the cells of the box they come within mReach of.
        const std::size_t cellCount = std::size_t(cells[0]) * cells[1] * cells[2];
        std::vector<std::vector<std::uint32_t>> inCell(cellCount);
        for (std::size_t k = 0; k < patch.size(); ++k) {
            const auto& c = mGraph.triangles[patch[k].first];
            std::array<int, 3> from{}, to{};
            bool outside = false;
            for (int a = 0; a < 3; ++a) {
                double low = mGraph.points[c[0]][a], high = low;
                for (int j = 1; j < 3; ++j) {
                    low = std::min(low, mGraph.points[c[j]][a]);
                    high = std::max(high, mGraph.points[c[j]][a]);
                }
                low -= mReach + lo[a];
                high += mReach - lo[a];
                if (high < 0 || low > size[a] - 1) outside = true;
                from[a] = std::clamp(int(std::floor(low)) / kCell, 0, cells[a] - 1);
                to[a] = std::clamp(int(std::floor(high)) / kCell, 0, cells[a] - 1);
                if (low < 0) from[a] = 0;
            }
            if (outside) continue;
            for (int z = from[2]; z <= to[2]; ++z)
                for (int y = from[1]; y <= to[1]; ++y)
                    for (int x = from[0]; x <= to[0]; ++x)
                        inCell[(std::size_t(z) * cells[1] + y) * cells[0] + x].push_back(
                            std::uint32_t(k));
        }
        // Each object voxel near both patches lies on the side in whose solid
        // it lies deeper: f = depth in side 0 - depth in side 1 (signed,
        // positive inside) is 0 on the middle surface between the patches and
        // changes by at most 2 * sqrt(3) between 26-neighbours. So the voxels
        // of one side with |f| <= 2 * sqrt(3) (about sqrt(3) voxels deep)
        // part it from the other side, and the voxels with |f| <= sqrt(3)
        // part both sides, half as deep into each. Voxels inside both solids
        // are where the two surfaces join (a crease beside the contact):
        // their middle surface runs through the solid, and they are left.
        const double band = std::sqrt(3.0);
        std::array<std::vector<std::uint32_t>, 2> oneSided;
        std::vector<std::uint32_t> bothSides;
        for (int z = lo[2]; z <= hi[2]; ++z)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int x = lo[0]; x <= hi[0]; ++x) {
                    if (!mMask(x, y, z)) continue;
                    const Vec3 p{double(x), double(y), double(z)};
                    std::array<double, 2> nearest{mReach, mReach}, depth{0, 0};
                    std::array<bool, 2> near{false, false};
                    const auto& list = inCell[(std::size_t((z - lo[2]) / kCell) * cells[1] +
                                               std::size_t((y - lo[1]) / kCell)) *
                                                  cells[0] +
                                              std::size_t((x - lo[0]) / kCell)];
                    for (std::uint32_t k : list) {
                        const auto [t, side] = patch[k];
                        const double s = signedDistance(t, p);
                        if (std::abs(s) < nearest[side] ||
                            (!near[side] && std::abs(s) <= nearest[side])) {
                            nearest[side] = std::abs(s);
                            depth[side] = s;
                            near[side] = true;
                        }
                    }
                    if (!near[0] || !near[1] || std::min(depth[0], depth[1]) > 0) continue;
                    const double f = depth[0] - depth[1];
                    const auto i = std::uint32_t(mMask.index(x, y, z));
                    if (std::abs(f) <= 2 * band) oneSided[f >= 0 ? 0 : 1].push_back(i);
                    if (std::abs(f) <= band) bothSides.push_back(i);
                }
        std::vector<std::vector<std::uint32_t>> result;
        const int larger = oneSided[1].size() > oneSided[0].size() ? 1 : 0;
        for (auto* seam : {&oneSided[larger], &oneSided[1 - larger], &bothSides})
            if (!seam->empty()) result.push_back(std::move(*seam));
        return result;
    }

    const SurfaceGraph& mGraph;
    const MaskVolume& mMask;
    double mGrowth, mReach;
    mutable std::once_flag mIncidenceBuilt;
    mutable std::vector<std::vector<std::uint32_t>> mIncidence;
};

}  // namespace

ContactSeparation separateContacts(const TriangleMesh& mesh, MaskVolume& mask,
                                   const std::vector<std::int32_t>& nearestTriangle,
                                   const ContactSeparationOptions& options,
                                   Interrupter& interrupter) {
    if (nearestTriangle.size() != mask.size())
        throw UsageError("separateContacts: one nearest triangle per voxel is needed");
    ContactSeparation result;
    if (mesh.triangles.empty() || mask.empty()) return result;
    const SurfaceGraph graph = buildSurfaceGraph(mesh, mask.geometry);
    throwIfInterrupted(interrupter);
    const Dims d = mask.dims();
    const std::int32_t triangleCount = std::int32_t(mesh.triangles.size());
    auto triangleAt = [&](std::size_t i) {
        const std::int32_t t = nearestTriangle[i];
        return t >= 0 && t < triangleCount ? t : -1;
    };
    auto surfacePoint = [&](std::int32_t t, const Vec3& p) {
        const auto& c = graph.triangles[std::size_t(t)];
        return closestPointOnTriangle(p, graph.points[c[0]], graph.points[c[1]],
                                      graph.points[c[2]]);
    };
    // Direction into the solid at a voxel's surface point, and the voxel's
    // depth (negative when its centre lies outside the surface). OpenVDB's
    // sign fill marks the voxels in a gap narrower than a voxel as inside;
    // where the mesh is consistently oriented, the nearest triangle's normal
    // tells them apart, so they turn to face the wall across the gap and
    // are the first to be cleared.
    auto inwardAt = [&](std::int32_t t, const Vec3& v, const Vec3& pv, double& depth) {
        Vec3 inward = sub(v, pv);
        depth = std::sqrt(dot(inward, inward));
        const std::int8_t orientation = graph.orientation[std::size_t(t)];
        if (orientation != 0) {
            const auto& c = graph.triangles[std::size_t(t)];
            const Vec3 e1 = sub(graph.points[c[1]], graph.points[c[0]]);
            const Vec3 e2 = sub(graph.points[c[2]], graph.points[c[0]]);
            const Vec3 normal{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                              e1[0] * e2[1] - e1[1] * e2[0]};
            if (orientation * dot(normal, inward) > 0) {
                inward = {-inward[0], -inward[1], -inward[2]};
                depth = -depth;
            }
        }
        return inward;
    };

    // 1. Pairs of neighbouring object voxels whose surfaces face each other
    //    (the 13 forward neighbours of each voxel: every pair once).
    static const int kForward[13][3] = {{1, 0, 0},  {-1, 1, 0}, {0, 1, 0},  {1, 1, 0}, {-1, -1, 1},
                                        {0, -1, 1}, {1, -1, 1}, {-1, 0, 1}, {0, 0, 1}, {1, 0, 1},
                                        {-1, 1, 1}, {0, 1, 1},  {1, 1, 1}};
    constexpr double kOnSurface = 1e-6;  // voxel centre on its triangle: no direction
    std::vector<std::vector<CandidatePair>> perSlab(std::size_t(d.z));
    std::atomic<bool> stopped{false};
    parallelFor(
        d.z,
        [&](int zBegin, int zEnd) {
            for (int z = zBegin; z < zEnd; ++z) {
                if (stopped || interrupter.wasInterrupted()) {
                    stopped = true;
                    return;
                }
                auto& out = perSlab[std::size_t(z)];
                for (int y = 0; y < d.y; ++y)
                    for (int x = 0; x < d.x; ++x) {
                        const std::size_t ia = mask.index(x, y, z);
                        const std::int32_t ta = triangleAt(ia);
                        if (!mask.data()[ia] || ta < 0) continue;
                        const Vec3 a{double(x), double(y), double(z)};
                        const Vec3 pa = surfacePoint(ta, a);
                        double depthA = 0;
                        const Vec3 inA = inwardAt(ta, a, pa, depthA);
                        if (std::abs(depthA) < kOnSurface) continue;
                        for (const auto& o : kForward) {
                            const int bx = x + o[0], by = y + o[1], bz = z + o[2];
                            if (!mask.contains(bx, by, bz)) continue;
                            const std::size_t ib = mask.index(bx, by, bz);
                            const std::int32_t tb = triangleAt(ib);
                            if (!mask.data()[ib] || tb < 0 || tb == ta) continue;
                            if (graph.piece[std::size_t(ta)] != graph.piece[std::size_t(tb)])
                                continue;
                            const Vec3 b{double(bx), double(by), double(bz)};
                            // Which side of the other's wall each voxel lies
                            // on (negative: outside that wall's solid).
                            const double bSideOfA = dot(sub(b, pa), inA);
                            if (bSideOfA >= 0 && depthA >= 0) continue;
                            const Vec3 pb = surfacePoint(tb, b);
                            double depthB = 0;
                            const Vec3 inB = inwardAt(tb, b, pb, depthB);
                            if (std::abs(depthB) < kOnSurface) continue;
                            const double aSideOfB = dot(sub(a, pb), inB);
                            const bool facing = bSideOfA < 0 && aSideOfB < 0;
                            const bool crossed =
                                depthA < 0 && depthB < 0 && bSideOfA > 0 && aSideOfB > 0;
                            if (!facing && !crossed) continue;
                            CandidatePair pair{std::uint32_t(ia),
                                               std::uint32_t(ib),
                                               ta,
                                               tb,
                                               depthA,
                                               depthB,
                                               distance(pa, pb),
                                               pa,
                                               pb};
                            if (pair.ta > pair.tb) {
                                std::swap(pair.a, pair.b);
                                std::swap(pair.ta, pair.tb);
                                std::swap(pair.depthA, pair.depthB);
                                std::swap(pair.pa, pair.pb);
                            }
                            out.push_back(pair);
                        }
                    }
            }
        },
        options.threaded);
    if (stopped) throwIfInterrupted(interrupter);
    std::vector<CandidatePair> candidates;
    for (auto& slab : perSlab) candidates.insert(candidates.end(), slab.begin(), slab.end());
    perSlab.clear();

    // 2. Far on the mesh? Decided once per triangle pair, from the pair of
    //    voxels whose surface points are closest (ties: the first in voxel
    //    order, so the answer does not depend on the thread count).
    std::vector<std::size_t> order(candidates.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) {
        const auto& p = candidates[i];
        const auto& q = candidates[j];
        if (p.ta != q.ta) return p.ta < q.ta;
        if (p.tb != q.tb) return p.tb < q.tb;
        if (p.spaceDistance != q.spaceDistance) return p.spaceDistance < q.spaceDistance;
        return i < j;
    });
    std::vector<std::size_t> representatives;  // first entry of each triangle pair in `order`
    for (std::size_t k = 0; k < order.size(); ++k)
        if (k == 0 || candidates[order[k]].ta != candidates[order[k - 1]].ta ||
            candidates[order[k]].tb != candidates[order[k - 1]].tb)
            representatives.push_back(k);
    std::vector<char> far(representatives.size(), 0);
    parallelForEach(
        representatives.size(),
        [&](std::size_t r) {
            if (stopped || ((r & 255) == 0 && interrupter.wasInterrupted())) {
                stopped = true;
                return;
            }
            const auto& p = candidates[order[representatives[r]]];
            const double limit = options.farOnMesh + options.farOnMeshRatio * p.spaceDistance;
            far[r] = !graph.nearOnMesh(p.ta, p.pa, p.tb, p.pb, limit);
        },
        options.threaded, 16);
    if (stopped) throwIfInterrupted(interrupter);

    // 3. The shallower voxel of every contact pair is to be cleared.
    //    Both voxels of each pair are kept too, for the wider seam of step 5.
    std::vector<std::uint32_t> cleared;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairVoxels;   // (cleared, other)
    std::vector<std::pair<std::int32_t, std::int32_t>> pairTriangles;  // beside pairVoxels
    std::size_t pairs = 0;
    for (std::size_t r = 0; r < representatives.size(); ++r) {
        if (!far[r]) continue;
        const std::size_t end =
            r + 1 < representatives.size() ? representatives[r + 1] : order.size();
        for (std::size_t k = representatives[r]; k < end; ++k) {
            const auto& p = candidates[order[k]];
            ++pairs;
            const std::uint32_t shallower = p.depthA <= p.depthB ? p.a : p.b;
            cleared.push_back(shallower);
            if (p.depthA == p.depthB) cleared.push_back(p.b);
            pairVoxels.emplace_back(shallower, shallower == p.a ? p.b : p.a);
            pairTriangles.emplace_back(p.ta, p.tb);
        }
    }
    std::sort(cleared.begin(), cleared.end());
    cleared.erase(std::unique(cleared.begin(), cleared.end()), cleared.end());

    // 4. Group them: 26-connected groups of voxels to clear, one per contact.
    std::vector<std::uint32_t> group(cleared.size());
    std::iota(group.begin(), group.end(), 0u);
    auto root = [&](std::uint32_t x) {
        while (group[x] != x) x = group[x] = group[group[x]];
        return x;
    };
    auto coordOf = [&](std::uint32_t i) {
        return std::array<int, 3>{int(i % std::uint32_t(d.x)),
                                  int(i / std::uint32_t(d.x) % std::uint32_t(d.y)),
                                  int(i / (std::uint32_t(d.x) * std::uint32_t(d.y)))};
    };
    for (std::size_t k = 0; k < cleared.size(); ++k) {
        const auto c = coordOf(cleared[k]);
        for (const auto& o : kForward) {
            if (!mask.contains(c[0] + o[0], c[1] + o[1], c[2] + o[2])) continue;
            const auto n = std::uint32_t(mask.index(c[0] + o[0], c[1] + o[1], c[2] + o[2]));
            const auto it = std::lower_bound(cleared.begin(), cleared.end(), n);
            if (it == cleared.end() || *it != n) continue;
            const std::uint32_t ra = root(std::uint32_t(k)),
                                rb = root(std::uint32_t(it - cleared.begin()));
            if (ra != rb) group[std::max(ra, rb)] = std::min(ra, rb);
        }
    }
    std::vector<std::vector<std::uint32_t>> contacts, wideContacts;
    std::vector<std::vector<std::size_t>> contactPairs;  // indices into pairVoxels
    {
        std::unordered_map<std::uint32_t, std::size_t> contactOf;
        for (std::size_t k = 0; k < cleared.size(); ++k) {
            const auto [it, inserted] = contactOf.emplace(root(std::uint32_t(k)), contacts.size());
            if (inserted) contacts.emplace_back();
            contacts[it->second].push_back(cleared[k]);
        }
        wideContacts = contacts;
        contactPairs.resize(contacts.size());
        for (std::size_t k = 0; k < pairVoxels.size(); ++k) {
            const auto [shallower, other] = pairVoxels[k];
            const auto it = std::lower_bound(cleared.begin(), cleared.end(), shallower);
            const std::size_t c = contactOf.at(root(std::uint32_t(it - cleared.begin())));
            wideContacts[c].push_back(other);
            contactPairs[c].push_back(k);
        }
        for (auto& wide : wideContacts) {
            std::sort(wide.begin(), wide.end());
            wide.erase(std::unique(wide.begin(), wide.end()), wide.end());
        }
    }

    // 5. A contact is cleared only when that does not add topology around it:
    //    where some pairs of a contact were missed (or judged near), clearing
    //    the rest can punch a hole or leave a cavity instead of separating.
    //    Judged on the box around the contact, two voxels wider, before and
    //    after clearing: accepted when its genus does not grow and no cavity
    //    appears.
    //    Where the walls cross or touch at a slant, the shallower voxels of
    //    neighbouring pairs can lie on alternate sides of the contact and
    //    leave diagonal links between them (a staircase seam, which the check
    //    rejects): then both voxels of every pair, a seam two voxels wide,
    //    are tried under the same check.
    auto cellsOf = [&](const std::vector<std::uint32_t>& voxels) {
        std::vector<std::array<int, 3>> cells;
        cells.reserve(voxels.size());
        for (std::uint32_t i : voxels) cells.push_back(coordOf(i));
        return cells;
    };
    std::vector<ClearedGroup> clearedGroups;
    std::vector<std::size_t> clearedContact;  // beside clearedGroups
    std::vector<std::size_t> keptContacts;
    std::vector<char> rejoined(contacts.size(), 0);
    for (std::size_t c = 0; c < contacts.size(); ++c) {
        throwIfInterrupted(interrupter);
        const std::vector<std::uint32_t>* seam = &contacts[c];
        if (changeAddsTopology(mask, cellsOf(*seam), 0)) {
            seam = &wideContacts[c];
            if (seam->size() == contacts[c].size() || changeAddsTopology(mask, cellsOf(*seam), 0)) {
                ++result.contactsKept;
                keptContacts.push_back(c);
                continue;
            }
        }
        ClearedGroup clearedNow;
        for (std::uint32_t i : *seam)
            if (mask.data()[i]) {
                mask.data()[i] = 0;
                clearedNow.push_back(coordOf(i));
            }
        ++result.contacts;
        result.voxelsCleared += clearedNow.size();
        clearedGroups.push_back(std::move(clearedNow));
        clearedContact.push_back(c);
    }
    // 6. A seam that cut an object in two (a thin limb next to the contact)
    //    is set back: the box of step 5 cannot see it (SeveredObjects.h).
    SeveredObjectsOptions severedOptions;
    severedOptions.threaded = options.threaded;
    const std::vector<bool> setBack =
        rejoinSeveredObjects(mask, clearedGroups, severedOptions, interrupter);
    for (std::size_t g = 0; g < setBack.size(); ++g) {
        if (!setBack[g]) continue;
        --result.contacts;
        ++result.contactsKept;
        ++result.contactsRejoined;
        result.voxelsCleared -= clearedGroups[g].size();
        keptContacts.push_back(clearedContact[g]);
        rejoined[clearedContact[g]] = 1;
    }
    result.contactPairs = pairs;

    // 7. Seams between the two mesh patches of each contact kept (see the
    //    header): tried only where the whole model has handles to lose.
    if (options.patchSeams && !keptContacts.empty()) {
        std::sort(keptContacts.begin(), keptContacts.end());
        VoxelTopologyOptions topologyOptions;
        topologyOptions.threaded = options.threaded;
        VoxelTopology before = voxelTopology(mask, topologyOptions, interrupter);
        const PatchSeamFinder finder(graph, mask, options);
        for (std::size_t c : keptContacts) {
            if (before.genus <= 0) break;
            throwIfInterrupted(interrupter);
            std::vector<std::pair<std::int32_t, std::int32_t>> triangles;
            triangles.reserve(contactPairs[c].size());
            for (std::size_t k : contactPairs[c]) triangles.push_back(pairTriangles[k]);
            for (const auto& seam : finder.seams(triangles, wideContacts[c])) {
                for (std::uint32_t i : seam) mask.data()[i] = 0;
                const VoxelTopology after = voxelTopology(mask, topologyOptions, interrupter);
                if (after.genus < before.genus && after.objects <= before.objects &&
                    after.cavities <= before.cavities) {
                    before = after;
                    --result.contactsKept;
                    ++result.contacts;
                    ++result.contactsPatchSeamed;
                    if (rejoined[c]) --result.contactsRejoined;
                    result.voxelsCleared += seam.size();
                    break;
                }
                for (std::uint32_t i : seam) mask.data()[i] = 1;
            }
        }
    }
    return result;
}

}  // namespace skelseg
