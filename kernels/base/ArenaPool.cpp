#include "kernels/base/ArenaPool.h"

#include <algorithm>

namespace skelseg {

ArenaPool::Lease::Lease(Lease&& other) noexcept : pool_(other.pool_), arena_(other.arena_) {
    other.pool_ = nullptr;
}

ArenaPool::Lease::~Lease() {
    if (pool_) pool_->release(*arena_);
}

ArenaPool::Lease ArenaPool::acquire(int concurrency) {
    concurrency = std::max(1, concurrency);
    std::lock_guard<std::mutex> lock(mutex_);
    ++leases_;
    for (Entry& entry : entries_)
        if (!entry.leased && entry.concurrency == concurrency) {
            entry.leased = true;
            return Lease(*this, *entry.arena);
        }
    Entry entry;
    entry.arena = std::make_unique<tbb::task_arena>(concurrency);
    entry.concurrency = concurrency;
    entry.leased = true;
    entries_.push_back(std::move(entry));
    return Lease(*this, *entries_.back().arena);
}

std::size_t ArenaPool::arenaCount() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return entries_.size();
}

std::size_t ArenaPool::leaseCount() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return leases_;
}

void ArenaPool::release(tbb::task_arena& arena) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (Entry& entry : entries_)
        if (entry.arena.get() == &arena) entry.leased = false;
}

ArenaPool& ArenaPool::process() {
    static ArenaPool* const pool = new ArenaPool;  // never destroyed (see the header)
    return *pool;
}

}  // namespace skelseg
