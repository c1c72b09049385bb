#include "io/mesh/MeshVoxelizer.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

#include "io/mesh/MeshCheck.h"
#include "io/mesh/VoxelObjectPieces.h"
#include "io/volume/VdbIO.h"
#include "kernels/base/ArenaPool.h"
#include "kernels/base/HugePages.h"

namespace skelseg {

namespace {

/// Two face-adjacent voxel centres (one voxel apart) on opposite sides of the
/// surface cannot both be more than half a voxel from it, so the voxels this
/// close to the surface form a layer that a 6-connected flood fill cannot
/// cross. The small excess absorbs float rounding of the distances.
constexpr double kSurfaceLayer = 0.501;

/// A TriangleMesh as OpenVDB's own adapter holds it: index-space points in
/// float and triangles, so that meshToVolume is the instantiation libopenvdb
/// already holds (OpenVDB declares it `extern template`). Instantiating it
/// for an adapter of our own took about 50 s of compile time in every build
/// (twice that under the sanitizers) for the same computation; the float
/// points round positions by at most 2^-24 of the grid's extent (3e-5 voxel
/// at 400), below the precision of the float vertices most mesh files store.
///
/// OpenVDB's answer depends on the order of the triangles it is given: where
/// a voxel centre is as near to two triangles, its nearest-triangle index is
/// the lower one, and the sign of a voxel on or halfway between surfaces is
/// taken from that triangle; a triangle's distances are rounded differently
/// when it starts at another corner. So the triangles are handed over in an
/// order of their geometry alone, each from its corner with the smallest
/// position (x, then y, then z) with its winding kept, and sorted by those
/// corners: the same surface in another face order, or with its faces
/// started at other corners, is then the same input to OpenVDB
/// (docs/meshes.md, "The same mesh in another face order"). Degenerate
/// triangles are not handed over.
class MeshAdapter {
public:
    MeshAdapter(const TriangleMesh& mesh, const VolumeGeometry& geometry)
        : mPoints(mesh.vertices.size()), mTriangle(mesh.triangles.size()) {
        const auto& v = mesh.vertices;
        const double inverseVoxelSize = 1.0 / geometry.voxelSize();
        for (std::size_t i = 0; i < v.size(); ++i)
            mPoints[i] = openvdb::Vec3s(float((v[i][0] - geometry.origin[0]) * inverseVoxelSize),
                                        float((v[i][1] - geometry.origin[1]) * inverseVoxelSize),
                                        float((v[i][2] - geometry.origin[2]) * inverseVoxelSize));
        std::vector<std::uint8_t> firstCorner(mesh.triangles.size());
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
            firstCorner[t] = std::uint8_t(smallestCorner(mesh, t));
        std::iota(mTriangle.begin(), mTriangle.end(), 0u);
        // Degenerate triangles bound nothing; OpenVDB rasterises one as the
        // segment it is (MeshCheck.h degenerateTriangles).
        const std::vector<char> degenerate = degenerateTriangles(mesh);
        mTriangle.erase(std::remove_if(mTriangle.begin(), mTriangle.end(),
                                       [&](std::uint32_t t) { return degenerate[t] != 0; }),
                        mTriangle.end());
        auto corner = [&](std::uint32_t t, std::size_t k) -> const std::array<double, 3>& {
            return v[mesh.triangles[t][(k + firstCorner[t]) % 3]];
        };
        // Stable: triangles with the same corners in the same winding are
        // the same input to OpenVDB whichever comes first.
        std::stable_sort(mTriangle.begin(), mTriangle.end(), [&](std::uint32_t a, std::uint32_t b) {
            for (std::size_t k = 0; k < 3; ++k)
                if (corner(a, k) != corner(b, k)) return corner(a, k) < corner(b, k);
            return false;
        });
        mPolygons.resize(mTriangle.size());
        for (std::size_t p = 0; p < mTriangle.size(); ++p) {
            const std::uint32_t t = mTriangle[p];
            const auto& tri = mesh.triangles[t];
            mPolygons[p] = openvdb::Vec3I(tri[firstCorner[t]], tri[(firstCorner[t] + 1) % 3],
                                          tri[(firstCorner[t] + 2) % 3]);
        }
    }
    /// What meshToVolume reads (it keeps references to this object's arrays).
    openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> vdbAdapter() const {
        return {mPoints, mPolygons};
    }
    /// The mesh's index of the triangle handed over as `polygon`.
    std::uint32_t triangleOf(std::size_t polygon) const { return mTriangle[polygon]; }

private:
    std::vector<openvdb::Vec3s> mPoints;    // per vertex of the mesh, index space
    std::vector<openvdb::Vec3I> mPolygons;  // per polygon handed over
    std::vector<std::uint32_t> mTriangle;   // per polygon handed over: the mesh's triangle
};

/// Forwards OpenVDB's interrupter calls to ours (stage names are ours).
class VdbInterrupter final : public openvdb::util::NullInterrupter {
public:
    explicit VdbInterrupter(Interrupter& interrupter) : mInterrupter(interrupter) {}
    void start(const char* = nullptr) override {}
    void end() override {}
    bool wasInterrupted(int percent = -1) override {
        if (mInterrupter.wasInterrupted(percent < 0 ? -1.0 : 0.8 * percent / 100.0))
            mStopped = true;
        return mStopped;
    }
    /// Throws if OpenVDB was told to stop: its result is then incomplete,
    /// whatever our interrupter would answer now.
    void throwIfStopped() {
        if (mStopped) throwInterrupted(mInterrupter);
    }

private:
    Interrupter& mInterrupter;
    std::atomic<bool> mStopped{false};
};

/// The length OpenVDB's distances are measured in. MeshAdapter hands it
/// index-space points, so the transform only scales the distances: world
/// units where OpenVDB holds the grid (vdbCanHoldVoxelVolume: it refuses
/// voxels whose volume is below 3e-15, e.g. a 1 mm part modelled in metres at
/// resolution 256), voxel units (1) where it does not or where float
/// distances would overflow (huge voxels). (Voxel units everywhere would
/// round a few distances differently and move single voxels on ordinary
/// meshes.)
double vdbDistanceUnit(const VoxelGrid& grid) {
    const double size = grid.geometry.voxelSize();
    const bool worldUnits = size <= 1e30 && vdbCanHoldVoxelVolume(grid.dims, grid.geometry);
    return worldUnits ? size : 1.0;
}

openvdb::math::Transform::Ptr transformFor(const VoxelGrid& grid) {
    const double unit = vdbDistanceUnit(grid);
    auto transform = openvdb::math::Transform::createLinearTransform(unit);
    if (unit == grid.geometry.voxelSize())
        transform->postTranslate(openvdb::Vec3d(grid.geometry.origin[0], grid.geometry.origin[1],
                                                grid.geometry.origin[2]));
    return transform;
}

/// Calls visit(x, y, z, value) for every voxel of the box [offset, offset+dims)
/// of `grid`, a z-slab per task. Whole 8-voxel runs inside one OpenVDB leaf
/// are read from the leaf, runs without a leaf from one tile lookup.
/// @throw InterruptedError when asked to stop.
template <typename Grid, typename Visit>
void forEachGridValue(const Grid& grid, const Dims& dims, const std::array<int, 3>& offset,
                      Interrupter& interrupter, Visit visit) {
    std::atomic<bool> stop{false};
    tbb::parallel_for(
        tbb::blocked_range<int>(0, dims.z), [&](const tbb::blocked_range<int>& slabs) {
            auto accessor = grid.getConstAccessor();
            for (int z = slabs.begin(); z < slabs.end(); ++z) {
                if (stop.load(std::memory_order_relaxed)) return;
                if (interrupter.wasInterrupted(0.8 + 0.1 * z / dims.z)) {
                    stop = true;
                    return;
                }
                for (int y = 0; y < dims.y; ++y) {
                    int x = 0;
                    while (x < dims.x) {
                        const openvdb::Coord coord(x + offset[0], y + offset[1], z + offset[2]);
                        // Length of the run up to the next leaf boundary (leaves are 8 wide).
                        // (* 8, not << 3: coordinates can be negative, and shifting a
                        // negative value left is undefined before C++20.)
                        const int leafEnd = ((coord.x() >> 3) + 1) * 8;
                        const int runLength = std::min(leafEnd - coord.x(), dims.x - x);
                        if (const auto* leaf = accessor.probeConstLeaf(coord)) {
                            for (int i = 0; i < runLength; ++i)
                                visit(x + i, y, z, leaf->getValue(coord.offsetBy(i, 0, 0)));
                        } else {
                            const auto value = accessor.getValue(coord);
                            for (int i = 0; i < runLength; ++i) visit(x + i, y, z, value);
                        }
                        x += runLength;
                    }
                }
            }
        });
    if (stop) throwInterrupted(interrupter);
}

/// nearestTriangle: when not null, filled with the index of the triangle
/// nearest to each voxel of the narrow band (-1 elsewhere).
MaskVolume signedVoxelization(const TriangleMesh& mesh, const VoxelGrid& grid, double bandWidth,
                              Interrupter& interrupter,
                              std::vector<std::int32_t>* nearestTriangle = nullptr) {
    VdbInterrupter vdbInterrupter(interrupter);
    const MeshAdapter adapter(mesh, grid.geometry);
    // A narrow band of 2 voxels is enough: only the sign is used; the deep
    // inside is filled with negative tiles by OpenVDB's sign flood fill. It
    // also covers every voxel a contact between two surfaces can involve.
    // Background -1: voxels OpenVDB gives no triangle (deep inside, far
    // outside) read as "unknown" rather than as triangle 0.
    openvdb::Int32Grid polygonIndex(-1);
    // Without OpenVDB's removal of "self-intersecting" voxels: where two
    // walls of the mesh are less than a voxel apart, it switches off every
    // band voxel between them that has no boundary neighbour and prunes
    // the leaves left empty, polygon index included. A contact across the
    // middle of an 8^3 leaf then has no nearest triangles, and the contact
    // separation cannot see it (docs/meshes.md, "Contacts across whole
    // OpenVDB leaves"). The sign of every voxel came out the same on every
    // mesh measured there.
    auto distance = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
        static_cast<openvdb::util::NullInterrupter&>(vdbInterrupter), adapter.vdbAdapter(),
        *transformFor(grid), float(bandWidth), float(bandWidth),
        openvdb::tools::DISABLE_INTERSECTING_VOXEL_REMOVAL,
        nearestTriangle ? &polygonIndex : nullptr);
    vdbInterrupter.throwIfStopped();
    if (nearestTriangle) {
        // Outside the band the index grid holds its background; voxels whose
        // distance OpenVDB did not compute get -1.
        assignWithHugePages(*nearestTriangle, grid.dims.voxelCount(), -1);
        const std::int32_t polygons = std::int32_t(mesh.triangles.size());
        std::int32_t* out = nearestTriangle->data();
        const Dims dims = grid.dims;
        forEachGridValue(polygonIndex, dims, {0, 0, 0}, interrupter,
                         [&](int x, int y, int z, std::int32_t value) {
                             if (value >= 0 && value < polygons)
                                 out[std::size_t(x) +
                                     std::size_t(dims.x) *
                                         (std::size_t(y) + std::size_t(dims.y) * std::size_t(z))] =
                                     std::int32_t(adapter.triangleOf(std::size_t(value)));
                         });
    }
    MaskVolume mask(grid.dims, 0);
    mask.geometry = grid.geometry;
    std::uint8_t* out = mask.data();
    const Dims dims = grid.dims;
    forEachGridValue(
        *distance, dims, {0, 0, 0}, interrupter, [&](int x, int y, int z, float value) {
            out[std::size_t(x) +
                std::size_t(dims.x) * (std::size_t(y) + std::size_t(dims.y) * std::size_t(z))] =
                value < 0.0f ? 1 : 0;
        });
    return mask;
}

/// The shell pass works on a grid padded so that its border lies outside the
/// thick shell, whatever the margin: the flood fill starts from that border.
int shellPadding(double holeClosing) {
    return int(std::ceil(holeClosing + kSurfaceLayer)) + 2;
}

Dims paddedShellGrid(const Dims& dims, double holeClosing) {
    const int pad = shellPadding(holeClosing);
    return {dims.x + 2 * pad, dims.y + 2 * pad, dims.z + 2 * pad};
}

/// The shell method (see the header). surfaceVoxels: how many voxels of the
/// result lie in the half-voxel surface layer; enclosedVoxels: how many lie
/// farther than the shell from the surface and out of the flood fill's reach,
/// i.e. an inside the shell sealed off.
MaskVolume shellVoxelization(const TriangleMesh& mesh, const VoxelGrid& grid, double holeClosing,
                             Interrupter& interrupter, std::size_t& surfaceVoxels,
                             std::size_t& enclosedVoxels) {
    VdbInterrupter vdbInterrupter(interrupter);
    const MeshAdapter adapter(mesh, grid.geometry);
    const double shellWidth = holeClosing + kSurfaceLayer;
    auto distance = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
        static_cast<openvdb::util::NullInterrupter&>(vdbInterrupter), adapter.vdbAdapter(),
        *transformFor(grid), float(shellWidth + 1.5), 0.0f,
        openvdb::tools::UNSIGNED_DISTANCE_FIELD);
    vdbInterrupter.throwIfStopped();

