#include "kernels/Cavities.h"

#include <algorithm>

namespace skelseg {

CavityRuns findCavities(const VoxelRuns& objects, bool threaded, Interrupter& interrupter) {
    CavityRuns cavities;
    cavities.background = backgroundRuns(objects, threaded);
    const VoxelRuns& background = cavities.background;
    const std::vector<std::uint32_t> root =
        runComponents(background, VoxelAdjacency::Face6, threaded, interrupter);
    const Dims d = background.dims;
    std::vector<std::uint8_t> reachesSide(root.size(), 0);
    for (std::size_t row = 0; row < background.rowCount(); ++row) {
        const int y = int(row % std::size_t(d.y)), z = int(row / std::size_t(d.y));
        const bool sideRow = y == 0 || z == 0 || y + 1 == d.y || z + 1 == d.z;
        for (std::uint32_t i = background.rowStart[row]; i < background.rowStart[row + 1]; ++i) {
            const VoxelRun& run = background.runs[i];
            if (sideRow || run.x0 == 0 || run.x1 + 1 == d.x) reachesSide[root[i]] = 1;
        }
    }
    cavities.inCavity.assign(root.size(), 0);
    for (std::size_t i = 0; i < root.size(); ++i) {
        cavities.inCavity[i] = !reachesSide[root[i]];
        cavities.count += root[i] == i && !reachesSide[i];
    }
    return cavities;
}

FilledCavities fillCavities(MaskVolume& mask, const CavityFillOptions& options,
                            Interrupter& interrupter) {
    FilledCavities filled;
    const CavityRuns cavities = findCavities(objectRuns(mask, options.threaded, interrupter),
                                             options.threaded, interrupter);
    throwIfInterrupted(interrupter);
    const VoxelRuns& background = cavities.background;
    filled.count = cavities.count;
    filled.runs.dims = background.dims;
    filled.runs.rowStart.assign(background.rowCount() + 1, 0);
    if (filled.count == 0) return filled;
    for (std::size_t row = 0; row < background.rowCount(); ++row) {
        filled.runs.rowStart[row] = filled.runs.runCount();
        const int y = int(row % std::size_t(background.dims.y)),
                  z = int(row / std::size_t(background.dims.y));
        for (std::uint32_t i = background.rowStart[row]; i < background.rowStart[row + 1]; ++i) {
            if (!cavities.inCavity[i]) continue;
            const VoxelRun& run = background.runs[i];
            filled.runs.runs.push_back(run);
            filled.voxels += std::uint64_t(run.x1 - run.x0 + 1);
            std::uint8_t* out = mask.data() + mask.index(0, y, z);
            std::fill(out + run.x0, out + run.x1 + 1, std::uint8_t(1));
        }
    }
    filled.runs.rowStart[background.rowCount()] = filled.runs.runCount();
    return filled;
}

}  // namespace skelseg
