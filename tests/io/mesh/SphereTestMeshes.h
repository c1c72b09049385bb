// Test meshes of spheres for the voxeliser's tests: a closed icosphere, the
// same with a cap cut off (an open mesh with one round hole), and how much of
// the closed sphere's solid an open one keeps.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <utility>
#include <vector>

#include "io/mesh/MeshIO.h"
#include "io/mesh/MeshVoxelizer.h"
#include "kernels/base/Volume.h"

namespace skelseg::test {

/// A closed sphere: an icosahedron subdivided `levels` times, projected onto
/// the sphere of `radius` around `centre`.
inline TriangleMesh icosphere(int levels, double radius, std::array<double, 3> centre) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<std::array<double, 3>> points = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                                 {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                                 {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    std::vector<std::array<std::uint32_t, 3>> faces = {
        {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int level = 0; level < levels; ++level) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            const auto found = midpoints.find(key);
            if (found != midpoints.end()) return found->second;
            const std::uint32_t index = std::uint32_t(points.size());
            points.push_back({(points[a][0] + points[b][0]) / 2, (points[a][1] + points[b][1]) / 2,
                              (points[a][2] + points[b][2]) / 2});
            midpoints.emplace(key, index);
            return index;
        };
        std::vector<std::array<std::uint32_t, 3>> finer;
        for (const auto& f : faces) {
            const std::uint32_t ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]),
                                ca = midpoint(f[2], f[0]);
            finer.push_back({f[0], ab, ca});
            finer.push_back({f[1], bc, ab});
            finer.push_back({f[2], ca, bc});
            finer.push_back({ab, bc, ca});
        }
        faces.swap(finer);
    }
    TriangleMesh mesh;
    for (auto p : points) {
        const double length = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        mesh.vertices.push_back({centre[0] + radius * p[0] / length,
                                 centre[1] + radius * p[1] / length,
                                 centre[2] + radius * p[2] / length});
    }
    mesh.triangles = faces;
    mesh.triangleFace.resize(faces.size());
    std::iota(mesh.triangleFace.begin(), mesh.triangleFace.end(), 0u);
    mesh.faceCount = faces.size();
    return mesh;
}

inline std::size_t solidCount(const MaskVolume& mask) {
    return std::size_t(std::count(mask.values().begin(), mask.values().end(), std::uint8_t(1)));
}

/// `mesh` without the triangles whose every corner lies at height y >= top.
inline TriangleMesh withoutCap(const TriangleMesh& mesh, double top) {
    TriangleMesh open = mesh;
    open.triangles.clear();
    for (const auto& t : mesh.triangles) {
        double lowest = HUGE_VAL;
        for (auto v : t) lowest = std::min(lowest, mesh.vertices[v][1]);
        if (lowest < top) open.triangles.push_back(t);
    }
    open.triangleFace.resize(open.triangles.size());
    std::iota(open.triangleFace.begin(), open.triangleFace.end(), 0u);
    open.faceCount = open.triangles.size();
    return open;
}

/// Solid voxels of `open` over those of `closed`, both at `resolution`: near
/// 1 where the hole was bridged and the inside filled, far below for a shell.
inline double solidShareOfClosed(const TriangleMesh& open, const TriangleMesh& closed,
                                 int resolution) {
    VoxelizeOptions options;
    options.resolution = resolution;
    return double(solidCount(voxelizeMesh(open, options))) /
           double(solidCount(voxelizeMesh(closed, options)));
}

}  // namespace skelseg::test
