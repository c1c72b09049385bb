// The huge-page helpers change where memory comes from, never what it holds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
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

TEST(HugePages, LargeArraysAreMarkedForHugePages) {
    if (!systemHasTransparentHugePages()) GTEST_SKIP() << "no transparent huge pages here";
    std::vector<std::uint32_t> values;
    assignWithHugePages(values, kHugePageAdviceBytes, 0u);
    const std::string flags = vmFlagsOf(values.data() + values.size() / 2);
    if (flags.empty()) GTEST_SKIP() << "/proc/self/smaps is not readable";
    // "hg": the mapping carries MADV_HUGEPAGE.
    EXPECT_NE(flags.find(" hg"), std::string::npos) << flags;
    // A small array stays on the heap, unmarked.
    std::vector<std::uint32_t> small;
    assignWithHugePages(small, 1000, 0u);
    EXPECT_EQ(vmFlagsOf(small.data()).find(" hg"), std::string::npos);
}

}  // namespace
}  // namespace skelseg
