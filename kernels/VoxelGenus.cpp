#include "kernels/VoxelGenus.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <vector>

#include "kernels/Cavities.h"
#include "kernels/VoxelRuns.h"
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

/// chi of the union of closed object cubes: per lattice row (y, z), the
/// four voxel rows around it, walked run boundary to run boundary. Between
/// two boundaries the four voxels beside a lattice point do not change, so
/// neither does its code after the first point.
std::int64_t eulerOfRuns(const VoxelRuns& runs, bool threaded, Interrupter& interrupter) {
    static const std::array<int, 256> table = makeEulerTable();
    const Dims d = runs.dims;
    // Lattice points are (x, y, z) with x in [0, nx] etc.; one task per plane z.
    std::atomic<std::int64_t> total{0};
    std::atomic<bool> stopped{false};
    constexpr int kRows = 4;
    // The voxel rows beside a lattice row and the bit of their voxel at dx = 0.
    constexpr int kDy[kRows] = {-1, 0, -1, 0}, kDz[kRows] = {-1, -1, 0, 0};
    constexpr int kBit[kRows] = {bitOf(0, -1, -1), bitOf(0, 0, -1), bitOf(0, -1, 0),
                                 bitOf(0, 0, 0)};
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
                    std::uint32_t next[kRows], end[kRows];
                    bool any = false;
                    for (int k = 0; k < kRows; ++k) {
                        const int vy = y + kDy[k], vz = z + kDz[k];
                        next[k] = end[k] = 0;
                        if (vy < 0 || vz < 0 || vy >= d.y || vz >= d.z) continue;
                        const std::size_t row = runs.rowOf(vy, vz);
                        next[k] = runs.rowStart[row];
                        end[k] = runs.rowStart[row + 1];
                        any = any || next[k] < end[k];
                    }
                    if (!any) continue;
                    int previousColumn = 0;  // the voxels at x - 1, as bits of dx = 0
                    for (int x = 0; x <= d.x;) {
                        int column = 0, boundary = d.x + 1;
                        for (int k = 0; k < kRows; ++k) {
                            while (next[k] < end[k] && runs.runs[next[k]].x1 < x) ++next[k];
                            if (next[k] == end[k]) continue;
                            const VoxelRun& run = runs.runs[next[k]];
                            if (run.x0 <= x) {
                                column |= 1 << kBit[k];
                                boundary = std::min(boundary, run.x1 + 1);
                            } else {
                                boundary = std::min(boundary, run.x0);
                            }
                        }
                        // dx = 0 bits of the column before become its dx = -1 bits.
                        sum += table[std::size_t(column | previousColumn >> 1)];
                        sum += std::int64_t(boundary - x - 1) *
                               table[std::size_t(column | column >> 1)];
                        previousColumn = column;
                        x = boundary;
                    }
                }
            }
            total += sum;
        },
        threaded);
    if (stopped) throwInterrupted(interrupter);
    return total.load();
}

}  // namespace

std::int64_t voxelEulerCharacteristic(const MaskVolume& mask, bool threaded,
                                      Interrupter& interrupter) {
    return eulerOfRuns(objectRuns(mask, threaded, interrupter), threaded, interrupter);
}

VoxelTopology voxelTopology(const MaskVolume& mask, const VoxelTopologyOptions& options,
                            Interrupter& interrupter) {
    const bool threaded = options.threaded;
    const VoxelRuns runs = objectRuns(mask, threaded, interrupter);
    VoxelTopology topology;
    topology.eulerCharacteristic = eulerOfRuns(runs, threaded, interrupter);
    const std::vector<std::uint32_t> root =
        runComponents(runs, VoxelAdjacency::Full26, threaded, interrupter);
    for (std::size_t i = 0; i < root.size(); ++i) topology.objects += root[i] == i;
    topology.cavities = findCavities(runs, threaded, interrupter).count;
    topology.genus = std::int64_t(topology.objects) + std::int64_t(topology.cavities) -
                     topology.eulerCharacteristic;
    return topology;
}

bool changeAddsTopology(const MaskVolume& mask, const std::vector<std::array<int, 3>>& cells,
                        std::uint8_t value, int margin) {
    if (cells.empty()) return false;
    const Dims d = mask.dims();
    std::array<int, 3> lo{d.x, d.y, d.z}, hi{-1, -1, -1};
    for (const auto& c : cells)
        for (std::size_t a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], c[a] - margin);
            hi[a] = std::max(hi[a], c[a] + margin);
        }
    lo = {std::max(lo[0], 0), std::max(lo[1], 0), std::max(lo[2], 0)};
    hi = {std::min(hi[0], d.x - 1), std::min(hi[1], d.y - 1), std::min(hi[2], d.z - 1)};
    MaskVolume box(Dims{hi[0] - lo[0] + 3, hi[1] - lo[1] + 3, hi[2] - lo[2] + 3}, 0);
    for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
            for (int x = lo[0]; x <= hi[0]; ++x)
                box(x - lo[0] + 1, y - lo[1] + 1, z - lo[2] + 1) = mask(x, y, z);
    VoxelTopologyOptions serial;
    serial.threaded = false;
    const VoxelTopology before = voxelTopology(box, serial);
    for (const auto& c : cells) box(c[0] - lo[0] + 1, c[1] - lo[1] + 1, c[2] - lo[2] + 1) = value;
    const VoxelTopology after = voxelTopology(box, serial);
    return after.genus > before.genus || after.cavities > before.cavities;
}

}  // namespace skelseg
