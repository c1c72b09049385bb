#include "kernels/SegmentNesting.h"

#include <algorithm>

#include "kernels/base/Error.h"

namespace skelseg {

NestedSegments nestSegments(const BoundaryGraph& graph, const SurfaceSegments& coarse,
                            const SurfaceSegments& fine) {
    const std::uint32_t n = graph.nodeCount();
    if (coarse.nodeLabel.size() != n || fine.nodeLabel.size() != n)
        throw UsageError("nestSegments: node labels do not match the boundary graph");

    // 1. Parents by largest overlap: (fine, coarse) pairs sorted, counted in runs.
    std::vector<std::uint64_t> pairs(n);
    for (std::uint32_t v = 0; v < n; ++v)
        pairs[v] = (std::uint64_t(fine.nodeLabel[v]) << 32) | coarse.nodeLabel[v];
    std::sort(pairs.begin(), pairs.end());
    std::vector<std::uint32_t> parentOf(fine.segmentCount, kNoNode);
    std::vector<std::uint64_t> bestOverlap(fine.segmentCount, 0);
    for (std::size_t i = 0; i < pairs.size();) {
        std::size_t j = i;
        while (j < pairs.size() && pairs[j] == pairs[i]) ++j;
        const std::uint32_t f = std::uint32_t(pairs[i] >> 32), c = std::uint32_t(pairs[i]);
        // Runs come in increasing coarse id: strictly larger wins, ties stay smaller.
        if (j - i > bestOverlap[f]) bestOverlap[f] = j - i, parentOf[f] = c;
        i = j;
    }

    // 2. Consistent nodes keep their label; the sweep gives the others one.
    constexpr std::uint32_t kUnset = kNoNode;
    std::vector<std::uint32_t> label(n, kUnset);
    std::vector<std::uint32_t> queue;
    NestedSegments out;
    for (std::uint32_t v = 0; v < n; ++v)
        if (parentOf[fine.nodeLabel[v]] == coarse.nodeLabel[v])
            label[v] = fine.nodeLabel[v], queue.push_back(v);
    for (std::size_t h = 0; h < queue.size(); ++h) {
        const std::uint32_t v = queue[h];
        for (std::uint32_t e = graph.offset[v]; e < graph.offset[v + 1]; ++e) {
            const std::uint32_t m = graph.neighbour[e];
            if (label[m] == kUnset && coarse.nodeLabel[m] == coarse.nodeLabel[v])
                label[m] = label[v], queue.push_back(m);
        }
    }
    // 3. Pieces no child reaches: new segments.
    std::uint32_t count = fine.segmentCount;
    parentOf.resize(count);
    for (std::uint32_t seed = 0; seed < n; ++seed) {
        if (label[seed] != kUnset) continue;
        const std::uint32_t c = coarse.nodeLabel[seed];
        parentOf.push_back(c);
        queue.assign(1, seed);
        label[seed] = count;
        for (std::size_t h = 0; h < queue.size(); ++h)
            for (std::uint32_t e = graph.offset[queue[h]]; e < graph.offset[queue[h] + 1]; ++e) {
                const std::uint32_t m = graph.neighbour[e];
                if (label[m] == kUnset && coarse.nodeLabel[m] == c)
                    label[m] = count, queue.push_back(m);
            }
        ++count;
    }

    // 4. Ids by decreasing area, ties by smallest node.
    std::vector<std::uint64_t> area(count, 0);
    std::vector<std::uint32_t> firstNode(count, kNoNode);
    for (std::uint32_t v = 0; v < n; ++v) {
        ++area[label[v]];
        if (firstNode[label[v]] == kNoNode) firstNode[label[v]] = v;
    }
    std::vector<std::uint32_t> used;
    for (std::uint32_t s = 0; s < count; ++s)
        if (area[s]) used.push_back(s);
    std::sort(used.begin(), used.end(), [&](std::uint32_t a, std::uint32_t b) {
        return area[a] != area[b] ? area[a] > area[b] : firstNode[a] < firstNode[b];
    });
    std::vector<std::uint32_t> id(count, kNoNode);
    for (std::uint32_t s : used) {
        id[s] = out.segments.segmentCount++;
        out.segments.area.push_back(area[s]);
        out.parent.push_back(parentOf[s]);
    }
    out.segments.nodeLabel.resize(n);
    for (std::uint32_t v = 0; v < n; ++v) {
        out.segments.nodeLabel[v] = id[label[v]];
        if (label[v] != fine.nodeLabel[v]) ++out.movedNodes;
    }
    return out;
}

}  // namespace skelseg
