// skelseg: whole-grid arrays that the kernel backs with huge pages.
//
// A 400^3 grid holds 64 million voxels: one array of them is 64 to 256 MB,
// and a run allocates several (mask, labels, crops, feature transform).
// glibc maps each such array fresh from the kernel and returns it on free,
// so every one is faulted in again page by page; with 4 KiB pages that is
// some 60,000 faults per array, and on a virtual machine a fault costs
// microseconds (docs/performance.md, "Stages outside the skeleton search at
// 400"). Transparent huge
// pages make it one fault per 2 MiB, but most systems grant them only to
// memory that asks (madvise mode), and std::vector cannot ask: it touches
// the memory as soon as it allocates it. assignLarge() reserves first, asks
// (madvise MADV_HUGEPAGE) while the memory is still untouched, then fills.
// The contents are exactly those of std::vector::assign; where the kernel
// refuses or the system has no huge pages, only the speed differs.
#pragma once

#include <cstddef>
#include <vector>

namespace skelseg {

/// Arrays at least this large ask for huge pages (smaller ones come from
/// glibc's heap, where pages are reused anyway).
constexpr std::size_t kLargeArrayBytes = std::size_t(8) << 20;

/// Asks the kernel to back the whole pages inside [data, data + bytes) with
/// transparent huge pages. Returns whether the request was accepted (false
/// when the range holds no whole page, or on systems without the advice).
/// Contents are unchanged; call it before the memory is first written.
bool adviseHugePages(void* data, std::size_t bytes) noexcept;

/// values.assign(count, fill), with the storage of a large array asked for
/// huge pages before it is filled. Keeps the storage when it is large
/// enough already (its pages are in memory).
template <typename T>
void assignLarge(std::vector<T>& values, std::size_t count, const T& fill) {
    if (values.capacity() >= count || count * sizeof(T) < kLargeArrayBytes) {
        values.assign(count, fill);
        return;
    }
    std::vector<T> fresh;
    fresh.reserve(count);
    adviseHugePages(fresh.data(), count * sizeof(T));
    fresh.assign(count, fill);
    values.swap(fresh);
}

}  // namespace skelseg
