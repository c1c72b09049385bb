#include "io/mesh/ContactSeparation.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <numeric>
#include <unordered_map>
#include <utility>

#include "io/mesh/ContactPatchSeams.h"
#include "io/mesh/ContactSurfaceGraph.h"
#include "io/mesh/Vec3Arithmetic.h"
#include "kernels/SeveredObjects.h"
#include "kernels/VoxelGenus.h"
#include "kernels/base/ParallelFor.h"

namespace skelseg {

namespace {

using vec3::closestPointOnTriangle;
using vec3::distance;
using vec3::dot;
using vec3::sub;
using vec3::Vec3;

struct CandidatePair {
    std::uint32_t a, b;     // voxel indices
    std::int32_t ta, tb;    // nearest triangles, ta < tb
    double depthA, depthB;  // signed depth of each voxel centre (negative: outside)
    double spaceDistance;   // |pa - pb|
    Vec3 pa, pb;            // surface points (index space), pa on ta
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
    // The nearest triangle of each object voxel of slice z as the mesh's
    // geometry names it, not its face order (SurfaceGraph::nearestOfTied);
    // -1 where unknown or outside.
    const std::size_t sliceSize = std::size_t(d.x) * std::size_t(d.y);
    auto nearestInSlice = [&](int z, std::vector<std::int32_t>& slice) {
        slice.assign(sliceSize, -1);
        if (z >= d.z) return;
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) {
                const std::size_t i = mask.index(x, y, z);
                const std::int32_t t = nearestTriangle[i];
                if (!mask.data()[i] || t < 0 || t >= triangleCount) continue;
                slice[i - sliceSize * std::size_t(z)] =
                    graph.nearestOfTied(t, Vec3{double(x), double(y), double(z)});
            }
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
            // The forward neighbours lie in this slice and the next.
            std::vector<std::int32_t> slice, nextSlice;
            nearestInSlice(zBegin, slice);
            for (int z = zBegin; z < zEnd; ++z) {
                if (stopped || interrupter.wasInterrupted()) {
                    stopped = true;
                    return;
                }
                nearestInSlice(z + 1, nextSlice);
                auto triangleAt = [&](std::size_t i) {
                    const std::size_t base = sliceSize * std::size_t(z);
                    return i < base + sliceSize ? slice[i - base] : nextSlice[i - base - sliceSize];
                };
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
                slice.swap(nextSlice);
            }
        },
        options.threaded);
    if (stopped) throwInterrupted(interrupter);
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
    if (stopped) throwInterrupted(interrupter);

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
    std::sort(keptContacts.begin(), keptContacts.end());
    VoxelTopologyOptions topologyOptions;
    topologyOptions.threaded = options.threaded;
    VoxelTopology before;
    bool topologyKnown = false;
    std::vector<char> separatedLate(contacts.size(), 0);
    // Clears `seam` and keeps it where the whole model loses a handle and
    // gains no object or cavity: a kept contact c then counts as separated.
    const auto separatesKept = [&](std::size_t c, const std::vector<std::uint32_t>& seam,
                                   std::size_t& counter) {
        for (std::uint32_t i : seam) mask.data()[i] = 0;
        const VoxelTopology after = voxelTopology(mask, topologyOptions, interrupter);
        if (after.genus < before.genus && after.objects <= before.objects &&
            after.cavities <= before.cavities) {
            before = after;
            --result.contactsKept;
            ++result.contacts;
            ++counter;
            if (rejoined[c]) --result.contactsRejoined;
            result.voxelsCleared += seam.size();
            separatedLate[c] = 1;
            return true;
        }
        for (std::uint32_t i : seam) mask.data()[i] = 1;
        return false;
    };
    if (options.patchSeams && !keptContacts.empty()) {
        before = voxelTopology(mask, topologyOptions, interrupter);
        topologyKnown = true;
        const PatchSeamFinder finder(graph, mask, options);
        for (std::size_t c : keptContacts) {
            if (before.genus <= 0) break;
            throwIfInterrupted(interrupter);
            std::vector<std::pair<std::int32_t, std::int32_t>> triangles;
            triangles.reserve(contactPairs[c].size());
            for (std::size_t k : contactPairs[c]) triangles.push_back(pairTriangles[k]);
            for (const auto& seam : finder.seams(triangles, wideContacts[c]))
                if (separatesKept(c, seam, result.contactsPatchSeamed)) break;
        }
    }
    // 8. A kept contact's wide seam grown by one voxel into the object: the
    //    pairs found stop short of the contact's rim (the walls diverge
    //    there, and test 1 misses pairs whose voxels lie on one side of each
    //    other's wall), so the seam leaves links at its rim. Kept only where
    //    the whole model loses a handle and gains no object or cavity: it
    //    must free a handle the mesh does not have and never cut a sheet or
    //    a limb loose.
    if (options.grownSeams && !keptContacts.empty()) {
        if (!topologyKnown) before = voxelTopology(mask, topologyOptions, interrupter);
        for (std::size_t c : keptContacts) {
            if (before.genus <= 0) break;
            if (separatedLate[c]) continue;
            throwIfInterrupted(interrupter);
            std::vector<std::uint32_t> seam;
            for (std::uint32_t i : wideContacts[c]) {
                const auto p = coordOf(i);
                for (int dz = -1; dz <= 1; ++dz)
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx) {
                            if (!mask.contains(p[0] + dx, p[1] + dy, p[2] + dz)) continue;
                            const auto n =
                                std::uint32_t(mask.index(p[0] + dx, p[1] + dy, p[2] + dz));
                            if (mask.data()[n]) seam.push_back(n);
                        }
            }
            std::sort(seam.begin(), seam.end());
            seam.erase(std::unique(seam.begin(), seam.end()), seam.end());
            separatesKept(c, seam, result.contactsGrown);
        }
    }
    return result;
}

}  // namespace skelseg
