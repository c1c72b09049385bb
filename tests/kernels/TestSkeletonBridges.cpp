#include "kernels/SkeletonBridges.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <tuple>

#include "kernels/DisjointSets.h"
#include "tests/kernels/KernelTestSupport.h"
#include "tests/support/StopAtOnce.h"

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

/// Pieces of a skeleton scattered in a ball with cubic holes: `groups`
/// random walks of `walk` nodes (a group each) drawn from `seed`, so that
/// some segments between them leave the object and many pairs tie.
struct ScatteredPieces {
    MaskVolume inside;
    std::vector<Coord> coord;
    std::vector<std::uint32_t> group;
};

/// insideOnly: nodes off the object are left out (a walk may step there).
ScatteredPieces scatteredPieces(std::uint32_t seed, int size, int holes, std::uint32_t groups,
                                int walk, bool insideOnly) {
    std::mt19937 rng(seed);
    const Dims dims{size, size, size};
    ScatteredPieces s{
        test::ballMask(dims, {size / 2.0, size / 2.0, size / 2.0}, size / 2.0), {}, {}};
    std::uniform_int_distribution<int> at(0, size - 1), step(-1, 1);
    for (int hole = 0; hole < holes; ++hole) {
        const int hx = at(rng), hy = at(rng), hz = at(rng);
        for (int z = std::max(0, hz - 2); z <= std::min(size - 1, hz + 2); ++z)
            for (int y = std::max(0, hy - 2); y <= std::min(size - 1, hy + 2); ++y)
                for (int x = std::max(0, hx - 2); x <= std::min(size - 1, hx + 2); ++x)
                    s.inside(x, y, z) = 0;
    }
    for (std::uint32_t k = 0; k < groups; ++k) {
        Coord c{at(rng), at(rng), at(rng)};
        for (int i = 0; i < walk; ++i) {
            if (!insideOnly || s.inside(c.x, c.y, c.z)) {
                s.coord.push_back(c);
                s.group.push_back(k);
            }
            c = {std::clamp(c.x + step(rng), 0, size - 1), std::clamp(c.y + step(rng), 0, size - 1),
                 std::clamp(c.z + step(rng), 0, size - 1)};
        }
    }
    return s;
}