    const int pad = shellPadding(holeClosing);
    const Dims work = paddedShellGrid(grid.dims, holeClosing);
    if (work.voxelCount() > kMaxVoxels)
        throw UsageError("the padded voxel grid for an open mesh is over the limit of " +
                         std::to_string(kMaxVoxels) + " voxels; lower the resolution");
    auto at = [&](int x, int y, int z) {
        return std::size_t(x) +
               std::size_t(work.x) * (std::size_t(y) + std::size_t(work.y) * std::size_t(z));
    };
    enum : std::uint8_t { kFree = 0, kShell = 1, kSurface = 2, kOutside = 3 };
    std::vector<std::uint8_t> state(work.voxelCount(), kFree);
    const float voxelSize = float(vdbDistanceUnit(grid));
    const float shellLimit = float(shellWidth) * voxelSize,
                surfaceLimit = float(kSurfaceLayer) * voxelSize;
    forEachGridValue(*distance, work, {-pad, -pad, -pad}, interrupter,
                     [&](int x, int y, int z, float value) {
                         state[at(x, y, z)] = value <= surfaceLimit ? kSurface
                                              : value <= shellLimit ? kShell
                                                                    : kFree;
                     });
    distance.reset();

    // Flood the outside from the border through free voxels (6-connected).
    std::vector<std::uint32_t> frontier, next;
    auto visitNeighbours = [&](std::uint32_t index, auto&& onNeighbour) {
        const int x = int(index % std::uint32_t(work.x));
        const int y = int((index / std::uint32_t(work.x)) % std::uint32_t(work.y));
        const int z = int(index / (std::uint32_t(work.x) * std::uint32_t(work.y)));
        if (x > 0) onNeighbour(index - 1);
        if (x + 1 < work.x) onNeighbour(index + 1);
        if (y > 0) onNeighbour(index - std::uint32_t(work.x));
        if (y + 1 < work.y) onNeighbour(index + std::uint32_t(work.x));
        if (z > 0) onNeighbour(index - std::uint32_t(work.x) * std::uint32_t(work.y));
        if (z + 1 < work.z) onNeighbour(index + std::uint32_t(work.x) * std::uint32_t(work.y));
    };
    frontier.push_back(0);  // a corner: free because of the padding
    state[0] = kOutside;
    std::size_t visited = 0;
    while (!frontier.empty()) {
        const std::uint32_t index = frontier.back();
        frontier.pop_back();
        if (++visited % (1u << 20) == 0) throwIfInterrupted(interrupter);
        visitNeighbours(index, [&](std::uint32_t neighbour) {
            if (state[neighbour] == kFree) {
                state[neighbour] = kOutside;
                frontier.push_back(neighbour);
            }
        });
    }

