#include "io/render/SegmentSurfaces.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <climits>
#include <cmath>
#include <limits>
#include <string>
#include "kernels/base/ParallelFor.h"

namespace skelseg {

namespace {

// Inside negative, as in a level set: volumeToMesh then orients its quads
// with normals pointing out of the region. Crossings sit half way between an
// inside and an outside voxel centre, i.e. on the shared voxel face.
constexpr float kInsideValue = -1.0f;
constexpr float kOutsideValue = 1.0f;
constexpr int kBlock = 8;  // OpenVDB leaf edge

/// Inclusive voxel bounding box; empty while min > max.
struct VoxelBox {
    std::array<int, 3> min{INT_MAX, INT_MAX, INT_MAX};
    std::array<int, 3> max{INT_MIN, INT_MIN, INT_MIN};

    bool empty() const noexcept { return min[0] > max[0]; }
    void add(int x, int y, int z) noexcept {
        const int c[3] = {x, y, z};
        for (int a = 0; a < 3; ++a) {
            min[a] = std::min(min[a], c[a]);
            max[a] = std::max(max[a], c[a]);
        }
    }
    void merge(const VoxelBox& other) noexcept {
        for (int a = 0; a < 3; ++a) {
            min[a] = std::min(min[a], other.min[a]);
            max[a] = std::max(max[a], other.max[a]);
        }
    }
};

/// Bounding box of each voxel value (index = value), from one pass over the
/// volume: far cheaper than one pass per label on a 400^3 volume.
template <typename T>
std::vector<VoxelBox> boundingBoxesByValue(const Volume<T>& volume, bool threaded,
                                           Interrupter& interrupter) {
    const Dims dims = volume.dims();
    using Boxes = std::vector<VoxelBox>;
    auto scanSlabs = [&](int zBegin, int zEnd, Boxes& boxes) {
        for (int z = zBegin; z < zEnd; ++z) {
            throwIfInterrupted(interrupter);
            for (int y = 0; y < dims.y; ++y) {
                const T* row = volume.data() + volume.index(0, y, z);
                for (int x = 0; x < dims.x; ++x) {
                    const T value = row[x];
                    if (value == T(0)) continue;
                    if (std::size_t(value) >= boxes.size()) boxes.resize(std::size_t(value) + 1);
                    boxes[value].add(x, y, z);
                }
            }
        }
    };
    auto join = [](Boxes a, const Boxes& b) {
        if (a.size() < b.size()) a.resize(b.size());
        for (std::size_t v = 0; v < b.size(); ++v) a[v].merge(b[v]);
        return a;
    };
    if (!threaded) {
        Boxes boxes;
        scanSlabs(0, dims.z, boxes);
        return boxes;
    }
    return tbb::parallel_reduce(
        tbb::blocked_range<int>(0, dims.z, 4), Boxes(),
        [&](const tbb::blocked_range<int>& range, Boxes boxes) {
            scanSlabs(range.begin(), range.end(), boxes);
            return boxes;
        },
        join);
}

int floorToBlock(int value) noexcept {
    return value >= 0 ? value / kBlock * kBlock : -((-value + kBlock - 1) / kBlock) * kBlock;
}

/// Polygons of one region in index coordinates.
struct RegionMesh {
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec4I> quads;
};

/// Taubin's lambda|mu smoothing (SIGGRAPH 1995): a shrinking Laplacian step
/// followed by an inflating one, which removes the one-voxel terraces without
/// the shrinkage of plain Laplacian smoothing. Jacobi updates (new positions
/// from old ones only), so the result does not depend on evaluation order.
void smoothTaubin(RegionMesh& mesh, int iterations) {
    if (iterations <= 0 || mesh.points.empty()) return;
    // Vertex adjacency (CSR) from the quad edges.
    const std::size_t count = mesh.points.size();
    std::vector<std::uint32_t> start(count + 1, 0);
    for (const auto& quad : mesh.quads)
        for (int k = 0; k < 4; ++k) start[quad[k] + 1] += 2;
    for (std::size_t v = 0; v < count; ++v) start[v + 1] += start[v];
    std::vector<std::uint32_t> neighbours(start.back());
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (const auto& quad : mesh.quads)
        for (int k = 0; k < 4; ++k) {
            const std::uint32_t v = quad[k];
            neighbours[fill[v]++] = quad[(k + 1) % 4];
            neighbours[fill[v]++] = quad[(k + 3) % 4];
        }
    // Each edge is listed from both of its quads: duplicates weigh every
    // neighbour equally twice, which leaves the average unchanged.
    std::vector<openvdb::Vec3s> next(count);
    auto step = [&](float factor) {
        for (std::size_t v = 0; v < count; ++v) {
            if (start[v] == start[v + 1]) {
                next[v] = mesh.points[v];
                continue;
            }
            openvdb::Vec3s sum(0.0f);
            for (std::uint32_t k = start[v]; k < start[v + 1]; ++k)
                sum += mesh.points[neighbours[k]];
            const openvdb::Vec3s average = sum / float(start[v + 1] - start[v]);
            next[v] = mesh.points[v] + factor * (average - mesh.points[v]);
        }
        mesh.points.swap(next);
    };
    for (int i = 0; i < iterations; ++i) {
        step(0.5f);
        step(-0.53f);
    }
}

/// Meshes the voxels of `volume` for which isInside(value) holds, within
/// `box`. The sparse grid holds dense leaves only where a leaf or its one-voxel
/// apron mixes inside and outside; leaves entirely inside (apron included)
/// become inactive inside tiles, entirely outside ones stay background. That
/// keeps memory proportional to the surface, and the mesher, which looks at
/// active voxels and their +1 neighbours, still sees every crossing.
template <typename T, typename IsInside>
RegionMesh meshRegion(const Volume<T>& volume, const VoxelBox& box, const IsInside& isInside,
                      int smoothingIterations, Interrupter& interrupter) {
    RegionMesh mesh;
    if (box.empty()) return mesh;
    const Dims dims = volume.dims();
    openvdb::FloatGrid grid(kOutsideValue);
    auto& tree = grid.tree();
    using LeafType = openvdb::FloatGrid::TreeType::LeafNodeType;

    auto insideAt = [&](int x, int y, int z) {
        return volume.contains(x, y, z) && isInside(volume(x, y, z));
    };
    std::array<int, 3> first, last;
    for (int a = 0; a < 3; ++a) {
        first[a] = floorToBlock(box.min[a] - 1);
        last[a] = floorToBlock(box.max[a] + 1);
    }
    for (int bz = first[2]; bz <= last[2]; bz += kBlock) {
        throwIfInterrupted(interrupter);
        for (int by = first[1]; by <= last[1]; by += kBlock)
            for (int bx = first[0]; bx <= last[0]; bx += kBlock) {
                // Classify the block with its apron. Voxels beyond the volume
                // are outside, so a clipped apron already counts as outside.
                const int lo[3] = {std::max(bx - 1, 0), std::max(by - 1, 0), std::max(bz - 1, 0)};
                const int hi[3] = {std::min(bx + kBlock, dims.x - 1),
                                   std::min(by + kBlock, dims.y - 1),
                                   std::min(bz + kBlock, dims.z - 1)};
                bool anyOutside = lo[0] != bx - 1 || lo[1] != by - 1 || lo[2] != bz - 1 ||
                                  hi[0] != bx + kBlock || hi[1] != by + kBlock ||
                                  hi[2] != bz + kBlock;
                bool anyInside = false;
                for (int z = lo[2]; z <= hi[2] && !(anyInside && anyOutside); ++z)
                    for (int y = lo[1]; y <= hi[1] && !(anyInside && anyOutside); ++y) {
                        const T* row = volume.data() + volume.index(0, y, z);
                        for (int x = lo[0]; x <= hi[0]; ++x) {
                            if (isInside(row[x]))
                                anyInside = true;
                            else
                                anyOutside = true;
                        }
                    }
                if (!anyInside) continue;
                const openvdb::Coord origin(bx, by, bz);
                if (!anyOutside) {
                    tree.addTile(1, origin, kInsideValue, false);
                    continue;
                }
                LeafType* leaf = tree.touchLeaf(origin);
                for (int x = 0; x < kBlock; ++x)
                    for (int y = 0; y < kBlock; ++y)
                        for (int z = 0; z < kBlock; ++z) {
                            const openvdb::Coord voxel(bx + x, by + y, bz + z);
                            leaf->setValueOn(
                                LeafType::coordToOffset(voxel),
                                insideAt(bx + x, by + y, bz + z) ? kInsideValue : kOutsideValue);
                        }
            }
    }
    throwIfInterrupted(interrupter);
    openvdb::tools::volumeToMesh(grid, mesh.points, mesh.quads, 0.0);
    smoothTaubin(mesh, smoothingIterations);
    return mesh;
}

/// Appends `mesh` to `surface`: points through the geometry into world
/// coordinates, each quad as two triangles (orientation kept; reversed when
/// the geometry mirrors, so normals still point outwards in world space).
/// `labelOfTriangle(centroidInIndexSpace)` tags each triangle.
template <typename LabelOf>
void appendRegion(LabelledSurface& surface, const RegionMesh& mesh, const VolumeGeometry& geometry,
                  const LabelOf& labelOfTriangle) {
    if (surface.vertices.size() + mesh.points.size() > std::numeric_limits<std::uint32_t>::max())
        throw Error("segment surfaces: more than 2^32 vertices");
    const auto& d = geometry.directions;
    const double determinant = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1]) -
                               d[1][0] * (d[0][1] * d[2][2] - d[0][2] * d[2][1]) +
                               d[2][0] * (d[0][1] * d[1][2] - d[0][2] * d[1][1]);
    const bool mirrored = determinant < 0.0;
    const auto offset = std::uint32_t(surface.vertices.size());
    // Grown geometrically: a reserve of the exact new size in every call
    // copied the whole surface once per segment, quadratic in the segments
    // (65,535 one-voxel segments never finished).
    auto reserveGrowing = [](auto& values, std::size_t needed) {
        if (needed > values.capacity()) values.reserve(std::max(needed, 2 * values.capacity()));
    };
    reserveGrowing(surface.vertices, surface.vertices.size() + mesh.points.size());
    for (const auto& p : mesh.points)
        surface.vertices.push_back(geometry.indexToWorld(double(p[0]), double(p[1]), double(p[2])));
    reserveGrowing(surface.triangles, surface.triangles.size() + 2 * mesh.quads.size());
    reserveGrowing(surface.triangleLabels, surface.triangleLabels.size() + 2 * mesh.quads.size());
    auto addTriangle = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        openvdb::Vec3s centroid = (mesh.points[a] + mesh.points[b] + mesh.points[c]) / 3.0f;
        if (mirrored) std::swap(b, c);
        surface.triangles.push_back({offset + a, offset + b, offset + c});
        surface.triangleLabels.push_back(labelOfTriangle(centroid));
    };
    for (const auto& quad : mesh.quads) {
        addTriangle(quad[0], quad[1], quad[2]);
        addTriangle(quad[0], quad[2], quad[3]);
    }
}

