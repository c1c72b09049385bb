#include "kernels/SkeletonBridges.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <map>
#include <tuple>

#include "kernels/DisjointSets.h"
#include "kernels/SkeletonGraphSearch.h"
#include "kernels/VoxelRuns.h"

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

/// The nodes of a graph in cubic cells of `cellSize` voxels (CSR by cell,
/// nodes in increasing order within a cell): the nodes within a distance of
/// a point are found in the cells the cube around it overlaps.
class NodeCells {
public:
    NodeCells(const std::vector<Coord>& coord, int cellSize) : mCellSize(cellSize) {
        mLow = {INT32_MAX, INT32_MAX, INT32_MAX};
        mHigh = {INT32_MIN, INT32_MIN, INT32_MIN};
        for (const Coord& c : coord) {
            mLow = {std::min(mLow[0], c.x), std::min(mLow[1], c.y), std::min(mLow[2], c.z)};
            mHigh = {std::max(mHigh[0], c.x), std::max(mHigh[1], c.y), std::max(mHigh[2], c.z)};
        }
        for (int k = 0; k < 3; ++k) mCells[k] = (mHigh[k] - mLow[k]) / cellSize + 1;
        mStart.assign(std::size_t(mCells[0]) * mCells[1] * mCells[2] + 1, 0);
        for (const Coord& c : coord) ++mStart[cellOf(c) + 1];
        for (std::size_t i = 1; i < mStart.size(); ++i) mStart[i] += mStart[i - 1];
        mNodes.resize(coord.size());
        std::vector<std::uint32_t> next(mStart.begin(), mStart.end() - 1);
        for (std::uint32_t n = 0; n < coord.size(); ++n) mNodes[next[cellOf(coord[n])]++] = n;
    }

    /// Calls visit(node) for every node in the cells that the cube of half
    /// side `radius` around c overlaps (a superset of the nodes within
    /// `radius` of c).
    template <typename Visit>
    void forEachNear(const Coord& c, double radius, const Visit& visit) const {
        const int reach = int(std::ceil(radius / mCellSize));
        const int cx = (c.x - mLow[0]) / mCellSize, cy = (c.y - mLow[1]) / mCellSize,
                  cz = (c.z - mLow[2]) / mCellSize;
        for (int z = std::max(0, cz - reach); z <= std::min(mCells[2] - 1, cz + reach); ++z)
            for (int y = std::max(0, cy - reach); y <= std::min(mCells[1] - 1, cy + reach); ++y) {
                const std::size_t row = (std::size_t(z) * mCells[1] + y) * mCells[0];
                const std::size_t first = row + std::size_t(std::max(0, cx - reach));
                const std::size_t last = row + std::size_t(std::min(mCells[0] - 1, cx + reach));
                for (std::uint32_t i = mStart[first]; i < mStart[last + 1]; ++i) visit(mNodes[i]);
            }
    }

    /// The squared diagonal of the nodes' bounding box.
    double diagonalSquared() const {
        double sum = 0.0;
        for (int k = 0; k < 3; ++k) sum += double(mHigh[k] - mLow[k]) * double(mHigh[k] - mLow[k]);
        return sum;
    }

private:
    std::size_t cellOf(const Coord& c) const {
        return (std::size_t((c.z - mLow[2]) / mCellSize) * mCells[1] +
                std::size_t((c.y - mLow[1]) / mCellSize)) *
                   mCells[0] +
               std::size_t((c.x - mLow[0]) / mCellSize);
    }

    int mCellSize;
    std::array<int, 3> mLow{}, mHigh{}, mCells{};
    std::vector<std::uint32_t> mStart, mNodes;
};

}  // namespace

