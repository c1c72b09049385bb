#include "io/mesh/SelfOverlapSeparation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "io/mesh/MeshCheck.h"
#include "io/mesh/MeshVoxelizer.h"
#include "kernels/SeveredObjects.h"
#include "kernels/VoxelGenus.h"
#include "kernels/base/ParallelFor.h"

namespace skelseg {
namespace {

// The rays pass a little off the voxel centres, by amounts no mesh vertex is
// likely to sit at, so that a ray through a shared edge or vertex (counted by
// two triangles or by none) has no measure; rows where it happens anyway are
// skipped (see RowCrossing::tie).
constexpr double kRayOffsetY = 3.1e-5;
constexpr double kRayOffsetZ = 1.7e-5;

/// A voxel as (x, y, z), ordered for sorting.
using Cell = std::array<int, 3>;

/// Dilates the marks of a byte grid of `size` (x fastest) by a cube of
/// half-width `reach`: one running count per axis, since a cube is the
/// product of three segments.
void dilateBoxAlongAxes(std::vector<std::uint8_t>& marks, const std::array<int, 3>& size,
                        int reach) {
    if (reach <= 0) return;
    const std::array<std::size_t, 3> stride{1, std::size_t(size[0]),
                                            std::size_t(size[0]) * std::size_t(size[1])};
    std::vector<std::uint8_t> line;
    for (std::size_t axis = 0; axis < 3; ++axis) {
        const int length = size[axis];
        line.resize(std::size_t(length));
        const std::size_t a = (axis + 1) % 3, b = (axis + 2) % 3;
        for (int j = 0; j < size[b]; ++j)
            for (int i = 0; i < size[a]; ++i) {
                const std::size_t base = std::size_t(i) * stride[a] + std::size_t(j) * stride[b];
                // marked[t] counts the marks in [t - reach, t + reach].
                int inWindow = 0;
                for (int t = 0; t < std::min(reach, length); ++t)
                    inWindow += marks[base + std::size_t(t) * stride[axis]];
                for (int t = 0; t < length; ++t) {
                    if (t + reach < length)
                        inWindow += marks[base + std::size_t(t + reach) * stride[axis]];
                    if (t - reach - 1 >= 0)
                        inWindow -= marks[base + std::size_t(t - reach - 1) * stride[axis]];
                    line[std::size_t(t)] = inWindow > 0 ? 1 : 0;
                }
                for (int t = 0; t < length; ++t)
                    marks[base + std::size_t(t) * stride[axis]] = line[std::size_t(t)];
            }
    }
}

/// The sign each piece's crossings count with: +1 or -1 for a closed,
/// consistently oriented piece (outward or inward), 0 for a piece without a
/// winding number. Topology is that of the canonical vertices
/// (canonicalVertices): a mesh written with its vertices duplicated (a
/// triangle soup, seams) is the same surface as the welded one. A triangle
/// with a repeated canonical corner has no area and bounds nothing: it joins
/// no pieces and takes no part in the closedness test (one such face on an
/// edge would otherwise make the whole piece look open), and sits in a last
/// piece of its own, of orientation 0, that has no crossings.
struct MeshPieces {
    std::vector<std::uint32_t> canonical;  // per vertex (canonicalVertices)
    std::vector<std::uint32_t> pieceOfTriangle;
    std::vector<int> orientation;  // per piece
};

MeshPieces pieceOrientations(const TriangleMesh& mesh) {
    MeshPieces pieces;
    pieces.canonical = canonicalVertices(mesh);
    const std::vector<std::uint32_t>& canonical = pieces.canonical;
    std::vector<std::array<std::uint32_t, 3>> corners;
    std::vector<bool> degenerate;
    corners.reserve(mesh.triangles.size());
    degenerate.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) {
        const std::array<std::uint32_t, 3> c{canonical[t[0]], canonical[t[1]], canonical[t[2]]};
        corners.push_back(c);
        degenerate.push_back(c[0] == c[1] || c[1] == c[2] || c[2] == c[0]);
    }
    const std::size_t vertexCount = mesh.vertices.size();
    std::vector<std::uint32_t> parent(vertexCount);
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](std::uint32_t v) {
        while (parent[v] != v) v = parent[v] = parent[parent[v]];
        return v;
    };
    for (std::size_t i = 0; i < corners.size(); ++i) {
        if (degenerate[i]) continue;
        const std::uint32_t a = find(corners[i][0]);
        for (std::size_t c = 1; c < 3; ++c) {
            const std::uint32_t b = find(corners[i][c]);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
    }
    std::unordered_map<std::uint32_t, std::uint32_t> pieceOfRoot;
    pieces.pieceOfTriangle.reserve(mesh.triangles.size());
    for (std::size_t i = 0; i < corners.size(); ++i) {
        if (degenerate[i]) {
            pieces.pieceOfTriangle.push_back(0);  // set below, to the last piece
            continue;
        }
        const auto inserted =
            pieceOfRoot.try_emplace(find(corners[i][0]), std::uint32_t(pieceOfRoot.size()));
        pieces.pieceOfTriangle.push_back(inserted.first->second);
    }
    const std::uint32_t degeneratePiece = std::uint32_t(pieceOfRoot.size());
    // Closed and consistently oriented: every directed edge used once, and
    // its reverse once.
    std::unordered_map<std::uint64_t, std::uint32_t> directedUses;
    directedUses.reserve(3 * mesh.triangles.size());
    auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; };
    for (std::size_t i = 0; i < corners.size(); ++i)
        if (!degenerate[i])
            for (std::size_t c = 0; c < 3; ++c)
                ++directedUses[key(corners[i][c], corners[i][(c + 1) % 3])];
    std::vector<bool> valid(pieceOfRoot.size() + 1, true);
    std::vector<double> volume(pieceOfRoot.size() + 1, 0.0);
    valid[degeneratePiece] = false;
    for (std::size_t i = 0; i < corners.size(); ++i) {
        if (degenerate[i]) {
            pieces.pieceOfTriangle[i] = degeneratePiece;
            continue;
        }
        const auto& t = corners[i];
        const std::uint32_t piece = pieces.pieceOfTriangle[i];
        for (std::size_t c = 0; c < 3; ++c) {
            const std::uint32_t a = t[c], b = t[(c + 1) % 3];
            const auto forward = directedUses.find(key(a, b));
            const auto backward = directedUses.find(key(b, a));
            if (forward->second != 1 || backward == directedUses.end() || backward->second != 1)
                valid[piece] = false;
        }
        const auto& p = mesh.vertices[t[0]];
        const auto& q = mesh.vertices[t[1]];
        const auto& r = mesh.vertices[t[2]];
        volume[piece] += p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) +
                         p[2] * (q[0] * r[1] - q[1] * r[0]);
    }
    pieces.orientation.resize(valid.size(), 0);
    for (std::size_t piece = 0; piece < valid.size(); ++piece)
        if (valid[piece] && volume[piece] != 0.0)
            pieces.orientation[piece] = volume[piece] > 0 ? 1 : -1;
    return pieces;
}

