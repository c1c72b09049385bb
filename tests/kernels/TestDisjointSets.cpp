#include "kernels/DisjointSets.h"

#include <gtest/gtest.h>

namespace skelseg {
namespace {

TEST(DisjointSets, RootIsTheSmallestMemberWhateverTheUnionOrder) {
    DisjointSets forward(8), backward(8);
    forward.unite(5, 7), forward.unite(7, 2), forward.unite(2, 6);
    backward.unite(6, 2), backward.unite(2, 7), backward.unite(7, 5);
    for (std::uint32_t x : {2u, 5u, 6u, 7u}) {
        EXPECT_EQ(forward.find(x), 2u);
        EXPECT_EQ(backward.find(x), 2u);
    }
    for (std::uint32_t x : {0u, 1u, 3u, 4u}) {
        EXPECT_EQ(forward.find(x), x);
        EXPECT_EQ(backward.find(x), x);
    }
}

TEST(DisjointSets, UnitingJoinedSetsChangesNothing) {
    DisjointSets sets(4);
    sets.unite(1, 3);
    sets.unite(3, 1);
    sets.unite(1, 1);
    EXPECT_EQ(sets.find(3), 1u);
    EXPECT_EQ(sets.find(0), 0u);
    EXPECT_EQ(sets.find(2), 2u);
}

}  // namespace
}  // namespace skelseg
