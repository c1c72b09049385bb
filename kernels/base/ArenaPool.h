// skelseg: task arenas kept for reuse, so a process that runs many shapes
// creates a handful of arenas instead of one per shape.
//
// oneTBB 2021.8 never frees the internal object of a task arena that asked
// for a worker the machine could not give it: an arena of two threads
// created inside a task while the only worker is busy (a batch with several
// shapes in flight on two cores). Each such arena kept its arena object,
// slots and task-stream lanes, so a batch grew with every input, without
// end (docs/scale-out.md, "The memory growth of a long batch"). An
// arena that is reused costs it once. The pool hands an idle arena of the
// asked concurrency to one caller at a time and creates one only when all
// of that concurrency are in use, so the count is bounded by the runs in
// flight at once.
#pragma once

#include <tbb/task_arena.h>

#include <cstddef>
#include <memory>
#include <mutex>
#include <vector>

namespace skelseg {

class ArenaPool {
public:
    /// One arena, the caller's alone until the lease ends.
    class Lease {
    public:
        Lease(Lease&& other) noexcept;
        Lease(const Lease&) = delete;
        Lease& operator=(const Lease&) = delete;
        Lease& operator=(Lease&&) = delete;
        ~Lease();
        tbb::task_arena& arena() const { return *mArena; }

    private:
        friend class ArenaPool;
        Lease(ArenaPool& pool, tbb::task_arena& arena) : mPool(&pool), mArena(&arena) {}
        ArenaPool* mPool;
        tbb::task_arena* mArena;
    };

    ArenaPool() = default;
    ArenaPool(const ArenaPool&) = delete;
    ArenaPool& operator=(const ArenaPool&) = delete;

    /// An idle arena of `concurrency` threads (>= 1), created if none is idle.
    Lease acquire(int concurrency);
    /// Arenas created so far (idle or leased).
    std::size_t arenaCount() const;
    /// Leases handed out so far.
    std::size_t leaseCount() const;

    /// The pool of the process. It is never destroyed: a task_arena
    /// destroyed at exit, after oneTBB may have shut down, is undefined.
    static ArenaPool& process();

private:
    struct Entry {
        std::unique_ptr<tbb::task_arena> arena;
        int concurrency = 0;
        bool leased = false;
    };
    void release(tbb::task_arena& arena);

    mutable std::mutex mMutex;
    std::vector<Entry> mEntries;
    std::size_t mLeases = 0;
};

}  // namespace skelseg
