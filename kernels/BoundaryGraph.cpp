#include "kernels/BoundaryGraph.h"

#include <algorithm>
#include <numeric>

#include "kernels/base/ParallelFor.h"

namespace skelseg {

namespace {

bool isObject(const MaskVolume& mask, int x, int y, int z) {
    return mask.contains(x, y, z) && mask(x, y, z) != 0;
}

bool isBoundary(const MaskVolume& mask, int x, int y, int z) {
    if (!mask(x, y, z)) return false;
    return !isObject(mask, x - 1, y, z) || !isObject(mask, x + 1, y, z) ||
           !isObject(mask, x, y - 1, z) || !isObject(mask, x, y + 1, z) ||
           !isObject(mask, x, y, z - 1) || !isObject(mask, x, y, z + 1);
}

}  // namespace

namespace {

/// Whether each voxel of row (y, z) is a boundary voxel: flag(x, bool).
/// Away from the volume's faces all six neighbours exist, so those voxels
/// read them by fixed offsets without bounds tests; the faces (the first and
/// last voxel of each row, and the outer rows) take the checked test.
template <class Flag>
void forEachBoundaryFlagOfRow(const MaskVolume& mask, int y, int z, Flag&& flag) {
    const Dims d = mask.dims();
    const bool innerRow = y > 0 && y < d.y - 1 && z > 0 && z < d.z - 1 && d.x > 2;
    if (!innerRow) {
        for (int x = 0; x < d.x; ++x) flag(x, isBoundary(mask, x, y, z));
        return;
    }
    const std::ptrdiff_t strideY = d.x, strideZ = std::ptrdiff_t(d.x) * d.y;
    const std::uint8_t* in = mask.data() + mask.index(0, y, z);
    flag(0, isBoundary(mask, 0, y, z));
    for (int x = 1; x < d.x - 1; ++x) {
        const std::uint8_t* v = in + x;
        flag(x, v[0] && (!v[-1] || !v[1] || !v[-strideY] || !v[strideY] || !v[-strideZ] ||
                         !v[strideZ]));
    }
    flag(d.x - 1, isBoundary(mask, d.x - 1, y, z));
}

}  // namespace

MaskVolume boundaryVoxels(const MaskVolume& mask, const BoundaryGraphOptions& options) {
    const Dims d = mask.dims();
    MaskVolume boundary(d, 0);
    boundary.geometry = mask.geometry;
    parallelForEach(
        d.z,
        [&](int z) {
            for (int y = 0; y < d.y; ++y) {
                std::uint8_t* out = boundary.data() + boundary.index(0, y, z);
                forEachBoundaryFlagOfRow(mask, y, z,
                                         [&](int x, bool isBoundary) { out[x] = isBoundary; });
            }
        },
        options.threaded);
    return boundary;
}

std::uint64_t countBoundaryVoxels(const MaskVolume& mask, const BoundaryGraphOptions& options) {
    const Dims d = mask.dims();
    // Per slice, summed in order afterwards: integers, so any order would
    // do, but the per-slice counts need no atomics.
    std::vector<std::uint64_t> perSlice(std::size_t(std::max(d.z, 0)), 0);
    parallelForEach(
        d.z,
        [&](int z) {
            std::uint64_t count = 0;
            for (int y = 0; y < d.y; ++y)
                forEachBoundaryFlagOfRow(mask, y, z,
                                         [&](int, bool isBoundary) { count += isBoundary; });
            perSlice[std::size_t(z)] = count;
        },
        options.threaded);
    return std::accumulate(perSlice.begin(), perSlice.end(), std::uint64_t(0));
}

BoundaryGraph buildBoundaryGraph(const MaskVolume& mask, const BoundaryGraphOptions& options,
                                 Interrupter& interrupter) {
    InterrupterScope scope(interrupter, "boundary graph");
    const Dims d = mask.dims();
    BoundaryGraph graph;
    graph.dims = d;

    // Node ids follow bricks of kBrick^3 voxels (bricks in z, y, x order,
    // voxels inside a brick in z, y, x order), not plain scanline order: a
    // search then finds most of a node's 26 neighbours among nearby ids, so
    // the per-node search state and landmark rows it touches share cache
    // lines and pages. Scanline order put every z-neighbour a whole slice of
    // boundary voxels away (docs/performance.md has the measured gain).
    // Count per slab of bricks, then number each slab in parallel.
    constexpr int kBrick = 8;
    const int slabs = (d.z + kBrick - 1) / kBrick;
    std::vector<std::uint32_t> perSlab(std::size_t(slabs) + 1, 0);
    const MaskVolume boundary = boundaryVoxels(mask, options);
    throwIfInterrupted(interrupter, 0.2);
    const std::size_t sliceSize = std::size_t(d.x) * std::size_t(d.y);
    parallelForEach(
        slabs,
        [&](int slab) {
            std::uint32_t count = 0;
            const int z1 = std::min(d.z, (slab + 1) * kBrick);
            for (int z = slab * kBrick; z < z1; ++z) {
                const std::uint8_t* b = boundary.data() + std::size_t(z) * sliceSize;
                for (std::size_t i = 0; i < sliceSize; ++i) count += b[i];
            }
            perSlab[std::size_t(slab) + 1] = count;
        },
        options.threaded);
    std::partial_sum(perSlab.begin(), perSlab.end(), perSlab.begin());
    const std::uint32_t nodes = perSlab.back();
    graph.voxel.resize(nodes);
    graph.coord.resize(nodes);
    resizeUnwrittenWithHugePages(graph.nodeOfVoxel, mask.size());
    parallelForEach(
        slabs,
        [&](int slab) {
            std::uint32_t id = perSlab[std::size_t(slab)];
            const int z0 = slab * kBrick, z1 = std::min(d.z, z0 + kBrick);
            // The slab's slices are one contiguous range of the map: mark it
            // here, so the first touch of its pages runs on every thread.
            std::fill(graph.nodeOfVoxel.begin() + std::ptrdiff_t(std::size_t(z0) * sliceSize),
                      graph.nodeOfVoxel.begin() + std::ptrdiff_t(std::size_t(z1) * sliceSize),
                      kNoNode);
            for (int y0 = 0; y0 < d.y; y0 += kBrick)
                for (int x0 = 0; x0 < d.x; x0 += kBrick) {
                    const int y1 = std::min(d.y, y0 + kBrick), x1 = std::min(d.x, x0 + kBrick);
                    for (int z = z0; z < z1; ++z)
                        for (int y = y0; y < y1; ++y)
                            for (int x = x0; x < x1; ++x) {
                                const std::size_t v = mask.index(x, y, z);
                                if (!boundary[v]) continue;
                                graph.voxel[id] = std::uint32_t(v);
                                graph.coord[id] = Coord{x, y, z};
                                graph.nodeOfVoxel[v] = id++;
                            }
                }
        },
        options.threaded);
    throwIfInterrupted(interrupter, 0.4);

    // 26-neighbourhood in a fixed order: the CSR order is part of the
    // deterministic tie-breaking of every search.
    struct Step {
        int dx, dy, dz;
        float length;
    };
    std::vector<Step> steps;
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int k = (dx != 0) + (dy != 0) + (dz != 0);
                if (k) steps.push_back({dx, dy, dz, std::sqrt(float(k))});
            }

