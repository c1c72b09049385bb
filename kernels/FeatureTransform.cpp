#include "kernels/FeatureTransform.h"

#include <tbb/enumerable_thread_specific.h>

#include <atomic>
#include <limits>
#include <vector>

#include "kernels/base/ParallelFor.h"

namespace skelseg {

namespace {

constexpr std::int64_t kInfiniteCost = std::numeric_limits<std::int64_t>::max() / 4;

/// Lower envelope of the parabolas cost[i] + (j - i)^2 over one line of n
/// samples; writes for every j the i that minimises it (or -1 if every cost is
/// infinite). Scratch vectors are passed in to avoid allocation per line.
/// apexHeight: scratch, the parabola's value at its own apex for each apex
/// (kept so that a parabola popped and compared again is not recomputed).
void nearestAlongLine(const std::int64_t* cost, int n, int* nearest, std::vector<int>& apex,
                      std::vector<double>& apexHeight, std::vector<double>& boundary) {
    apex.resize(std::size_t(n));
    apexHeight.resize(std::size_t(n));
    boundary.resize(std::size_t(n) + 1);
    int k = -1;
    for (int q = 0; q < n; ++q) {
        if (cost[q] >= kInfiniteCost) continue;
        const double fq = double(cost[q]) + double(q) * double(q);
        while (k >= 0) {
            const int v = apex[std::size_t(k)];
            const double fv = apexHeight[std::size_t(k)];
            const double s = (fq - fv) / (2.0 * double(q - v));
            if (s <= boundary[std::size_t(k)]) {
                --k;
            } else {
                ++k;
                apex[std::size_t(k)] = q;
                apexHeight[std::size_t(k)] = fq;
                boundary[std::size_t(k)] = s;
                boundary[std::size_t(k) + 1] = std::numeric_limits<double>::infinity();
                goto placed;
            }
        }
        k = 0;
        apex[0] = q;
        apexHeight[0] = fq;
        boundary[0] = -std::numeric_limits<double>::infinity();
        boundary[1] = std::numeric_limits<double>::infinity();
    placed:;
    }
    if (k < 0) {
        for (int j = 0; j < n; ++j) nearest[j] = -1;
        return;
    }
    int segment = 0;
    for (int j = 0; j < n; ++j) {
        while (boundary[std::size_t(segment) + 1] < double(j)) ++segment;
        nearest[j] = apex[std::size_t(segment)];
    }
}

/// floor(n / d) for 32-bit n by a multiply and a shift, exact for every n:
/// m = floor((2^64 - 1) / d) + 1 is at least 2^64 / d and exceeds it by less
/// than 1, so n * m / 2^64 exceeds n / d by less than n / 2^64 < 1 / d and
/// cannot reach the next integer. The last pass needs one division by the
/// row length per voxel, and a hardware division is several times slower.
class RowDivider {
public:
    explicit RowDivider(std::uint32_t divisor) noexcept
        : mDivisor(divisor), mMultiplier(divisor > 1 ? ~std::uint64_t(0) / divisor + 1 : 0) {}