    // Grow the outside back towards the surface, one voxel per step, at most
    // holeClosing + 1 steps, never into the surface layer: this undoes the
    // thickening where the shell was closed, and can leak only a few voxels
    // through a hole that was too wide to bridge.
    for (std::size_t i = 0; i < state.size(); ++i)
        if (state[i] == kOutside) {
            bool nearShell = false;
            visitNeighbours(std::uint32_t(i),
                            [&](std::uint32_t n) { nearShell |= state[n] == kShell; });
            if (nearShell) frontier.push_back(std::uint32_t(i));
        }
    const int growSteps = int(std::ceil(holeClosing)) + 1;
    for (int step = 0; step < growSteps && !frontier.empty(); ++step) {
        throwIfInterrupted(interrupter);
        next.clear();
        for (std::uint32_t index : frontier)
            visitNeighbours(index, [&](std::uint32_t neighbour) {
                if (state[neighbour] == kShell) {
                    state[neighbour] = kOutside;
                    next.push_back(neighbour);
                }
            });
        frontier.swap(next);
    }

    MaskVolume mask(grid.dims, 0);
    mask.geometry = grid.geometry;
    surfaceVoxels = 0;
    enclosedVoxels = 0;
    for (int z = 0; z < grid.dims.z; ++z)
        for (int y = 0; y < grid.dims.y; ++y)
            for (int x = 0; x < grid.dims.x; ++x) {
                const std::uint8_t s = state[at(x + pad, y + pad, z + pad)];
                mask(x, y, z) = s == kOutside ? 0 : 1;
                surfaceVoxels += s == kSurface;
                enclosedVoxels += s == kFree;
            }
    return mask;
}

}  // namespace

