#include "kernels/SurfaceLabelling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "io/shapes/SyntheticShapes.h"
#include "kernels/FeatureTransform.h"
#include "tests/kernels/KernelTestSupport.h"

namespace skelseg {
namespace {

/// A capsule along x and cut loops made of the boundary nodes of one x
/// slice (a closed ring around the capsule).
class LabellingOnCapsule : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        mask = new MaskVolume(rasterise(makeShape("capsule"), {56, 2}));
        graph = new BoundaryGraph(buildBoundaryGraph(*mask, {false}));
        xMin = xMax = graph->coord[0].x;
        for (const Coord& c : graph->coord) xMin = std::min(xMin, c.x), xMax = std::max(xMax, c.x);
    }
    static void TearDownTestSuite() {
        delete graph;
        delete mask;
        graph = nullptr, mask = nullptr;
    }
    static std::vector<std::uint32_t> ring(int x) {
        std::vector<std::uint32_t> nodes;
        for (std::uint32_t n = 0; n < graph->nodeCount(); ++n)
            if (graph->coord[n].x == x) nodes.push_back(n);
        return nodes;
    }
    /// Nodes of the cut band of ring(x): the ring and its graph neighbours.
    static std::uint64_t bandSize(int x) {
        std::vector<std::uint8_t> in(graph->nodeCount(), 0);
        for (std::uint32_t v : ring(x)) {
            in[v] = 1;
            for (std::uint32_t e = graph->offset[v]; e < graph->offset[v + 1]; ++e)
                in[graph->neighbour[e]] = 1;
        }
        return std::uint64_t(std::count(in.begin(), in.end(), std::uint8_t(1)));
    }
    /// x at a fraction of the capsule's length.
    static int at(double fraction) { return xMin + int(std::lround(fraction * (xMax - xMin))); }
    /// A boundary node of slice x.
    static std::uint32_t nodeAt(int x) { return ring(x).front(); }

    /// Every label is in range, the areas are the label counts in decreasing
    /// order, and every segment is connected.
    static void expectWellFormed(const SurfaceSegments& s) {
        ASSERT_EQ(s.nodeLabel.size(), graph->nodeCount());
        ASSERT_EQ(s.area.size(), s.segmentCount);
        std::vector<std::uint64_t> count(s.segmentCount, 0);
        for (std::uint32_t label : s.nodeLabel) {
            ASSERT_LT(label, s.segmentCount);
            ++count[label];
        }
        EXPECT_EQ(count, s.area);
        EXPECT_TRUE(std::is_sorted(s.area.begin(), s.area.end(), std::greater<>()))
            << "ids not by decreasing area";
        for (std::uint32_t label = 0; label < s.segmentCount; ++label) {
            std::vector<std::uint32_t> components;
            const auto sizes = test::floodFill(
                *graph, [&](std::uint32_t n) { return s.nodeLabel[n] == label; }, components);
            EXPECT_EQ(sizes.size(), 1u) << "segment " << label << " is not connected";
        }
    }

    static MaskVolume* mask;
    static BoundaryGraph* graph;
    static int xMin, xMax;
};
MaskVolume* LabellingOnCapsule::mask = nullptr;
BoundaryGraph* LabellingOnCapsule::graph = nullptr;
int LabellingOnCapsule::xMin = 0;
int LabellingOnCapsule::xMax = 0;

TEST_F(LabellingOnCapsule, NoCutIsOneSegment) {
    const SurfaceSegments s = labelSurface(*graph, {}, 0.0);
    ASSERT_EQ(s.segmentCount, 1u);
    EXPECT_EQ(s.area[0], graph->nodeCount());
    expectWellFormed(s);
}

TEST_F(LabellingOnCapsule, SmallestAreaPastAnyIntegerKeepsTheLoneSegment) {
    // --tau 1e20: the segment has no neighbour to merge into and stays. Its
    // area was raised to the smallest area plus one, which 2^64 cannot hold,
    // and the merge loop picked it again forever (SIGINT ignored as well).
    for (const double smallest : {1e20, 1e300}) {
        const SurfaceSegments s = labelSurface(*graph, {}, smallest);
        ASSERT_EQ(s.segmentCount, 1u);
        EXPECT_EQ(s.area[0], graph->nodeCount());
        expectWellFormed(s);
    }
}