/// Runs `work` serially (OpenVDB's internal loops included) or as it is.
template <typename Work>
auto runWithThreading(bool threaded, const Work& work) {
    if (threaded) return work();
    tbb::task_arena singleThread(1);
    return singleThread.execute(work);
}

template <typename T>
LabelledSurface objectSurface(const Volume<T>& volume, const SegmentSurfaceOptions& options,
                              Interrupter& interrupter, bool labelByVoxel) {
    InterrupterScope scope(interrupter, "object surface");
    return runWithThreading(options.threaded, [&] {
        VoxelBox box;
        for (const auto& valueBox : boundingBoxesByValue(volume, options.threaded, interrupter))
            box.merge(valueBox);
        const RegionMesh mesh = meshRegion(
            volume, box, [](T value) { return value != T(0); }, options.smoothingIterations,
            interrupter);
        LabelledSurface surface;
        appendRegion(
            surface, mesh, volume.geometry, [&](const openvdb::Vec3s& centroid) -> std::uint32_t {
                if (!labelByVoxel) return 1;
                // The object voxel whose centre is nearest to the centroid; the
                // surface runs between voxel centres, so one is within a voxel.
                const int cx = int(std::floor(centroid[0])), cy = int(std::floor(centroid[1])),
                          cz = int(std::floor(centroid[2]));
                std::uint32_t best = 0;
                float bestDistance = std::numeric_limits<float>::max();
                for (int z = cz - 1; z <= cz + 2; ++z)
                    for (int y = cy - 1; y <= cy + 2; ++y)
                        for (int x = cx - 1; x <= cx + 2; ++x) {
                            if (!volume.contains(x, y, z) || volume(x, y, z) == T(0)) continue;
                            const float dx = float(x) - centroid[0], dy = float(y) - centroid[1],
                                        dz = float(z) - centroid[2];
                            const float distance = dx * dx + dy * dy + dz * dz;
                            if (distance < bestDistance) {
                                bestDistance = distance;
                                best = std::uint32_t(volume(x, y, z));
                            }
                        }
                return best;
            });
        return surface;
    });
}

}  // namespace