    std::vector<std::uint32_t> degree(std::size_t(nodes) + 1, 0);
    auto neighbourNode = [&](std::uint32_t n, const Step& s) -> std::uint32_t {
        const Coord c = graph.coord[n];
        const int x = c.x + s.dx, y = c.y + s.dy, z = c.z + s.dz;
        if (!mask.contains(x, y, z)) return kNoNode;
        return graph.nodeOfVoxel[mask.index(x, y, z)];
    };
    parallelForEach(
        nodes,
        [&](std::uint32_t n) {
            std::uint32_t k = 0;
            for (const Step& s : steps) k += neighbourNode(n, s) != kNoNode;
            degree[std::size_t(n) + 1] = k;
        },
        options.threaded, 1024);
    std::partial_sum(degree.begin(), degree.end(), degree.begin());
    graph.offset = std::move(degree);
    graph.neighbour.resize(graph.offset.back());
    graph.weight.resize(graph.offset.back());
    parallelForEach(
        nodes,
        [&](std::uint32_t n) {
            std::uint32_t e = graph.offset[n];
            for (const Step& s : steps) {
                const std::uint32_t m = neighbourNode(n, s);
                if (m == kNoNode) continue;
                graph.neighbour[e] = m;
                graph.weight[e] = s.length;
                ++e;
            }
        },
        options.threaded, 1024);
    throwIfInterrupted(interrupter, 0.8);

    // Connected components (serial BFS: linear and small next to the rest).
    graph.component.assign(nodes, kNoNode);
    std::vector<std::uint32_t> queue;
    queue.reserve(nodes);
    for (std::uint32_t seed = 0; seed < nodes; ++seed) {
        if (graph.component[seed] != kNoNode) continue;
        const std::uint32_t label = std::uint32_t(graph.componentSize.size());
        queue.clear();
        queue.push_back(seed);
        graph.component[seed] = label;
        for (std::size_t head = 0; head < queue.size(); ++head) {
            const std::uint32_t n = queue[head];
            for (std::uint32_t e = graph.offset[n]; e < graph.offset[n + 1]; ++e) {
                const std::uint32_t m = graph.neighbour[e];
                if (graph.component[m] == kNoNode) {
                    graph.component[m] = label;
                    queue.push_back(m);
                }
            }
        }
        graph.componentSize.push_back(std::uint32_t(queue.size()));
    }
    return graph;
}

}  // namespace skelseg