TEST_F(LabellingOnCapsule, TwoCutsGiveThreeSegmentsByDecreasingArea) {
    // Cuts at 30% and 85% of the length: middle > left > right.
    const int x1 = at(0.30), x2 = at(0.85);
    const SurfaceSegments s = labelSurface(*graph, {ring(x1), ring(x2)}, 0.0);
    ASSERT_EQ(s.segmentCount, 3u);
    expectWellFormed(s);
    const std::uint32_t left = s.nodeLabel[nodeAt(xMin)], middle = s.nodeLabel[nodeAt(at(0.55))],
                        right = s.nodeLabel[nodeAt(xMax)];
    EXPECT_EQ(middle, 0u);
    EXPECT_EQ(left, 1u);
    EXPECT_EQ(right, 2u);
    // Every node away from the cuts has the label of its side.
    for (std::uint32_t n = 0; n < graph->nodeCount(); ++n) {
        const int x = graph->coord[n].x;
        if (x < x1 - 1) {
            EXPECT_EQ(s.nodeLabel[n], left);
        }
        if (x > x1 + 1 && x < x2 - 1) {
            EXPECT_EQ(s.nodeLabel[n], middle);
        }
        if (x > x2 + 1) {
            EXPECT_EQ(s.nodeLabel[n], right);
        }
    }
    // The cut band (ring dilated by one step) is shared out to the sides.
    std::uint64_t leftOfCut = 0;
    for (std::uint32_t n = 0; n < graph->nodeCount(); ++n) leftOfCut += graph->coord[n].x < x1 - 1;
    EXPECT_GT(s.area[left], leftOfCut);
    // Deterministic.
    const SurfaceSegments again = labelSurface(*graph, {ring(x1), ring(x2)}, 0.0);
    EXPECT_EQ(again.nodeLabel, s.nodeLabel);
}

TEST_F(LabellingOnCapsule, SmallSegmentMergesIntoItsNeighbour) {
    // A cut 3 voxels from the right tip leaves a small cap.
    const int x1 = at(0.30), x2 = xMax - 3;
    const SurfaceSegments unmerged = labelSurface(*graph, {ring(x1), ring(x2)}, 0.0);
    ASSERT_EQ(unmerged.segmentCount, 3u);
    const std::uint64_t tip = unmerged.area[unmerged.nodeLabel[nodeAt(xMax)]];
    ASSERT_LT(tip, unmerged.area[1]);
    // The merge measures the cap with its whole cut band, as rho_C does.
    const SurfaceSegments merged =
        labelSurface(*graph, {ring(x1), ring(x2)}, double(tip + bandSize(x2)) + 1.0);
    ASSERT_EQ(merged.segmentCount, 2u);
    expectWellFormed(merged);
    EXPECT_EQ(merged.nodeLabel[nodeAt(xMax)], merged.nodeLabel[nodeAt(at(0.6))]);
    EXPECT_NE(merged.nodeLabel[nodeAt(xMin)], merged.nodeLabel[nodeAt(at(0.6))]);
    EXPECT_EQ(merged.area[0], unmerged.area[0] + tip);
}

TEST_F(LabellingOnCapsule, SmallBandMergesIntoItsLargestNeighbour) {
    // A narrow band between two close cuts touches the left piece and the
    // (larger) middle piece: it must join the middle one.
    const int x1 = at(0.25), x2 = x1 + 4, x3 = at(0.72);
    const SurfaceSegments unmerged = labelSurface(*graph, {ring(x1), ring(x2), ring(x3)}, 0.0);
    ASSERT_EQ(unmerged.segmentCount, 4u);
    const std::uint32_t band = unmerged.nodeLabel[nodeAt(x1 + 2)];
    const std::uint32_t left = unmerged.nodeLabel[nodeAt(xMin)],
                        middle = unmerged.nodeLabel[nodeAt(at(0.6))],
                        right = unmerged.nodeLabel[nodeAt(xMax)];
    ASSERT_LT(unmerged.area[band], unmerged.area[left]);
    ASSERT_LT(unmerged.area[band], unmerged.area[right]);
    ASSERT_GT(unmerged.area[middle], unmerged.area[left]);
    // The band is measured with both of its cut bands (as rho_C would).
    const double threshold = double(unmerged.area[band] + bandSize(x1) + bandSize(x2)) + 1.0;
    ASSERT_LT(threshold, double(std::min(unmerged.area[left], unmerged.area[right])));
    const SurfaceSegments merged = labelSurface(*graph, {ring(x1), ring(x2), ring(x3)}, threshold);
    ASSERT_EQ(merged.segmentCount, 3u);
    expectWellFormed(merged);
    EXPECT_EQ(merged.nodeLabel[nodeAt(x1 + 2)], merged.nodeLabel[nodeAt(at(0.6))]);
    EXPECT_NE(merged.nodeLabel[nodeAt(x1 + 2)], merged.nodeLabel[nodeAt(xMin)]);
}

