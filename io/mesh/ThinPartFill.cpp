#include "io/mesh/ThinPartFill.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <utility>
#include <vector>

#include "io/mesh/MeshOrientation.h"
#include "io/mesh/Vec3Arithmetic.h"
#include "kernels/base/ParallelFor.h"

namespace skelseg {

namespace {

using vec3::cross;
using vec3::dot;
using vec3::sub;
using vec3::Vec3;

/// Side of the cubic cells the triangles are binned in (voxels). Rays are at
/// most maxThickness long, so one ray looks at a few cells.
constexpr double kCellSize = 2.0;
/// Voxels added on every side of a ray's box before its cells are listed.
constexpr double kCellPadding = 1e-6;

/// Triangles by cell: the cells each triangle's bounding box overlaps, as a
/// sorted list of occupied cells with their triangles (CSR).
class TriangleBins {
public:
    TriangleBins(const CanonicalSurface& surface, bool threaded) {
        std::vector<std::vector<std::pair<std::uint64_t, std::uint32_t>>> perChunk;
        std::mutex lock;
        parallelFor(
            surface.triangles.size(),
            [&](std::size_t begin, std::size_t end) {
                std::vector<std::pair<std::uint64_t, std::uint32_t>> entries;
                for (std::size_t t = begin; t < end; ++t) {
                    const auto& c = surface.triangles[t];
                    std::array<std::int64_t, 3> low{}, high{};
                    for (std::size_t a = 0; a < 3; ++a) {
                        double lo = HUGE_VAL, hi = -HUGE_VAL;
                        for (std::uint32_t v : c) {
                            lo = std::min(lo, surface.points[v][a]);
                            hi = std::max(hi, surface.points[v][a]);
                        }
                        low[a] = cellOf(lo);
                        high[a] = cellOf(hi);
                    }
                    const std::int64_t boxCells =
                        (high[0] - low[0] + 1) * (high[1] - low[1] + 1) * (high[2] - low[2] + 1);
                    if (boxCells <= 27) {
                        for (std::int64_t z = low[2]; z <= high[2]; ++z)
                            for (std::int64_t y = low[1]; y <= high[1]; ++y)
                                for (std::int64_t x = low[0]; x <= high[0]; ++x)
                                    entries.emplace_back(key(x, y, z), std::uint32_t(t));
                        continue;
                    }
                    // A large triangle: its bounding box can hold far more
                    // cells than the triangle touches. Every point of the
                    // triangle lies within a cell of a sample at most one
                    // cell apart, so the cells around the samples cover it.
                    const auto &a = surface.points[c[0]], &b = surface.points[c[1]],
                               &e = surface.points[c[2]];
                    double longest = 0.0;
                    for (std::size_t k = 0; k < 3; ++k)
                        longest = std::max({longest, std::abs(b[k] - a[k]), std::abs(e[k] - b[k]),
                                            std::abs(a[k] - e[k])});
                    const int m = std::max(1, int(std::ceil(2.0 * longest / kCellSize)));
                    // Samples are at most half a cell apart, so several
                    // share a cell: their cells are made unique before the
                    // 27 around each are listed.
                    std::vector<std::uint64_t> sampleCells, cells;
                    for (int i = 0; i <= m; ++i)
                        for (int j = 0; i + j <= m; ++j) {
                            const double u = double(i) / m, v = double(j) / m;
                            std::array<std::int64_t, 3> cell{};
                            for (std::size_t k = 0; k < 3; ++k)
                                cell[k] = cellOf(a[k] + u * (b[k] - a[k]) + v * (e[k] - a[k]));
                            sampleCells.push_back(key(cell[0], cell[1], cell[2]));
                        }
                    std::sort(sampleCells.begin(), sampleCells.end());
                    sampleCells.erase(std::unique(sampleCells.begin(), sampleCells.end()),
                                      sampleCells.end());
                    for (std::uint64_t centre : sampleCells) {
                        const std::int64_t cx = std::int64_t(centre & kKeyMask),
                                           cy = std::int64_t((centre >> 21) & kKeyMask),
                                           cz = std::int64_t(centre >> 42);
                        for (std::int64_t z = -1; z <= 1; ++z)
                            for (std::int64_t y = -1; y <= 1; ++y)
                                for (std::int64_t x = -1; x <= 1; ++x)
                                    cells.push_back(key(cx + x, cy + y, cz + z));
                    }
                    std::sort(cells.begin(), cells.end());
                    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
                    for (std::uint64_t cell : cells) entries.emplace_back(cell, std::uint32_t(t));
                }
                std::lock_guard<std::mutex> guard(lock);
                perChunk.push_back(std::move(entries));
            },
            threaded, 4096);
        std::vector<std::pair<std::uint64_t, std::uint32_t>> entries;
        for (auto& chunk : perChunk) entries.insert(entries.end(), chunk.begin(), chunk.end());
        std::sort(entries.begin(), entries.end());
        for (std::size_t i = 0; i < entries.size(); ++i) {
            if (i == 0 || entries[i].first != entries[i - 1].first) {
                mKeys.push_back(entries[i].first);
                mFirst.push_back(std::uint32_t(i));
            }
            mTriangles.push_back(entries[i].second);
        }
        mFirst.push_back(std::uint32_t(entries.size()));
    }