double widestHoleClosing(int resolution) {
    return std::min(48.0, std::max(16.0, double(resolution) / 12.0));
}

VoxelGrid voxelGridFor(const TriangleMesh& mesh, const VoxelizeOptions& options) {
    if (options.resolution < 8 || options.resolution > 2048)
        throw UsageError("voxel resolution " + std::to_string(options.resolution) +
                         " is outside [8, 2048]");
    if (options.margin < 0 || options.margin > 64)
        throw UsageError("voxel margin " + std::to_string(options.margin) + " is outside [0, 64]");
    if (!(options.holeClosing >= 0.0 && options.holeClosing <= 16.0))
        throw UsageError("hole closing " + std::to_string(options.holeClosing) +
                         " is outside [0, 16] voxels");
    if (!(options.bandWidth >= 1.0 && options.bandWidth <= 4.0))
        throw UsageError("distance band width " + std::to_string(options.bandWidth) +
                         " is outside [1, 4] voxels");
    if (mesh.vertices.empty() || mesh.triangles.empty())
        throw UsageError("cannot voxelise a mesh without faces");

    // Bounding box of the vertices that faces use (stray vertices do not count).
    const VertexBox box = usedVertexBox(mesh);
    const std::array<double, 3>& low = box.low;
    const std::array<double, 3>& high = box.high;
    const double longest = std::max({high[0] - low[0], high[1] - low[1], high[2] - low[2]});
    if (longest == 0.0)
        throw UsageError(
            "cannot voxelise the mesh: the vertices its faces use all lie at one point (no face "
            "has an area)");
    // Squared lengths and areas (mesh checks, contacts, face labels) must
    // neither overflow nor underflow a double: 1e-100..1e100 keeps them
    // far inside, in any unit of length anyone uses.
    if (!(longest >= 1e-100 && longest <= 1e100)) {
        char side[32];
        std::snprintf(side, sizeof side, "%g", longest);
        throw UsageError("cannot voxelise the mesh: its bounding box (longest side " +
                         std::string(side) + ") is too " + (longest < 1.0 ? "small" : "large") +
                         " (1e-100 to 1e100 are supported)");
    }
    const double voxelSize = longest / options.resolution;

    std::int64_t extents[3];
    std::array<double, 3> origin{};
    for (std::size_t c = 0; c < 3; ++c) {
        // The 1e-9 keeps the longest axis at exactly `resolution` voxels
        // despite rounding in longest / resolution * resolution.
        const std::int64_t inner = std::max<std::int64_t>(
            1, std::int64_t(std::ceil((high[c] - low[c]) / voxelSize - 1e-9)));
        extents[c] = inner + 2 * options.margin;
        // Centre the shape: the grid's middle is the box's middle; origin is
        // the centre of voxel 0.
        origin[c] =
            0.5 * (low[c] + high[c]) - 0.5 * double(extents[c]) * voxelSize + 0.5 * voxelSize;
    }
    const std::uint64_t voxels =
        std::uint64_t(extents[0]) * std::uint64_t(extents[1]) * std::uint64_t(extents[2]);
    if (voxels > kMaxVoxels)
        throw UsageError("voxel resolution " + std::to_string(options.resolution) + " gives a " +
                         std::to_string(extents[0]) + "x" + std::to_string(extents[1]) + "x" +
                         std::to_string(extents[2]) + " grid, over the limit of " +
                         std::to_string(kMaxVoxels) + " voxels");
    VoxelGrid grid;
    grid.dims = Dims{int(extents[0]), int(extents[1]), int(extents[2])};
    grid.geometry = VolumeGeometry::uniform(voxelSize, origin);
    // The rule every volume reader applies to its header: a mesh far from
    // the origin for its size would give voxels whose world coordinates,
    // and so the outputs' placement, round together.
    if (const std::string problem = grid.geometry.problemOver(grid.dims); !problem.empty())
        throw UsageError("cannot voxelise the mesh at resolution " +
                         std::to_string(options.resolution) + ": " + problem +
                         " (move the mesh nearer the origin)");
    return grid;
}

