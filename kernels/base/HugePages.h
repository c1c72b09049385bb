// skelseg: transparent huge pages for the large arrays of one run.
//
// A run at 400^3 fills several crop-sized arrays (the mask, the boundary
// mask, the feature transform, the voxel -> node map: 40 to 170 MB each),
// and each is touched for the first time right after it is allocated. With
// 4 KB pages that first touch is one page fault per 4 KB, which on the
// virtual machines we run on costs far more than writing the memory
// (figures in docs/performance.md, "Skeleton stages at 400"). Asking the
// kernel for 2 MB pages
// (madvise MADV_HUGEPAGE, honoured where transparent huge pages are in
// "madvise" or "always" mode) makes it 512 times fewer faults. The advice is
// a hint: where the kernel refuses it, or on other systems, nothing changes
// but speed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace skelseg {

/// Smallest block worth advising: below a few huge pages the faults saved do
/// not pay for the call.
constexpr std::size_t kHugePageAdviceBytes = std::size_t(8) << 20;

/// Asks for huge pages on the 2 MB-aligned part of [data, data + bytes).
/// Call it before the memory is first written; a no-op below
/// kHugePageAdviceBytes and where the system has no such advice.
inline void adviseHugePages(void* data, std::size_t bytes) noexcept {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (!data || bytes < kHugePageAdviceBytes) return;
    constexpr std::uintptr_t kHuge = std::uintptr_t(2) << 20;
    const std::uintptr_t begin =
        (reinterpret_cast<std::uintptr_t>(data) + kHuge - 1) & ~(kHuge - 1);
    const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(data) + bytes) & ~(kHuge - 1);
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
    (void)data, (void)bytes;
#endif
}

/// Resizes an empty or cleared `values` to `count` copies of `fill`, with
/// huge pages asked for before the fill touches the memory.
template <typename T, typename Allocator>
void assignWithHugePages(std::vector<T, Allocator>& values, std::size_t count, const T& fill) {
    if (count * sizeof(T) >= kHugePageAdviceBytes && values.capacity() < count) {
        std::vector<T, Allocator>().swap(values);
        values.reserve(count);
        adviseHugePages(values.data(), values.capacity() * sizeof(T));
    }
    values.assign(count, fill);
}

/// Reserves room for `count` elements with huge pages asked for (when the
/// vector has to grow for it).
template <typename T, typename Allocator>
void reserveWithHugePages(std::vector<T, Allocator>& values, std::size_t count) {
    if (values.capacity() >= count) return;
    values.reserve(count);
    if (values.empty()) adviseHugePages(values.data(), values.capacity() * sizeof(T));
}

}  // namespace skelseg
