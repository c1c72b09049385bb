// Generation-stamped marks and maps: a clear forgets everything, in O(1).
#include <gtest/gtest.h>

#include <cstdint>

#include "kernels/BoundaryGraph.h"
#include "kernels/GenerationMarks.h"

namespace skelseg {
namespace {

TEST(GenerationMap, AbsentUntilSetAndAgainAfterClear) {
    GenerationMap<std::uint32_t> map(10, kNoNode);
    for (std::uint32_t n = 0; n < 10; ++n) {
        EXPECT_FALSE(map.contains(n));
        EXPECT_EQ(map.get(n), kNoNode);
    }
    map.set(3, 7u);
    map.set(9, 0u);
    EXPECT_TRUE(map.contains(3));
    EXPECT_EQ(map.get(3), 7u);
    EXPECT_EQ(map.get(9), 0u);
    EXPECT_FALSE(map.contains(4));
    map.set(3, 8u);  // overwrite within one generation
    EXPECT_EQ(map.get(3), 8u);
    map.clear();
    EXPECT_FALSE(map.contains(3));
    EXPECT_EQ(map.get(3), kNoNode);
    EXPECT_EQ(map.get(9), kNoNode);
    map.set(9, 5u);
    EXPECT_EQ(map.get(9), 5u);
    map.resize(4);
    for (std::uint32_t n = 0; n < 4; ++n) EXPECT_EQ(map.get(n), kNoNode);
}

TEST(GenerationMarks, InsertReportsOnlyTheFirstMarkOfAGeneration) {
    GenerationMarks marks(5);
    EXPECT_TRUE(marks.insert(2));
    EXPECT_FALSE(marks.insert(2));
    EXPECT_TRUE(marks.isMarked(2));
    EXPECT_FALSE(marks.isMarked(1));
    marks.nextGeneration();
    EXPECT_FALSE(marks.isMarked(2));
    EXPECT_TRUE(marks.insert(2));
}

}  // namespace
}  // namespace skelseg
