#include "kernels/base/LargeArray.h"

#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>

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

TEST(LargeArray, ContentsAreThoseOfAssign) {
    for (std::size_t count : {std::size_t(0), std::size_t(1000), (kLargeArrayBytes / 4) * 3}) {
        std::vector<std::uint32_t> large = {7, 8, 9}, plain = {7, 8, 9};
        assignLarge(large, count, 0xABCDu);
        plain.assign(count, 0xABCDu);
        EXPECT_TRUE(large == plain) << count << " values";
    }
    const Volume<std::uint16_t> volume(Dims{300, 200, 100}, 5);
    EXPECT_EQ(volume.size(), std::size_t(300 * 200 * 100));
    for (std::size_t i = 0; i < volume.size(); i += 4099) ASSERT_EQ(volume[i], 5);
}

TEST(LargeArray, KeepsStorageThatIsLargeEnough) {
    std::vector<std::uint8_t> values;
    assignLarge(values, kLargeArrayBytes * 2, std::uint8_t(1));
    const std::uint8_t* storage = values.data();
    assignLarge(values, kLargeArrayBytes, std::uint8_t(2));
    EXPECT_EQ(values.data(), storage);
    EXPECT_EQ(values.size(), kLargeArrayBytes);
    EXPECT_EQ(values.back(), 2);
}

TEST(LargeArray, NoWholePageIsNoAdvice) {
    alignas(64) static std::uint8_t small[64];
    EXPECT_FALSE(adviseHugePages(small, sizeof small));
    EXPECT_FALSE(adviseHugePages(nullptr, 1 << 22));
}

TEST(LargeArray, LargeArraysAreMarkedForHugePages) {
    if (!systemHasTransparentHugePages()) GTEST_SKIP() << "no transparent huge pages here";
    std::vector<std::uint32_t> values;
    assignLarge(values, kLargeArrayBytes, 0u);
    const std::string flags = vmFlagsOf(values.data() + values.size() / 2);
    if (flags.empty()) GTEST_SKIP() << "/proc/self/smaps is not readable";
    // "hg": the mapping carries MADV_HUGEPAGE.
    EXPECT_NE(flags.find(" hg"), std::string::npos) << flags;
    // A small array stays on the heap, unmarked.
    std::vector<std::uint32_t> small;
    assignLarge(small, 1000, 0u);
    EXPECT_EQ(vmFlagsOf(small.data()).find(" hg"), std::string::npos);
}

}  // namespace
}  // namespace skelseg