/// The tip beyond a cut near one end of a capsule rasterised at `size`
/// voxels: a part whose rho_C (the tip's piece plus the whole cut band) just
/// reaches the smallest segment area is kept, although the sweep gives it
/// only part of the band; one node more and it merges. The band is a fixed
/// number of voxels across, so the share it takes grows as the resolution
/// drops (dino.off's arms at 128: docs/algorithm.md §9.2).
void expectTipMeasuredWithItsCutBand(int size) {
    SCOPED_TRACE("capsule at " + std::to_string(size));
    const MaskVolume mask = rasterise(makeShape("capsule"), {size, 2});
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    int xMin = graph.coord[0].x, xMax = xMin;
    for (const Coord& c : graph.coord) xMin = std::min(xMin, c.x), xMax = std::max(xMax, c.x);
    const int x = xMax - (xMax - xMin) / 6;
    std::vector<std::uint32_t> loop;
    for (std::uint32_t n = 0; n < graph.nodeCount(); ++n)
        if (graph.coord[n].x == x) loop.push_back(n);
    std::vector<std::uint8_t> inBand(graph.nodeCount(), 0);
    for (std::uint32_t v : loop) {
        inBand[v] = 1;
        for (std::uint32_t e = graph.offset[v]; e < graph.offset[v + 1]; ++e)
            inBand[graph.neighbour[e]] = 1;
    }
    // rho_C of the loop: the surface minus the larger side without the band.
    std::uint64_t tipPiece = 0, band = 0;
    for (std::uint32_t n = 0; n < graph.nodeCount(); ++n) {
        band += inBand[n];
        tipPiece += !inBand[n] && graph.coord[n].x > x;
    }
    const double rhoC = double(tipPiece + band);
    const SurfaceSegments unmerged = labelSurface(graph, {loop}, 0.0);
    ASSERT_EQ(unmerged.segmentCount, 2u);
    const std::uint64_t tipSegment = unmerged.area[1];
    ASSERT_LT(double(tipSegment) + 1.0, rhoC) << "the tip got the whole band";
    EXPECT_EQ(labelSurface(graph, {loop}, double(tipSegment) + 1.0).segmentCount, 2u)
        << "a tip whose rho_C reaches the smallest area was merged";
    EXPECT_EQ(labelSurface(graph, {loop}, rhoC).segmentCount, 2u);
    EXPECT_EQ(labelSurface(graph, {loop}, rhoC + 1.0).segmentCount, 1u);
}

TEST(SurfaceLabelling, SmallSegmentIsMeasuredWithItsCutBandAtTwoScales) {
    expectTipMeasuredWithItsCutBand(48);
    expectTipMeasuredWithItsCutBand(96);
}

TEST_F(LabellingOnCapsule, PocketOfAWideLoopIsNotAPart) {
    // One cut loop made of two rings 4 apart (a wide path set): the slice
    // between them is a piece of its own, smaller than the loop's band. It
    // is a pocket of the loop, not a part behind it, so it is measured
    // without the band and merges below the smallest area.
    const int x = at(0.5);
    std::vector<std::uint32_t> wide = ring(x);
    for (std::uint32_t n : ring(x + 4)) wide.push_back(n);
    const SurfaceSegments unmerged = labelSurface(*graph, {wide}, 0.0);
    ASSERT_EQ(unmerged.segmentCount, 3u);
    const std::uint64_t pocket = unmerged.area[unmerged.nodeLabel[nodeAt(x + 2)]];
    ASSERT_LT(pocket, bandSize(x) + bandSize(x + 4));
    const SurfaceSegments merged = labelSurface(*graph, {wide}, double(pocket) + 1.0);
    EXPECT_EQ(merged.segmentCount, 2u) << "the pocket was kept as a part";
    expectWellFormed(merged);
}