std::vector<std::array<std::uint32_t, 2>> joinGroupsThroughObject(
    const std::vector<Coord>& coord, const std::vector<std::uint32_t>& group, std::uint32_t groups,
    const MaskVolume& inside) {
    std::vector<std::array<std::uint32_t, 2>> bridges;
    const std::uint32_t n = std::uint32_t(coord.size());
    if (groups <= 1 || n == 0) return bridges;
    // Candidates are taken shortest first; those of length up to R are all
    // known from the nodes within R of each node (a node's nearest node of
    // another part, if that is within R, is the nearest of the nodes there),
    // so they are generated in rounds of doubling R, each round sorted, and
    // the rounds stop once every part is joined. Candidates, their order and
    // the bridges are those of one sort of all candidates.
    constexpr int kCellSize = 8;
    const NodeCells cells(coord, kCellSize);
    const double diagonal2 = cells.diagonalSquared();
    std::vector<std::tuple<double, std::uint32_t, std::uint32_t>> candidates;
    std::vector<std::pair<double, std::uint32_t>> nearest(groups, {HUGE_VAL, kNoJunction});
    std::vector<std::uint32_t> touched;
    DisjointSets groupsJoined(groups);
    std::uint32_t apart = groups;
    double below2 = -1.0;  // candidates up to this squared length are done
    for (double radius = kCellSize; apart > 1; radius *= 2.0) {
        const bool everything = radius * radius >= diagonal2;
        const double upTo2 = everything ? HUGE_VAL : radius * radius;
        candidates.clear();
        for (std::uint32_t a = 0; a < n; ++a) {
            const auto consider = [&](std::uint32_t b) {
                if (group[b] == group[a]) return;
                const double dx = coord[b].x - coord[a].x, dy = coord[b].y - coord[a].y,
                             dz = coord[b].z - coord[a].z;
                const double d2 = dx * dx + dy * dy + dz * dz;
                if (d2 > upTo2) return;
                auto& best = nearest[group[b]];
                if (best.second == kNoJunction) touched.push_back(group[b]);
                if (std::make_pair(d2, b) < best) best = {d2, b};
            };
            if (everything)
                for (std::uint32_t b = 0; b < n; ++b) consider(b);
            else
                cells.forEachNear(coord[a], radius, consider);
            for (std::uint32_t k : touched) {
                const auto [d2, b] = nearest[k];
                if (d2 > below2) {
                    if (group[a] < k)
                        candidates.emplace_back(d2, a, b);
                    else
                        candidates.emplace_back(d2, b, a);
                }
                nearest[k] = {HUGE_VAL, kNoJunction};
            }
            touched.clear();
        }
        std::sort(candidates.begin(), candidates.end());
        candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
        for (const auto& [d2, a, b] : candidates) {
            if (groupsJoined.find(group[a]) == groupsJoined.find(group[b])) continue;
            if (!segmentInside(coord[a], coord[b], inside)) continue;
            groupsJoined.unite(group[a], group[b]);
            --apart;
            bridges.push_back({std::min(a, b), std::max(a, b)});
        }
        if (everything) break;
        below2 = upTo2;
    }
    return bridges;
}

namespace {

/// The voxels of a mask numbered in voxel order through its x-runs, so that
/// a flood over the object holds its state per object voxel, not per voxel
/// of the box (a bird with spread wings fills 4% of its box).
class ObjectVoxelIndex {
public:
    ObjectVoxelIndex(const MaskVolume& inside, Interrupter& interrupter)
        : mRuns(objectRuns(inside, /*threaded=*/false, interrupter)) {
        mFirst.reserve(mRuns.runs.size() + 1);
        mRowOfRun.reserve(mRuns.runs.size());
        std::uint32_t voxels = 0;
        for (std::size_t r = 0; r < mRuns.rowCount(); ++r)
            for (std::uint32_t k = mRuns.rowStart[r]; k < mRuns.rowStart[r + 1]; ++k) {
                mFirst.push_back(voxels);
                mRowOfRun.push_back(std::uint32_t(r));
                voxels += std::uint32_t(mRuns.runs[k].x1 - mRuns.runs[k].x0 + 1);
            }
        mFirst.push_back(voxels);
    }

    std::uint32_t voxelCount() const noexcept { return mFirst.back(); }

    /// The number of voxel (x, y, z), or kNoJunction where it is outside
    /// the grid or the object.
    std::uint32_t indexOf(int x, int y, int z) const noexcept {
        const Dims& d = mRuns.dims;
        if (x < 0 || y < 0 || z < 0 || x >= d.x || y >= d.y || z >= d.z) return kNoJunction;
        const std::size_t r = mRuns.rowOf(y, z);
        const auto first = mRuns.runs.begin() + mRuns.rowStart[r];
        const auto last = mRuns.runs.begin() + mRuns.rowStart[r + 1];
        // The run starting last at or before x.
        const auto after = std::upper_bound(
            first, last, x, [](int value, const VoxelRun& run) { return value < run.x0; });
        if (after == first || std::prev(after)->x1 < x) return kNoJunction;
        const std::size_t k = std::size_t(std::prev(after) - mRuns.runs.begin());
        return mFirst[k] + std::uint32_t(x - mRuns.runs[k].x0);
    }

