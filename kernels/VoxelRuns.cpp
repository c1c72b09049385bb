#include "kernels/VoxelRuns.h"

#include <algorithm>
#include <atomic>
#include <numeric>

#include "kernels/base/ParallelFor.h"

namespace skelseg {

namespace {

constexpr int kSlabDepth = 8;  // z-planes per parallel task

int slabCount(const Dims& d) {
    return (d.z + kSlabDepth - 1) / kSlabDepth;
}

/// Runs body(z0, z1) for every slab of kSlabDepth planes, polling the
/// interrupter between slabs; throws once all tasks have stopped.
template <typename SlabBody>
void forEachSlab(const Dims& d, bool threaded, Interrupter& interrupter, const SlabBody& body) {
    std::atomic<bool> stop{false};
    parallelFor(
        slabCount(d),
        [&](int begin, int end) {
            for (int slab = begin; slab < end; ++slab) {
                if (stop.load(std::memory_order_relaxed)) return;
                if (interrupter.wasInterrupted()) {
                    stop = true;
                    return;
                }
                body(slab * kSlabDepth, std::min(d.z, (slab + 1) * kSlabDepth));
            }
        },
        threaded);
    if (stop) throwInterrupted(interrupter);
}

std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

void unite(std::vector<std::uint32_t>& parent, std::uint32_t a, std::uint32_t b) {
    a = findRoot(parent, a);
    b = findRoot(parent, b);
    if (a == b) return;
    if (a < b)
        parent[b] = a;
    else
        parent[a] = b;
}

}  // namespace

VoxelRuns objectRuns(const MaskVolume& mask, bool threaded, Interrupter& interrupter) {
    VoxelRuns result;
    const Dims d = mask.dims();
    result.dims = d;
    result.rowStart.assign(result.rowCount() + 1, 0);
    if (mask.size() == 0) return result;
    // One read of the mask: each slab keeps its runs, counted per row; the
    // slabs are then copied into place.
    std::vector<std::vector<VoxelRun>> slabRuns(std::size_t(slabCount(d)));
    forEachSlab(d, threaded, interrupter, [&](int z0, int z1) {
        std::vector<VoxelRun>& out = slabRuns[std::size_t(z0 / kSlabDepth)];
        for (int z = z0; z < z1; ++z)
            for (int y = 0; y < d.y; ++y) {
                const std::uint8_t* row = mask.data() + mask.index(0, y, z);
                const std::size_t before = out.size();
                for (int x = 0; x < d.x;) {
                    if (!row[x]) {
                        ++x;
                        continue;
                    }
                    const int x0 = x;
                    while (x < d.x && row[x]) ++x;
                    out.push_back({x0, x - 1});
                }
                result.rowStart[result.rowOf(y, z) + 1] = std::uint32_t(out.size() - before);
            }
    });
    std::partial_sum(result.rowStart.begin(), result.rowStart.end(), result.rowStart.begin());
    result.runs.resize(result.rowStart.back());
    parallelForEach(
        slabCount(d),
        [&](int slab) {
            const std::vector<VoxelRun>& runs = slabRuns[std::size_t(slab)];
            std::copy(runs.begin(), runs.end(),
                      result.runs.begin() +
                          std::ptrdiff_t(result.rowStart[result.rowOf(0, slab * kSlabDepth)]));
        },
        threaded);
    return result;
}

VoxelRuns backgroundRuns(const VoxelRuns& objects, bool threaded) {
    VoxelRuns result;
    const Dims d = objects.dims;
    result.dims = d;
    const std::size_t rows = objects.rowCount();
    result.rowStart.assign(rows + 1, 0);
    // The gaps of a row: before its first run, between runs, after its last.
    auto forGaps = [&](std::size_t row, const auto& visit) {
        int next = 0;  // first x not yet covered
        for (std::uint32_t i = objects.rowStart[row]; i < objects.rowStart[row + 1]; ++i) {
            const VoxelRun& run = objects.runs[i];
            if (run.x0 > next) visit(VoxelRun{next, run.x0 - 1});
            next = run.x1 + 1;
        }
        if (next < d.x) visit(VoxelRun{next, d.x - 1});
    };
    parallelFor(
        rows,
        [&](std::size_t begin, std::size_t end) {
            for (std::size_t row = begin; row < end; ++row) {
                std::uint32_t count = 0;
                forGaps(row, [&](const VoxelRun&) { ++count; });
                result.rowStart[row + 1] = count;
            }
        },
        threaded, 256);
    std::partial_sum(result.rowStart.begin(), result.rowStart.end(), result.rowStart.begin());
    result.runs.resize(result.rowStart.back());
    parallelFor(
        rows,
        [&](std::size_t begin, std::size_t end) {
            for (std::size_t row = begin; row < end; ++row) {
                std::uint32_t k = result.rowStart[row];
                forGaps(row, [&](const VoxelRun& gap) { result.runs[k++] = gap; });
            }
        },
        threaded, 256);
    return result;
}

std::vector<std::uint32_t> runComponents(const VoxelRuns& runs, VoxelAdjacency adjacency,
                                         bool threaded, Interrupter& interrupter) {
    const Dims d = runs.dims;
    std::vector<std::uint32_t> parent(runs.runs.size());
    std::iota(parent.begin(), parent.end(), 0u);
    if (parent.empty()) return parent;
    // Runs of two rows touch when their x-intervals overlap; with corner and
    // edge contacts (26) also when they are one voxel apart.
    const int reach = adjacency == VoxelAdjacency::Full26 ? 1 : 0;
    auto joinRows = [&](std::size_t rowA, std::size_t rowB) {
        std::uint32_t i = runs.rowStart[rowA], j = runs.rowStart[rowB];
        const std::uint32_t iEnd = runs.rowStart[rowA + 1], jEnd = runs.rowStart[rowB + 1];
        while (i < iEnd && j < jEnd) {
            const VoxelRun& a = runs.runs[i];
            const VoxelRun& b = runs.runs[j];
            if (a.x1 + reach < b.x0) {
                ++i;
            } else if (b.x1 + reach < a.x0) {
                ++j;
            } else {
                unite(parent, i, j);
                if (a.x1 < b.x1)
                    ++i;
                else
                    ++j;
            }
        }
    };
    // The rows before (y, z) in voxel order that touch it: the one in its
    // own plane (samePlane) and those in the plane below (planeBelow).
    auto joinEarlierRows = [&](int y, int z, bool samePlane, bool planeBelow) {
        const std::size_t row = runs.rowOf(y, z);
        if (samePlane && y > 0) joinRows(row, runs.rowOf(y - 1, z));
        if (!planeBelow || z == 0) return;
        for (int dy = -reach; dy <= reach; ++dy)
            if (y + dy >= 0 && y + dy < d.y) joinRows(row, runs.rowOf(y + dy, z - 1));
    };
    // Unions inside a slab touch only the slab's runs: no data race.
    forEachSlab(d, threaded, interrupter, [&](int z0, int z1) {
        for (int z = z0; z < z1; ++z)
            for (int y = 0; y < d.y; ++y) joinEarlierRows(y, z, true, z > z0);
    });
    for (int z = kSlabDepth; z < d.z; z += kSlabDepth)
        for (int y = 0; y < d.y; ++y) joinEarlierRows(y, z, false, true);
    // Every link points to a smaller id, so one pass in id order leaves
    // each run pointing at its root.
    for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = parent[parent[i]];
    return parent;
}

}  // namespace skelseg
