#include "kernels/base/UninitialisedStorage.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

namespace skelseg {
namespace {

/// The bytes of the first `count` elements (read as unsigned char, which may
/// read memory no one has written).
template <typename Vector>
std::vector<unsigned char> bytesOf(const Vector& values, std::size_t count) {
    std::vector<unsigned char> bytes(count * sizeof(values[0]));
    std::memcpy(bytes.data(), values.data(), bytes.size());
    return bytes;
}

TEST(UninitialisedStorage, ResizeLeavesTheElementsUnwrittenWhereStdVectorZeroesThem) {
    constexpr std::size_t kCount = 4096;
    UninitialisedVector<std::uint32_t> unwritten;
    unwritten.assign(kCount, 0xABCDEF01u);
    const std::vector<unsigned char> before = bytesOf(unwritten, kCount);
    unwritten.clear();
    unwritten.resize(kCount);  // within the capacity: the same memory
    EXPECT_EQ(bytesOf(unwritten, kCount), before);

    // The same steps on a std::vector write zeros: what the allocator saves.
    std::vector<std::uint32_t> zeroed;
    zeroed.assign(kCount, 0xABCDEF01u);
    zeroed.clear();
    zeroed.resize(kCount);
    EXPECT_EQ(zeroed, std::vector<std::uint32_t>(kCount, 0u));
}

TEST(UninitialisedStorage, EveryOtherConstructionIsStdVectors) {
    UninitialisedVector<float> values(5, 2.5f);
    EXPECT_EQ(std::vector<float>(values.begin(), values.end()), std::vector<float>(5, 2.5f));
    values.push_back(-1.0f);
    values.insert(values.begin(), 7.0f);
    const UninitialisedVector<float> copy = values;
    EXPECT_EQ(copy, values);
    EXPECT_EQ(std::vector<float>(copy.begin(), copy.end()),
              (std::vector<float>{7.0f, 2.5f, 2.5f, 2.5f, 2.5f, 2.5f, -1.0f}));
    values.assign(3, 4.0f);
    EXPECT_EQ(std::vector<float>(values.begin(), values.end()), std::vector<float>(3, 4.0f));
}

TEST(UninitialisedStorage, ResizeWithHugePagesGivesTheCountWhateverWasThere) {
    // Above kHugePageAdviceBytes the vector is replaced by one reserved for
    // the count; below, it keeps its buffer. Either way the size is the count.
    const std::size_t large = kHugePageAdviceBytes / sizeof(std::uint32_t) + 1000;
    UninitialisedVector<std::uint32_t> values(10, 3u);
    resizeUnwrittenWithHugePages(values, large);
    EXPECT_EQ(values.size(), large);
    EXPECT_GE(values.capacity(), large);
    resizeUnwrittenWithHugePages(values, 16);
    EXPECT_EQ(values.size(), 16u);
    values[15] = 9u;  // writable
    EXPECT_EQ(values[15], 9u);
}

}  // namespace
}  // namespace skelseg
