#include "kernels/SkeletonBridges.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <tuple>

#include "kernels/DisjointSets.h"
#include "tests/kernels/KernelTestSupport.h"

namespace skelseg {
namespace {

/// The definition, computed directly: every node's nearest node in every
/// other group is a candidate, all candidates are sorted once, and taken in
/// that order while their groups are apart and their segment stays inside.
std::vector<std::array<std::uint32_t, 2>> joinByDefinition(const std::vector<Coord>& coord,
                                                           const std::vector<std::uint32_t>& group,
                                                           std::uint32_t groups,
                                                           const MaskVolume& inside) {
    const std::uint32_t n = std::uint32_t(coord.size());
    std::vector<std::tuple<double, std::uint32_t, std::uint32_t>> candidates;
    for (std::uint32_t a = 0; a < n; ++a) {
        std::vector<std::pair<double, std::uint32_t>> nearest(groups, {HUGE_VAL, kNoJunction});
        for (std::uint32_t b = 0; b < n; ++b) {
            if (group[b] == group[a]) continue;
            const double dx = coord[b].x - coord[a].x, dy = coord[b].y - coord[a].y,
                         dz = coord[b].z - coord[a].z;
            nearest[group[b]] = std::min(nearest[group[b]], {dx * dx + dy * dy + dz * dz, b});
        }
        for (std::uint32_t k = 0; k < groups; ++k) {
            if (nearest[k].second == kNoJunction) continue;
            if (group[a] < k)
                candidates.emplace_back(nearest[k].first, a, nearest[k].second);
            else
                candidates.emplace_back(nearest[k].first, nearest[k].second, a);
        }
    }
    std::sort(candidates.begin(), candidates.end());
    const auto inObject = [&](const Coord& p, const Coord& q) {
        const double dx = q.x - p.x, dy = q.y - p.y, dz = q.z - p.z;
        const int steps = std::max(1, int(std::ceil(2.0 * std::sqrt(dx * dx + dy * dy + dz * dz))));
        for (int s = 0; s <= steps; ++s) {
            const double t = double(s) / steps;
            const int x = int(std::lround(p.x + t * dx)), y = int(std::lround(p.y + t * dy)),
                      z = int(std::lround(p.z + t * dz));
            if (!inside.contains(x, y, z) || !inside(x, y, z)) return false;
        }
        return true;
    };
    DisjointSets joined(groups);
    std::vector<std::array<std::uint32_t, 2>> bridges;
    for (const auto& [d2, a, b] : candidates) {
        if (joined.find(group[a]) == joined.find(group[b])) continue;
        if (!inObject(coord[a], coord[b])) continue;
        joined.unite(group[a], group[b]);
        bridges.push_back({std::min(a, b), std::max(a, b)});
    }
    return bridges;
}

TEST(SkeletonBridges, JoiningThroughTheObjectTakesTheCandidatesOfTheDefinition) {
    // Scattered pieces (short random walks) in a ball with holes, so that
    // some segments leave the object; many ties of equal length.
    for (const std::uint32_t seed : {1u, 2u, 3u, 4u}) {
        SCOPED_TRACE(seed);
        std::mt19937 rng(seed);
        const int size = 40 + int(seed) * 15;
        const Dims dims{size, size, size};
        MaskVolume inside = test::ballMask(dims, {size / 2.0, size / 2.0, size / 2.0}, size / 2.0);
        std::uniform_int_distribution<int> at(0, size - 1), step(-1, 1);
        for (int hole = 0; hole < 30; ++hole) {
            const int hx = at(rng), hy = at(rng), hz = at(rng);
            for (int z = std::max(0, hz - 2); z <= std::min(size - 1, hz + 2); ++z)
                for (int y = std::max(0, hy - 2); y <= std::min(size - 1, hy + 2); ++y)
                    for (int x = std::max(0, hx - 2); x <= std::min(size - 1, hx + 2); ++x)
                        inside(x, y, z) = 0;
        }
        std::vector<Coord> coord;
        std::vector<std::uint32_t> group;
        const std::uint32_t groups = 20 + seed * 10;
        for (std::uint32_t k = 0; k < groups; ++k) {
            Coord c{at(rng), at(rng), at(rng)};
            for (int i = 0; i < 12; ++i) {
                coord.push_back(c);
                group.push_back(k);
                c = {std::clamp(c.x + step(rng), 0, size - 1),
                     std::clamp(c.y + step(rng), 0, size - 1),
                     std::clamp(c.z + step(rng), 0, size - 1)};
            }
        }
        const auto expected = joinByDefinition(coord, group, groups, inside);
        ASSERT_GT(expected.size(), groups / 3);
        EXPECT_EQ(joinGroupsThroughObject(coord, group, groups, inside), expected);
    }
}

TEST(SkeletonBridges, GroupsThatCannotJoinAreLeftApart) {
    // Two groups with background between them: no bridge; one group: none.
    MaskVolume inside(Dims{30, 5, 5}, 1);
    for (int y = 0; y < 5; ++y)
        for (int z = 0; z < 5; ++z) inside(15, y, z) = 0;
    const std::vector<Coord> coord = {{2, 2, 2}, {3, 2, 2}, {26, 2, 2}, {27, 2, 2}};
    EXPECT_TRUE(joinGroupsThroughObject(coord, {0, 0, 1, 1}, 2, inside).empty());
    EXPECT_TRUE(joinGroupsThroughObject(coord, {0, 0, 0, 0}, 1, inside).empty());
    inside(15, 2, 2) = 1;
    const auto bridges = joinGroupsThroughObject(coord, {0, 0, 1, 1}, 2, inside);
    ASSERT_EQ(bridges.size(), 1u);
    EXPECT_EQ(bridges.front(), (std::array<std::uint32_t, 2>{1, 2}));
}

}  // namespace
}  // namespace skelseg