TEST(SkeletonBridges, JoiningThroughTheObjectTakesTheCandidatesOfTheDefinition) {
    for (const std::uint32_t seed : {1u, 2u, 3u, 4u}) {
        SCOPED_TRACE(seed);
        const std::uint32_t groups = 20 + seed * 10;
        const ScatteredPieces s = scatteredPieces(seed, 40 + int(seed) * 15, 30, groups, 12, false);
        const auto expected = joinByDefinition(s.coord, s.group, groups, s.inside);
        ASSERT_GT(expected.size(), groups / 3);
        EXPECT_EQ(joinGroupsThroughObject(s.coord, s.group, groups, s.inside), expected);
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

/// Steps of the shortest 6-connected path inside `inside` from each voxel
/// to `from` (UINT32_MAX where none).
std::vector<std::uint32_t> stepsFrom(const Coord& from, const MaskVolume& inside) {
    std::vector<std::uint32_t> steps(inside.size(), UINT32_MAX);
    std::vector<Coord> queue{from};
    steps[inside.index(from.x, from.y, from.z)] = 0;
    for (std::size_t head = 0; head < queue.size(); ++head) {
        const Coord c = queue[head];
        const std::uint32_t here = steps[inside.index(c.x, c.y, c.z)];
        for (const Coord o : {Coord{-1, 0, 0}, Coord{1, 0, 0}, Coord{0, -1, 0}, Coord{0, 1, 0},
                              Coord{0, 0, -1}, Coord{0, 0, 1}}) {
            const Coord n{c.x + o.x, c.y + o.y, c.z + o.z};
            if (!inside.contains(n.x, n.y, n.z) || !inside(n.x, n.y, n.z)) continue;
            std::uint32_t& there = steps[inside.index(n.x, n.y, n.z)];
            if (there != UINT32_MAX) continue;
            there = here + 1;
            queue.push_back(n);
        }
    }
    return steps;
}

TEST(SkeletonBridges, AFoldedLimbIsJoinedAlongTheObjectWhereNoStraightSegmentStaysInside) {
    // A U of two bars joined at x >= 30, with background between the bars:
    // the pieces near the open ends see each other only across the gap.
    MaskVolume inside(Dims{36, 13, 5}, 0);
    for (int z = 0; z < 5; ++z)
        for (int y = 0; y < 13; ++y)
            for (int x = 0; x < 36; ++x)
                if (y < 5 || y > 7 || x >= 30) inside(x, y, z) = 1;
    std::vector<Coord> coord;
    std::vector<std::uint32_t> group;
    for (int x = 2; x <= 10; ++x) {
        coord.push_back({x, 2, 2});
        group.push_back(0);
    }
    for (int x = 2; x <= 10; ++x) {
        coord.push_back({x, 10, 2});
        group.push_back(1);
    }
    EXPECT_TRUE(joinGroupsThroughObject(coord, group, 2, inside).empty());
    const auto bridges = joinGroupsAlongObject(coord, group, 2, inside);
    ASSERT_EQ(bridges.size(), 1u);
    // The two nodes nearest the U's base, x = 10 in each bar.
    EXPECT_EQ(bridges.front(), (std::array<std::uint32_t, 2>{8, 17}));
    // Cut one bar: nothing joins them.
    for (int z = 0; z < 5; ++z)
        for (int y = 8; y < 13; ++y) inside(20, y, z) = 0;
    EXPECT_TRUE(joinGroupsAlongObject(coord, group, 2, inside).empty());
    EXPECT_TRUE(joinGroupsAlongObject(coord, {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0},
                                      1, inside)
                    .empty());
}

TEST(SkeletonBridges, JoiningAlongTheObjectStopsWhenAsked) {
    // Two pieces at the poles of a ball of 113,000 voxels, joined by a flood
    // that polls every 65,536 voxels: a stop at any poll throws.
    const Dims dims{60, 60, 60};
    const MaskVolume inside = test::ballMask(dims, {30.0, 30.0, 30.0}, 30.0);
    const std::vector<Coord> coord = {{30, 30, 2}, {30, 30, 3}, {30, 30, 57}, {30, 30, 58}};
    const std::vector<std::uint32_t> group = {0, 0, 1, 1};
    ASSERT_EQ(joinGroupsAlongObject(coord, group, 2, inside).size(), 1u);
    const std::int64_t polls = test::expectAStopAtAnyPollThrows(
        [&](Interrupter& stop) { joinGroupsAlongObject(coord, group, 2, inside, stop); });
    EXPECT_GE(polls, 2);
}

TEST(SkeletonBridges, JoiningAlongTheObjectSpansTheGroupsAtTheLeastLength) {
    // The floods' meetings hold a spanning forest of the shortest paths
    // between the groups (Mehlhorn 1988): the bridges' summed length equals
    // that of a minimum spanning forest of the groups' distances inside the
    // object, computed here from one search per node.
    for (const std::uint32_t seed : {5u, 6u, 7u}) {
        SCOPED_TRACE(seed);
        const std::uint32_t groups = 12;
        const ScatteredPieces s = scatteredPieces(seed, 24 + int(seed) * 3, 25, groups, 6, true);
        const MaskVolume& inside = s.inside;
        const std::vector<Coord>& coord = s.coord;
        const std::vector<std::uint32_t>& group = s.group;
        const std::uint32_t n = std::uint32_t(coord.size());
        // Group distances inside the object, and node distances for the
        // bridges taken.
        std::vector<std::vector<std::uint32_t>> steps;
        for (const Coord& c : coord) steps.push_back(stepsFrom(c, inside));
        const auto between = [&](std::uint32_t a, std::uint32_t b) {
            return steps[a][inside.index(coord[b].x, coord[b].y, coord[b].z)];
        };
        std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> pairs;
        for (std::uint32_t a = 0; a < n; ++a)
            for (std::uint32_t b = a + 1; b < n; ++b)
                if (group[a] != group[b] && between(a, b) != UINT32_MAX)
                    pairs.emplace_back(between(a, b), group[a], group[b]);
        std::sort(pairs.begin(), pairs.end());
        DisjointSets minimum(groups);
        std::uint64_t minimumLength = 0;
        std::size_t minimumEdges = 0;
        for (const auto& [length, ga, gb] : pairs) {
            if (minimum.find(ga) == minimum.find(gb)) continue;
            minimum.unite(ga, gb);
            minimumLength += length;
            ++minimumEdges;
        }
        const auto bridges = joinGroupsAlongObject(coord, group, groups, inside);
        ASSERT_GE(minimumEdges, 3u);
        ASSERT_EQ(bridges.size(), minimumEdges);
        std::uint64_t length = 0;
        DisjointSets joined(groups);
        for (const auto& [a, b] : bridges) {
            EXPECT_NE(joined.find(group[a]), joined.find(group[b]));
            joined.unite(group[a], group[b]);
            length += between(a, b);
        }
        EXPECT_EQ(length, minimumLength);
    }
}

}  // namespace
}  // namespace skelseg
