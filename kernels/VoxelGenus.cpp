#include "kernels/VoxelGenus.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <vector>

#include "kernels/ConnectedObjects.h"
#include "kernels/base/ParallelFor.h"

namespace skelseg {

namespace {

/// Bit of the voxel at offset (dx, dy, dz) in {-1, 0}^3 from a lattice point:
/// the voxel with index (x + dx, y + dy, z + dz) has its corner at (x, y, z).
constexpr int bitOf(int dx, int dy, int dz) {
    return (dx + 1) | ((dy + 1) << 1) | ((dz + 1) << 2);
}

/// chi contribution of a lattice point for each of the 256 configurations of
/// its 8 voxels: + vertex - (edges +x, +y, +z) + (faces normal to x, y, z) - cube.
std::array<int, 256> makeEulerTable() {
    std::array<int, 256> table{};
    for (int code = 0; code < 256; ++code) {
        auto has = [&](int dx, int dy, int dz) { return (code >> bitOf(dx, dy, dz)) & 1; };
        auto any = [&](std::initializer_list<std::array<int, 3>> voxels) {
            for (const auto& v : voxels)
                if (has(v[0], v[1], v[2])) return 1;
            return 0;
        };
        const int vertex = code != 0;
        // Edge from the point along +x: the voxels x in {0}, y and z in {-1, 0}.
        const int edges = any({{0, -1, -1}, {0, 0, -1}, {0, -1, 0}, {0, 0, 0}}) +
                          any({{-1, 0, -1}, {0, 0, -1}, {-1, 0, 0}, {0, 0, 0}}) +
                          any({{-1, -1, 0}, {0, -1, 0}, {-1, 0, 0}, {0, 0, 0}});
        // Face normal to x spanning +y, +z: the voxels on either side of it.
        const int faces = any({{-1, 0, 0}, {0, 0, 0}}) + any({{0, -1, 0}, {0, 0, 0}}) +
                          any({{0, 0, -1}, {0, 0, 0}});
        const int cube = has(0, 0, 0);
        table[std::size_t(code)] = vertex - edges + faces - cube;
    }
    return table;
}

/// 6-connected background components that do not touch the grid's border.
/// A scanline fill: each step takes a whole x-run of background, so memory
/// is read in rows (a voxel-by-voxel flood was four times the Euler sum).
std::size_t countCavities(const MaskVolume& mask, Interrupter& interrupter) {
    const Dims d = mask.dims();
    const std::uint8_t* in = mask.data();
    std::vector<std::uint8_t> seen(mask.size(), 0);
    auto isFree = [&](std::size_t i) { return !in[i] && !seen[i]; };
    std::vector<std::array<int, 3>> seeds;
    auto flood = [&](int sx, int sy, int sz) {
        seeds.push_back({sx, sy, sz});
        while (!seeds.empty()) {
            const auto [x0, y, z] = seeds.back();
            seeds.pop_back();
            const std::size_t row = mask.index(0, y, z);
            if (!isFree(row + std::size_t(x0))) continue;
            int left = x0, right = x0;
            while (left > 0 && isFree(row + std::size_t(left - 1))) --left;
            while (right + 1 < d.x && isFree(row + std::size_t(right + 1))) ++right;
            std::fill(seen.begin() + std::ptrdiff_t(row + std::size_t(left)),
                      seen.begin() + std::ptrdiff_t(row + std::size_t(right) + 1), 1);
            auto scanRow = [&](int ny, int nz) {
                if (ny < 0 || nz < 0 || ny >= d.y || nz >= d.z) return;
                const std::size_t other = mask.index(0, ny, nz);
                bool inRun = false;
                for (int x = left; x <= right; ++x) {
                    const bool free = isFree(other + std::size_t(x));
                    if (free && !inRun) seeds.push_back({x, ny, nz});
                    inRun = free;
                }
            };
            scanRow(y - 1, z);
            scanRow(y + 1, z);
            scanRow(y, z - 1);
            scanRow(y, z + 1);
        }
    };
    // The outside: every background component that reaches the border.
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y) {
            const bool borderRow = y == 0 || z == 0 || y + 1 == d.y || z + 1 == d.z;
            for (int x = 0; x < d.x; x += (borderRow || x + 1 == d.x) ? 1 : d.x - 1)
                if (isFree(mask.index(x, y, z))) flood(x, y, z);
        }
    throwIfInterrupted(interrupter);
    std::size_t cavities = 0;
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x)
                if (isFree(mask.index(x, y, z))) {
                    ++cavities;
                    flood(x, y, z);
                }
    return cavities;
}

}  // namespace

std::int64_t voxelEulerCharacteristic(const MaskVolume& mask, bool threaded,
                                      Interrupter& interrupter) {
    static const std::array<int, 256> table = makeEulerTable();
    const Dims d = mask.dims();
    auto at = [&](int x, int y, int z) -> int {
        return x >= 0 && y >= 0 && z >= 0 && x < d.x && y < d.y && z < d.z && mask(x, y, z) != 0;
    };
    // Lattice points are (x, y, z) with x in [0, nx] etc.; one task per plane z.
    std::atomic<std::int64_t> total{0};
    std::atomic<bool> stopped{false};
    parallelFor(
        d.z + 1,
        [&](int zBegin, int zEnd) {
            std::int64_t sum = 0;
            for (int z = zBegin; z < zEnd; ++z) {
                if (stopped.load(std::memory_order_relaxed) ||
                    interrupter.wasInterrupted(double(z) / (d.z + 1))) {
                    stopped = true;
                    return;
                }
                for (int y = 0; y <= d.y; ++y) {
                    // The codes of consecutive points share four voxels: keep the
                    // column x - 1 and read only the column x.
                    int previousColumn = 0;  // voxels x - 1: bits of dx = -1
                    for (int x = 0; x <= d.x; ++x) {
                        const int column = at(x, y - 1, z - 1) << bitOf(0, -1, -1) |
                                           at(x, y, z - 1) << bitOf(0, 0, -1) |
                                           at(x, y - 1, z) << bitOf(0, -1, 0) |
                                           at(x, y, z) << bitOf(0, 0, 0);
                        const int code = column | previousColumn;
                        if (code != 0) sum += table[std::size_t(code)];
                        previousColumn = column >> 1;  // dx = 0 bits become dx = -1 bits
                    }
                }
            }
            total += sum;
        },
        threaded);
    if (stopped) throwIfInterrupted(interrupter);
    return total.load();
}

VoxelTopology voxelTopology(const MaskVolume& mask, const VoxelTopologyOptions& options,
                            Interrupter& interrupter) {
    VoxelTopology topology;
    topology.eulerCharacteristic = voxelEulerCharacteristic(mask, options.threaded, interrupter);
    ConnectedObjectsOptions objectOptions;
    objectOptions.threaded = options.threaded;
    topology.objects = findConnectedObjects(mask, objectOptions, interrupter).objects.size();
    topology.cavities = countCavities(mask, interrupter);
    topology.genus = std::int64_t(topology.objects) + std::int64_t(topology.cavities) -
                     topology.eulerCharacteristic;
    return topology;
}

}  // namespace skelseg
