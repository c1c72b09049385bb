#include "kernels/Islands.h"

#include <tbb/enumerable_thread_specific.h>

#include <map>

#include "kernels/base/ParallelFor.h"

namespace skelseg {

std::vector<std::uint64_t> objectBoundaryAreas(const MaskVolume& mask,
                                               const ConnectedObjects& objects,
                                               const IslandOptions& options) {
    const std::size_t objectCount = objects.objects.size();
    const Dims d = mask.dims();
    if (objectCount == 0 || mask.size() == 0) return std::vector<std::uint64_t>(objectCount, 0);
    // Counts per thread, summed at the end: integer sums, so the result does
    // not depend on how the planes were shared out.
    tbb::enumerable_thread_specific<std::vector<std::uint64_t>> partial(
        [&] { return std::vector<std::uint64_t>(objectCount, 0); });
    const std::size_t nx = std::size_t(d.x), plane = nx * std::size_t(d.y);
    const VoxelRuns& runs = objects.runs;
    auto planes = [&](int z0, int z1) {
        std::vector<std::uint64_t>& area = partial.local();
        const std::uint8_t* m = mask.data();
        for (int z = z0; z < z1; ++z)
            for (int y = 0; y < d.y; ++y) {
                const std::size_t row = runs.rowOf(y, z);
                // A row on the grid's side: every voxel has a face outside.
                const bool side = y == 0 || y + 1 == d.y || z == 0 || z + 1 == d.z;
                for (std::uint32_t k = runs.rowStart[row]; k < runs.rowStart[row + 1]; ++k) {
                    const VoxelRun& run = runs.runs[k];
                    std::uint64_t count = 0;
                    if (side) {
                        count = std::uint64_t(run.x1 - run.x0 + 1);
                    } else {
                        // A run's ends face the background along x (runs are
                        // maximal); inside it only the y and z faces decide.
                        count = run.x1 > run.x0 ? 2 : 1;
                        for (int x = run.x0 + 1; x < run.x1; ++x) {
                            const std::size_t i = mask.index(x, y, z);
                            count += !m[i - nx] || !m[i + nx] || !m[i - plane] || !m[i + plane];
                        }
                    }
                    area[objects.objectOfRun[k]] += count;
                }
            }
    };
    parallelFor(d.z, planes, options.threaded);
    std::vector<std::uint64_t> total(objectCount, 0);
    for (const std::vector<std::uint64_t>& area : partial)
        for (std::size_t o = 0; o < objectCount; ++o) total[o] += area[o];
    return total;
}

std::uint32_t largestObject(const std::vector<std::uint64_t>& boundaryAreas) {
    std::uint32_t best = 0;
    for (std::uint32_t o = 1; o < boundaryAreas.size(); ++o)
        if (boundaryAreas[o] > boundaryAreas[best]) best = o;
    return best;
}

Islands findIslands(const std::vector<ObjectExtent>& objects,
                    const std::vector<std::uint64_t>& boundaryAreas, double noiseArea) {
    Islands islands;
    islands.isIsland.assign(objects.size(), 0);
    if (objects.empty()) return islands;
    const std::uint32_t largest = largestObject(boundaryAreas);
    for (std::uint32_t o = 0; o < objects.size(); ++o) {
        if (o == largest || !(double(boundaryAreas[o]) < noiseArea)) continue;
        islands.isIsland[o] = 1;
        ++islands.count;
        islands.voxels += objects[o].voxels;
    }
    return islands;
}

Fragments findFragments(const ConnectedObjects& found,
                        const std::vector<std::uint64_t>& boundaryAreas,
                        const std::vector<ObjectSource>& sources,
                        const std::vector<std::uint8_t>& skip,
                        const std::function<double(double)>& partArea) {
    const std::size_t objectCount = found.objects.size();
    Fragments fragments;
    fragments.isFragment.assign(objectCount, 0);
    constexpr std::uint32_t kNoPiece = ~std::uint32_t(0);
    std::vector<std::uint32_t> pieceOf(objectCount, kNoPiece);
    for (const ObjectSource& source : sources) {
        const auto& v = source.voxel;
        if (v[0] < 0 || v[1] < 0 || v[2] < 0 || v[0] >= found.runs.dims.x ||
            v[1] >= found.runs.dims.y || v[2] >= found.runs.dims.z)
            continue;
        if (const std::uint32_t component = found.componentAt(v[0], v[1], v[2]))
            pieceOf[component - 1] = source.piece;
    }
    std::map<std::uint32_t, std::uint32_t> largestOfPiece;
    for (std::uint32_t o = 0; o < objectCount; ++o) {
        if (pieceOf[o] == kNoPiece || (o < skip.size() && skip[o])) continue;
        const auto [at, inserted] = largestOfPiece.emplace(pieceOf[o], o);
        if (!inserted && boundaryAreas[o] > boundaryAreas[at->second]) at->second = o;
    }
    for (std::uint32_t o = 0; o < objectCount; ++o) {
        if (pieceOf[o] == kNoPiece || (o < skip.size() && skip[o])) continue;
        const std::uint32_t largest = largestOfPiece.at(pieceOf[o]);
        if (o == largest || !(double(boundaryAreas[o]) < partArea(double(boundaryAreas[largest]))))
            continue;
        fragments.isFragment[o] = 1;
        ++fragments.count;
        fragments.voxels += found.objects[o].voxels;
    }
    return fragments;
}

}  // namespace skelseg
