#include "kernels/ConnectedObjects.h"

#include <algorithm>

namespace skelseg {

std::uint32_t ConnectedObjects::componentAt(int x, int y, int z) const {
    const std::size_t row = runs.rowOf(y, z);
    const auto begin = runs.runs.begin() + std::ptrdiff_t(runs.rowStart[row]);
    const auto end = runs.runs.begin() + std::ptrdiff_t(runs.rowStart[row + 1]);
    // The first run that ends at or after x.
    const auto run =
        std::lower_bound(begin, end, x, [](const VoxelRun& r, int value) { return r.x1 < value; });
    if (run == end || run->x0 > x) return 0;
    return objectOfRun[std::size_t(run - runs.runs.begin())] + 1;
}

ConnectedObjects findConnectedObjects(const MaskVolume& mask,
                                      const ConnectedObjectsOptions& options,
                                      Interrupter& interrupter) {
    InterrupterScope scope(interrupter, "objects");
    ConnectedObjects result;
    result.runs = objectRuns(mask, options.threaded, interrupter);
    const std::vector<std::uint32_t> root =
        runComponents(result.runs, VoxelAdjacency::Full26, options.threaded, interrupter);
    throwIfInterrupted(interrupter, 0.6);

    // Number the objects by their first run (every root is the smallest run
    // id of its set) and collect their extents.
    const VoxelRuns& runs = result.runs;
    const Dims d = runs.dims;
    result.objectOfRun.resize(runs.runCount());
    for (std::size_t row = 0; row < runs.rowCount(); ++row) {
        const int y = int(row % std::size_t(d.y)), z = int(row / std::size_t(d.y));
        for (std::uint32_t i = runs.rowStart[row]; i < runs.rowStart[row + 1]; ++i) {
            if (root[i] == i) {
                ObjectExtent o;
                o.id = std::uint32_t(result.objects.size());
                o.lo = {d.x, d.y, d.z};
                o.hi = {-1, -1, -1};
                result.objects.push_back(o);
            }
            const std::uint32_t object = root[i] == i ? std::uint32_t(result.objects.size() - 1)
                                                      : result.objectOfRun[root[i]];
            result.objectOfRun[i] = object;
            const VoxelRun& run = runs.runs[i];
            ObjectExtent& o = result.objects[object];
            o.voxels += std::uint64_t(run.x1 - run.x0 + 1);
            o.lo = {std::min(o.lo[0], run.x0), std::min(o.lo[1], y), std::min(o.lo[2], z)};
            o.hi = {std::max(o.hi[0], run.x1), std::max(o.hi[1], y), std::max(o.hi[2], z)};
        }
    }
    return result;
}

}  // namespace skelseg
