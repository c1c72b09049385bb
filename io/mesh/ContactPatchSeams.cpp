#include "io/mesh/ContactPatchSeams.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>
#include <unordered_map>
#include <utility>

namespace skelseg {

using vec3::closestPointOnTriangle;
using vec3::distance;
using vec3::dot;
using vec3::sub;
using vec3::Vec3;

PatchSeamFinder::PatchSeamFinder(const SurfaceGraph& graph, const MaskVolume& mask,
                                 const ContactSeparationOptions& options)
    : mGraph(graph), mMask(mask), mGrowth(options.patchGrowth), mReach(options.patchReach) {}

std::vector<std::vector<std::uint32_t>> PatchSeamFinder::seams(
    const std::vector<std::pair<std::int32_t, std::int32_t>>& pairs,
    const std::vector<std::uint32_t>& voxels) const {
    std::vector<std::pair<std::uint32_t, int>> patch;  // (triangle, side), by triangle
    if (!sidesOf(pairs, patch)) return {};
    return seamsAround(patch, voxels);
}

bool PatchSeamFinder::sidesOf(const std::vector<std::pair<std::int32_t, std::int32_t>>& pairs,
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
        for (std::uint32_t n = mGraph.firstNeighbour[u]; n < mGraph.firstNeighbour[u + 1]; ++n) {
            const std::uint32_t v = mGraph.neighbours[n];
            const double next = d + distance(mGraph.points[u], mGraph.points[v]);
            const auto it = reached.find(v);
            if (it != reached.end() && it->second.settled && next + it->second.distance <= mGrowth)
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
    for (const auto& [ta, tb] : pairs) crossing += sideOfSeed[seedOf(ta)] == sideOfSeed[seedOf(tb)];
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

const std::vector<std::uint32_t>& PatchSeamFinder::trianglesAt(std::uint32_t v) const {
    std::call_once(mIncidenceBuilt, [this] {
        mIncidence.assign(mGraph.points.size(), {});
        for (std::uint32_t t = 0; t < mGraph.triangles.size(); ++t)
            for (std::uint32_t u : mGraph.triangles[t])
                if (mIncidence[u].empty() || mIncidence[u].back() != t) mIncidence[u].push_back(t);
    });
    return mIncidence[v];
}

double PatchSeamFinder::signedDistance(std::uint32_t t, const Vec3& p) const {
    const auto& c = mGraph.triangles[t];
    const Vec3& a = mGraph.points[c[0]];
    const Vec3 q = closestPointOnTriangle(p, a, mGraph.points[c[1]], mGraph.points[c[2]]);
    const Vec3 e1 = sub(mGraph.points[c[1]], a), e2 = sub(mGraph.points[c[2]], a);
    const Vec3 normal{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                      e1[0] * e2[1] - e1[1] * e2[0]};
    const double length = distance(p, q);
    return mGraph.orientation[t] * dot(normal, sub(p, q)) > 0 ? -length : length;
}

std::vector<std::vector<std::uint32_t>> PatchSeamFinder::seamsAround(
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

}  // namespace skelseg