/// Where a triangle crosses the ray of one row of voxel centres.
struct RowCrossing {
    std::uint64_t row = 0;  // y + ny * z
    double x = 0.0;         // continuous voxel index along x
    std::uint32_t piece = 0;
    int sign = 0;  // +1: the surface leaves towards +x; 0: the ray hit an edge (a tie)
    bool operator<(const RowCrossing& other) const {
        if (row != other.row) return row < other.row;
        if (x != other.x) return x < other.x;
        if (piece != other.piece) return piece < other.piece;
        return sign < other.sign;
    }
};

/// Edge function of the ray point (y, z) against the edge a -> b, computed on
/// the edge with its endpoints in a fixed order (lower canonical vertex index
/// first), so that the two triangles sharing an edge get exactly opposite
/// values, also where they name its ends by different vertices.
double edgeSide(std::uint32_t ia, std::uint32_t ib, const std::array<double, 3>& a,
                const std::array<double, 3>& b, double y, double z) {
    if (ia > ib) return -edgeSide(ib, ia, b, a, y, z);
    return (b[1] - a[1]) * (z - a[2]) - (b[2] - a[2]) * (y - a[1]);
}

std::vector<RowCrossing> rowCrossings(const TriangleMesh& mesh, const MeshPieces& pieces,
                                      const std::vector<std::array<double, 3>>& index,
                                      const Dims& dims, bool threaded, Interrupter& interrupter) {
    const std::size_t triangleCount = mesh.triangles.size();
    constexpr std::size_t kChunk = 4096;
    const std::size_t chunks = (triangleCount + kChunk - 1) / kChunk;
    std::vector<std::vector<RowCrossing>> found(chunks);
    parallelFor(
        chunks,
        [&](std::size_t chunkBegin, std::size_t chunkEnd) {
            for (std::size_t chunk = chunkBegin; chunk < chunkEnd; ++chunk) {
                throwIfInterrupted(interrupter);
                std::vector<RowCrossing>& out = found[chunk];
                const std::size_t end = std::min(triangleCount, (chunk + 1) * kChunk);
                for (std::size_t t = chunk * kChunk; t < end; ++t) {
                    const std::uint32_t piece = pieces.pieceOfTriangle[t];
                    const int orientation = pieces.orientation[piece];
                    if (orientation == 0) continue;
                    const auto& raw = mesh.triangles[t];
                    const std::array<std::uint32_t, 3> tri{pieces.canonical[raw[0]],
                                                           pieces.canonical[raw[1]],
                                                           pieces.canonical[raw[2]]};
                    const auto &p0 = index[tri[0]], &p1 = index[tri[1]], &p2 = index[tri[2]];
                    // Twice the signed area of the triangle seen along x.
                    const double area =
                        (p1[1] - p0[1]) * (p2[2] - p0[2]) - (p1[2] - p0[2]) * (p2[1] - p0[1]);
                    if (area == 0.0) continue;
                    const double yLow = std::min({p0[1], p1[1], p2[1]}) - kRayOffsetY;
                    const double yHigh = std::max({p0[1], p1[1], p2[1]}) - kRayOffsetY;
                    const double zLow = std::min({p0[2], p1[2], p2[2]}) - kRayOffsetZ;
                    const double zHigh = std::max({p0[2], p1[2], p2[2]}) - kRayOffsetZ;
                    const int y0 = std::max(0, int(std::ceil(yLow)));
                    const int y1 = std::min(dims.y - 1, int(std::floor(yHigh)));
                    const int z0 = std::max(0, int(std::ceil(zLow)));
                    const int z1 = std::min(dims.z - 1, int(std::floor(zHigh)));
                    const int sign = (area > 0 ? 1 : -1) * orientation;
                    for (int z = z0; z <= z1; ++z)
                        for (int y = y0; y <= y1; ++y) {
                            const double ry = y + kRayOffsetY, rz = z + kRayOffsetZ;
                            const double e0 = edgeSide(tri[1], tri[2], p1, p2, ry, rz);
                            const double e1 = edgeSide(tri[2], tri[0], p2, p0, ry, rz);
                            const double e2 = edgeSide(tri[0], tri[1], p0, p1, ry, rz);
                            const bool tie = e0 == 0.0 || e1 == 0.0 || e2 == 0.0;
                            const bool inside = area > 0 ? (e0 >= 0 && e1 >= 0 && e2 >= 0)
                                                         : (e0 <= 0 && e1 <= 0 && e2 <= 0);
                            if (!inside) continue;
                            // Barycentric weights are the edge functions over the area.
                            const double x = (e0 * p0[0] + e1 * p1[0] + e2 * p2[0]) / area;
                            out.push_back(RowCrossing{
                                std::uint64_t(y) + std::uint64_t(dims.y) * std::uint64_t(z), x,
                                piece, tie ? 0 : sign});
                        }
                }
            }
        },
        threaded);
    std::vector<RowCrossing> all;
    for (auto& part : found) all.insert(all.end(), part.begin(), part.end());
    return all;
}