    std::uint32_t operator()(std::uint32_t n) const noexcept {
        if (mDivisor <= 1) return n;
        __extension__ typedef unsigned __int128 Wide;
        return std::uint32_t((Wide(n) * Wide(mMultiplier)) >> 64);
    }

private:
    std::uint32_t mDivisor;
    std::uint64_t mMultiplier;
};

struct LineScratch {
    std::vector<std::int64_t> cost;
    std::vector<int> nearest, apex;
    std::vector<double> apexHeight, boundary;
    std::vector<std::uint32_t> features;
    std::vector<std::uint32_t> result;  // the slab's new features, same layout
};

}  // namespace

Volume<std::uint32_t> featureTransform(const MaskVolume& sites,
                                       const FeatureTransformOptions& options,
                                       Interrupter& interrupter) {
    InterrupterScope scope(interrupter, "feature transform");
    const Dims dims = sites.dims();
    const int nx = dims.x, ny = dims.y, nz = dims.z;
    const std::size_t sliceSize = std::size_t(nx) * std::size_t(ny);
    Volume<std::uint32_t> ft(dims, kNoFeature);
    ft.geometry = sites.geometry;
    std::uint32_t* feature = ft.data();
    std::atomic<bool> stop{false};

    // Pass 1, along x: nearest site in the same row (two sweeps).
    parallelFor(
        nz,
        [&](int z0, int z1) {
            for (int z = z0; z < z1; ++z) {
                if (stop.load(std::memory_order_relaxed)) return;
                if (interrupter.wasInterrupted(double(z) / (3.0 * nz))) {
                    stop = true;
                    return;
                }
                for (int y = 0; y < ny; ++y) {
                    const std::size_t row =
                        std::size_t(z) * sliceSize + std::size_t(y) * std::size_t(nx);
                    const std::uint8_t* s = sites.data() + row;
                    std::uint32_t* f = feature + row;
                    int last = -1;
                    for (int x = 0; x < nx; ++x) {
                        if (s[x]) last = x;
                        if (last >= 0) f[x] = std::uint32_t(row + std::size_t(last));
                    }
                    last = -1;
                    for (int x = nx - 1; x >= 0; --x) {
                        if (s[x]) last = x;
                        if (last < 0) continue;
                        // Strictly nearer on the right only: ties keep the left site.
                        if (f[x] == kNoFeature || (last - x) < (x - int(f[x] - row)))
                            f[x] = std::uint32_t(row + std::size_t(last));
                    }
                }
            }
        },
        options.threaded);
    if (stop) throwInterrupted(interrupter);

    // Passes 2 and 3 along y and z: per line, cost(i) = squared distance from
    // the line's sample i to its current feature in the other dimensions.
    // Lines of one slab are gathered into a tile whose rows are contiguous in
    // memory so the strided axis is read once.
    const RowDivider rowOf{std::uint32_t(nx)};
    auto pass = [&](int axis) {
        const int lineLength = axis == 1 ? ny : nz;
        const int outer = axis == 1 ? nz : ny;  // one slab per outer index
        tbb::enumerable_thread_specific<LineScratch> scratchPerThread;
        parallelFor(
            outer,
            [&](int o0, int o1) {
                LineScratch& scratch = scratchPerThread.local();
                scratch.cost.resize(std::size_t(lineLength));
                scratch.nearest.resize(std::size_t(lineLength));
                scratch.features.resize(std::size_t(lineLength) * std::size_t(nx));
                scratch.result.resize(std::size_t(lineLength) * std::size_t(nx));
                for (int o = o0; o < o1; ++o) {
                    if (stop.load(std::memory_order_relaxed)) return;
                    if (interrupter.wasInterrupted((double(axis) + double(o) / outer) / 3.0)) {
                        stop = true;
                        return;
                    }
                    // Gather the slab: features[i * nx + x] for line position i.
                    auto voxelIndex = [&](int i, int x) -> std::size_t {
                        return axis == 1 ? std::size_t(o) * sliceSize +
                                               std::size_t(i) * std::size_t(nx) + std::size_t(x)
                                         : std::size_t(i) * sliceSize +
                                               std::size_t(o) * std::size_t(nx) + std::size_t(x);
                    };
                    for (int i = 0; i < lineLength; ++i) {
                        const std::uint32_t* src = feature + voxelIndex(i, 0);
                        std::copy(src, src + nx, scratch.features.begin() + std::ptrdiff_t(i) * nx);
                    }
                    for (int x = 0; x < nx; ++x) {
                        for (int i = 0; i < lineLength; ++i) {
                            const std::uint32_t f =
                                scratch.features[std::size_t(i) * std::size_t(nx) + std::size_t(x)];
                            if (f == kNoFeature) {
                                scratch.cost[std::size_t(i)] = kInfiniteCost;
                                continue;
                            }
                            // The earlier passes move features only within a
                            // row (pass 1), then within a slice (pass 2), so
                            // f's row or slice is the sample's own: its
                            // coordinates need one division, not three.
                            std::int64_t c;
                            if (axis == 1) {
                                const std::int64_t dx =
                                    std::int64_t(f - std::uint32_t(voxelIndex(i, 0))) - x;
                                c = dx * dx;
                            } else {
                                const std::uint32_t inSlice =
                                    f - std::uint32_t(std::size_t(i) * sliceSize);
                                const std::uint32_t fy = rowOf(inSlice);
                                const std::int64_t dx =
                                    std::int64_t(inSlice - fy * std::uint32_t(nx)) - x;
                                const std::int64_t dy = std::int64_t(fy) - o;
                                c = dx * dx + dy * dy;
                            }
                            scratch.cost[std::size_t(i)] = c;
                        }
                        nearestAlongLine(scratch.cost.data(), lineLength, scratch.nearest.data(),
                                         scratch.apex, scratch.apexHeight, scratch.boundary);
                        for (int j = 0; j < lineLength; ++j) {
                            const int i = scratch.nearest[std::size_t(j)];
                            scratch.result[std::size_t(j) * std::size_t(nx) + std::size_t(x)] =
                                i < 0 ? kNoFeature
                                      : scratch.features[std::size_t(i) * std::size_t(nx) +
                                                         std::size_t(x)];
                        }
                    }
                    // Scatter the slab back row by row, as it was gathered:
                    // writing each line's results straight into the volume
                    // would touch a new page per sample along z.
                    for (int i = 0; i < lineLength; ++i) {
                        const std::uint32_t* src =
                            scratch.result.data() + std::ptrdiff_t(i) * std::ptrdiff_t(nx);
                        std::copy(src, src + nx, feature + voxelIndex(i, 0));
                    }
                }
            },
            options.threaded);
        if (stop) throwInterrupted(interrupter);
    };
    pass(1);
    pass(2);
    return ft;
}

}  // namespace skelseg
