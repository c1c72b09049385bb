#include "kernels/ConnectedObjects.h"

#include <algorithm>
#include <atomic>
#include <numeric>

#include "kernels/base/ParallelFor.h"

namespace skelseg {

namespace {

constexpr int kSlabDepth = 8;  // z-planes per parallel task

struct Run {
    int x0, x1;  // inclusive
};

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

ConnectedObjects findConnectedObjects(const MaskVolume& mask,
                                      const ConnectedObjectsOptions& options,
                                      Interrupter& interrupter) {
    InterrupterScope scope(interrupter, "objects");
    const Dims d = mask.dims();
    ConnectedObjects result;
    if (mask.size() == 0) return result;
    const std::size_t rows = std::size_t(d.y) * std::size_t(d.z);
    const int slabs = (d.z + kSlabDepth - 1) / kSlabDepth;
    std::atomic<bool> stop{false};
    auto forSlabs = [&](const auto& body) {
        auto range = [&](int begin, int end) {
            for (int slab = begin; slab < end; ++slab) {
                if (stop.load(std::memory_order_relaxed)) return;
                if (interrupter.wasInterrupted()) {
                    stop = true;
                    return;
                }
                body(slab * kSlabDepth, std::min(d.z, (slab + 1) * kSlabDepth));
            }
        };
        parallelFor(slabs, range, options.threaded);
        if (stop) throwIfInterrupted(interrupter);
    };
    auto rowOf = [&](int y, int z) { return std::size_t(z) * std::size_t(d.y) + std::size_t(y); };
    auto forRuns = [&](int y, int z, const auto& visit) {
        const std::uint8_t* row = mask.data() + mask.index(0, y, z);
        for (int x = 0; x < d.x;) {
            if (!row[x]) {
                ++x;
                continue;
            }
            const int x0 = x;
            while (x < d.x && row[x]) ++x;
            visit(Run{x0, x - 1});
        }
    };

    // Runs of every row, rows in voxel order.
    std::vector<std::uint32_t> rowStart(rows + 1, 0);
    forSlabs([&](int z0, int z1) {
        for (int z = z0; z < z1; ++z)
            for (int y = 0; y < d.y; ++y) {
                std::uint32_t count = 0;
                forRuns(y, z, [&](const Run&) { ++count; });
                rowStart[rowOf(y, z) + 1] = count;
            }
    });
    std::partial_sum(rowStart.begin(), rowStart.end(), rowStart.begin());
    const std::uint32_t runCount = rowStart.back();
    std::vector<Run> runs(runCount);
    std::vector<std::uint32_t> parent(runCount);
    std::iota(parent.begin(), parent.end(), 0u);

    // Joins the runs of two 26-adjacent rows: x-intervals that overlap once
    // widened by one voxel.
    auto joinRows = [&](std::size_t rowA, std::size_t rowB) {
        std::uint32_t i = rowStart[rowA], j = rowStart[rowB];
        const std::uint32_t iEnd = rowStart[rowA + 1], jEnd = rowStart[rowB + 1];
        while (i < iEnd && j < jEnd) {
            if (runs[i].x1 + 1 < runs[j].x0) {
                ++i;
            } else if (runs[j].x1 + 1 < runs[i].x0) {
                ++j;
            } else {
                unite(parent, i, j);
                if (runs[i].x1 < runs[j].x1)
                    ++i;
                else
                    ++j;
            }
        }
    };
    // The rows before (y, z) in voxel order that touch it, optionally only
    // those in the same z-plane or only those in the plane below.
    auto joinEarlierRows = [&](int y, int z, bool samePlane, bool planeBelow) {
        const std::size_t row = rowOf(y, z);
        if (samePlane && y > 0) joinRows(row, rowOf(y - 1, z));
        if (planeBelow && z > 0)
            for (int dy = -1; dy <= 1; ++dy)
                if (y + dy >= 0 && y + dy < d.y) joinRows(row, rowOf(y + dy, z - 1));
    };
    forSlabs([&](int z0, int z1) {
        for (int z = z0; z < z1; ++z)
            for (int y = 0; y < d.y; ++y) {
                std::uint32_t k = rowStart[rowOf(y, z)];
                forRuns(y, z, [&](const Run& run) { runs[k++] = run; });
            }
        // Unions inside the slab touch only the slab's runs: no data race.
        for (int z = z0; z < z1; ++z)
            for (int y = 0; y < d.y; ++y) joinEarlierRows(y, z, true, z > z0);
    });
    // The seams between slabs.
    for (int z = kSlabDepth; z < d.z; z += kSlabDepth)
        for (int y = 0; y < d.y; ++y) joinEarlierRows(y, z, false, true);
    throwIfInterrupted(interrupter, 0.6);

    // Number the objects by their first run (every root is the smallest run
    // id of its set) and collect their extents.
    std::vector<std::uint32_t> objectOfRun(runCount);
    for (std::size_t row = 0; row < rows; ++row) {
        const int y = int(row % std::size_t(d.y)), z = int(row / std::size_t(d.y));
        for (std::uint32_t i = rowStart[row]; i < rowStart[row + 1]; ++i) {
            const std::uint32_t root = findRoot(parent, i);
            if (root == i) {
                ObjectExtent o;
                o.id = std::uint32_t(result.objects.size());
                o.lo = {d.x, d.y, d.z};
                o.hi = {-1, -1, -1};
                result.objects.push_back(o);
            }
            objectOfRun[i] =
                root == i ? std::uint32_t(result.objects.size() - 1) : objectOfRun[root];
            ObjectExtent& o = result.objects[objectOfRun[i]];
            o.voxels += std::uint64_t(runs[i].x1 - runs[i].x0 + 1);
            o.lo = {std::min(o.lo[0], runs[i].x0), std::min(o.lo[1], y), std::min(o.lo[2], z)};
            o.hi = {std::max(o.hi[0], runs[i].x1), std::max(o.hi[1], y), std::max(o.hi[2], z)};
        }
    }

    result.component.assign(mask.size(), 0);
    forSlabs([&](int z0, int z1) {
        for (int z = z0; z < z1; ++z)
            for (int y = 0; y < d.y; ++y) {
                std::uint32_t* out = result.component.data() + mask.index(0, y, z);
                const std::size_t row = rowOf(y, z);
                for (std::uint32_t i = rowStart[row]; i < rowStart[row + 1]; ++i)
                    std::fill(out + runs[i].x0, out + runs[i].x1 + 1, objectOfRun[i] + 1);
            }
    });
    return result;
}

}  // namespace skelseg