    static std::int64_t cellOf(double coordinate) {
        // Index-space coordinates of the mesh are above -1 (margin >= 0), so
        // the shifted cells (and their neighbours) are positive.
        return std::int64_t(std::floor(coordinate / kCellSize)) + 2;
    }
    static constexpr std::uint64_t kKeyMask = (std::uint64_t(1) << 21) - 1;
    static std::uint64_t key(std::int64_t x, std::int64_t y, std::int64_t z) {
        return std::uint64_t(x) | (std::uint64_t(y) << 21) | (std::uint64_t(z) << 42);
    }

    /// Calls visit(triangle) for every triangle of the cell (a triangle in
    /// several cells is visited once per cell).
    template <typename Visit>
    void forEachInCell(std::int64_t x, std::int64_t y, std::int64_t z, Visit&& visit) const {
        const auto it = std::lower_bound(mKeys.begin(), mKeys.end(), key(x, y, z));
        if (it == mKeys.end() || *it != key(x, y, z)) return;
        const std::size_t cell = std::size_t(it - mKeys.begin());
        for (std::uint32_t k = mFirst[cell]; k < mFirst[cell + 1]; ++k) visit(mTriangles[k]);
    }

private:
    std::vector<std::uint64_t> mKeys;
    std::vector<std::uint32_t> mFirst, mTriangles;
};

/// A triangle a ray may meet, with its plane put in the ray's terms: the
/// ray origin + s * direction meets the plane at s = offset - dot(slope,
/// origin). `planeTest` is false where the ray runs almost along the plane,
/// where that quotient says little.
struct ListedTriangle {
    std::uint32_t triangle = 0;
    bool planeTest = false;
    Vec3 slope{0, 0, 0};
    double offset = 0.0;
};

/// Rays whose direction makes a cosine below this with a triangle's plane
/// normal are tested against the triangle itself, never rejected by plane.
constexpr double kPlaneTestCosine = 1e-3;
/// How far outside (0, reach] the plane distance must lie to reject a
/// triangle without the exact test: far above the rounding of either
/// distance, so the rejected triangles are exactly those the exact test
/// would reject.
constexpr double kPlaneTestSlack = 1e-6;

/// Distance along the ray origin + t * direction to triangle (a, b, c), or a
/// negative value when the ray misses it (Moller and Trumbore's test).
double rayHit(const Vec3& origin, const Vec3& direction, const Vec3& a, const Vec3& b,
              const Vec3& c) {
    const Vec3 e1 = sub(b, a), e2 = sub(c, a);
    const Vec3 p = cross(direction, e2);
    const double determinant = dot(e1, p);
    if (std::abs(determinant) < 1e-14) return -1.0;
    const double inverse = 1.0 / determinant;
    const Vec3 s = sub(origin, a);
    const double u = dot(s, p) * inverse;
    if (u < 0.0 || u > 1.0) return -1.0;
    const Vec3 q = cross(s, e1);
    const double v = dot(direction, q) * inverse;
    if (v < 0.0 || u + v > 1.0) return -1.0;
    return dot(e2, q) * inverse;
}

ListedTriangle listTriangle(const CanonicalSurface& surface, const std::vector<Vec3>& planeNormal,
                            std::uint32_t triangle, const Vec3& direction) {
    ListedTriangle listed;
    listed.triangle = triangle;
    const Vec3& n = planeNormal[triangle];
    const double cosine = dot(n, direction);
    if (std::abs(cosine) < kPlaneTestCosine) return listed;
    listed.planeTest = true;
    listed.slope = {n[0] / cosine, n[1] / cosine, n[2] / cosine};
    listed.offset = dot(n, surface.points[surface.triangles[triangle][0]]) / cosine;
    return listed;
}

}  // namespace

ThinPartFill fillThinParts(const TriangleMesh& mesh, MaskVolume& mask,
                           const ThinPartOptions& options, Interrupter& interrupter) {
    ThinPartFill result;
    if (mesh.triangles.empty() || mask.empty()) return result;
    const CanonicalSurface surface = canonicalSurface(mesh, mask.geometry);
    const std::vector<std::int8_t> orientation =
        triangleOrientation(surface.triangles, surface.points, surface.piece);
    throwIfInterrupted(interrupter);
    // Unit plane normals (zero without area), for the plane test of
    // ListedTriangle, and the outward normals (zero where the side is
    // unknown too).
    std::vector<Vec3> planeNormal(surface.triangles.size(), Vec3{0, 0, 0});
    std::vector<Vec3> outward(surface.triangles.size(), Vec3{0, 0, 0});
    parallelForEach(
        surface.triangles.size(),
        [&](std::size_t t) {
            const auto& c = surface.triangles[t];
            const Vec3 n = cross(sub(surface.points[c[1]], surface.points[c[0]]),
                                 sub(surface.points[c[2]], surface.points[c[0]]));
            const double length = std::sqrt(dot(n, n));
            if (length == 0.0) return;
            planeNormal[t] = {n[0] / length, n[1] / length, n[2] / length};
            if (orientation[t] != 0)
                outward[t] = {orientation[t] * planeNormal[t][0],
                              orientation[t] * planeNormal[t][1],
                              orientation[t] * planeNormal[t][2]};
        },
        options.threaded, 4096);
    const TriangleBins bins(surface, options.threaded);
    throwIfInterrupted(interrupter);

    const double reach = options.maxThickness;
    const double radius = options.coverRadius;
    std::vector<std::uint32_t> filled;
    std::mutex lock;
    std::atomic<std::size_t> thinSamples{0};
    std::atomic<bool> stopped{false};
    parallelFor(
        surface.triangles.size(),
        [&](std::size_t begin, std::size_t end) {
            if (stopped || interrupter.wasInterrupted()) {
                stopped = true;
                return;
            }
            std::vector<std::uint32_t> local;
            std::vector<ListedTriangle> candidates;
            std::size_t localThin = 0;
            for (std::size_t t = begin; t < end; ++t) {
                const Vec3& normal = outward[t];
                if (normal[0] == 0 && normal[1] == 0 && normal[2] == 0) continue;
                const Vec3 direction{-normal[0], -normal[1], -normal[2]};
                // Whether `other` faces away from this triangle: only such a
                // wall can make the part thin.
                auto facesAway = [&](std::uint32_t other) {
                    return dot(normal, outward[other]) < options.opposingCosine;
                };
                const auto& c = surface.triangles[t];
                const Vec3 &a = surface.points[c[0]], &b = surface.points[c[1]],
                           &e = surface.points[c[2]];
                const double longest =
                    std::sqrt(std::max({dot(sub(b, a), sub(b, a)), dot(sub(e, b), sub(e, b)),
                                        dot(sub(a, e), sub(a, e))}));
                // Only a wall facing the other way can make the part thin: a
                // triangle with none in the cells of the box it sweeps along
                // the ray (almost every triangle of a thick part) stops here.
                {
                    std::array<std::int64_t, 3> low{}, high{};
                    for (std::size_t k = 0; k < 3; ++k) {
                        const double lo = std::min({a[k], b[k], e[k]}),
                                     hi = std::max({a[k], b[k], e[k]});
                        low[k] = TriangleBins::cellOf(std::min(lo, lo + reach * direction[k]));
                        high[k] = TriangleBins::cellOf(std::max(hi, hi + reach * direction[k]));
                    }
                    bool opposingWall = false;
                    for (std::int64_t z = low[2]; z <= high[2] && !opposingWall; ++z)
                        for (std::int64_t y = low[1]; y <= high[1] && !opposingWall; ++y)
                            for (std::int64_t x = low[0]; x <= high[0] && !opposingWall; ++x)
                                bins.forEachInCell(x, y, z, [&](std::uint32_t other) {
                                    opposingWall |= other != t && facesAway(other);
                                });
                    if (!opposingWall) continue;
                }
                // Each sample's ray, at most `reach` long, meets only
                // triangles in the one to eight cells of its own box, where
                // a large triangle's swept box holds many; neighbouring
                // samples mostly share those cells, so their list is kept.
                std::array<std::int64_t, 3> listedLow{-1, -1, -1}, listedHigh{-1, -1, -1};
                candidates.clear();
                // Whether the list holds a wall facing the other way: where
                // it does not, no hit can make the sample thin.
                bool listOpposes = true;
                // Brings the list up to the cells of the ray from `origin`.
                auto listFor = [&](const Vec3& origin) {
                    if (options.testEveryTriangle) {
                        // The reference: the exact test alone, no plane test.
                        if (candidates.empty())
                            for (std::uint32_t other = 0; other < surface.triangles.size(); ++other)
                                if (other != t) candidates.push_back({other});
                        return;
                    }
                    std::array<std::int64_t, 3> low{}, high{};
                    for (std::size_t k = 0; k < 3; ++k) {
                        // Padded: a hit on an edge may lie an ulp outside
                        // the triangle's own cells.
                        const double rayEnd = origin[k] + reach * direction[k];
                        low[k] = TriangleBins::cellOf(std::min(origin[k], rayEnd) - kCellPadding);
                        high[k] = TriangleBins::cellOf(std::max(origin[k], rayEnd) + kCellPadding);
                    }
                    if (low == listedLow && high == listedHigh) return;
                    candidates.clear();
                    for (std::int64_t z = low[2]; z <= high[2]; ++z)
                        for (std::int64_t y = low[1]; y <= high[1]; ++y)
                            for (std::int64_t x = low[0]; x <= high[0]; ++x)
                                bins.forEachInCell(x, y, z, [&](std::uint32_t other) {
                                    if (other != t)
                                        candidates.push_back(
                                            listTriangle(surface, planeNormal, other, direction));
                                });
                    listedLow = low;
                    listedHigh = high;
                    listOpposes = false;
                    for (const ListedTriangle& listed : candidates)
                        listOpposes |= facesAway(listed.triangle);
                };
                const int m = std::max(1, int(std::ceil(longest / options.sampleSpacing)));
                // Centroids of the m x m sub-triangles: (i + 1/3, j + 1/3) / m
                // for the upright ones, (i + 2/3, j + 2/3) / m for the others.
                for (int i = 0; i < m; ++i)
                    for (int j = 0; i + j < m; ++j)
                        for (int flipped = 0; flipped < 2; ++flipped) {
                            if (flipped && i + j + 1 >= m) continue;
                            const double shift = flipped ? 2.0 / 3.0 : 1.0 / 3.0;
                            const double u = (i + shift) / m, v = (j + shift) / m;
                            const Vec3 origin{a[0] + u * (b[0] - a[0]) + v * (e[0] - a[0]),
                                              a[1] + u * (b[1] - a[1]) + v * (e[1] - a[1]),
                                              a[2] + u * (b[2] - a[2]) + v * (e[2] - a[2])};
                            listFor(origin);
                            if (!listOpposes) continue;
                            // A triangle in several cells is tested once per
                            // cell; equal distances go to the lowest index,
                            // so the order of the list does not matter.
                            double nearest = HUGE_VAL;
                            std::uint32_t hit = 0;
                            for (const ListedTriangle& listed : candidates) {
                                if (listed.planeTest) {
                                    const double along = listed.offset - dot(listed.slope, origin);
                                    if (along < -kPlaneTestSlack || along > reach + kPlaneTestSlack)
                                        continue;
                                }
                                const std::uint32_t other = listed.triangle;
                                const auto& o = surface.triangles[other];
                                const double distance =
                                    rayHit(origin, direction, surface.points[o[0]],
                                           surface.points[o[1]], surface.points[o[2]]);
                                if (distance > 0.0 && distance <= reach &&
                                    (distance < nearest || (distance == nearest && other < hit))) {
                                    nearest = distance;
                                    hit = other;
                                }
                            }
                            if (!(nearest <= reach) || !facesAway(hit)) continue;
                            ++localThin;
                            const Vec3 middle{origin[0] + 0.5 * nearest * direction[0],
                                              origin[1] + 0.5 * nearest * direction[1],
                                              origin[2] + 0.5 * nearest * direction[2]};
                            std::array<int, 3> from{}, to{};
                            for (std::size_t k = 0; k < 3; ++k) {
                                from[k] = int(std::ceil(middle[k] - radius - 0.5));
                                to[k] = int(std::floor(middle[k] + radius + 0.5));
                            }
                            for (int z = from[2]; z <= to[2]; ++z)
                                for (int y = from[1]; y <= to[1]; ++y)
                                    for (int x = from[0]; x <= to[0]; ++x) {
                                        if (!mask.contains(x, y, z)) continue;
                                        // Squared distance from the middle to the cube.
                                        const int voxel[3] = {x, y, z};
                                        double squared = 0.0;
                                        for (std::size_t k = 0; k < 3; ++k) {
                                            const double gap = std::abs(middle[k] - voxel[k]) - 0.5;
                                            if (gap > 0.0) squared += gap * gap;
                                        }
                                        if (squared <= radius * radius)
                                            local.push_back(std::uint32_t(mask.index(x, y, z)));
                                    }
                        }
            }
            thinSamples += localThin;
            std::lock_guard<std::mutex> guard(lock);
            filled.insert(filled.end(), local.begin(), local.end());
        },
        options.threaded, 256);
    if (stopped) throwInterrupted(interrupter);
    std::sort(filled.begin(), filled.end());
    filled.erase(std::unique(filled.begin(), filled.end()), filled.end());
    std::uint8_t* data = mask.data();
    for (std::uint32_t index : filled)
        if (!data[index]) {
            data[index] = 1;
            ++result.voxelsAdded;
        }
    result.thinSamples = thinSamples;
    return result;
}

}  // namespace skelseg