MaskVolume voxelizeMesh(const TriangleMesh& mesh, const VoxelizeOptions& options,
                        Interrupter& interrupter) {
    return voxelizeMeshWithContacts(mesh, options, interrupter).mask;
}

namespace {

MaskVolume copyOfMask(const MaskVolume& mask) {
    MaskVolume copy(mask.dims(), 0);
    copy.geometry = mask.geometry;
    std::copy(mask.values().begin(), mask.values().end(), copy.values().begin());
    return copy;
}

bool sameGeometry(const VolumeGeometry& a, const VolumeGeometry& b) {
    return a.origin == b.origin && a.directions == b.directions && a.spaceName == b.spaceName;
}

}  // namespace

bool SignedVoxelization::fits(const TriangleMesh& forMesh, const VoxelGrid& grid,
                              const VoxelizeOptions& options) const noexcept {
    return mesh == &forMesh && !mask.empty() && dims == grid.dims &&
           sameGeometry(geometry, grid.geometry) && bandWidth == options.bandWidth &&
           (!options.keepMeshTopology || nearestTriangle.size() == grid.dims.voxelCount());
}

MeshVoxelization voxelizeMeshWithContacts(const TriangleMesh& mesh, const VoxelizeOptions& options,
                                          Interrupter& interrupter,
                                          SignedVoxelization* signedVoxels) {
    const VoxelGrid grid = voxelGridFor(mesh, options);
    InterrupterScope scope(interrupter, "voxelize");
    openvdb::initialize();
    const bool closed = options.meshIsClosed ? *options.meshIsClosed : checkMesh(mesh).closed;
    throwIfInterrupted(interrupter, 0.0);

    MaskVolume mask;
    ContactSeparation contacts;
    SelfOverlapSeparation selfOverlaps;
    ThinPartFill thinParts;
    std::vector<ObjectSource> objectSources;
    // OpenVDB's tools have no serial switch; a one-thread arena makes every
    // TBB loop inside (theirs and ours) run on this thread. Threaded, the
    // arena is as wide as the caller's, so a caller's thread limit holds.
    // Pooled: oneTBB leaks a wider arena created in a busy task (ArenaPool.h).
    const ArenaPool::Lease arena = ArenaPool::process().acquire(
        options.threaded ? tbb::this_task_arena::max_concurrency() : 1);
    arena.arena().execute([&] {
        std::vector<std::int32_t> ownTriangles;  // the nearest triangles when nobody keeps them
        const std::vector<std::int32_t>* nearestTriangle = &ownTriangles;
        bool hasInside = false;
        if (closed && signedVoxels && signedVoxels->fits(mesh, grid, options)) {
            mask = copyOfMask(signedVoxels->mask);
            nearestTriangle = &signedVoxels->nearestTriangle;
            hasInside = true;  // kept only when it had one
        } else if (closed) {
            mask = signedVoxelization(mesh, grid, options.bandWidth, interrupter,
                                      options.keepMeshTopology ? &ownTriangles : nullptr);
            // The sign computation can fail on badly broken "closed" meshes
            // (nothing comes out inside): fall back to the shell method.
            hasInside = std::find(mask.values().begin(), mask.values().end(), std::uint8_t(1)) !=
                        mask.values().end();
            if (signedVoxels) {
                *signedVoxels = SignedVoxelization{};
                if (hasInside) {
                    signedVoxels->mesh = &mesh;
                    signedVoxels->dims = grid.dims;
                    signedVoxels->geometry = grid.geometry;
                    signedVoxels->bandWidth = options.bandWidth;
                    signedVoxels->mask = copyOfMask(mask);
                    signedVoxels->nearestTriangle = std::move(ownTriangles);
                    nearestTriangle = &signedVoxels->nearestTriangle;
                }
            }
        }
        if (hasInside) {
            if (options.fillThinParts) {
                ThinPartOptions thinOptions = options.thinPartOptions;
                thinOptions.threaded = options.threaded;
                thinParts = fillThinParts(mesh, mask, thinOptions, interrupter);
            }
            if (options.keepMeshTopology) {
                // First: the walls of a part sunk into another cross
                // instead of facing each other, which the contact tests
                // would misread.
                SelfOverlapOptions overlapOptions = options.selfOverlapOptions;
                overlapOptions.threaded = options.threaded;
                selfOverlaps = separateSelfOverlaps(mesh, mask, overlapOptions, interrupter);
                ContactSeparationOptions contactOptions = options.contactOptions;
                contactOptions.threaded = options.threaded;
                contacts =
                    separateContacts(mesh, mask, *nearestTriangle, contactOptions, interrupter);
                objectSources =
                    voxelObjectPieces(mesh, mask, *nearestTriangle, options.threaded, interrupter);
            }
            return;
        }
        // A hole wider than the closing lets the flood fill in, and leaves
        // little more than the surface layer: retry with twice the closing
        // (up to widestHoleClosing) while the result is that hollow. "Little more"
        // alone is not enough from a closing of 4 on: the 6-connected growth
        // back eats only (closing + 1) / sqrt(3) voxels of the shell where
        // the surface runs diagonally, and that residue can pass for an
        // inside (the open Stanford bunny at 192 came out a hollow shell 3
        // voxels thick at 8). So a result whose shell sealed off an inside
        // is taken at once; otherwise the first that is not that hollow,
        // unless a wider closing seals an inside.
        std::optional<MaskVolume> notHollow;
        const double widest = widestHoleClosing(options.resolution);
        for (double closing = options.holeClosing;;) {
            std::size_t surfaceVoxels = 0, enclosedVoxels = 0;
            mask =
                shellVoxelization(mesh, grid, closing, interrupter, surfaceVoxels, enclosedVoxels);
            if (enclosedVoxels > surfaceVoxels / 100) return;
            const auto solid = std::size_t(
                std::count(mask.values().begin(), mask.values().end(), std::uint8_t(1)));
            if (!notHollow && solid > 2 * surfaceVoxels) {
                // The first closing is the reference for thin shapes, which
                // have no inside beyond the shell at any closing.
                if (closing == options.holeClosing) return;
                notHollow = std::move(mask);
            }
            // The last step is taken only where it widens the closing by a
            // quarter or more (32 -> 33.3 at resolution 400 would repeat a
            // pass), and only on a padded grid within the voxel limit (a
            // wider closing is no reason to refuse what narrower ones made).
            const double next = std::min(widest, std::max(1.0, 2.0 * closing));
            if (closing >= widest || (next == widest && widest < 1.25 * closing) ||
                paddedShellGrid(grid.dims, next).voxelCount() > kMaxVoxels)
                break;
            closing = next;
        }
        if (notHollow) mask = std::move(*notHollow);
    });
    throwIfInterrupted(interrupter, 1.0);
    return MeshVoxelization{std::move(mask), contacts, selfOverlaps, thinParts,
                            std::move(objectSources)};
}