LabelledSurface extractSegmentSurfaces(const LabelVolume& labels,
                                       const SegmentSurfaceOptions& options,
                                       Interrupter& interrupter) {
    InterrupterScope scope(interrupter, "segment surfaces");
    return runWithThreading(options.threaded, [&] {
        const std::vector<VoxelBox> boxes =
            boundingBoxesByValue(labels, options.threaded, interrupter);
        std::vector<RegionMesh> meshes(boxes.size());
        std::atomic<std::size_t> labelsDone{0};
        // One task per label; labels differ a lot in size, so grain 1 lets
        // TBB balance them. Index 0 (background) has an empty box.
        parallelFor(
            boxes.size(),
            [&](std::size_t begin, std::size_t end) {
                for (std::size_t label = begin; label < end; ++label) {
                    if (label == 0 || boxes[label].empty()) continue;
                    throwIfInterrupted(interrupter,
                                       double(labelsDone.load()) / double(boxes.size()));
                    const auto value = LabelVolume::ValueType(label);
                    meshes[label] = meshRegion(
                        labels, boxes[label],
                        [value](LabelVolume::ValueType v) { return v == value; },
                        options.smoothingIterations, interrupter);
                    ++labelsDone;
                }
            },
            options.threaded);
        LabelledSurface surface;
        for (std::size_t label = 1; label < meshes.size(); ++label)
            appendRegion(surface, meshes[label], labels.geometry,
                         [label](const openvdb::Vec3s&) { return std::uint32_t(label); });
        return surface;
    });
}

LabelledSurface extractSegmentSurfaces(const LabelVolume& labels, Interrupter& interrupter) {
    return extractSegmentSurfaces(labels, SegmentSurfaceOptions{}, interrupter);
}

LabelledSurface extractObjectSurface(const LabelVolume& labels,
                                     const SegmentSurfaceOptions& options,
                                     Interrupter& interrupter) {
    return objectSurface(labels, options, interrupter, true);
}

LabelledSurface extractObjectSurface(const MaskVolume& mask, const SegmentSurfaceOptions& options,
                                     Interrupter& interrupter) {
    return objectSurface(mask, options, interrupter, false);
}

}  // namespace skelseg
