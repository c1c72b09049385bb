#include "kernels/Geodesicness.h"

#include <algorithm>

namespace skelseg {

GeodesicnessEvaluator::GeodesicnessEvaluator(const BoundaryGraph& graph)
    : mGraph(graph),
      mBlob(graph.nodeCount()),
      mHops(graph.nodeCount(), 0),
      mArcOf(graph.nodeCount(), kNoNode) {}

void GeodesicnessEvaluator::markBlob(const RimCounter& rims, std::uint32_t seed, int radius) {
    mHops.clear();
    mQueue.clear();
    mQueue.push_back(seed);
    mHops.set(seed, 0);
    mBlob.mark(seed);
    for (std::size_t head = 0; head < mQueue.size(); ++head) {
        const std::uint32_t n = mQueue[head];
        const std::uint32_t h = mHops.get(n);
        if (int(h) >= radius) continue;
        for (std::uint32_t e = mGraph.offset[n]; e < mGraph.offset[n + 1]; ++e) {
            const std::uint32_t m = mGraph.neighbour[e];
            if (!rims.isInDilated(m) || mHops.contains(m)) continue;
            mHops.set(m, h + 1);
            mBlob.mark(m);
            mQueue.push_back(m);
        }
    }
}

GeodesicnessResult GeodesicnessEvaluator::evaluate(const RimCounter& rims, std::uint32_t a,
                                                   std::uint32_t b, GeodesicSearch& search) {
    GeodesicnessResult result;
    const std::vector<std::uint32_t>& annulus = rims.result().dilated;
    if (a == b || annulus.empty()) return result;

    struct Arc {
        std::uint32_t id, size;
    };
    std::vector<Arc> arcs;
    // Grow the cut-out neighbourhoods until the annulus falls apart into arcs
    // that join a's neighbourhood to b's.
    for (int radius : {2, 3, 4, 6}) {
        mBlob.nextGeneration();
        markBlob(rims, a, radius);
        markBlob(rims, b, radius);
        mArcOf.clear();
        arcs.clear();
        for (std::uint32_t seed : annulus) {
            if (mBlob.isMarked(seed) || mArcOf.contains(seed)) continue;
            const std::uint32_t id = std::uint32_t(arcs.size());
            mQueue.clear();
            mQueue.push_back(seed);
            mArcOf.set(seed, id);
            bool touchesA = false, touchesB = false;
            for (std::size_t head = 0; head < mQueue.size(); ++head) {
                const std::uint32_t n = mQueue[head];
                for (std::uint32_t e = mGraph.offset[n]; e < mGraph.offset[n + 1]; ++e) {
                    const std::uint32_t m = mGraph.neighbour[e];
                    if (!rims.isInDilated(m)) continue;
                    if (mBlob.isMarked(m)) {
                        // Which neighbourhood: the nearer of a and b.
                        (mGraph.euclidean(m, a) <= mGraph.euclidean(m, b) ? touchesA : touchesB) =
                            true;
                        continue;
                    }
                    if (!mArcOf.contains(m)) {
                        mArcOf.set(m, id);
                        mQueue.push_back(m);
                    }
                }
            }
            // Pieces that do not join both ends are spurs, not arcs; their id
            // is kept (so they are not re-walked) but they are not recorded.
            if (touchesA && touchesB)
                arcs.push_back({id, std::uint32_t(mQueue.size())});
            else
                arcs.push_back({id, 0});
        }
        arcs.erase(
            std::remove_if(arcs.begin(), arcs.end(), [](const Arc& arc) { return arc.size == 0; }),
            arcs.end());
        if (arcs.size() >= 2) break;
    }
    result.arcCount = std::uint32_t(arcs.size());
    if (arcs.size() < 2) return result;
    // The largest arcs carry the loop(s); cap the pairs examined.
    std::stable_sort(arcs.begin(), arcs.end(),
                     [](const Arc& x, const Arc& y) { return x.size > y.size; });
    if (arcs.size() > 4) arcs.resize(4);

    struct ArcPath {
        float length;
        std::uint32_t midpoint;
    };
    std::vector<ArcPath> arcPaths;
    for (const Arc& arc : arcs) {
        const std::uint32_t id = arc.id;
        auto inArc = [&](std::uint32_t n) { return mBlob.isMarked(n) || mArcOf.get(n) == id; };
        float length = search.shortestPathWithin(
            a, b, [&](std::uint32_t n) { return rims.isInPathSet(n) && inArc(n); }, &mPath);
        if (length == kUnreachable)
            length = search.shortestPathWithin(
                a, b, [&](std::uint32_t n) { return rims.isInDilated(n) && inArc(n); }, &mPath);
        if (length == kUnreachable || mPath.empty()) continue;
        // Arc-length midpoint.
        float walked = 0.0f;
        std::uint32_t midpoint = mPath.back();
        for (std::size_t i = 1; i < mPath.size(); ++i) {
            walked += mGraph.euclidean(mPath[i - 1], mPath[i]);
            if (walked >= 0.5f * length) {
                midpoint = mPath[i];
                break;
            }
        }
        arcPaths.push_back({length, midpoint});
    }
    if (arcPaths.size() < 2) return result;
    float best = 2.0f;
    for (std::size_t i = 0; i < arcPaths.size(); ++i)
        for (std::size_t j = i + 1; j < arcPaths.size(); ++j) {
            const float loop = 0.5f * (arcPaths[i].length + arcPaths[j].length);
            if (loop <= 0.0f) continue;
            const float direct = search.shortestPath(arcPaths[i].midpoint, arcPaths[j].midpoint);
            const float sigma = std::min(1.0f, direct / loop);
            if (sigma < best) {
                best = sigma;
                result.midpointC = arcPaths[i].midpoint;
                result.midpointD = arcPaths[j].midpoint;
                result.loopLength = arcPaths[i].length + arcPaths[j].length;
            }
        }
    result.sigma = best > 1.0f ? 0.0f : best;
    return result;
}

}  // namespace skelseg