WorldToIndex::WorldToIndex(const VolumeGeometry& geometry) : mOrigin(geometry.origin) {
    // Columns of M are the step vectors: world = origin + M * index.
    const auto& d = geometry.directions;
    const double m[3][3] = {
        {d[0][0], d[1][0], d[2][0]}, {d[0][1], d[1][1], d[2][1]}, {d[0][2], d[1][2], d[2][2]}};
    const double cofactor[3][3] = {
        {m[1][1] * m[2][2] - m[1][2] * m[2][1], m[1][2] * m[2][0] - m[1][0] * m[2][2],
         m[1][0] * m[2][1] - m[1][1] * m[2][0]},
        {m[0][2] * m[2][1] - m[0][1] * m[2][2], m[0][0] * m[2][2] - m[0][2] * m[2][0],
         m[0][1] * m[2][0] - m[0][0] * m[2][1]},
        {m[0][1] * m[1][2] - m[0][2] * m[1][1], m[0][2] * m[1][0] - m[0][0] * m[1][2],
         m[0][0] * m[1][1] - m[0][1] * m[1][0]}};
    const double determinant =
        m[0][0] * cofactor[0][0] + m[0][1] * cofactor[0][1] + m[0][2] * cofactor[0][2];
    mValid = std::isfinite(determinant) && std::abs(determinant) > 0.0;
    const double inverseDeterminant =
        mValid ? 1.0 / determinant : std::numeric_limits<double>::quiet_NaN();
    // inverse = adjugate / det, adjugate = cofactor transposed.
    for (std::size_t r = 0; r < 3; ++r)
        for (std::size_t c = 0; c < 3; ++c) mInverse[r][c] = cofactor[c][r] * inverseDeterminant;
}

std::array<double, 3> WorldToIndex::operator()(const std::array<double, 3>& world) const noexcept {
    const double p[3] = {world[0] - mOrigin[0], world[1] - mOrigin[1], world[2] - mOrigin[2]};
    std::array<double, 3> index{};
    for (std::size_t r = 0; r < 3; ++r)
        index[r] = mInverse[r][0] * p[0] + mInverse[r][1] * p[1] + mInverse[r][2] * p[2];
    return index;
}

std::array<double, 3> worldToIndex(const VolumeGeometry& geometry,
                                   const std::array<double, 3>& world) {
    return WorldToIndex(geometry)(world);
}

Coord voxelContaining(const VolumeGeometry& geometry, const std::array<double, 3>& world) {
    const auto index = worldToIndex(geometry, world);
    // Clamped so that far-away (or NaN) points give a valid, outside Coord.
    auto rounded = [](double value) {
        const double r = std::floor(value + 0.5);
        return r >= -1e9 && r <= 1e9 ? int(r) : (r > 0 ? 1000000000 : -1000000000);
    };
    return Coord{rounded(index[0]), rounded(index[1]), rounded(index[2])};
}

}  // namespace skelseg
