#include "kernels/CutLoopOrder.h"

#include <algorithm>

namespace skelseg {

std::vector<std::uint32_t> orderCutLoop(const BoundaryGraph& graph,
                                        const std::vector<std::uint32_t>& gamma, std::uint32_t a,
                                        std::uint32_t b, GeodesicSearch& search, RimCounter& rims) {
    rims.countRims(gamma);
    std::vector<std::uint32_t> arc1, arc2;
    if (search.shortestPathWithin(
            a, b, [&](std::uint32_t n) { return rims.isInPathSet(n); }, &arc1) == kUnreachable)
        return gamma;
    // Block the first arc and its neighbours, except near the ends, so the
    // way back goes round the other side of the shape.
    std::vector<std::uint32_t> blocked;
    const float keepRadius = 2.5f;
    for (std::size_t i = 1; i + 1 < arc1.size(); ++i) {
        const std::uint32_t n = arc1[i];
        if (graph.euclidean(n, a) < keepRadius || graph.euclidean(n, b) < keepRadius) continue;
        blocked.push_back(n);
        for (std::uint32_t e = graph.offset[n]; e < graph.offset[n + 1]; ++e) {
            const std::uint32_t m = graph.neighbour[e];
            if (graph.euclidean(m, a) >= keepRadius && graph.euclidean(m, b) >= keepRadius)
                blocked.push_back(m);
        }
    }
    std::sort(blocked.begin(), blocked.end());
    auto isBlocked = [&](std::uint32_t n) {
        return std::binary_search(blocked.begin(), blocked.end(), n);
    };
    float back = search.shortestPathWithin(
        b, a, [&](std::uint32_t n) { return rims.isInPathSet(n) && !isBlocked(n); }, &arc2);
    if (back == kUnreachable)
        back = search.shortestPathWithin(
            b, a, [&](std::uint32_t n) { return rims.isInDilated(n) && !isBlocked(n); }, &arc2);
    if (back == kUnreachable) return arc1;
    arc1.insert(arc1.end(), arc2.begin() + 1, arc2.end() - 1);
    return arc1;
}

std::vector<std::uint32_t> orderCutLoop(const BoundaryGraph& graph,
                                        const std::vector<std::uint32_t>& gamma, std::uint32_t a,
                                        std::uint32_t b, const Landmarks* landmarks) {
    GeodesicSearch search(graph, landmarks);
    RimCounter rims(graph);
    return orderCutLoop(graph, gamma, a, b, search, rims);
}

}  // namespace skelseg
