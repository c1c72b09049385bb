// skelseg: lazily reset per-node marks for thread-local search workspaces.
//
// A search touches a few hundred nodes of a graph with 10^5..10^6 nodes and
// runs millions of times; clearing a boundary-sized array per search would
// cost more than the search. Each slot stores the generation that last wrote
// it, so nextGeneration() "clears" everything in O(1).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace skelseg {

/// A set of node ids with O(1) clear.
class GenerationMarks {
public:
    explicit GenerationMarks(std::size_t size = 0) : mStamp(size, 0) {}
    void resize(std::size_t size) { mStamp.assign(size, 0), mGeneration = 1; }
    std::size_t size() const noexcept { return mStamp.size(); }

    /// Forgets every mark.
    void nextGeneration() noexcept {
        if (++mGeneration == 0) {  // wrapped: really clear once every 2^32 generations
            std::fill(mStamp.begin(), mStamp.end(), 0u);
            mGeneration = 1;
        }
    }
    bool isMarked(std::uint32_t node) const noexcept { return mStamp[node] == mGeneration; }
    void mark(std::uint32_t node) noexcept { mStamp[node] = mGeneration; }
    /// Marks node; returns true if it was not marked before.
    bool insert(std::uint32_t node) noexcept {
        if (mStamp[node] == mGeneration) return false;
        mStamp[node] = mGeneration;
        return true;
    }

private:
    std::vector<std::uint32_t> mStamp;
    std::uint32_t mGeneration = 1;
};

/// A map node id -> T with O(1) clear; absent nodes read as `absent`. Each
/// node's stamp sits beside its value, so a look-up (component growth asks
/// one per neighbour of every node it takes) is one cache line, not two.
template <typename T>
class GenerationMap {
public:
    explicit GenerationMap(std::size_t size = 0, T absent = T())
        : mSlots(size, Slot{0, absent}), mAbsent(absent) {}
    void resize(std::size_t size) { mSlots.assign(size, Slot{0, mAbsent}), mGeneration = 1; }
    void clear() noexcept {
        if (++mGeneration == 0) {  // wrapped: really clear once every 2^32 generations
            for (Slot& slot : mSlots) slot.stamp = 0;
            mGeneration = 1;
        }
    }
    bool contains(std::uint32_t node) const noexcept { return mSlots[node].stamp == mGeneration; }
    T get(std::uint32_t node) const noexcept {
        const Slot& slot = mSlots[node];
        return slot.stamp == mGeneration ? slot.value : mAbsent;
    }
    void set(std::uint32_t node, T value) noexcept { mSlots[node] = Slot{mGeneration, value}; }
    /// Requests node's slot into the cache (a hint; no effect on the map).
    void prefetch(std::uint32_t node) const noexcept { __builtin_prefetch(&mSlots[node]); }

private:
    struct Slot {
        std::uint32_t stamp;
        T value;
    };
    std::vector<Slot> mSlots;
    std::uint32_t mGeneration = 1;
    T mAbsent;
};

}  // namespace skelseg