TEST_F(LabellingOnCapsule, InteriorTakesTheLabelOfItsFeatureVoxel) {
    const int x1 = at(0.30), x2 = at(0.85);
    const SurfaceSegments s = labelSurface(*graph, {ring(x1), ring(x2)}, 0.0);
    const MaskVolume sites = boundaryVoxels(*mask, {false});
    const Volume<std::uint32_t> ft = featureTransform(sites, {false});
    const std::vector<std::uint16_t> labelOf = {7, 8, 9};
    Volume<std::uint16_t> serial(mask->dims(), 0), parallel(mask->dims(), 0);
    labelInterior(*mask, ft, *graph, s, labelOf, serial, false);
    labelInterior(*mask, ft, *graph, s, labelOf, parallel, true);
    EXPECT_EQ(serial.values(), parallel.values());
    for (std::size_t v = 0; v < mask->size(); ++v) {
        if (!(*mask)[v]) {
            ASSERT_EQ(serial[v], 0u);
            continue;
        }
        ASSERT_EQ(serial[v], labelOf[s.nodeLabel[graph->nodeOfVoxel[ft[v]]]]);
    }
    // The axis voxel near the left end is in the left segment (label 8).
    const Dims d = mask->dims();
    EXPECT_EQ(serial(xMin + 3, d.y / 2, d.z / 2), 8u);
    EXPECT_EQ(serial(at(0.55), d.y / 2, d.z / 2), 7u);
}

TEST(SurfaceLabelling, GeodesicLoopSeparatesTheSphere) {
    // A loop of shortest paths takes diagonal steps: 26-connected regions on
    // either side touch through them unless the loop is dilated.
    const std::array<double, 3> centre{15.0, 15.0, 15.0};
    const MaskVolume mask = test::ballMask(Dims{31, 31, 31}, centre, 12.5);
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    GeodesicSearch search(graph);
    std::vector<std::uint32_t> points;
    for (double longitude : {10.0, 100.0, 190.0, 280.0})
        points.push_back(test::nodeOnSphere(graph, centre, 12.5, 35.0, longitude));
    const std::vector<std::uint32_t> loop = test::pathThrough(search, points, true);
    const SurfaceSegments s = labelSurface(graph, {loop}, 0.0);
    ASSERT_EQ(s.segmentCount, 2u);
    const std::uint32_t north = test::nodeOnSphere(graph, centre, 12.5, 90.0, 0.0);
    const std::uint32_t south = test::nodeOnSphere(graph, centre, 12.5, -90.0, 0.0);
    EXPECT_EQ(s.nodeLabel[north], 1u);  // the cap is the smaller side
    EXPECT_EQ(s.nodeLabel[south], 0u);
    EXPECT_GT(s.area[0], 2 * s.area[1]);
    EXPECT_EQ(s.area[0] + s.area[1], graph.nodeCount());
}

TEST(SurfaceLabelling, DiagonalCutSeparatesABox) {
    // The plane x + y = 25 meets the top and bottom faces of a box in
    // diagonal staircases: the nodes on either side of such a staircase are
    // 26-neighbours, so only the dilated cut separates the two halves.
    MaskVolume mask(Dims{26, 26, 26}, 0);
    test::fillBox(mask, {3, 3, 3}, {22, 22, 22});
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    std::vector<std::uint32_t> cut;
    for (std::uint32_t n = 0; n < graph.nodeCount(); ++n)
        if (graph.coord[n].x + graph.coord[n].y == 25) cut.push_back(n);
    const SurfaceSegments s = labelSurface(graph, {cut}, 0.0);
    ASSERT_EQ(s.segmentCount, 2u);
    const std::uint32_t low = graph.nodeOfVoxel[mask.index(3, 3, 12)],
                        high = graph.nodeOfVoxel[mask.index(22, 22, 12)];
    EXPECT_NE(s.nodeLabel[low], s.nodeLabel[high]);
    // Symmetric halves: equal areas up to the shared-out cut band.
    EXPECT_LT(double(s.area[0]) - double(s.area[1]), 0.2 * double(graph.nodeCount()));
    for (std::uint32_t n = 0; n < graph.nodeCount(); ++n) {
        const int sum = graph.coord[n].x + graph.coord[n].y;
        if (sum < 23) {
            EXPECT_EQ(s.nodeLabel[n], s.nodeLabel[low]);
        }
        if (sum > 27) {
            EXPECT_EQ(s.nodeLabel[n], s.nodeLabel[high]);
        }
    }
}

