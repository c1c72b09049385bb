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
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairVoxels;  // (cleared, other)
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
    {
        std::unordered_map<std::uint32_t, std::size_t> contactOf;
        for (std::size_t k = 0; k < cleared.size(); ++k) {
            const auto [it, inserted] = contactOf.emplace(root(std::uint32_t(k)), contacts.size());
            if (inserted) contacts.emplace_back();
            contacts[it->second].push_back(cleared[k]);
        }
        wideContacts = contacts;
        for (const auto& [shallower, other] : pairVoxels) {
            const auto it = std::lower_bound(cleared.begin(), cleared.end(), shallower);
            wideContacts[contactOf.at(root(std::uint32_t(it - cleared.begin())))].push_back(other);
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
    for (std::size_t c = 0; c < contacts.size(); ++c) {
        throwIfInterrupted(interrupter);
        const std::vector<std::uint32_t>* seam = &contacts[c];
        if (changeAddsTopology(mask, cellsOf(*seam), 0)) {
            seam = &wideContacts[c];
            if (seam->size() == contacts[c].size() || changeAddsTopology(mask, cellsOf(*seam), 0)) {
                ++result.contactsKept;
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
    }
    result.contactPairs = pairs;
    return result;
}

}  // namespace skelseg