/// Voxels of one row (its crossings sorted by x) that a piece encloses twice
/// or more, appended to `out` in increasing x.
void doublyEnclosedInRow(const RowCrossing* begin, const RowCrossing* end, const Dims& dims,
                         std::vector<int>& winding, std::vector<std::uint64_t>& out) {
    for (const RowCrossing* c = begin; c != end; ++c)
        if (c->sign == 0) return;  // a ray through an edge: this row's count is unreliable
    std::vector<std::uint64_t> row;
    int doubled = 0;  // pieces whose winding number is >= 2 here
    // Sweep from +x (winding 0) towards -x: between crossings c-1 and c the
    // winding numbers are the sums of the signs of the crossings at c and beyond.
    for (const RowCrossing* c = end; c != begin;) {
        --c;
        int& w = winding[c->piece];
        doubled -= w >= 2;
        w += c->sign;
        doubled += w >= 2;
        if (doubled == 0) continue;
        const double lowX = c == begin ? -1.0 : (c - 1)->x;
        const int first = std::max(0, int(std::floor(lowX)) + 1);
        const int last = std::min(dims.x - 1, int(std::ceil(c->x)) - 1);
        for (int x = last; x >= first; --x) row.push_back(std::uint64_t(x));
    }
    for (const RowCrossing* c = begin; c != end; ++c) winding[c->piece] = 0;
    const std::uint64_t base = begin->row * std::uint64_t(dims.x);
    for (auto it = row.rbegin(); it != row.rend(); ++it) out.push_back(base + *it);
}

