#include "io/mesh/FaceLabels.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <string>
#include <utility>

#include "io/mesh/MeshCheck.h"
#include "io/mesh/MeshVoxelizer.h"
#include "kernels/base/ParallelFor.h"

namespace skelseg {

namespace {

constexpr std::uint32_t kNoLabel = 0;  // voxel label 0 is background

/// Label of the labelled voxel nearest to a continuous index within a cube
/// of Chebyshev radius `radius`, or kNoLabel.
std::uint32_t nearestLabel(const LabelVolume& labels, const std::array<double, 3>& point,
                           int radius) {
    if (!(std::abs(point[0]) < 1e9 && std::abs(point[1]) < 1e9 && std::abs(point[2]) < 1e9))
        return kNoLabel;
    const int cx = int(std::floor(point[0] + 0.5)), cy = int(std::floor(point[1] + 0.5)),
              cz = int(std::floor(point[2] + 0.5));
    const Dims& dims = labels.dims();
    double bestDistance = HUGE_VAL;
    std::uint32_t bestLabel = kNoLabel;
    auto consider = [&](int x, int y, int z) {
        if (x < 0 || y < 0 || z < 0 || x >= dims.x || y >= dims.y || z >= dims.z) return;
        const std::uint32_t label = labels(x, y, z);
        if (label == kNoLabel) return;
        const double dx = x - point[0], dy = y - point[1], dz = z - point[2];
        const double distance = dx * dx + dy * dy + dz * dz;
        if (distance < bestDistance || (distance == bestDistance && label < bestLabel)) {
            bestDistance = distance;
            bestLabel = label;
        }
    };
    for (int r = 0; r <= radius; ++r) {
        // The shell of the cube at radius r: x runs over the whole row only
        // where y or z is on the shell, else just its two ends.
        for (int dz = -r; dz <= r; ++dz)
            for (int dy = -r; dy <= r; ++dy) {
                if (std::abs(dz) == r || std::abs(dy) == r) {
                    for (int dx = -r; dx <= r; ++dx) consider(cx + dx, cy + dy, cz + dz);
                } else {
                    consider(cx - r, cy + dy, cz + dz);
                    if (r > 0) consider(cx + r, cy + dy, cz + dz);
                }
            }
        // The point lies within half a voxel of (cx, cy, cz) in every axis,
        // so voxels of the next shell are at least r + 0.5 away.
        if (bestLabel != kNoLabel && bestDistance <= (r + 0.5) * (r + 0.5)) break;
    }
    return bestLabel;
}

struct Vote {
    std::uint32_t label;
    double weight;
    std::uint32_t count;
};

/// The winning label of a face's votes (see the header's rule 3).
std::uint32_t winner(const std::vector<Vote>& votes) {
    const Vote* best = nullptr;
    for (const Vote& vote : votes)
        if (!best || vote.weight > best->weight ||
            (vote.weight == best->weight &&
             (vote.count > best->count || (vote.count == best->count && vote.label < best->label))))
            best = &vote;
    return best ? best->label : kNoLabel;
}

/// Faces sharing an edge (between distinct canonical vertices), as CSR.
struct FaceAdjacency {
    std::vector<std::uint32_t> offsets, neighbours;
};

FaceAdjacency faceAdjacency(const TriangleMesh& mesh) {
    const std::vector<std::uint32_t> canonical = canonicalVertices(mesh);
    std::vector<std::pair<std::uint64_t, std::uint32_t>> edgeFaces;
    edgeFaces.reserve(mesh.triangles.size() * 3);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int corner = 0; corner < 3; ++corner) {
            std::uint32_t a = canonical[mesh.triangles[t][std::size_t(corner)]];
            std::uint32_t b = canonical[mesh.triangles[t][std::size_t((corner + 1) % 3)]];
            if (a == b) continue;
            if (a > b) std::swap(a, b);
            edgeFaces.emplace_back((std::uint64_t(a) << 32) | b, mesh.triangleFace[t]);
        }
    std::sort(edgeFaces.begin(), edgeFaces.end());
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    for (std::size_t begin = 0; begin < edgeFaces.size();) {
        std::size_t end = begin + 1;
        while (end < edgeFaces.size() && edgeFaces[end].first == edgeFaces[begin].first) ++end;
        for (std::size_t i = begin; i < end; ++i)
            for (std::size_t j = i + 1; j < end; ++j)
                if (edgeFaces[i].second != edgeFaces[j].second) {
                    pairs.emplace_back(edgeFaces[i].second, edgeFaces[j].second);
                    pairs.emplace_back(edgeFaces[j].second, edgeFaces[i].second);
                }
        begin = end;
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    FaceAdjacency adjacency;
    adjacency.offsets.assign(mesh.faceCount + 1, 0);
    for (const auto& pair : pairs) ++adjacency.offsets[pair.first + 1];
    for (std::size_t f = 0; f < mesh.faceCount; ++f)
        adjacency.offsets[f + 1] += adjacency.offsets[f];
    adjacency.neighbours.reserve(pairs.size());
    for (const auto& pair : pairs) adjacency.neighbours.push_back(pair.second);
    return adjacency;
}

/// For every voxel, the label of a nearest labelled voxel (6-connected
/// breadth-first sweep from all labelled voxels; sources in index order, so
/// the result is deterministic). Empty when no voxel is labelled.
std::vector<std::uint16_t> nearestLabelMap(const LabelVolume& labels, Interrupter& interrupter) {
    std::vector<std::uint16_t> map(labels.values());
    std::vector<std::uint32_t> frontier, next;
    for (std::size_t i = 0; i < map.size(); ++i)
        if (map[i] != kNoLabel) frontier.push_back(std::uint32_t(i));
    if (frontier.empty()) return {};
    const Dims dims = labels.dims();
    const std::uint32_t strideY = std::uint32_t(dims.x),
                        strideZ = std::uint32_t(dims.x) * std::uint32_t(dims.y);
    while (!frontier.empty()) {
        throwIfInterrupted(interrupter);
        next.clear();
        for (std::uint32_t index : frontier) {
            const std::uint32_t x = index % strideY, y = (index / strideY) % std::uint32_t(dims.y),
                                z = index / strideZ;
            auto spread = [&](std::uint32_t neighbour) {
                if (map[neighbour] == kNoLabel) {
                    map[neighbour] = map[index];
                    next.push_back(neighbour);
                }
            };
            if (x > 0) spread(index - 1);
            if (x + 1 < std::uint32_t(dims.x)) spread(index + 1);
            if (y > 0) spread(index - strideY);
            if (y + 1 < std::uint32_t(dims.y)) spread(index + strideY);
            if (z > 0) spread(index - strideZ);
            if (z + 1 < std::uint32_t(dims.z)) spread(index + strideZ);
        }
        frontier.swap(next);
    }
    return map;
}

}  // namespace

std::vector<std::uint32_t> labelFaces(const TriangleMesh& mesh, const LabelVolume& labels,
                                      const FaceLabelOptions& options, Interrupter& interrupter,
                                      FaceLabelStatistics* statistics) {
    if (options.searchRadius < 0 || options.searchRadius > 16)
        throw UsageError("face label search radius " + std::to_string(options.searchRadius) +
                         " is outside [0, 16]");
    if (labels.empty()) throw UsageError("cannot label faces from an empty label volume");
    InterrupterScope scope(interrupter, "label faces");

    const std::size_t faceCount = mesh.faceCount;
    // Triangles of each face (CSR); readMesh makes them consecutive, but do
    // not rely on it.
    std::vector<std::uint32_t> faceOffsets(faceCount + 1, 0), faceTriangles(mesh.triangles.size());
    for (std::uint32_t face : mesh.triangleFace) ++faceOffsets[std::size_t(face) + 1];
    for (std::size_t f = 0; f < faceCount; ++f) faceOffsets[f + 1] += faceOffsets[f];
    {
        std::vector<std::uint32_t> fill(faceOffsets.begin(), faceOffsets.end() - 1);
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
            faceTriangles[fill[mesh.triangleFace[t]]++] = std::uint32_t(t);
    }

    const WorldToIndex toIndex(labels.geometry);
    const double voxelSize = labels.geometry.voxelSize();
    std::vector<std::uint32_t> voxelLabel(faceCount, kNoLabel);

    std::atomic<bool> stop{false};
    auto labelRange = [&](std::size_t begin, std::size_t end) {
        std::vector<Vote> votes;
        for (std::size_t face = begin; face < end; ++face) {
            if ((face & 1023) == 0 &&
                (stop.load(std::memory_order_relaxed) ||
                 interrupter.wasInterrupted(0.9 * double(face) / double(faceCount)))) {
                stop = true;
                return;
            }
            votes.clear();
            for (std::uint32_t k = faceOffsets[face]; k < faceOffsets[face + 1]; ++k) {
                const auto& triangle = mesh.triangles[faceTriangles[k]];
                const auto& a = mesh.vertices[triangle[0]];
                const auto& b = mesh.vertices[triangle[1]];
                const auto& c = mesh.vertices[triangle[2]];
                const std::array<double, 3> u{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
                const std::array<double, 3> v{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
                const double nx = u[1] * v[2] - u[2] * v[1], ny = u[2] * v[0] - u[0] * v[2],
                             nz = u[0] * v[1] - u[1] * v[0];
                const double area = 0.5 * std::sqrt(nx * nx + ny * ny + nz * nz);
                const double side = voxelSize > 0 ? std::sqrt(area) / voxelSize : 0.0;
                const int m = side > 5.0 ? 6 : side > 2.0 ? int(std::ceil(side)) : 2;
                const double weight = area / double(m * m);
                auto sample = [&](double s, double t) {
                    const std::array<double, 3> world{a[0] + s * u[0] + t * v[0],
                                                      a[1] + s * u[1] + t * v[1],
                                                      a[2] + s * u[2] + t * v[2]};
                    const std::uint32_t label =
                        nearestLabel(labels, toIndex(world), options.searchRadius);
                    if (label == kNoLabel) return;
                    for (Vote& vote : votes)
                        if (vote.label == label) {
                            vote.weight += weight;
                            ++vote.count;
                            return;
                        }
                    votes.push_back({label, weight, 1});
                };
                // Centroids of the m*m sub-triangles in barycentric steps of 1/m.
                for (int i = 0; i < m; ++i)
                    for (int j = 0; i + j < m; ++j) {
                        sample((i + 1.0 / 3.0) / m, (j + 1.0 / 3.0) / m);
                        if (i + j + 2 <= m) sample((i + 2.0 / 3.0) / m, (j + 2.0 / 3.0) / m);
                    }
            }
            voxelLabel[face] = winner(votes);
        }
    };
    parallelFor(faceCount, labelRange, options.threaded, 256);
    if (stop) throwInterrupted(interrupter);

    FaceLabelStatistics stats;
    std::vector<std::uint32_t> unlabelled;
    for (std::size_t f = 0; f < faceCount; ++f)
        if (voxelLabel[f] == kNoLabel) unlabelled.push_back(std::uint32_t(f));
    stats.votedFaces = faceCount - unlabelled.size();

    if (!unlabelled.empty()) {
        // Rounds over the mesh: a face takes the most common label among its
        // neighbours labelled in earlier rounds. Decisions of one round are
        // applied together, so the order of faces within it does not matter.
        const FaceAdjacency adjacency = faceAdjacency(mesh);
        std::vector<std::uint32_t> frontier;
        std::vector<char> queued(faceCount, 0);
        for (std::uint32_t f : unlabelled)
            for (std::uint32_t k = adjacency.offsets[f]; k < adjacency.offsets[f + 1]; ++k)
                if (voxelLabel[adjacency.neighbours[k]] != kNoLabel) {
                    frontier.push_back(f);
                    queued[f] = 1;
                    break;
                }
        std::vector<std::pair<std::uint32_t, std::uint32_t>> decided;
        std::vector<Vote> votes;
        while (!frontier.empty()) {
            throwIfInterrupted(interrupter);
            decided.clear();
            for (std::uint32_t f : frontier) {
                votes.clear();
                for (std::uint32_t k = adjacency.offsets[f]; k < adjacency.offsets[f + 1]; ++k) {
                    const std::uint32_t label = voxelLabel[adjacency.neighbours[k]];
                    if (label == kNoLabel) continue;
                    auto found = std::find_if(votes.begin(), votes.end(),
                                              [&](const Vote& v) { return v.label == label; });
                    if (found == votes.end())
                        votes.push_back({label, 1.0, 1});
                    else
                        found->weight += 1.0, ++found->count;
                }
                decided.emplace_back(f, winner(votes));
            }
            frontier.clear();
            for (const auto& [face, label] : decided) voxelLabel[face] = label;
            stats.propagatedFaces += decided.size();
            for (const auto& [face, label] : decided) {
                (void)label;
                for (std::uint32_t k = adjacency.offsets[face]; k < adjacency.offsets[face + 1];
                     ++k) {
                    const std::uint32_t neighbour = adjacency.neighbours[k];
                    if (voxelLabel[neighbour] == kNoLabel && !queued[neighbour]) {
                        queued[neighbour] = 1;
                        frontier.push_back(neighbour);
                    }
                }
            }
            std::sort(frontier.begin(), frontier.end());
        }

        // Pieces of the mesh without a single labelled sample.
        std::vector<std::uint16_t> nearestMap;
        bool mapBuilt = false;
        for (std::uint32_t f : unlabelled) {
            if (voxelLabel[f] != kNoLabel) continue;
            if (!mapBuilt) {
                nearestMap = nearestLabelMap(labels, interrupter);
                mapBuilt = true;
            }
            if (nearestMap.empty()) break;  // no labelled voxel at all
            std::array<double, 3> centroid{0, 0, 0};
            double corners = 0;
            for (std::uint32_t k = faceOffsets[f]; k < faceOffsets[f + 1]; ++k)
                for (std::uint32_t vertex : mesh.triangles[faceTriangles[k]]) {
                    for (std::size_t c = 0; c < 3; ++c) centroid[c] += mesh.vertices[vertex][c];
                    corners += 1;
                }
            for (double& c : centroid) c /= std::max(corners, 1.0);
            const auto index = toIndex(centroid);
            const Dims& dims = labels.dims();
            auto clampAxis = [](double value, int extent) {
                const double r = std::floor(value + 0.5);
                return r >= 0 && r < extent ? int(r)
                                            : (r >= extent ? extent - 1 : 0);  // NaN goes to 0
            };
            voxelLabel[f] =
                nearestMap[labels.index(clampAxis(index[0], dims.x), clampAxis(index[1], dims.y),
                                        clampAxis(index[2], dims.z))];
            ++stats.nearestVoxelFaces;
        }
    }

    // Renumber 0..K-1 by ascending voxel label (no label left: all 0).
    std::vector<std::uint32_t> used(voxelLabel);
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    used.erase(std::remove(used.begin(), used.end(), kNoLabel), used.end());
    std::vector<std::uint32_t> faceLabels(faceCount, 0);
    for (std::size_t f = 0; f < faceCount; ++f)
        if (voxelLabel[f] != kNoLabel)
            faceLabels[f] = std::uint32_t(
                std::lower_bound(used.begin(), used.end(), voxelLabel[f]) - used.begin());
    stats.segments = std::max<std::size_t>(used.size(), faceCount > 0 ? 1 : 0);
    stats.voxelLabels = std::move(used);
    if (statistics) *statistics = stats;
    return faceLabels;
}

}  // namespace skelseg
