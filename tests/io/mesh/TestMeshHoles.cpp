#include "io/mesh/MeshHoles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "io/mesh/MeshCheck.h"
#include "tests/support/CurledTube.h"
#include "tests/support/MeshEdits.h"

namespace skelseg {
namespace {

/// Six times the volume the triangles enclose: positive when they face out.
double signedVolume(const TriangleMesh& mesh) {
    double volume = 0.0;
    for (const auto& t : mesh.triangles) {
        const auto& a = mesh.vertices[t[0]];
        const auto& b = mesh.vertices[t[1]];
        const auto& c = mesh.vertices[t[2]];
        volume += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                  a[2] * (b[0] * c[1] - b[1] * c[0]);
    }
    return volume;
}

TEST(MeshHoles, AClosedMeshHasNone) {
    EXPECT_FALSE(closedWithHolesCapped(test::sphereMesh({0, 0, 0}, 1.0)).has_value());
}

TEST(MeshHoles, SmallHolesAreCappedFacingOutAndTheInputIsKept) {
    // Eye sockets: the fans round both poles of a sphere, 0.4% of its area
    // each, and one triangle of its side.
    const TriangleMesh sphere = test::sphereMesh({0, 0, 0}, 1.0);
    const TriangleMesh open = test::withoutTrianglesWhere(sphere, [&](std::size_t t) {
        return std::abs(test::centroidZ(sphere, t)) > 0.99 || t == sphere.triangles.size() / 2 + 23;
    });
    ASSERT_FALSE(checkMesh(open).closed);
    const auto capped = closedWithHolesCapped(open);
    ASSERT_TRUE(capped.has_value());
    EXPECT_EQ(capped->holes, 3u);
    EXPECT_TRUE(capped->diagnostics.closed);
    EXPECT_TRUE(checkMesh(capped->mesh).closed);
    EXPECT_EQ(capped->mesh.faceCount, open.faceCount + 3);
    EXPECT_EQ(capped->mesh.vertices.size(), open.vertices.size() + 3);
    EXPECT_TRUE(
        std::equal(open.triangles.begin(), open.triangles.end(), capped->mesh.triangles.begin()));
    EXPECT_GT(capped->capAreaShare, 0.0);
    EXPECT_LT(capped->capAreaShare, 0.02);
    // The caps wind as the surface does: the capped sphere encloses the
    // sphere's volume with its sign (caps wound the other way would take
    // about 0.2 from it).
    EXPECT_NEAR(signedVolume(capped->mesh), signedVolume(sphere),
                0.001 * std::abs(signedVolume(sphere)));
}

TEST(MeshHoles, AnOpenSheetIsNoMeshWithHoles) {
    // A hemisphere's cap would be half its area: a shell, not a hole.
    const TriangleMesh sphere = test::sphereMesh({0, 0, 0}, 1.0);
    const TriangleMesh bowl = test::withoutTrianglesWhere(
        sphere, [&](std::size_t t) { return test::centroidZ(sphere, t) > 0; });
    EXPECT_FALSE(closedWithHolesCapped(bowl).has_value());
}

TEST(MeshHoles, EveryPieceMustBeClosedButForSmallHoles) {
    // A large sphere with a small hole beside a small open bowl: the bowl's
    // cap is a tiny share of the whole area but half its own piece's, so the
    // mesh keeps the shell method (an eyeball modelled as a half shell).
    const TriangleMesh big = test::sphereMesh({0, 0, 0}, 1.0);
    TriangleMesh mesh = test::withoutTrianglesWhere(
        big, [&](std::size_t t) { return test::centroidZ(big, t) > 0.99; });
    ASSERT_TRUE(closedWithHolesCapped(mesh).has_value());
    const TriangleMesh small = test::sphereMesh({3, 0, 0}, 0.1);
    const TriangleMesh bowl = test::withoutTrianglesWhere(
        small, [&](std::size_t t) { return test::centroidZ(small, t) > 0; });
    test::appendPiece(mesh, bowl);
    EXPECT_FALSE(closedWithHolesCapped(mesh).has_value());
}

TEST(MeshHoles, HolesMeetingInAVertexAreNotCapped) {
    // Two triangles of the sphere's side sharing one corner only: their
    // holes touch there, and which border runs on where is not told.
    const TriangleMesh sphere = test::sphereMesh({0, 0, 0}, 1.0);
    const std::size_t first = sphere.triangles.size() / 2;
    std::size_t second = 0;
    for (std::size_t t = 0; t < sphere.triangles.size() && second == 0; ++t) {
        int shared = 0;
        for (auto a : sphere.triangles[t])
            for (auto b : sphere.triangles[first]) shared += a == b;
        if (shared == 1) second = t;
    }
    ASSERT_NE(second, 0u);
    const TriangleMesh open = test::withoutTrianglesWhere(
        sphere, [&](std::size_t t) { return t == first || t == second; });
    EXPECT_FALSE(closedWithHolesCapped(open).has_value());
}

TEST(MeshHoles, TheFaceOrderGivesTheSameCaps) {
    const TriangleMesh sphere = test::sphereMesh({0, 0, 0}, 1.0);
    const TriangleMesh open = test::withoutTrianglesWhere(
        sphere, [&](std::size_t t) { return std::abs(test::centroidZ(sphere, t)) > 0.99; });
    TriangleMesh shuffled = open;
    std::mt19937 random(3);
    std::shuffle(shuffled.triangles.begin(), shuffled.triangles.end(), random);
    const auto a = closedWithHolesCapped(open);
    const auto b = closedWithHolesCapped(shuffled);
    ASSERT_TRUE(a && b);
    const std::vector<std::array<double, 3>> capsA(
        a->mesh.vertices.begin() + long(open.vertices.size()), a->mesh.vertices.end());
    const std::vector<std::array<double, 3>> capsB(
        b->mesh.vertices.begin() + long(open.vertices.size()), b->mesh.vertices.end());
    EXPECT_EQ(capsA, capsB);
}

TEST(MeshHoles, AnAreaBeyondADoubleGivesNoShare) {
    // Coordinates near 1e160 overflow the areas: inf over inf is no share.
    TriangleMesh sphere = test::sphereMesh({0, 0, 0}, 1.0);
    for (auto& v : sphere.vertices)
        for (double& c : v) c *= 1e160;
    const TriangleMesh open = test::withoutTrianglesWhere(
        sphere, [&](std::size_t t) { return test::centroidZ(sphere, t) > 0.99e160; });
    EXPECT_FALSE(closedWithHolesCapped(open).has_value());
}

}  // namespace
}  // namespace skelseg
