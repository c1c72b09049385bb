// skelseg: union-find over node ids 0..n-1.
//
// Union by smaller root keeps every set's root its smallest member, so
// results that number sets by their roots do not depend on the order of the
// unions. Path halving keeps find() near constant without recursion.
#pragma once

#include <cstdint>
#include <numeric>
#include <vector>

namespace skelseg {

class DisjointSets {
public:
    explicit DisjointSets(std::size_t n) : mParent(n) {
        std::iota(mParent.begin(), mParent.end(), 0u);
    }
    /// The root of x's set: the set's smallest member.
    std::uint32_t find(std::uint32_t x) noexcept {
        while (mParent[x] != x) {
            mParent[x] = mParent[mParent[x]];
            x = mParent[x];
        }
        return x;
    }
    /// Joins the sets of a and b.
    void unite(std::uint32_t a, std::uint32_t b) noexcept {
        a = find(a);
        b = find(b);
        if (a == b) return;
        if (a < b)
            mParent[b] = a;
        else
            mParent[a] = b;
    }

private:
    std::vector<std::uint32_t> mParent;
};

}  // namespace skelseg