/// 26-connected groups of the sorted voxel indices, each as indices into `voxels`.
std::vector<std::vector<std::size_t>> groupsOf(const std::vector<std::uint64_t>& voxels,
                                               const Dims& dims) {
    std::vector<std::size_t> parent(voxels.size());
    std::iota(parent.begin(), parent.end(), std::size_t(0));
    auto find = [&](std::size_t v) {
        while (parent[v] != v) v = parent[v] = parent[parent[v]];
        return v;
    };
    const std::uint64_t nx = std::uint64_t(dims.x), nxy = nx * std::uint64_t(dims.y);
    for (std::size_t i = 0; i < voxels.size(); ++i) {
        const std::uint64_t v = voxels[i];
        const int x = int(v % nx), y = int((v / nx) % std::uint64_t(dims.y)), z = int(v / nxy);
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy, zz = z + dz;
                    if (xx < 0 || yy < 0 || zz < 0 || xx >= dims.x || yy >= dims.y || zz >= dims.z)
                        continue;
                    const std::uint64_t n =
                        std::uint64_t(xx) + nx * std::uint64_t(yy) + nxy * std::uint64_t(zz);
                    if (n <= v) continue;
                    const auto it = std::lower_bound(voxels.begin(), voxels.end(), n);
                    if (it == voxels.end() || *it != n) continue;
                    const std::size_t a = find(i), b = find(std::size_t(it - voxels.begin()));
                    if (a != b) parent[std::max(a, b)] = std::min(a, b);
                }
    }
    std::vector<std::vector<std::size_t>> groups;
    std::unordered_map<std::size_t, std::size_t> groupOfRoot;
    for (std::size_t i = 0; i < voxels.size(); ++i) {
        const auto [it, added] = groupOfRoot.try_emplace(find(i), groups.size());
        if (added) groups.emplace_back();
        groups[it->second].push_back(i);
    }
    return groups;
}

}  // namespace

