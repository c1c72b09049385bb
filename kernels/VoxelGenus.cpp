#include "kernels/VoxelGenus.h"

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
std::size_t countCavities(const MaskVolume& mask, Interrupter& interrupter) {
    const Dims d = mask.dims();
    const std::size_t sx = 1, sy = std::size_t(d.x), sz = std::size_t(d.x) * std::size_t(d.y);
    const std::uint8_t* in = mask.data();
    std::vector<std::uint8_t> seen(mask.size(), 0);
    std::vector<std::uint32_t> stack;
    auto flood = [&](std::size_t start) {
        seen[start] = 1;
        stack.push_back(std::uint32_t(start));
        while (!stack.empty()) {
            const std::size_t i = stack.back();
            stack.pop_back();
            const int x = int(i % sy), y = int((i / sy) % std::size_t(d.y)), z = int(i / sz);
            auto visit = [&](bool inside, std::size_t n) {
                if (inside && !in[n] && !seen[n]) {
                    seen[n] = 1;
                    stack.push_back(std::uint32_t(n));
                }
            };
            visit(x > 0, i - sx);
            visit(x + 1 < d.x, i + sx);
            visit(y > 0, i - sy);
            visit(y + 1 < d.y, i + sy);
            visit(z > 0, i - sz);
            visit(z + 1 < d.z, i + sz);
        }
    };
    // The outside: every background component that reaches the border.
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) {
                const bool border =
                    x == 0 || y == 0 || z == 0 || x + 1 == d.x || y + 1 == d.y || z + 1 == d.z;
                if (!border) {
                    x = d.x - 2;  // jump to the last voxel of the row
                    continue;
                }
                const std::size_t i = mask.index(x, y, z);
                if (!in[i] && !seen[i]) flood(i);
            }
    throwIfInterrupted(interrupter);
    std::size_t cavities = 0;
    for (std::size_t i = 0; i < seen.size(); ++i)
        if (!in[i] && !seen[i]) {
            ++cavities;
            flood(i);
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
