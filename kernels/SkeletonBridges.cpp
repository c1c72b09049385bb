#include "kernels/SkeletonBridges.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "kernels/DisjointSets.h"
#include "kernels/SkeletonGraphSearch.h"

namespace skelseg {

namespace {

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
                         DisjointSets& joined, const MaskVolume& inside) {
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
    DisjointSets groupsJoined(groups);
    for (const auto& [d2, a, b] : candidates) {
        if (groupsJoined.find(group[a]) == groupsJoined.find(group[b])) continue;
        if (!segmentInside(g.coord[a], g.coord[b], inside)) continue;
        groupsJoined.unite(group[a], group[b]);
        g.edges.push_back({std::min(a, b), std::max(a, b)});
        ++g.bridgeCount;
    }
}

}  // namespace

bool bridgeSkeletonParts(SkeletonGraph& g, const std::vector<SkeletonPoint>& points,
                         const SkeletonGraphOptions& options) {
    std::vector<std::uint32_t> part;
    const std::uint32_t parts = labelComponents(
        g, [](std::uint32_t) { return true; }, part);
    if (parts <= 1 || !(options.bridgeGap >= 1.0)) return false;
    const std::uint32_t bridgesBefore = g.bridgeCount;
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
        order.emplace_back(std::get<0>(value), std::get<1>(value), std::get<2>(value), key.first,
                           key.second);
    std::sort(order.begin(), order.end());
    DisjointSets joined(parts);
    std::uint32_t apart = parts;
    for (const auto& [d2, n, m, pa, pb] : order) {
        if (joined.find(pa) == joined.find(pb)) continue;
        joined.unite(pa, pb);
        --apart;
        g.edges.push_back({std::min(n, m), std::max(n, m)});
        ++g.bridgeCount;
    }
    if (apart > 1 && options.inside) bridgeThroughObject(g, part, joined, *options.inside);
    return g.bridgeCount != bridgesBefore;
}

}  // namespace skelseg