std::vector<std::uint64_t> selfOverlapVoxels(const TriangleMesh& mesh, const Dims& dims,
                                             const VolumeGeometry& geometry, bool threaded,
                                             Interrupter& interrupter) {
    const MeshPieces pieces = pieceOrientations(mesh);
    if (std::all_of(pieces.orientation.begin(), pieces.orientation.end(),
                    [](int o) { return o == 0; }))
        return {};
    const WorldToIndex toIndex(geometry);
    std::vector<std::array<double, 3>> index(mesh.vertices.size());
    parallelFor(
        mesh.vertices.size(),
        [&](std::size_t begin, std::size_t end) {
            for (std::size_t v = begin; v < end; ++v) index[v] = toIndex(mesh.vertices[v]);
        },
        threaded, 4096);
    std::vector<RowCrossing> crossings =
        rowCrossings(mesh, pieces, index, dims, threaded, interrupter);
    std::sort(crossings.begin(), crossings.end());
    // Rows start where the row number changes; they are swept in chunks
    // whose outputs are joined in order, so the result is the same threaded.
    std::vector<std::size_t> rowStarts;
    for (std::size_t i = 0; i < crossings.size(); ++i)
        if (i == 0 || crossings[i].row != crossings[i - 1].row) rowStarts.push_back(i);
    rowStarts.push_back(crossings.size());
    const std::size_t rows = rowStarts.size() - 1;
    constexpr std::size_t kRowsPerChunk = 1024;
    const std::size_t chunks = (rows + kRowsPerChunk - 1) / kRowsPerChunk;
    std::vector<std::vector<std::uint64_t>> found(chunks);
    parallelFor(
        chunks,
        [&](std::size_t chunkBegin, std::size_t chunkEnd) {
            std::vector<int> winding(pieces.orientation.size(), 0);
            for (std::size_t chunk = chunkBegin; chunk < chunkEnd; ++chunk) {
                throwIfInterrupted(interrupter);
                const std::size_t last = std::min(rows, (chunk + 1) * kRowsPerChunk);
                for (std::size_t r = chunk * kRowsPerChunk; r < last; ++r)
                    doublyEnclosedInRow(crossings.data() + rowStarts[r],
                                        crossings.data() + rowStarts[r + 1], dims, winding,
                                        found[chunk]);
            }
        },
        threaded);
    std::vector<std::uint64_t> voxels;
    for (const auto& part : found) voxels.insert(voxels.end(), part.begin(), part.end());
    return voxels;
}

