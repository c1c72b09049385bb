// skelseg: the one serial switch of every parallel loop.
//
// parallelFor(count, body, threaded, grain) calls body(begin, end) on
// disjoint half-open ranges that together cover [0, count). With threaded
// true the ranges run on oneTBB's workers (tbb::parallel_for over a
// blocked_range with the given grain); with threaded false body(0, count)
// runs once on the calling thread. Every parallel kernel goes through here,
// so "serial equals parallel" is one switch to flip in a test, and a kernel
// never hand-writes its own if/else around tbb::parallel_for.
//
// Bodies must not depend on how the range is split: each index's work writes
// only its own outputs, or reduces with a combine that is order-independent.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstddef>
#include <type_traits>

namespace skelseg {

namespace detail {
/// parallelFor and parallelForSmallRanges: the same loop, TBB's partitioner
/// apart.
template <typename Index, typename RangeBody, typename Partitioner>
void parallelForWith(Index count, const RangeBody& body, bool threaded, std::size_t grain,
                     const Partitioner& partitioner) {
    static_assert(std::is_integral<Index>::value, "parallelFor counts with an integer type");
    if (count <= Index(0)) return;
    if (!threaded) {
        body(Index(0), count);
        return;
    }
    tbb::parallel_for(
        tbb::blocked_range<Index>(Index(0), count, grain > 0 ? grain : 1),
        [&](const tbb::blocked_range<Index>& range) { body(range.begin(), range.end()); },
        partitioner);
}
}  // namespace detail

/// Runs body(begin, end) over [0, count) in parallel (threaded) or as one
/// serial call. grain: the smallest range TBB hands to one task (>= 1).
template <typename Index, typename RangeBody>
void parallelFor(Index count, const RangeBody& body, bool threaded = true, std::size_t grain = 1) {
    detail::parallelForWith(count, body, threaded, grain, tbb::auto_partitioner());
}

/// parallelFor for loops whose cost per index varies by orders of magnitude
/// (a skeleton measure near the curve skeleton costs a hundred times one far
/// from it). parallelFor's adaptive split hands out ranges far longer than
/// `grain` while no thread is idle, and a range that is running cannot be
/// split: one long range of costly indices at the end of the loop keeps one
/// thread busy while the others wait. Here (threaded) every range holds at
/// most `grain` indices (oneTBB's simple_partitioner), so the wait is at
/// most one such range; serial, body(0, count) runs once as in parallelFor.
template <typename Index, typename RangeBody>
void parallelForSmallRanges(Index count, const RangeBody& body, bool threaded, std::size_t grain) {
    detail::parallelForWith(count, body, threaded, grain, tbb::simple_partitioner());
}

/// The same with a per-index body: body(i) for every i in [0, count).
template <typename Index, typename IndexBody>
void parallelForEach(Index count, const IndexBody& body, bool threaded = true,
                     std::size_t grain = 1) {
    parallelFor(
        count,
        [&](Index begin, Index end) {
            for (Index i = begin; i < end; ++i) body(i);
        },
        threaded, grain);
}

}  // namespace skelseg
