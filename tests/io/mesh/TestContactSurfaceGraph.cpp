#include "io/mesh/ContactSurfaceGraph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <vector>

#include "tests/support/ShapeMeshes.h"

namespace skelseg {
namespace {

using vec3::Vec3;

/// An axis-aligned cube with corners 0 and 4 in voxel space, two triangles
/// per side, outward normals.
TriangleMesh cube() {
    TriangleMesh mesh;
    for (int k = 0; k < 8; ++k)
        mesh.vertices.push_back({k & 1 ? 4.0 : 0.0, k & 2 ? 4.0 : 0.0, k & 4 ? 4.0 : 0.0});
    const std::array<std::array<std::uint32_t, 4>, 6> sides{
        {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}}};
    for (const auto& s : sides) {
        mesh.triangles.push_back({s[0], s[1], s[2]});
        mesh.triangles.push_back({s[0], s[2], s[3]});
    }
    mesh.faceCount = mesh.triangles.size();
    mesh.triangleFace.resize(mesh.faceCount);
    std::iota(mesh.triangleFace.begin(), mesh.triangleFace.end(), 0u);
    return mesh;
}

std::array<Vec3, 3> sortedCorners(const SurfaceGraph& graph, std::int32_t t) {
    std::array<Vec3, 3> c{graph.points[graph.triangles[std::size_t(t)][0]],
                          graph.points[graph.triangles[std::size_t(t)][1]],
                          graph.points[graph.triangles[std::size_t(t)][2]]};
    std::sort(c.begin(), c.end());
    return c;
}

/// Index of the first triangle (in the graph's order) that has `corner`.
std::int32_t firstTriangleAt(const SurfaceGraph& graph, const Vec3& corner) {
    for (std::size_t t = 0; t < graph.triangles.size(); ++t)
        for (std::uint32_t v : graph.triangles[t])
            if (graph.points[v] == corner) return std::int32_t(t);
    return -1;
}

TEST(ContactSurfaceGraph, TiesAtAVertexGoToTheTriangleFacingThePoint) {
    // Off the corner (4, 4, 4), mostly along +x: every triangle at the corner
    // is nearest (at the corner itself); the ones on the side x = 4 face p.
    const Vec3 p{5.0, 4.2, 4.1};
    for (unsigned seed = 0; seed < 6; ++seed) {
        const SurfaceGraph graph =
            buildSurfaceGraph(test::reorderedTriangles(cube(), seed), VolumeGeometry{});
        const std::int32_t first = firstTriangleAt(graph, {4, 4, 4});
        ASSERT_GE(first, 0);
        const std::int32_t chosen = graph.nearestOfTied(first, p);
        for (const Vec3& corner : sortedCorners(graph, chosen))
            EXPECT_EQ(corner[0], 4.0) << "seed " << seed;
    }
}

TEST(ContactSurfaceGraph, ExactTiesAreBrokenByGeometryNotFaceOrder) {
    // On the cube's diagonal every side at the corner faces p equally: the
    // choice must still be one triangle, the same whatever the face order.
    const Vec3 p{5.0, 5.0, 5.0};
    std::array<Vec3, 3> expected{};
    for (unsigned seed = 0; seed < 8; ++seed) {
        const SurfaceGraph graph =
            buildSurfaceGraph(test::reorderedTriangles(cube(), seed), VolumeGeometry{});
        for (std::size_t t = 0; t < graph.triangles.size(); ++t) {
            const auto& c = graph.triangles[t];
            const bool atCorner = std::any_of(c.begin(), c.end(), [&](std::uint32_t v) {
                return graph.points[v] == Vec3{4, 4, 4};
            });
            if (!atCorner) continue;
            const auto corners = sortedCorners(graph, graph.nearestOfTied(std::int32_t(t), p));
            if (seed == 0 && t == std::size_t(firstTriangleAt(graph, {4, 4, 4})))
                expected = corners;
            EXPECT_EQ(corners, expected) << "seed " << seed << ", from triangle " << t;
        }
    }
}

TEST(ContactSurfaceGraph, TiesOnAnEdgeStayOnThatEdge) {
    // Nearest point on the edge x = 4, y = 4: only its two sides' triangles
    // tie; the one on y = 4 faces p more squarely.
    const Vec3 p{4.3, 5.0, 2.0};
    for (unsigned seed = 0; seed < 6; ++seed) {
        const SurfaceGraph graph =
            buildSurfaceGraph(test::reorderedTriangles(cube(), seed), VolumeGeometry{});
        for (std::size_t t = 0; t < graph.triangles.size(); ++t) {
            const auto& c = graph.triangles[t];
            int onEdge = 0;
            for (std::uint32_t v : c) {
                const Vec3& q = graph.points[v];
                onEdge += q[0] == 4.0 && q[1] == 4.0;
            }
            if (onEdge < 2) continue;  // not a triangle of that edge
            for (const Vec3& corner : sortedCorners(graph, graph.nearestOfTied(std::int32_t(t), p)))
                EXPECT_EQ(corner[1], 4.0) << "seed " << seed;
        }
    }
}

/// A closed cone in voxel space: apex (0, 0, 8), a ring of `ring` vertices
/// of radius 6 at z = 0 and a base centre, so the apex and the base centre
/// each have `ring` triangles and every ring vertex four. Outward normals.
TriangleMesh cone(std::uint32_t ring) {
    TriangleMesh mesh;
    mesh.vertices.push_back({0.0, 0.0, 8.0});
    mesh.vertices.push_back({0.0, 0.0, 0.0});
    const double step = 2.0 * M_PI / ring;
    for (std::uint32_t i = 0; i < ring; ++i)
        mesh.vertices.push_back({6.0 * std::cos(step * i), 6.0 * std::sin(step * i), 0.0});
    for (std::uint32_t i = 0; i < ring; ++i) {
        const std::uint32_t a = 2 + i, b = 2 + (i + 1) % ring;
        mesh.triangles.push_back({0, a, b});
        mesh.triangles.push_back({1, b, a});
    }
    mesh.faceCount = mesh.triangles.size();
    mesh.triangleFace.resize(mesh.faceCount);
    std::iota(mesh.triangleFace.begin(), mesh.triangleFace.end(), 0u);
    return mesh;
}

TEST(ContactSurfaceGraph, TiesOnAnEdgeOfACrowdedVertexStayOnThatEdge) {
    // Off the middle of the spoke from the apex to ring vertex i, turned a
    // little towards ring vertex i + 1: the nearest point is on the spoke,
    // its two side triangles tie, and the one towards i + 1 faces p more
    // squarely. The apex's 2,000 triangles are the longer list of the two
    // the spoke's triangles are found in.
    constexpr std::uint32_t kRing = 2000;
    const TriangleMesh mesh = cone(kRing);
    const double step = 2.0 * M_PI / kRing;
    for (unsigned seed = 0; seed < 3; ++seed) {
        const SurfaceGraph graph =
            buildSurfaceGraph(test::reorderedTriangles(mesh, seed), VolumeGeometry{});
        for (std::uint32_t i : {0u, 1u, 777u, kRing - 1}) {
            const Vec3 spoke = mesh.vertices[2 + i];
            const Vec3 next = mesh.vertices[2 + (i + 1) % kRing];
            const double turned = step * (i + 0.3);
            const Vec3 p{0.5 * spoke[0] + 0.5 * std::cos(turned),
                         0.5 * spoke[1] + 0.5 * std::sin(turned), 4.0};
            std::array<Vec3, 3> expected{Vec3{0, 0, 8}, spoke, next};
            std::sort(expected.begin(), expected.end());
            for (std::size_t t = 0; t < graph.triangles.size(); ++t) {
                const auto corners = sortedCorners(graph, std::int32_t(t));
                const bool onSpoke =
                    std::count(corners.begin(), corners.end(), Vec3{0, 0, 8}) == 1 &&
                    std::count(corners.begin(), corners.end(), spoke) == 1;
                if (!onSpoke) continue;
                EXPECT_EQ(sortedCorners(graph, graph.nearestOfTied(std::int32_t(t), p)), expected)
                    << "seed " << seed << ", spoke " << i << ", from triangle " << t;
            }
        }
    }
}

TEST(ContactSurfaceGraph, ANearestPointInsideATriangleKeepsIt) {
    const SurfaceGraph graph = buildSurfaceGraph(cube(), VolumeGeometry{});
    // (1, 3, 4.5) lies above the second triangle of the side z = 4
    // (corners 4, 7, 6: x <= y), inside it.
    const std::int32_t t = 3;
    ASSERT_EQ(sortedCorners(graph, t)[0], (Vec3{0, 0, 4}));
    EXPECT_EQ(graph.nearestOfTied(t, {1.0, 3.0, 4.5}), t);
    // And a point on the surface has no side to choose.
    EXPECT_EQ(graph.nearestOfTied(t, {4.0, 4.0, 4.0}), t);
}

}  // namespace
}  // namespace skelseg
