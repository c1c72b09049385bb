#include "io/render/SegmentMeshes.h"

#include <gtest/gtest.h>

#include <cmath>

#include "io/render/MeshSimplification.h"
#include "kernels/base/Error.h"

namespace skelseg {
namespace {

TEST(SegmentMeshes, SplitCopiesSharedVerticesAndKeepsOrder) {
    // Two triangles of label 3 and one of label 1 sharing vertices 1 and 2.
    const std::vector<std::array<double, 3>> vertices = {
        {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {5, 5, 5}};  // vertex 4 unused
    const std::vector<std::array<std::uint32_t, 3>> triangles = {{1, 3, 2}, {0, 1, 2}, {2, 3, 1}};
    const auto meshes = splitSegmentMeshes(vertices, triangles, {3, 1, 3});
    ASSERT_EQ(meshes.size(), 2u);
    EXPECT_EQ(meshes[0].label, 1u);
    EXPECT_EQ(meshes[1].label, 3u);
    // Label 1: vertices 0 1 2 in order of first use.
    ASSERT_EQ(meshes[0].positions.size(), 3u);
    EXPECT_EQ(meshes[0].triangles, (std::vector<std::array<std::uint32_t, 3>>{{0, 1, 2}}));
    EXPECT_EQ(meshes[0].positions[1], (std::array<float, 3>{1, 0, 0}));
    // Label 3: vertices 1 3 2, triangles in input order, orientation kept.
    ASSERT_EQ(meshes[1].positions.size(), 3u);
    EXPECT_EQ(meshes[1].triangles,
              (std::vector<std::array<std::uint32_t, 3>>{{0, 1, 2}, {2, 1, 0}}));
    EXPECT_EQ(meshes[1].positions[1], (std::array<float, 3>{1, 1, 0}));
    EXPECT_EQ(triangleCount(meshes), 3u);
}

TEST(SegmentMeshes, SplitRefusesBadInput) {
    const std::vector<std::array<double, 3>> vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    EXPECT_THROW(splitSegmentMeshes(vertices, {{0, 1, 3}}, {1}), UsageError);
    EXPECT_THROW(splitSegmentMeshes(vertices, {{0, 1, 2}}, {}), UsageError);
}

/// A UV sphere of `rings` x `sectors` quads, its upper half label 1, lower 2.
SegmentMesh sphereHalf(int rings, int sectors, bool upper) {
    std::vector<std::array<double, 3>> vertices;
    for (int r = 0; r <= rings; ++r)
        for (int s = 0; s < sectors; ++s) {
            const double theta = M_PI * r / rings, phi = 2 * M_PI * s / sectors;
            vertices.push_back({std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                std::cos(theta)});
        }
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<std::uint32_t> labels;
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < sectors; ++s) {
            const auto at = [&](int rr, int ss) {
                return std::uint32_t(rr * sectors + ss % sectors);
            };
            triangles.push_back({at(r, s), at(r + 1, s), at(r + 1, s + 1)});
            triangles.push_back({at(r, s), at(r + 1, s + 1), at(r, s + 1)});
            labels.insert(labels.end(), 2, r < rings / 2 ? 1u : 2u);
        }
    auto meshes = splitSegmentMeshes(vertices, triangles, labels);
    return meshes[upper ? 0 : 1];
}

TEST(MeshSimplification, MeetsTheBudgetAndKeepsTheShape) {
    std::vector<SegmentMesh> meshes = {sphereHalf(120, 160, true), sphereHalf(120, 160, false)};
    const std::size_t before = triangleCount(meshes);
    ASSERT_EQ(before, 120u * 160u * 2u);
    simplifyForDisplay(meshes, 4000);
    const std::size_t after = triangleCount(meshes);
    EXPECT_LE(after, 4000u * 3 / 2);
    EXPECT_GE(after, 2 * kMinTrianglesPerSegment);
    for (const SegmentMesh& mesh : meshes) {
        EXPECT_FALSE(mesh.triangles.empty());
        std::vector<bool> used(mesh.positions.size(), false);
        for (const auto& t : mesh.triangles)
            for (std::uint32_t v : t) {
                ASSERT_LT(v, mesh.positions.size());
                used[v] = true;
            }
        for (bool u : used) EXPECT_TRUE(u);  // no unused vertex left behind
        // The kept vertices are input vertices: still on the unit sphere, and
        // the half still spans its extent.
        float zLow = 2, zHigh = -2;
        for (const auto& p : mesh.positions) {
            EXPECT_NEAR(std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]), 1.0, 1e-5);
            zLow = std::fmin(zLow, p[2]);
            zHigh = std::fmax(zHigh, p[2]);
        }
        EXPECT_NEAR(zHigh - zLow, 1.0, 0.05) << "segment " << mesh.label;
    }
}

TEST(MeshSimplification, LeavesMeshesWithinBudgetUntouched) {
    std::vector<SegmentMesh> meshes = {sphereHalf(10, 12, true)};
    const auto copy = meshes;
    simplifyForDisplay(meshes, 1000);
    EXPECT_EQ(meshes[0].triangles, copy[0].triangles);
    EXPECT_EQ(meshes[0].positions, copy[0].positions);
}

TEST(MeshSimplification, MeetsTheBudgetOnAFanRoundOneVertex) {
    // A closed cone: apex and base centre each shared by half the triangles.
    constexpr std::uint32_t kRing = 20000;
    SegmentMesh cone;
    cone.label = 1;
    cone.positions.push_back({0, 0, 2});
    cone.positions.push_back({0, 0, 0});
    for (std::uint32_t i = 0; i < kRing; ++i) {
        const double angle = 2.0 * M_PI * i / kRing;
        cone.positions.push_back({float(std::cos(angle)), float(std::sin(angle)), 0});
    }
    for (std::uint32_t i = 0; i < kRing; ++i) {
        const std::uint32_t a = 2 + i, b = 2 + (i + 1) % kRing;
        cone.triangles.push_back({0, a, b});
        cone.triangles.push_back({1, b, a});
    }
    std::vector<SegmentMesh> meshes = {cone};
    simplifyForDisplay(meshes, 2000);
    const SegmentMesh& simplified = meshes[0];
    EXPECT_LE(simplified.triangles.size(), 2000u * 3 / 2);
    EXPECT_GE(simplified.triangles.size(), kMinTrianglesPerSegment);
    std::vector<bool> used(simplified.positions.size(), false);
    for (const auto& t : simplified.triangles)
        for (std::uint32_t v : t) {
            ASSERT_LT(v, simplified.positions.size());
            used[v] = true;
        }
    for (bool u : used) EXPECT_TRUE(u);
    // Kept vertices are the cone's: the apex, the base centre or the rim.
    for (const auto& p : simplified.positions) {
        const bool axis = p[0] == 0 && p[1] == 0;
        EXPECT_TRUE(axis || (p[2] == 0 && std::abs(std::hypot(p[0], p[1]) - 1.0) < 1e-5));
    }
}

}  // namespace
}  // namespace skelseg