    Coord coordOf(std::uint32_t index) const noexcept {
        const std::size_t k =
            std::size_t(std::upper_bound(mFirst.begin(), mFirst.end(), index) - mFirst.begin()) - 1;
        const std::uint32_t row = mRowOfRun[k];
        return {mRuns.runs[k].x0 + int(index - mFirst[k]), int(row % std::uint32_t(mRuns.dims.y)),
                int(row / std::uint32_t(mRuns.dims.y))};
    }

private:
    VoxelRuns mRuns;
    std::vector<std::uint32_t> mFirst;     // per run, the number of its first voxel; then the count
    std::vector<std::uint32_t> mRowOfRun;  // per run, its row
};

}  // namespace

std::vector<std::array<std::uint32_t, 2>> joinGroupsAlongObject(
    const std::vector<Coord>& coord, const std::vector<std::uint32_t>& group, std::uint32_t groups,
    const MaskVolume& inside, Interrupter& interrupter) {
    std::vector<std::array<std::uint32_t, 2>> bridges;
    const std::uint32_t n = std::uint32_t(coord.size());
    if (groups <= 1 || n == 0) return bridges;
    const ObjectVoxelIndex voxels(inside, interrupter);
    // The flood's state per object voxel: the node it came from and its
    // steps; the queue holds object voxels in the order reached.
    std::vector<std::uint32_t> from(voxels.voxelCount(), kNoJunction);
    std::vector<std::uint32_t> steps(voxels.voxelCount(), 0);
    std::vector<std::uint32_t> queue;
    for (std::uint32_t a = 0; a < n; ++a) {
        const std::uint32_t v = voxels.indexOf(coord[a].x, coord[a].y, coord[a].z);
        if (v == kNoJunction || from[v] != kNoJunction) continue;
        from[v] = a;
        queue.push_back(v);
    }
    // Shortest candidate per pair of groups (lower group first); std::map
    // keeps the order deterministic.
    std::map<std::pair<std::uint32_t, std::uint32_t>,
             std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>>
        best;
    for (std::size_t head = 0; head < queue.size(); ++head) {
        if ((head & 0xFFFFu) == 0)
            throwIfInterrupted(interrupter, double(head) / double(voxels.voxelCount()));
        const std::uint32_t v = queue[head];
        const Coord c = voxels.coordOf(v);
        const std::array<std::array<int, 3>, 6> offsets{
            {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}}};
        for (const auto& o : offsets) {
            const std::uint32_t w = voxels.indexOf(c.x + o[0], c.y + o[1], c.z + o[2]);
            if (w == kNoJunction) continue;
            if (from[w] == kNoJunction) {
                from[w] = from[v];
                steps[w] = steps[v] + 1;
                queue.push_back(w);
                continue;
            }
            const std::uint32_t a = from[v], b = from[w];
            if (group[a] == group[b]) continue;
            const bool aLow = group[a] < group[b];
            const auto key =
                aLow ? std::make_pair(group[a], group[b]) : std::make_pair(group[b], group[a]);
            const auto candidate =
                std::make_tuple(steps[v] + steps[w] + 1, aLow ? a : b, aLow ? b : a);
            auto it = best.find(key);
            if (it == best.end() || candidate < it->second) best[key] = candidate;
        }
    }
    std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> order;
    for (const auto& entry : best) order.push_back(entry.second);
    std::sort(order.begin(), order.end());
    DisjointSets groupsJoined(groups);
    for (const auto& [length, a, b] : order) {
        if (groupsJoined.find(group[a]) == groupsJoined.find(group[b])) continue;
        groupsJoined.unite(group[a], group[b]);
        bridges.push_back({std::min(a, b), std::max(a, b)});
    }
    return bridges;
}

