// The huge-page helpers change where memory comes from, never what it holds.
#include <gtest/gtest.h>

#include <sys/mman.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#include "kernels/base/HugePages.h"
#include "kernels/base/Volume.h"

namespace skelseg {
namespace {

/// The VmFlags line of /proc/self/smaps for the mapping holding `address`;
/// empty when the file cannot be read.
std::string vmFlagsOf(const void* address) {
    std::ifstream smaps("/proc/self/smaps");
    std::string line;
    bool inside = false;
    const std::uintptr_t a = std::uintptr_t(address);
    while (std::getline(smaps, line)) {
        std::uintptr_t begin = 0, end = 0;
        char dash = 0;
        std::istringstream header(line);
        if (header >> std::hex >> begin >> dash >> end && dash == '-' &&
            line.find(':') > line.find(' ')) {
            inside = a >= begin && a < end;
            continue;
        }
        if (inside && line.rfind("VmFlags:", 0) == 0) return line;
    }
    return {};
}

bool systemHasTransparentHugePages() {
    std::ifstream mode("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string text;
    return std::getline(mode, text) && text.find("[never]") == std::string::npos;
}

TEST(HugePages, AssignFillsEveryElementAboveAndBelowTheAdviceSize) {
    for (std::size_t count : {std::size_t(1000), kHugePageAdviceBytes / 4 + 12345}) {
        std::vector<std::uint32_t> values(7, 3u);
        assignWithHugePages(values, count, 0xFFFFFFFFu);
        ASSERT_EQ(values.size(), count);
        EXPECT_TRUE(std::all_of(values.begin(), values.end(),
                                [](std::uint32_t v) { return v == 0xFFFFFFFFu; }));
        // A second assignment that fits reuses the block.
        const std::uint32_t* block = values.data();
        assignWithHugePages(values, count / 2, 5u);
        EXPECT_EQ(values.data(), block);
        ASSERT_EQ(values.size(), count / 2);
        EXPECT_EQ(values.front(), 5u);
        EXPECT_EQ(values.back(), 5u);
    }
}

TEST(HugePages, ReserveKeepsTheContentAndMakesRoom) {
    std::vector<float> values = {1.0f, 2.0f};
    reserveWithHugePages(values, kHugePageAdviceBytes / 2);
    EXPECT_GE(values.capacity(), kHugePageAdviceBytes / 2);
    EXPECT_EQ(values, (std::vector<float>{1.0f, 2.0f}));
    std::vector<float> empty;
    reserveWithHugePages(empty, kHugePageAdviceBytes);
    EXPECT_GE(empty.capacity(), kHugePageAdviceBytes);
    EXPECT_TRUE(empty.empty());
}

TEST(HugePages, LargeVolumeHoldsItsFillValue) {
    const Dims dims{200, 110, 100};  // 8.8 MB of uint32: above the advice size
    Volume<std::uint32_t> volume(dims, 42u);
    ASSERT_EQ(volume.size(), std::size_t(dims.voxelCount()));
    EXPECT_EQ(volume(0, 0, 0), 42u);
    EXPECT_EQ(volume(199, 109, 99), 42u);
    EXPECT_EQ(std::count(volume.values().begin(), volume.values().end(), 42u),
              std::ptrdiff_t(volume.size()));
}

/// Memory from a mapping of its own for each allocation, so that a block's
/// VmFlags show only what was done to that block: blocks of the heap share
/// their mapping with whatever else the process allocated (in a test process
/// that ran other tests first, a small heap array sat in a region an earlier
/// large array had advised).
template <typename T>
struct OwnMappingAllocator {
    using value_type = T;
    OwnMappingAllocator() = default;
    template <typename U>
    OwnMappingAllocator(const OwnMappingAllocator<U>&) noexcept {}
    T* allocate(std::size_t count) {
        void* block = mmap(nullptr, count * sizeof(T), PROT_READ | PROT_WRITE,
                           MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (block == MAP_FAILED) throw std::bad_alloc();
        return static_cast<T*>(block);
    }
    void deallocate(T* block, std::size_t count) noexcept { munmap(block, count * sizeof(T)); }
    template <typename U>
    bool operator==(const OwnMappingAllocator<U>&) const noexcept {
        return true;
    }
    template <typename U>
    bool operator!=(const OwnMappingAllocator<U>&) const noexcept {
        return false;
    }
};

TEST(HugePages, ArraysFromTheAdviceSizeUpAreMarkedForHugePagesAndSmallerOnesAreNot) {
    if (!systemHasTransparentHugePages()) GTEST_SKIP() << "no transparent huge pages here";
    using Values = std::vector<std::uint32_t, OwnMappingAllocator<std::uint32_t>>;
    Values large;
    assignWithHugePages(large, kHugePageAdviceBytes / sizeof(std::uint32_t), 0u);
    const std::string flags = vmFlagsOf(large.data() + large.size() / 2);
    if (flags.empty()) GTEST_SKIP() << "/proc/self/smaps is not readable";
    // "hg": the mapping carries MADV_HUGEPAGE.
    EXPECT_NE(flags.find(" hg"), std::string::npos) << flags;
    // One page less: still several whole huge pages inside, but below the
    // size worth the advice.
    Values smaller;
    assignWithHugePages(smaller, (kHugePageAdviceBytes - 4096) / sizeof(std::uint32_t), 0u);
    const std::string smallerFlags = vmFlagsOf(smaller.data() + smaller.size() / 2);
    EXPECT_EQ(smallerFlags.find(" hg"), std::string::npos) << smallerFlags;
}

TEST(HugePages, TheAdviceItselfIsANoOpBelowItsSize) {
    if (!systemHasTransparentHugePages()) GTEST_SKIP() << "no transparent huge pages here";
    for (const std::size_t bytes : {kHugePageAdviceBytes - 4096, kHugePageAdviceBytes}) {
        OwnMappingAllocator<char> mapping;
        char* block = mapping.allocate(bytes);
        adviseHugePages(block, bytes);
        const std::string flags = vmFlagsOf(block + bytes / 2);
        mapping.deallocate(block, bytes);
        if (flags.empty()) GTEST_SKIP() << "/proc/self/smaps is not readable";
        EXPECT_EQ(flags.find(" hg") != std::string::npos, bytes >= kHugePageAdviceBytes)
            << bytes << " bytes: " << flags;
    }
}

}  // namespace
}  // namespace skelseg