SelfOverlapSeparation separateSelfOverlaps(const TriangleMesh& mesh, MaskVolume& mask,
                                           const SelfOverlapOptions& options,
                                           Interrupter& interrupter) {
    SelfOverlapSeparation result;
    const Dims dims = mask.dims();
    const std::vector<std::uint64_t> voxels =
        selfOverlapVoxels(mesh, dims, mask.geometry, options.threaded, interrupter);
    result.overlapVoxels = voxels.size();
    if (voxels.empty()) return result;
    const std::uint64_t nx = std::uint64_t(dims.x), nxy = nx * std::uint64_t(dims.y);
    auto cellOf = [&](std::uint64_t v) {
        return Cell{int(v % nx), int((v / nx) % std::uint64_t(dims.y)), int(v / nxy)};
    };
    // The lowest and highest corner of a group's bounding box.
    auto boundsOf = [&](const std::vector<std::size_t>& group) {
        Cell low{dims.x, dims.y, dims.z}, high{-1, -1, -1};
        for (std::size_t i : group) {
            const Cell c = cellOf(voxels[i]);
            for (std::size_t k = 0; k < 3; ++k) {
                low[k] = std::min(low[k], c[k]);
                high[k] = std::max(high[k], c[k]);
            }
        }
        return std::make_pair(low, high);
    };
    const int firstReach = std::max(0, options.clearance);
    const int lastReach = std::max(firstReach, options.maxClearance);
    // The object voxels within `reach` (Chebyshev distance) of the group, in
    // (x, y, z) order. The cube around every voxel is separable: the group
    // is marked in a byte grid over its bounding box grown by `reach` and
    // dilated along x, y and z in turn, so a group costs its box, not
    // (2 reach + 1)^3 entries per voxel to sort.
    auto cellsAround = [&](const std::vector<std::size_t>& group, int reach) {
        auto [low, high] = boundsOf(group);
        const std::array<int, 3> limit{dims.x, dims.y, dims.z};
        std::array<int, 3> size{};
        for (std::size_t k = 0; k < 3; ++k) {
            low[k] = std::max(0, low[k] - reach);
            high[k] = std::min(limit[k] - 1, high[k] + reach);
            size[k] = high[k] - low[k] + 1;
        }
        const std::size_t sx = std::size_t(size[0]), sxy = sx * std::size_t(size[1]);
        std::vector<std::uint8_t> near(sxy * std::size_t(size[2]), 0);
        for (std::size_t i : group) {
            const Cell c = cellOf(voxels[i]);
            near[std::size_t(c[0] - low[0]) + std::size_t(c[1] - low[1]) * sx +
                 std::size_t(c[2] - low[2]) * sxy] = 1;
        }
        dilateBoxAlongAxes(near, size, reach);
        std::vector<Cell> cells;
        for (int x = 0; x < size[0]; ++x)
            for (int y = 0; y < size[1]; ++y)
                for (int z = 0; z < size[2]; ++z)
                    if (near[std::size_t(x) + std::size_t(y) * sx + std::size_t(z) * sxy] &&
                        mask(low[0] + x, low[1] + y, low[2] + z))
                        cells.push_back(Cell{low[0] + x, low[1] + y, low[2] + z});
        return cells;
    };
    // The thickness of a group: the narrowest side of its bounding box.
    auto thicknessOf = [&](const std::vector<std::size_t>& group) {
        const auto [low, high] = boundsOf(group);
        return 1 + std::min({high[0] - low[0], high[1] - low[1], high[2] - low[2]});
    };
    auto setCells = [&](const std::vector<Cell>& cells, std::uint8_t value) {
        for (const Cell& c : cells) mask(c[0], c[1], c[2]) = value;
    };
    VoxelTopologyOptions topologyOptions;
    topologyOptions.threaded = options.threaded;
    std::int64_t maskGenus = -1;  // the genus of the mask as it stands; -1: not known
    std::vector<ClearedGroup> clearedGroups;
    for (const auto& group : groupsOf(voxels, dims)) {
        throwIfInterrupted(interrupter);
        // A clearing that adds topology in its box is tried again wider:
        // where the host's wall around the buried limb is thinner than the
        // clearing, a narrow clearing perforates it and a wider one removes
        // it. The wider clearing goes no further than the place is thick,
        // and is kept only where it removes a handle of the whole voxel
        // model: elsewhere it would carve the surroundings of a crossing
        // that joins nothing (SelfOverlapOptions::maxClearance).
        bool separated = false, nothingToClear = false;
        const int groupReach = std::max(firstReach, std::min(lastReach, thicknessOf(group)));
        for (int reach = firstReach; reach <= groupReach && !separated; ++reach) {
            const std::vector<Cell> cells = cellsAround(group, reach);
            if (cells.empty()) {
                nothingToClear = true;
                break;
            }
            if (changeAddsTopology(mask, cells, 0)) continue;
            if (reach > firstReach) {
                if (maskGenus < 0)
                    maskGenus = voxelTopology(mask, topologyOptions, interrupter).genus;
                setCells(cells, 0);
                const std::int64_t genus = voxelTopology(mask, topologyOptions, interrupter).genus;
                if (genus >= maskGenus) {
                    setCells(cells, 1);
                    continue;
                }
                maskGenus = genus;
            } else {
                setCells(cells, 0);
                maskGenus = -1;
            }
            ++result.overlaps;
            result.voxelsCleared += cells.size();
            clearedGroups.push_back(cells);
            separated = true;
        }
        if (!separated && !nothingToClear) ++result.overlapsKept;
    }
    // A clearing that cut an object in two (a limb passing through another)
    // is counted, and set back when asked: its box cannot see that
    // (SeveredObjects.h).
    SeveredObjectsOptions severedOptions;
    severedOptions.threaded = options.threaded;
    severedOptions.setBack = options.rejoinSevered;
    const std::vector<bool> severing =
        rejoinSeveredObjects(mask, clearedGroups, severedOptions, interrupter);
    for (std::size_t g = 0; g < severing.size(); ++g) {
        if (!severing[g]) continue;
        ++result.overlapsSevering;
        if (!options.rejoinSevered) continue;
        --result.overlaps;
        ++result.overlapsKept;
        result.voxelsCleared -= clearedGroups[g].size();
    }
    return result;
}

}  // namespace skelseg
