#include "kernels/Geodesicness.h"

#include <algorithm>
#include <cmath>

namespace skelseg {

/// Nodes closer than this (voxels) to a or b, and than 0.35 |a - b|, may be
/// shared by both arcs of a small loop.
constexpr float kSmallLoopEndRadius = 2.5f;

/// Path lengths are measured along chords over this many graph steps. One
/// step is the plain 26-neighbour length, which charges every one-voxel pip
/// of a digital surface (2 sqrt 2 instead of 2) and so depends on how a loop
/// lies in the grid; 3 steps skip the pips and still follow a loop of radius
/// 2 voxels (docs/algorithm.md, "Geodesicness on digital surfaces").
constexpr std::size_t kChordStride = 3;
/// How far (in nodes) d may move from its arc's midpoint to balance the halves.
constexpr std::size_t kBalanceSteps = 2;

float chordLength(const BoundaryGraph& graph, const std::uint32_t* nodes, std::size_t count,
                  std::size_t stride) {
    if (count < 2) return 0.0f;
    stride = std::min(std::max<std::size_t>(stride, 1), count - 1);
    // The mean over the stride's phases: which nodes the chords join must not
    // change the length (a one-voxel pip on the path costs 0.83 when a chord
    // ends on it and nothing when a chord steps over it).
    float total = 0.0f;
    for (std::size_t phase = 0; phase < stride; ++phase) {
        float length = phase > 0 ? graph.euclidean(nodes[0], nodes[phase]) : 0.0f;
        std::size_t i = phase;
        for (; i + stride < count; i += stride)
            length += graph.euclidean(nodes[i], nodes[i + stride]);
        if (i + 1 < count) length += graph.euclidean(nodes[i], nodes[count - 1]);
        total += length;
    }
    return total / float(stride);
}

namespace {

/// Position in nodes[0..count) halfway along the chord length `length`.
std::size_t chordMidpoint(const BoundaryGraph& graph, const std::uint32_t* nodes, std::size_t count,
                          std::size_t stride, float length) {
    const float half = 0.5f * length;
    float walked = 0.0f;
    for (std::size_t i = 0; i + 1 < count; i += stride) {
        const std::size_t next = std::min(i + stride, count - 1);
        const float step = graph.euclidean(nodes[i], nodes[next]);
        if (walked + step >= half) {
            const float t = step > 0.0f ? (half - walked) / step : 0.0f;
            return i + std::size_t(std::lround(t * float(next - i)));
        }
        walked += step;
    }
    return count > 0 ? count - 1 : 0;
}

}  // namespace

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

bool GeodesicnessEvaluator::splitLoop(const RimCounter& rims, std::uint32_t a, std::uint32_t b,
                                      GeodesicSearch& search) {
    // First arc: the shortest way from a to b through Gamma (or Gamma').
    float length = search.shortestPathWithin(
        a, b, [&](std::uint32_t n) { return rims.isInPathSet(n); }, &mFirstArc);
    if (length == kUnreachable)
        length = search.shortestPathWithin(
            a, b, [&](std::uint32_t n) { return rims.isInDilated(n); }, &mFirstArc);
    if (length == kUnreachable || mFirstArc.size() < 3) return false;
    // Second arc: the way back that does not touch the first arc, except
    // close to a and b where both arcs must meet.
    const float endRadius = std::min(kSmallLoopEndRadius, 0.35f * mGraph.euclidean(a, b));
    auto nearEnds = [&](std::uint32_t n) {
        return mGraph.euclidean(n, a) < endRadius || mGraph.euclidean(n, b) < endRadius;
    };
    mBlob.nextGeneration();
    for (std::size_t i = 1; i + 1 < mFirstArc.size(); ++i) {
        const std::uint32_t n = mFirstArc[i];
        if (nearEnds(n)) continue;
        mBlob.mark(n);
        for (std::uint32_t e = mGraph.offset[n]; e < mGraph.offset[n + 1]; ++e)
            if (!nearEnds(mGraph.neighbour[e])) mBlob.mark(mGraph.neighbour[e]);
    }
    length = search.shortestPathWithin(
        b, a, [&](std::uint32_t n) { return rims.isInPathSet(n) && !mBlob.isMarked(n); },
        &mSecondArc);
    if (length == kUnreachable)
        length = search.shortestPathWithin(
            b, a, [&](std::uint32_t n) { return rims.isInDilated(n) && !mBlob.isMarked(n); },
            &mSecondArc);
    return length != kUnreachable && mSecondArc.size() >= 3;
}

std::uint32_t GeodesicnessEvaluator::splitAnnulus(const RimCounter& rims, std::uint32_t a,
                                                  std::uint32_t b, GeodesicSearch& search) {
    const std::vector<std::uint32_t>& annulus = rims.result().dilated;
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
    if (arcs.size() < 2) return std::uint32_t(arcs.size());
    // The largest arcs carry the loop(s); cap the pairs examined.
    std::stable_sort(arcs.begin(), arcs.end(),
                     [](const Arc& x, const Arc& y) { return x.size > y.size; });
    if (arcs.size() > 4) arcs.resize(4);
    for (const Arc& arc : arcs) {
        const std::uint32_t id = arc.id;
        auto inArc = [&](std::uint32_t n) { return mBlob.isMarked(n) || mArcOf.get(n) == id; };
        float length = search.shortestPathWithin(
            a, b, [&](std::uint32_t n) { return rims.isInPathSet(n) && inArc(n); }, &mPath);
        if (length == kUnreachable)
            length = search.shortestPathWithin(
                a, b, [&](std::uint32_t n) { return rims.isInDilated(n) && inArc(n); }, &mPath);
        if (length == kUnreachable || mPath.empty()) continue;
        addArc(mPath, false);
    }
    return std::uint32_t(arcs.size());
}

void GeodesicnessEvaluator::addArc(const std::vector<std::uint32_t>& path, bool reversed) {
    ArcNodes arc;
    arc.begin = mArcPool.size();
    arc.count = path.size();
    if (reversed)
        mArcPool.insert(mArcPool.end(), path.rbegin(), path.rend());
    else
        mArcPool.insert(mArcPool.end(), path.begin(), path.end());
    const std::uint32_t* nodes = mArcPool.data() + arc.begin;
    arc.midpoint = chordMidpoint(mGraph, nodes, arc.count, kChordStride,
                                 chordLength(mGraph, nodes, arc.count, kChordStride));
    mArcs.push_back(arc);
}

GeodesicnessResult GeodesicnessEvaluator::evaluate(const RimCounter& rims, std::uint32_t a,
                                                   std::uint32_t b, GeodesicSearch& search) {
    GeodesicnessResult result;
    if (a == b || rims.result().dilated.empty()) return result;
    mArcs.clear();
    mArcPool.clear();
    // A simple loop (two rim pieces) has exactly two arcs, found directly;
    // otherwise (a junction's several loops, or noise holes between parallel
    // paths) the annulus is cut at a and b into its arcs.
    if (rims.result().pieceCount <= 2 && splitLoop(rims, a, b, search)) {
        result.arcCount = 2;
        addArc(mFirstArc, false);
        addArc(mSecondArc, true);  // found from b to a
    } else {
        result.arcCount = splitAnnulus(rims, a, b, search);
    }
    if (mArcs.size() < 2) return result;
    float best = 2.0f;
    for (std::size_t i = 0; i < mArcs.size(); ++i)
        for (std::size_t j = i + 1; j < mArcs.size(); ++j) {
            // Arcs i and j (both from a to b) make a closed loop; c and d,
            // their midpoints, split it into the half through b and the half
            // through a. The halves and the direct path are all paths from c
            // to d measured the same way, so a direct path that runs along
            // the loop gives exactly 1. (Halving each arc's own length would
            // not: chords across a corner at a or b are shorter than the two
            // arcs' chords meeting there.)
            const std::uint32_t* arcI = mArcPool.data() + mArcs[i].begin;
            const std::uint32_t* arcJ = mArcPool.data() + mArcs[j].begin;
            const std::size_t ci = mArcs[i].midpoint;
            const std::size_t countI = mArcs[i].count, countJ = mArcs[j].count;
            auto halves = [&](std::size_t dj, float& throughA, float& throughB) {
                mHalf.assign(arcI + ci, arcI + countI);                                // c .. b
                for (std::size_t k = countJ - 1; k-- > dj;) mHalf.push_back(arcJ[k]);  // .. d
                throughB = chordLength(mGraph, mHalf.data(), mHalf.size(), kChordStride);
                mHalf.assign(arcJ, arcJ + dj + 1);                   // a .. d
                std::reverse(mHalf.begin(), mHalf.end());            // d .. a
                mHalf.insert(mHalf.end(), arcI + 1, arcI + ci + 1);  // .. c
                throughA = chordLength(mGraph, mHalf.data(), mHalf.size(), kChordStride);
            };
            // d: the node near arc j's midpoint that splits the loop most
            // evenly (on a loop of a dozen nodes the midpoints alone can leave
            // one half two steps longer than the other).
            std::size_t dj = mArcs[j].midpoint;
            float throughA = 0.0f, throughB = 0.0f;
            halves(dj, throughA, throughB);
            const std::size_t first = std::max<std::size_t>(dj, kBalanceSteps + 1) - kBalanceSteps;
            const std::size_t last = std::min(dj + kBalanceSteps, countJ - 2);
            for (std::size_t k = first; k <= last; ++k) {
                float a2 = 0.0f, b2 = 0.0f;
                halves(k, a2, b2);
                if (std::fabs(a2 - b2) < std::fabs(throughA - throughB)) {
                    dj = k;
                    throughA = a2, throughB = b2;
                }
            }
            const float loop = 0.5f * (throughA + throughB);
            if (loop <= 0.0f) continue;
            search.shortestPath(arcI[ci], arcJ[dj], &mPath);
            const float direct = chordLength(mGraph, mPath.data(), mPath.size(), kChordStride);
            const float sigma = std::min(1.0f, direct / loop);
            if (sigma < best) {
                best = sigma;
                result.midpointC = arcI[ci];
                result.midpointD = arcJ[dj];
                result.loopLength = throughA + throughB;
            }
        }
    result.sigma = best > 1.0f ? 0.0f : best;
    return result;
}

}  // namespace skelseg