namespace {

/// Whether the nodes `members` of g reach across at least the width of the
/// part around them (the diagonal of their box at least twice loopRadius of
/// their median rho_S): a limb's skeleton broken at a bend does, a lone
/// point or a knot of C_tau does not.
bool reachesAcrossItsPart(const SkeletonGraph& g, const std::vector<SkeletonPoint>& points,
                          const std::vector<std::uint32_t>& members) {
    std::array<int, 3> low{INT32_MAX, INT32_MAX, INT32_MAX}, high{INT32_MIN, INT32_MIN, INT32_MIN};
    std::vector<float> rhoS;
    for (const std::uint32_t n : members) {
        const Coord& c = g.coord[n];
        low = {std::min(low[0], c.x), std::min(low[1], c.y), std::min(low[2], c.z)};
        high = {std::max(high[0], c.x), std::max(high[1], c.y), std::max(high[2], c.z)};
        rhoS.push_back(points[g.point[n]].rhoS);
    }
    std::nth_element(rhoS.begin(), rhoS.begin() + rhoS.size() / 2, rhoS.end());
    double diagonal2 = 0.0;
    for (int k = 0; k < 3; ++k) diagonal2 += double(high[k] - low[k]) * double(high[k] - low[k]);
    const double width = 2.0 * loopRadius(double(rhoS[rhoS.size() / 2]));
    return diagonal2 >= width * width;
}

/// Joins the parts of g that `joined` still keeps apart: by straight
/// segments through the object (joinGroupsThroughObject), then those still
/// apart along it (joinGroupsAlongObject): the largest of those and the
/// others that reach across their part (reachesAcrossItsPart).
void bridgeThroughObject(SkeletonGraph& g, const std::vector<SkeletonPoint>& points,
                         const std::vector<std::uint32_t>& part, DisjointSets& joined,
                         const MaskVolume& inside, Interrupter& interrupter) {
    const std::uint32_t n = g.nodeCount();
    std::vector<std::uint32_t> group(n);
    std::map<std::uint32_t, std::uint32_t> groupIndex;
    for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t root = joined.find(part[i]);
        group[i] = groupIndex.emplace(root, std::uint32_t(groupIndex.size())).first->second;
    }
    const std::uint32_t groups = std::uint32_t(groupIndex.size());
    DisjointSets groupsJoined(groups);
    std::uint32_t apart = groups;
    for (const auto& edge : joinGroupsThroughObject(g.coord, group, groups, inside)) {
        g.edges.push_back(edge);
        ++g.bridgeCount;
        groupsJoined.unite(group[edge[0]], group[edge[1]]);
        --apart;
    }
    if (apart <= 1) return;
    std::vector<std::vector<std::uint32_t>> members(groups);
    for (std::uint32_t i = 0; i < n; ++i) members[groupsJoined.find(group[i])].push_back(i);
    // The largest part (most nodes) takes part whatever its shape: a
    // compact knot of the body's skeleton still receives the limbs.
    std::size_t largest = 0;
    for (std::size_t k = 1; k < members.size(); ++k)
        if (members[k].size() > members[largest].size()) largest = k;
    std::vector<Coord> coord;
    std::vector<std::uint32_t> node, stillApart;
    std::uint32_t stillApartCount = 0;
    for (std::size_t k = 0; k < members.size(); ++k) {
        const std::vector<std::uint32_t>& piece = members[k];
        if (piece.empty() || (k != largest && !reachesAcrossItsPart(g, points, piece))) continue;
        for (const std::uint32_t i : piece) {
            coord.push_back(g.coord[i]);
            node.push_back(i);
            stillApart.push_back(stillApartCount);
        }
        ++stillApartCount;
    }
    for (const auto& [a, b] :
         joinGroupsAlongObject(coord, stillApart, stillApartCount, inside, interrupter)) {
        g.edges.push_back({std::min(node[a], node[b]), std::max(node[a], node[b])});
        ++g.bridgeCount;
        ++g.bridgesAlongObject;
    }
}

}  // namespace

bool bridgeSkeletonParts(SkeletonGraph& g, const std::vector<SkeletonPoint>& points,
                         const SkeletonGraphOptions& options, Interrupter& interrupter) {
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
    for (std::uint32_t n = 0; n < g.nodeCount(); ++n) {
        reach[n] = std::max(options.bridgeGap, loopRadius(double(points[g.point[n]].rhoS)));
    }
    // Sweep along x: a pair needs the reach of both nodes, so a node pairs
    // only with the nodes after it within its own reach in x (a few nodes
    // with loops round the whole body reach far; the others do not).
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
            if (double(cb.x - ca.x) > reach[a]) break;
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
    if (apart > 1 && options.inside)
        bridgeThroughObject(g, points, part, joined, *options.inside, interrupter);
    return g.bridgeCount != bridgesBefore;
}

}  // namespace skelseg
