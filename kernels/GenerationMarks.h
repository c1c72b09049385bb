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

/// A map node id -> T with O(1) clear; absent nodes read as `absent`.
template <typename T>
class GenerationMap {
public:
    explicit GenerationMap(std::size_t size = 0, T absent = T())
        : mMarks(size), mValues(size, absent), mAbsent(absent) {}
    void resize(std::size_t size) { mMarks.resize(size), mValues.assign(size, mAbsent); }
    void clear() noexcept { mMarks.nextGeneration(); }
    bool contains(std::uint32_t node) const noexcept { return mMarks.isMarked(node); }
    T get(std::uint32_t node) const noexcept {
        return mMarks.isMarked(node) ? mValues[node] : mAbsent;
    }
    void set(std::uint32_t node, T value) noexcept { mMarks.mark(node), mValues[node] = value; }

private:
    GenerationMarks mMarks;
    std::vector<T> mValues;
    T mAbsent;
};

}  // namespace skelseg
