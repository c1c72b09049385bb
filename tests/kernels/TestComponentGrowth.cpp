#include "kernels/ComponentGrowth.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

#include "tests/kernels/KernelTestSupport.h"

namespace skelseg {
namespace {

constexpr std::array<double, 3> kCentre{15.0, 15.0, 15.0};
constexpr double kRadius = 12.5;

/// Brute-force reference: flood fill of the surface minus Gamma'. Checks the
/// grower's areas, the piece -> component map and rho_C.
void expectMatchesFloodFill(const BoundaryGraph& graph, const RimCounter& rims,
                            const ComponentAreas& areas) {
    const RimPieces& pieces = rims.result();
    std::vector<std::uint32_t> label;
    const std::vector<std::uint64_t> sizes = test::floodFill(
        graph, [&](std::uint32_t n) { return !rims.isInDilated(n); }, label);
    ASSERT_EQ(areas.componentCount, sizes.size());
    ASSERT_EQ(areas.componentOfPiece.size(), pieces.pieceCount);
    // Pieces map to the same component exactly when their rim nodes lie in
    // the same flood-fill component, and the areas agree.
    std::map<std::uint32_t, std::uint32_t> floodOfComponent;
    for (std::size_t i = 0; i < pieces.rimNodes.size(); ++i) {
        const std::uint32_t component = areas.componentOfPiece[pieces.pieceOfRimNode[i]];
        const std::uint32_t flood = label[pieces.rimNodes[i]];
        auto [it, inserted] = floodOfComponent.emplace(component, flood);
        EXPECT_EQ(it->second, flood) << "one component spans two flood-fill components";
    }
    std::set<std::uint32_t> floods;
    for (const auto& [component, flood] : floodOfComponent) {
        EXPECT_TRUE(floods.insert(flood).second) << "two components are one flood-fill component";
        EXPECT_EQ(areas.area[component], sizes[flood]) << "component " << component;
        EXPECT_TRUE(areas.exact[component]);
    }
    std::uint64_t sum = 0, largest = 0;
    for (std::uint64_t s : sizes) sum += s, largest = std::max(largest, s);
    EXPECT_EQ(sum + pieces.dilated.size(), graph.nodeCount());
    EXPECT_EQ(areas.surfaceArea, graph.nodeCount());
    EXPECT_TRUE(areas.rhoCExact);
    EXPECT_EQ(areas.rhoC, graph.nodeCount() - largest);
}

class GrowthOnSphere : public test::BallBoundaryFixture {
protected:
    std::vector<std::uint32_t> loopAt(double latitude) const {
        GeodesicSearch search(*graph);
        return BallBoundaryFixture::loopAt(latitude, search);
    }
};

TEST_F(GrowthOnSphere, ExactAreasOfALoopMatchFloodFill) {
    for (double latitude : {0.0, 35.0, 60.0}) {
        SCOPED_TRACE("latitude " + std::to_string(latitude));
        RimCounter rims(*graph);
        ASSERT_EQ(rims.countRims(loopAt(latitude)).pieceCount, 2u);
        ComponentGrower grower(*graph);
        const ComponentAreas& areas = grower.grow(rims, ComponentGrower::kExactArea);
        ASSERT_EQ(areas.componentCount, 2u);
        EXPECT_NE(areas.componentOfPiece[0], areas.componentOfPiece[1]);
        // The two sides sum to the surface minus Gamma'.
        EXPECT_EQ(areas.area[0] + areas.area[1] + rims.result().dilated.size(), graph->nodeCount());
        expectMatchesFloodFill(*graph, rims, areas);
        if (latitude > 10.0) {
            // rho_C is the cap (the smaller side) plus the loop's own area.
            const std::uint64_t cap = std::min(areas.area[0], areas.area[1]);
            EXPECT_EQ(areas.rhoC, cap + rims.result().dilated.size());
            EXPECT_LT(areas.rhoC, graph->nodeCount() / 2);
        }
        EXPECT_GT(areas.growthSteps, 0u);
    }
}

TEST_F(GrowthOnSphere, RhoCGrowsAsTheLoopMovesTowardTheMiddle) {
    std::uint64_t previous = 0;
    for (double latitude : {70.0, 55.0, 40.0, 25.0, 10.0}) {
        RimCounter rims(*graph);
        rims.countRims(loopAt(latitude));
        ComponentGrower grower(*graph);
        const std::uint64_t rhoC = grower.grow(rims, ComponentGrower::kExactArea).rhoC;
        EXPECT_GT(rhoC, previous) << "latitude " << latitude;
        previous = rhoC;
    }
}

TEST_F(GrowthOnSphere, ThetaGivesThreeComponents) {
    GeodesicSearch search(*graph);
    std::vector<std::uint32_t> theta = loopAt(0.0);
    for (std::uint32_t n : test::pathThrough(search, {at(0, 0), at(90, 0), at(0, 180)}, false))
        theta.push_back(n);
    RimCounter rims(*graph);
    ASSERT_EQ(rims.countRims(theta).pieceCount, 3u);
    ComponentGrower grower(*graph);
    const ComponentAreas& areas = grower.grow(rims, ComponentGrower::kExactArea);
    EXPECT_EQ(areas.componentCount, 3u);
    expectMatchesFloodFill(*graph, rims, areas);
}

TEST_F(GrowthOnSphere, CapGivesALowerBound) {
    RimCounter rims(*graph);
    rims.countRims(loopAt(35.0));
    ComponentGrower grower(*graph);
    const ComponentAreas exact = grower.grow(rims, ComponentGrower::kExactArea);
    const std::uint64_t smaller = std::min(exact.area[0], exact.area[1]);
    ASSERT_GT(smaller, 60u);
    const std::uint64_t blocked = rims.result().dilated.size();

    // A cap below both sides: growth stops early, rho_C is a lower bound.
    for (std::uint64_t cap : {std::uint64_t(5), std::uint64_t(30), smaller / 2}) {
        SCOPED_TRACE("cap " + std::to_string(cap));
        const ComponentAreas& capped = grower.grow(rims, cap);
        EXPECT_FALSE(capped.rhoCExact);
        EXPECT_LE(capped.rhoC, exact.rhoC);
        EXPECT_GE(capped.rhoC, blocked + cap);  // the smaller side is known to hold >= cap
        ASSERT_EQ(capped.componentCount, 2u);
        for (std::uint32_t c = 0; c < 2; ++c) {
            EXPECT_LE(capped.area[c], exact.area[c]);
            EXPECT_GE(capped.area[c], cap);
        }
        EXPECT_LT(capped.growthSteps, exact.growthSteps);
    }
    // A cap above the smaller side: that side is exhausted first, which
    // leaves one survivor, so the result is exact after all.
    const ComponentAreas& above = grower.grow(rims, smaller + 1);
    EXPECT_TRUE(above.rhoCExact);
    EXPECT_EQ(above.rhoC, exact.rhoC);
    EXPECT_EQ(above.area, exact.area);
}

TEST_F(GrowthOnSphere, OpenPathHasOneComponent) {
    GeodesicSearch search(*graph);
    RimCounter rims(*graph);
    ASSERT_EQ(rims.countRims(test::pathThrough(search, {at(0, 0), at(30, 90)}, false)).pieceCount,
              1u);
    ComponentGrower grower(*graph);
    const ComponentAreas& areas = grower.grow(rims, ComponentGrower::kExactArea);
    ASSERT_EQ(areas.componentCount, 1u);
    EXPECT_EQ(areas.area[0], graph->nodeCount() - rims.result().dilated.size());
    EXPECT_EQ(areas.rhoC, rims.result().dilated.size());
    expectMatchesFloodFill(*graph, rims, areas);
}

/// A torus: ring radius 11, tube radius 5, axis z.
MaskVolume torusMask() {
    MaskVolume mask(Dims{36, 36, 16}, 0);
    for (int z = 0; z < 16; ++z)
        for (int y = 0; y < 36; ++y)
            for (int x = 0; x < 36; ++x) {
                const double dx = x - 17.5, dy = y - 17.5, dz = z - 7.5;
                const double ring = std::sqrt(dx * dx + dy * dy) - 11.0;
                mask(x, y, z) = ring * ring + dz * dz <= 25.0 ? 1 : 0;
            }
    return mask;
}

TEST(ComponentGrowth, MeridianLoopOnTorusGivesTwoRimsOneComponent) {
    const MaskVolume mask = torusMask();
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    ASSERT_EQ(graph.componentSize.size(), 1u);
    // Four points around the tube in the plane y = 17.5, x > centre.
    std::vector<std::uint32_t> waypoints;
    for (double theta : {0.0, 90.0, 180.0, 270.0}) {
        const double t = theta * test::kPi / 180.0;
        waypoints.push_back(test::nearestNode(
            graph, {17.5 + 11.0 + 5.0 * std::cos(t), 17.5, 7.5 + 5.0 * std::sin(t)}));
    }
    GeodesicSearch search(graph);
    const std::vector<std::uint32_t> loop = test::pathThrough(search, waypoints, true);
    RimCounter rims(graph);
    ASSERT_EQ(rims.countRims(loop).pieceCount, 2u);
    ComponentGrower grower(graph);
    const ComponentAreas& areas = grower.grow(rims, ComponentGrower::kExactArea);
    // Both rims bound the same (only) component: a handle loop.
    ASSERT_EQ(areas.componentCount, 1u);
    EXPECT_EQ(areas.componentOfPiece[0], areas.componentOfPiece[1]);
    EXPECT_EQ(areas.area[0], graph.nodeCount() - rims.result().dilated.size());
    EXPECT_EQ(areas.rhoC, rims.result().dilated.size());
    expectMatchesFloodFill(graph, rims, areas);
}

TEST(ComponentGrowth, CavityIsNotPartOfTheSurfaceArea) {
    // A hollow ball: the loop lies on the outer surface; the inner surface is
    // another graph component and must not enter the areas.
    MaskVolume mask = test::ballMask(Dims{31, 31, 31}, kCentre, kRadius);
    const MaskVolume hole = test::ballMask(Dims{31, 31, 31}, kCentre, 5.0);
    for (std::size_t i = 0; i < mask.size(); ++i)
        if (hole[i]) mask[i] = 0;
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    ASSERT_EQ(graph.componentSize.size(), 2u);
    const std::uint64_t outer = graph.componentSize[0];
    GeodesicSearch search(graph);
    auto at = [&](double lat, double lon) {
        return test::nodeOnSphere(graph, kCentre, kRadius, lat, lon);
    };
    RimCounter rims(graph);
    ASSERT_EQ(rims.countRims(test::pathThrough(
                                 search, {at(30, 0), at(30, 90), at(30, 180), at(30, 270)}, true))
                  .pieceCount,
              2u);
    ComponentGrower grower(graph);
    const ComponentAreas& areas = grower.grow(rims, ComponentGrower::kExactArea);
    EXPECT_EQ(areas.surfaceArea, outer);
    ASSERT_EQ(areas.componentCount, 2u);
    EXPECT_EQ(areas.area[0] + areas.area[1] + rims.result().dilated.size(), outer);
    EXPECT_EQ(areas.rhoC, outer - std::max(areas.area[0], areas.area[1]));
}

}  // namespace
}  // namespace skelseg