TEST(SurfaceLabelling, CavitySurfaceJoinsTheLargestSegment) {
    MaskVolume mask = test::ballMask(Dims{25, 25, 25}, {12, 12, 12}, 11.0);
    const MaskVolume hole = test::ballMask(Dims{25, 25, 25}, {12, 12, 12}, 4.0);
    for (std::size_t i = 0; i < mask.size(); ++i)
        if (hole[i]) mask[i] = 0;
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    ASSERT_EQ(graph.componentSize.size(), 2u);
    const SurfaceSegments s = labelSurface(graph, {}, 0.0);
    ASSERT_EQ(s.segmentCount, 1u);
    EXPECT_EQ(s.area[0], graph.nodeCount());

    // With a cut on the outer surface the cavity joins the larger side.
    std::vector<std::uint32_t> equator;
    for (std::uint32_t n = 0; n < graph.nodeCount(); ++n)
        if (graph.coord[n].z == 16 && graph.component[n] == 0) equator.push_back(n);
    const SurfaceSegments cut = labelSurface(graph, {equator}, 0.0);
    ASSERT_EQ(cut.segmentCount, 2u);
    const std::uint32_t inner = graph.nodeOfVoxel[mask.index(12, 12, 17)];  // on the cavity wall
    ASSERT_NE(inner, kNoNode);
    ASSERT_EQ(graph.component[inner], 1u);
    EXPECT_EQ(cut.nodeLabel[inner], 0u);
    EXPECT_EQ(cut.nodeLabel[graph.nodeOfVoxel[mask.index(12, 12, 1)]],
              0u);  // south pole: the larger side
    EXPECT_EQ(cut.nodeLabel[graph.nodeOfVoxel[mask.index(12, 12, 23)]], 1u);
}

TEST(SurfaceLabelling, LoopRoundAHandleSeparatesNothing) {
    // A torus cut once round its tube stays one piece: the loop separates
    // nothing (docs/algorithm.md §8.10). Cut twice, both loops border the two
    // pieces. The merge's measures of every piece are reported.
    const MaskVolume mask = rasterise(makeShape("torus"), {60, 2});
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    int xMin = graph.coord[0].x, xMax = xMin, yMin = graph.coord[0].y, yMax = yMin;
    for (const Coord& c : graph.coord) {
        xMin = std::min(xMin, c.x), xMax = std::max(xMax, c.x);
        yMin = std::min(yMin, c.y), yMax = std::max(yMax, c.y);
    }
    const int cx = (xMin + xMax) / 2, cy = (yMin + yMax) / 2;
    std::vector<std::uint32_t> near, far;
    for (std::uint32_t n = 0; n < graph.nodeCount(); ++n)
        if (graph.coord[n].x == cx) (graph.coord[n].y > cy ? far : near).push_back(n);
    const SurfaceSegments once = labelSurface(graph, {near}, 0.0);
    EXPECT_EQ(once.segmentCount, 1u);
    EXPECT_EQ(once.loopSeparates, (std::vector<std::uint8_t>{0}));
    const SurfaceSegments twice = labelSurface(graph, {near, far}, 0.0);
    EXPECT_EQ(twice.segmentCount, 2u);
    EXPECT_EQ(twice.loopSeparates, (std::vector<std::uint8_t>{1, 1}));
    ASSERT_EQ(twice.before.size(), 2u);
    for (const SegmentMeasure& m : twice.before) {
        EXPECT_LT(m.core, m.area);
        EXPECT_LT(m.area, m.measured);
        EXPECT_FALSE(m.merged);
    }
    EXPECT_EQ(twice.before[0].area + twice.before[1].area, graph.nodeCount());
    // Merged with a threshold above both halves but the largest: the other goes.
    const SurfaceSegments merged = labelSurface(graph, {near, far}, double(graph.nodeCount()));
    EXPECT_EQ(merged.segmentCount, 1u);
    EXPECT_EQ(int(merged.before[0].merged) + int(merged.before[1].merged), 1);
}

}  // namespace
}  // namespace skelseg
