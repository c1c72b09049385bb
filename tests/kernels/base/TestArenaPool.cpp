// ArenaPool: arenas are reused, one per run in flight, never one per run.
#include "kernels/base/ArenaPool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

namespace skelseg {
namespace {

TEST(ArenaPool, SequentialRunsShareOneArena) {
    ArenaPool pool;
    const tbb::task_arena* first = nullptr;
    for (int run = 0; run < 50; ++run) {
        const ArenaPool::Lease lease = pool.acquire(2);
        if (!first) first = &lease.arena();
        EXPECT_EQ(&lease.arena(), first);
        int concurrency = 0;
        lease.arena().execute([&] { concurrency = tbb::this_task_arena::max_concurrency(); });
        EXPECT_EQ(concurrency, 2);
    }
    EXPECT_EQ(pool.arenaCount(), 1u);
    EXPECT_EQ(pool.leaseCount(), 50u);
}

TEST(ArenaPool, RunsAtOnceGetTheirOwnArenasAndLeaveThemForLaterRuns) {
    ArenaPool pool;
    {
        const ArenaPool::Lease a = pool.acquire(2);
        const ArenaPool::Lease b = pool.acquire(2);
        const ArenaPool::Lease c = pool.acquire(2);
        EXPECT_NE(&a.arena(), &b.arena());
        EXPECT_NE(&b.arena(), &c.arena());
        EXPECT_NE(&a.arena(), &c.arena());
    }
    EXPECT_EQ(pool.arenaCount(), 3u);
    // Threads running 200 shapes, at most 3 at a time: still 3 arenas.
    std::vector<std::thread> threads;
    for (int t = 0; t < 3; ++t)
        threads.emplace_back([&] {
            for (int run = 0; run < 200 / 3 + 1; ++run) {
                const ArenaPool::Lease lease = pool.acquire(2);
                lease.arena().execute([] {});
            }
        });
    for (auto& thread : threads) thread.join();
    EXPECT_EQ(pool.arenaCount(), 3u);
}

TEST(ArenaPool, ConcurrencyIsPartOfTheKey) {
    ArenaPool pool;
    { const ArenaPool::Lease one = pool.acquire(1); }
    const ArenaPool::Lease two = pool.acquire(2);
    int concurrency = 0;
    two.arena().execute([&] { concurrency = tbb::this_task_arena::max_concurrency(); });
    EXPECT_EQ(concurrency, 2);
    EXPECT_EQ(pool.arenaCount(), 2u);
    // Below one thread is one thread.
    { const ArenaPool::Lease zero = pool.acquire(0); }
    EXPECT_EQ(pool.arenaCount(), 2u);
}

TEST(ArenaPool, MovedLeaseReturnsTheArenaOnce) {
    ArenaPool pool;
    {
        ArenaPool::Lease first = pool.acquire(2);
        const ArenaPool::Lease moved(std::move(first));
    }
    const ArenaPool::Lease again = pool.acquire(2);
    EXPECT_EQ(pool.arenaCount(), 1u);
}

}  // namespace
}  // namespace skelseg
