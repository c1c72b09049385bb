#include "kernels/TunnelPlugs.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <queue>
#include <utility>

#include "kernels/NeighbourhoodTopology.h"

namespace skelseg {

namespace {

/// What a voxel of the working grid is (object and background alike are
/// kUntouched), and a flag for "on the queue".
enum : std::uint8_t { kUntouched = 0, kAdded = 2, kTakenAway = 3, kQueued = 4 };

/// The 26 offsets of a 3x3x3 neighbourhood, as index steps and squared
/// lengths.
struct Neighbours {
    std::array<std::ptrdiff_t, 26> step{};
    std::array<int, 26> squaredLength{};
    explicit Neighbours(const Dims& d) {
        int k = 0;
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    if (!dx && !dy && !dz) continue;
                    step[std::size_t(k)] =
                        (std::ptrdiff_t(dz) * d.y + dy) * std::ptrdiff_t(d.x) + dx;
                    squaredLength[std::size_t(k)] = dx * dx + dy * dy + dz * dz;
                    ++k;
                }
    }
};

/// Takes added voxels away, farthest from the object first (ties by
/// index), while they are simple; pushes the added neighbours of each voxel
/// taken away back on the queue, since its removal can make them simple.
class SimpleRemoval {
public:
    SimpleRemoval(MaskVolume& mask, std::vector<std::uint8_t>& kind, const Neighbours& around,
                  const std::vector<std::uint8_t>& distance)
        : mMask(mask), mKind(kind), mAround(around), mDistance(distance) {}

    /// Queues an added voxel once: its priority never changes, and a copy
    /// queued before it is popped would be judged on the same mask.
    void push(std::size_t i) {
        if (mKind[i] & kQueued) return;
        mKind[i] |= kQueued;
        mQueue.push({mDistance[i], ~std::uint64_t(i)});
    }

    /// Runs until no queued voxel is simple. Polls `interrupter` every so
    /// many voxels; returns false when it asks to stop.
    bool run(Interrupter& interrupter) {
        std::size_t polls = 0;
        while (!mQueue.empty()) {
            const std::size_t i = std::size_t(~mQueue.top().second);
            mQueue.pop();
            mKind[i] &= std::uint8_t(~kQueued);
            if ((++polls & 0xFFFF) == 0 && interrupter.wasInterrupted()) return false;
            if (mKind[i] != kAdded) continue;
            const std::uint32_t bits = bitsAt(i);
            if (objectPieces26(bits) != 1 || backgroundPieces6(bits) != 1) continue;
            takeAway(i);
        }
        return true;
    }

    std::uint32_t bitsAt(std::size_t i) const {
        const Dims d = mMask.dims();
        const auto x = int(i % std::size_t(d.x)), y = int(i / std::size_t(d.x) % std::size_t(d.y)),
                   z = int(i / (std::size_t(d.x) * std::size_t(d.y)));
        return neighbourhoodBits(mMask, x, y, z);
    }

    void takeAway(std::size_t i) {
        mMask[i] = 0;
        mKind[i] = kTakenAway;
        for (std::ptrdiff_t step : mAround.step) {
            const auto j = std::size_t(std::ptrdiff_t(i) + step);
            if ((mKind[j] & ~kQueued) == kAdded) push(j);
        }
    }

private:
    MaskVolume& mMask;
    std::vector<std::uint8_t>& mKind;
    const Neighbours& mAround;
    const std::vector<std::uint8_t>& mDistance;
    // Largest distance first, then smallest index (stored complemented).
    std::priority_queue<std::pair<std::uint8_t, std::uint64_t>> mQueue;
};

}  // namespace

std::vector<std::size_t> plugTunnelsTwoVoxelsWide(MaskVolume& mask, Interrupter& interrupter) {
    const Dims d = mask.dims();
    std::vector<std::size_t> plugs;
    if (d.x < 3 || d.y < 3 || d.z < 3) return plugs;
    const Neighbours around(d);
    std::vector<std::uint8_t> kind(mask.size(), kUntouched);
    // Squared distance to the nearest object voxel among the 26 neighbours
    // (1, 2 or 3), for the order of removal.
    std::vector<std::uint8_t> distance(mask.size(), 0);
    std::vector<std::size_t> added;
    for (int z = 1; z + 1 < d.z; ++z) {
        if (interrupter.wasInterrupted(0.5 * z / d.z)) throwInterrupted(interrupter);
        for (int y = 1; y + 1 < d.y; ++y)
            for (int x = 1; x + 1 < d.x; ++x) {
                const std::size_t i = mask.index(x, y, z);
                if (mask[i]) continue;
                int nearest = 4;
                for (std::size_t k = 0; k < 26; ++k)
                    if (mask[std::size_t(std::ptrdiff_t(i) + around.step[k])])
                        nearest = std::min(nearest, around.squaredLength[k]);
                if (nearest == 4) continue;
                distance[i] = std::uint8_t(nearest);
                added.push_back(i);
            }
    }
    for (std::size_t i : added) {
        kind[i] = kAdded;
        mask[i] = 1;
    }
    const auto restore = [&] {
        for (std::size_t i : added) mask[i] = 0;
        throwInterrupted(interrupter);
    };
    SimpleRemoval removal(mask, kind, around, distance);
    for (std::size_t i : added) removal.push(i);
    if (!removal.run(interrupter)) restore();
    // Bridges between places of the object that are apart, and voxels
    // joined to nothing, are no plugs: take them away and thin again, until
    // every voxel left has one object piece around it.
    for (bool changed = true; changed;) {
        changed = false;
        for (std::size_t i : added) {
            if (kind[i] != kAdded || objectPieces26(removal.bitsAt(i)) == 1) continue;
            removal.takeAway(i);
            changed = true;
        }
        if (interrupter.wasInterrupted() || !removal.run(interrupter)) restore();
    }
    for (std::size_t i : added)
        if (kind[i] == kAdded) plugs.push_back(i);
    return plugs;
}

}  // namespace skelseg
