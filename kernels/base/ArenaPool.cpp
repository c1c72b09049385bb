#include "kernels/base/ArenaPool.h"

#include <algorithm>

namespace skelseg {

ArenaPool::Lease::Lease(Lease&& other) noexcept : mPool(other.mPool), mArena(other.mArena) {
    other.mPool = nullptr;
}

ArenaPool::Lease::~Lease() {
    if (mPool) mPool->release(*mArena);
}

ArenaPool::Lease ArenaPool::acquire(int concurrency) {
    concurrency = std::max(1, concurrency);
    std::lock_guard<std::mutex> lock(mMutex);
    ++mLeases;
    for (Entry& entry : mEntries)
        if (!entry.leased && entry.concurrency == concurrency) {
            entry.leased = true;
            return Lease(*this, *entry.arena);
        }
    Entry entry;
    entry.arena = std::make_unique<tbb::task_arena>(concurrency);
    entry.concurrency = concurrency;
    entry.leased = true;
    mEntries.push_back(std::move(entry));
    return Lease(*this, *mEntries.back().arena);
}

std::size_t ArenaPool::arenaCount() const {
    std::lock_guard<std::mutex> lock(mMutex);
    return mEntries.size();
}

std::size_t ArenaPool::leaseCount() const {
    std::lock_guard<std::mutex> lock(mMutex);
    return mLeases;
}

void ArenaPool::release(tbb::task_arena& arena) {
    std::lock_guard<std::mutex> lock(mMutex);
    for (Entry& entry : mEntries)
        if (entry.arena.get() == &arena) entry.leased = false;
}

ArenaPool& ArenaPool::process() {
    static ArenaPool* const pool = new ArenaPool;  // never destroyed (see the header)
    return *pool;
}

}  // namespace skelseg
