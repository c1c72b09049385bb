// skelseg: vectors whose new elements are left unwritten, for arrays that a
// parallel kernel fills completely.
//
// std::vector value-initialises what resize() adds: for a grid-sized array
// (the voxel -> node map of the boundary graph, the landmark rows) that is a
// serial pass over 50 to 150 MB at 400^3, and on our virtual machines also
// the first touch of every page, which the kernel clears (docs/performance.md,
// "A fresh machine's memory"). The kernel that fills the array afterwards
// runs in parallel, so leaving the elements unwritten moves both the writes
// and the page faults onto all threads. DefaultInitAllocator does that: its
// construct() with no arguments default-initialises, which for the
// trivially constructible element types used here writes nothing.
// Every other construction (copies, fills, push_back) is std::allocator's.
//
// The rule for callers: every element a reader can reach must be written
// before it is read, by the kernel that resized it. A copy of such a vector
// copies whatever the elements hold, so callers also write the slack they
// never read (padding, alignment offsets).
#pragma once

#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include "kernels/base/HugePages.h"

namespace skelseg {

template <typename T>
class DefaultInitAllocator : public std::allocator<T> {
public:
    static_assert(std::is_trivially_default_constructible<T>::value,
                  "only trivially constructible elements may be left unwritten");
    using std::allocator<T>::allocator;
    template <typename U>
    struct rebind {
        using other = DefaultInitAllocator<U>;
    };
    DefaultInitAllocator() noexcept = default;
    template <typename U>
    DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}

    template <typename U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value) {
        ::new (static_cast<void*>(p)) U;
    }
    template <typename U, typename... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

template <typename T, typename U>
bool operator==(const DefaultInitAllocator<T>&, const DefaultInitAllocator<U>&) noexcept {
    return true;
}
template <typename T, typename U>
bool operator!=(const DefaultInitAllocator<T>&, const DefaultInitAllocator<U>&) noexcept {
    return false;
}

/// A vector whose resize() leaves the new elements unwritten.
template <typename T>
using UninitialisedVector = std::vector<T, DefaultInitAllocator<T>>;

/// Resizes an empty or cleared `values` to `count` unwritten elements, with
/// huge pages asked for (as assignWithHugePages does) before anything
/// touches the memory. The caller writes every element it will read.
template <typename T>
void resizeUnwrittenWithHugePages(UninitialisedVector<T>& values, std::size_t count) {
    if (count * sizeof(T) >= kHugePageAdviceBytes && values.capacity() < count) {
        UninitialisedVector<T>().swap(values);
        values.reserve(count);
        adviseHugePages(values.data(), values.capacity() * sizeof(T));
    }
    values.clear();
    values.resize(count);
}

}  // namespace skelseg
