#include "kernels/SurfaceLabelling.h"

#include <algorithm>
#include <numeric>
#include <utility>

#include "kernels/FeatureTransform.h"
#include "kernels/base/ParallelFor.h"

namespace skelseg {

namespace {

constexpr std::uint32_t kCut = 0xFFFFFFFEu;

/// The pieces of the surface without the dilated cut loops: label[v] is the
/// piece of node v (0..count-1, in node order of their first node), or kCut
/// for a node of a band. Returns the piece count.
std::uint32_t piecesWithoutBands(const BoundaryGraph& graph,
                                 const std::vector<std::vector<std::uint32_t>>& cutLoops,
                                 std::vector<std::uint32_t>& label) {
    const std::uint32_t n = graph.nodeCount();
    label.assign(n, kNoNode);
    for (const auto& loop : cutLoops)
        for (std::uint32_t v : loop) {
            label[v] = kCut;
            for (std::uint32_t e = graph.offset[v]; e < graph.offset[v + 1]; ++e)
                label[graph.neighbour[e]] = kCut;
        }
    std::uint32_t count = 0;
    std::vector<std::uint32_t> queue;
    for (std::uint32_t seed = 0; seed < n; ++seed) {
        if (label[seed] != kNoNode) continue;
        queue.assign(1, seed);
        label[seed] = count;
        for (std::size_t h = 0; h < queue.size(); ++h)
            for (std::uint32_t e = graph.offset[queue[h]]; e < graph.offset[queue[h] + 1]; ++e) {
                const std::uint32_t m = graph.neighbour[e];
                if (label[m] == kNoNode) label[m] = count, queue.push_back(m);
            }
        ++count;
    }
    return count;
}

/// Per loop: 1 when the pieces next to its band (label from
/// piecesWithoutBands, `count` pieces) are two or more of at least
/// `minPieceArea` nodes each (a smaller one is a pocket between the paths of
/// a wide loop, as a rim behind less than the noise area does not count).
std::vector<std::uint8_t> loopsBorderingTwoPieces(
    const BoundaryGraph& graph, const std::vector<std::vector<std::uint32_t>>& cutLoops,
    const std::vector<std::uint32_t>& label, std::uint32_t count, double minPieceArea) {
    std::vector<std::uint64_t> pieceArea(count, 0);
    for (std::uint32_t l : label)
        if (l < kCut) ++pieceArea[l];
    std::vector<std::uint8_t> separates(cutLoops.size(), 0);
    for (std::size_t i = 0; i < cutLoops.size(); ++i) {
        std::uint32_t seen = kNoNode;
        const auto look = [&](std::uint32_t v) {
            for (std::uint32_t e = graph.offset[v]; e < graph.offset[v + 1]; ++e) {
                const std::uint32_t l = label[graph.neighbour[e]];
                if (l >= kCut || double(pieceArea[l]) < minPieceArea) continue;
                if (seen == kNoNode) seen = l;
                if (l != seen) return true;
            }
            return false;
        };
        for (std::uint32_t v : cutLoops[i]) {
            bool found = look(v);
            for (std::uint32_t e = graph.offset[v]; !found && e < graph.offset[v + 1]; ++e)
                found = look(graph.neighbour[e]);
            if (found) {
                separates[i] = 1;
                break;
            }
        }
    }
    return separates;
}

}  // namespace

std::vector<std::uint8_t> separatingLoops(const BoundaryGraph& graph,
                                          const std::vector<std::vector<std::uint32_t>>& cutLoops,
                                          double noiseArea) {
    std::vector<std::uint32_t> label;
    const std::uint32_t count = piecesWithoutBands(graph, cutLoops, label);
    return loopsBorderingTwoPieces(graph, cutLoops, label, count, noiseArea);
}

SurfaceSegments labelSurface(const BoundaryGraph& graph,
                             const std::vector<std::vector<std::uint32_t>>& cutLoops,
                             double minSegmentArea, double noiseArea) {
    const std::uint32_t n = graph.nodeCount();
    std::vector<std::uint32_t> label;
    std::uint32_t count = piecesWithoutBands(graph, cutLoops, label);
    std::vector<std::uint32_t> queue;
    std::vector<std::uint64_t> core(count, 0);
    for (std::uint32_t v = 0; v < n; ++v)
        if (label[v] < kCut) ++core[label[v]];
    // Which loops separate: the pieces next to each band (before the cut
    // nodes join them).
    std::vector<std::uint8_t> loopSeparates =
        loopsBorderingTwoPieces(graph, cutLoops, label, count, noiseArea);
    // Cut nodes: breadth-first from the labelled nodes, seeded in node order.
    queue.clear();
    for (std::uint32_t v = 0; v < n; ++v)
        if (label[v] < kCut) queue.push_back(v);
    for (std::size_t h = 0; h < queue.size(); ++h)
        for (std::uint32_t e = graph.offset[queue[h]]; e < graph.offset[queue[h] + 1]; ++e) {
            const std::uint32_t m = graph.neighbour[e];
            if (label[m] == kCut) label[m] = label[queue[h]], queue.push_back(m);
        }
    // A surface piece made only of cut nodes (cannot really happen on a
    // closed surface, but never leave a node unlabelled).
    for (std::uint32_t v = 0; v < n; ++v)
        if (label[v] == kCut) label[v] = count++;

    std::vector<std::uint64_t> area(count, 0);
    for (std::uint32_t v = 0; v < n; ++v) ++area[label[v]];

    // The merge test measures a segment as rho_C measures a part: with the
    // whole dilated loop of every cut bounding it (rho_C(p) is the surface
    // minus the largest piece left without Gamma'(p), so it counts
    // Gamma'(p)). The sweep above gives a segment only its share of a band,
    // about one loop's worth of nodes: a fixed number of voxels across, so a
    // larger fraction of a small part at a low resolution. Without this, a
    // limb that the junction rule kept (rho_C >= tau) could be merged away at
    // one resolution and kept at the next (docs/algorithm.md §9.2).
    std::vector<std::uint64_t> bandExtra(count, 0);
    {
        std::vector<std::uint32_t> stamp(n, kNoNode);
        std::vector<std::uint32_t> band;
        std::vector<std::pair<std::uint32_t, std::uint64_t>> share;  // segment, band nodes it got
        for (std::uint32_t i = 0; i < cutLoops.size(); ++i) {
            band.clear();
            for (std::uint32_t v : cutLoops[i]) {
                if (stamp[v] != i) stamp[v] = i, band.push_back(v);
                for (std::uint32_t e = graph.offset[v]; e < graph.offset[v + 1]; ++e)
                    if (const std::uint32_t m = graph.neighbour[e]; stamp[m] != i)
                        stamp[m] = i, band.push_back(m);
            }
            share.clear();
            for (std::uint32_t v : band) {
                auto it = std::find_if(share.begin(), share.end(),
                                       [&](const auto& entry) { return entry.first == label[v]; });
                if (it == share.end())
                    share.emplace_back(label[v], 1);
                else
                    ++it->second;
            }
            // A piece smaller than the band it touches is a pocket between
            // the paths of a wide loop, not a part behind it.
            for (const auto& [segment, got] : share)
                if (area[segment] > band.size()) bandExtra[segment] += band.size() - got;
        }
    }

    std::vector<std::uint32_t> parent(count);
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    // Cavities: segments on a graph component other than the largest one,
    // where that component holds no other segment, join the largest segment.
    if (graph.componentSize.size() > 1) {
        const std::uint32_t outer =
            std::uint32_t(std::max_element(graph.componentSize.begin(), graph.componentSize.end()) -
                          graph.componentSize.begin());
        std::uint32_t largest = 0;
        for (std::uint32_t s = 1; s < count; ++s)
            if (area[s] > area[largest]) largest = s;
        for (std::uint32_t v = 0; v < n; ++v)
            if (graph.component[v] != outer && find(label[v]) != find(largest)) {
                const std::uint32_t s = find(label[v]);
                parent[s] = find(largest);
                area[find(largest)] += area[s];
            }
    }
    std::vector<SegmentMeasure> before(count);
    for (std::uint32_t s = 0; s < count; ++s)
        before[s] = {s < core.size() ? core[s] : 0, area[s], area[s] + bandExtra[s], false};
    // Merge small segments into their largest neighbour, smallest first. A
    // segment with no neighbour stays, marked rather than given a large
    // area: a tau past 2^64 voxels (--tau 1e20) has no such area, and the
    // loop picked the same segment forever.
    std::vector<std::uint8_t> isolated(count, 0);
    for (;;) {
        std::uint32_t smallest = kNoNode;
        for (std::uint32_t s = 0; s < count; ++s)
            if (find(s) == s && !isolated[s] && double(area[s] + bandExtra[s]) < minSegmentArea &&
                (smallest == kNoNode || area[s] < area[smallest]))
                smallest = s;
        if (smallest == kNoNode) break;
        std::uint32_t target = kNoNode;
        for (std::uint32_t v = 0; v < n; ++v) {
            if (find(label[v]) != smallest) continue;
            for (std::uint32_t e = graph.offset[v]; e < graph.offset[v + 1]; ++e) {
                const std::uint32_t other = find(label[graph.neighbour[e]]);
                if (other != smallest && (target == kNoNode || area[other] > area[target] ||
                                          (area[other] == area[target] && other < target)))
                    target = other;
            }
        }
        if (target == kNoNode) {
            isolated[smallest] = 1;
            continue;
        }
        parent[smallest] = target;
        area[target] += area[smallest];
        before[smallest].merged = true;
    }

    // Final ids by decreasing area, ties by smallest node.
    std::vector<std::uint32_t> firstNode(count, kNoNode);
    for (std::uint32_t v = 0; v < n; ++v) {
        const std::uint32_t s = find(label[v]);
        if (firstNode[s] == kNoNode) firstNode[s] = v;
    }
    std::vector<std::uint32_t> roots;
    for (std::uint32_t s = 0; s < count; ++s)
        if (find(s) == s && firstNode[s] != kNoNode) roots.push_back(s);
    std::vector<std::uint64_t> finalArea(count, 0);
    for (std::uint32_t v = 0; v < n; ++v) ++finalArea[find(label[v])];
    std::sort(roots.begin(), roots.end(), [&](std::uint32_t a, std::uint32_t b) {
        return finalArea[a] != finalArea[b] ? finalArea[a] > finalArea[b]
                                            : firstNode[a] < firstNode[b];
    });
    std::vector<std::uint32_t> id(count, kNoNode);
    SurfaceSegments out;
    out.loopSeparates = std::move(loopSeparates);
    out.before = std::move(before);
    for (std::uint32_t r : roots) {
        id[r] = out.segmentCount++;
        out.area.push_back(finalArea[r]);
    }
    out.nodeLabel.resize(n);
    for (std::uint32_t v = 0; v < n; ++v) out.nodeLabel[v] = id[find(label[v])];
    return out;
}

void labelInterior(const MaskVolume& mask, const Volume<std::uint32_t>& featureTransform,
                   const BoundaryGraph& graph, const SurfaceSegments& segments,
                   const std::vector<std::uint16_t>& labelOfSegment, Volume<std::uint16_t>& out,
                   bool threaded) {
    const std::size_t n = mask.size();
    auto body = [&](std::size_t begin, std::size_t end) {
        for (std::size_t v = begin; v < end; ++v) {
            if (!mask[v]) continue;
            const std::uint32_t f = featureTransform[v];
            const std::uint32_t node = f == kNoFeature ? kNoNode : graph.nodeOfVoxel[f];
            if (node == kNoNode) continue;
            out[v] = labelOfSegment[segments.nodeLabel[node]];
        }
    };
    parallelFor(n, body, threaded, std::size_t(1) << 16);
}

}  // namespace skelseg
