#include "io/mesh/MeshFinsAndHoles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "io/mesh/MeshCheck.h"
#include "tests/support/CurledTube.h"
#include "tests/support/MeshEdits.h"

namespace skelseg {
namespace {

/// A unit sphere whose top fan is missing: a body with one small hole.
TriangleMesh bodyWithAHole() {
    const TriangleMesh sphere = test::sphereMesh({0, 0, 0}, 1.0);
    return test::withoutTrianglesWhere(
        sphere, [&](std::size_t t) { return test::centroidZ(sphere, t) > 0.99; });
}

/// The lower half of a sphere of `radius` at `centre`: an open shell whose
/// cap would be half its area, as an eyelid or a tongue modelled so.
TriangleMesh bowl(const std::array<double, 3>& centre, double radius) {
    const TriangleMesh sphere = test::sphereMesh(centre, radius);
    return test::withoutTrianglesWhere(
        sphere, [&](std::size_t t) { return test::centroidZ(sphere, t) > centre[2]; });
}

TEST(MeshFinsAndHoles, ABodyWithAHoleBesideAnOpenShellIsCappedWithoutTheShell) {
    TriangleMesh mesh = bodyWithAHole();
    const std::size_t bodyTriangles = mesh.triangles.size();
    const TriangleMesh shell = bowl({3, 0, 0}, 0.1);  // 0.5% of the area
    test::appendPiece(mesh, shell);
    // Neither rule alone: the body's sheet is open too, and far over the
    // fin share; the shell's cap is half of its piece.
    ASSERT_FALSE(closedWithoutFins(mesh).has_value());
    ASSERT_FALSE(closedWithHolesCapped(mesh).has_value());

    const auto both = closedWithoutFinsAndHoles(mesh);
    ASSERT_TRUE(both.has_value());
    EXPECT_EQ(both->withoutFins.finFaces, shell.triangles.size());
    EXPECT_GT(both->withoutFins.finAreaShare, 0.003);
    EXPECT_LT(both->withoutFins.finAreaShare, 0.01);
    EXPECT_FALSE(both->withoutFins.diagnostics.closed);
    EXPECT_EQ(both->capped.holes, 1u);
    EXPECT_TRUE(both->capped.diagnostics.closed);
    EXPECT_TRUE(checkMesh(both->capped.mesh).closed);
    // The body's triangles, then the cap's fan: the shell is gone.
    EXPECT_TRUE(std::equal(mesh.triangles.begin(), mesh.triangles.begin() + long(bodyTriangles),
                           both->capped.mesh.triangles.begin()));
    EXPECT_EQ(both->capped.mesh.faceCount, bodyTriangles + 1);
}

TEST(MeshFinsAndHoles, AnOpenPieceWhoseHoleCanBeCappedIsCappedNotDropped) {
    // An eyeball missing one triangle beside the body, and the open shell:
    // the eyeball encloses a volume and stays, capped; the shell is a fin.
    TriangleMesh mesh = bodyWithAHole();
    const TriangleMesh eyeball = test::sphereMesh({0, 3, 0}, 0.1);
    test::appendPiece(mesh, test::withoutTrianglesWhere(eyeball, [&](std::size_t t) {
                          return t == eyeball.triangles.size() / 2;
                      }));
    const TriangleMesh shell = bowl({3, 0, 0}, 0.1);
    test::appendPiece(mesh, shell);
    const auto both = closedWithoutFinsAndHoles(mesh);
    ASSERT_TRUE(both.has_value());
    EXPECT_EQ(both->withoutFins.finFaces, shell.triangles.size());
    EXPECT_EQ(both->capped.holes, 2u);
    EXPECT_EQ(checkMesh(both->capped.mesh).pieces, 2u);
}

TEST(MeshFinsAndHoles, ATriangleStandingOnTheBodyBesideAHoleIsAFin) {
    // A stray triangle standing on an edge of the body (that edge is then
    // used three times) and an eye socket: the fin is its own sheet, and
    // the body's sheet is closed but for its hole.
    TriangleMesh mesh = bodyWithAHole();
    const std::size_t bodyTriangles = mesh.triangles.size();
    std::size_t onTheEquator = 0;
    while (std::abs(test::centroidZ(mesh, onTheEquator)) > 0.1) ++onTheEquator;
    const auto edge = mesh.triangles[onTheEquator];
    const auto& a = mesh.vertices[edge[0]];
    const auto& b = mesh.vertices[edge[1]];
    mesh.vertices.push_back(
        {1.2 * (a[0] + b[0]) / 2, 1.2 * (a[1] + b[1]) / 2, 1.2 * (a[2] + b[2]) / 2});
    mesh.triangles.push_back({edge[0], edge[1], std::uint32_t(mesh.vertices.size() - 1)});
    mesh.triangleFace.push_back(std::uint32_t(mesh.faceCount++));
    ASSERT_EQ(checkMesh(mesh).nonManifoldEdges, 1u);
    ASSERT_FALSE(closedWithoutFins(mesh).has_value());
    ASSERT_FALSE(closedWithHolesCapped(mesh).has_value());
    const auto both = closedWithoutFinsAndHoles(mesh);
    ASSERT_TRUE(both.has_value());
    EXPECT_EQ(both->withoutFins.finFaces, 1u);
    EXPECT_EQ(both->capped.holes, 1u);
    EXPECT_TRUE(checkMesh(both->capped.mesh).closed);
    EXPECT_EQ(checkMesh(both->capped.mesh).nonManifoldEdges, 0u);
}

TEST(MeshFinsAndHoles, OpenPiecesOverTheFinShareAreRefused) {
    // A shell of radius 0.3 holds about 4% of the area: it could be a part
    // (a wing modelled as one layer), so it must not vanish.
    TriangleMesh mesh = bodyWithAHole();
    test::appendPiece(mesh, bowl({3, 0, 0}, 0.3));
    EXPECT_FALSE(closedWithoutFinsAndHoles(mesh).has_value());
}

TEST(MeshFinsAndHoles, ALargeHoleInTheBodyIsRefused) {
    // The body itself half open: no piece is closed but for small holes.
    TriangleMesh mesh = bowl({0, 0, 0}, 1.0);
    test::appendPiece(mesh, bowl({3, 0, 0}, 0.1));
    EXPECT_FALSE(closedWithoutFinsAndHoles(mesh).has_value());
}

TEST(MeshFinsAndHoles, AMeshOneRuleTakesAloneIsLeftToThatRule) {
    TriangleMesh closedWithAShell = test::sphereMesh({0, 0, 0}, 1.0);
    test::appendPiece(closedWithAShell, bowl({3, 0, 0}, 0.1));
    ASSERT_TRUE(closedWithoutFins(closedWithAShell).has_value());
    EXPECT_FALSE(closedWithoutFinsAndHoles(closedWithAShell).has_value());
    const TriangleMesh holeOnly = bodyWithAHole();
    ASSERT_TRUE(closedWithHolesCapped(holeOnly).has_value());
    EXPECT_FALSE(closedWithoutFinsAndHoles(holeOnly).has_value());
}

TEST(MeshFinsAndHoles, TheFaceOrderGivesTheSameResult) {
    TriangleMesh mesh = bodyWithAHole();
    test::appendPiece(mesh, bowl({3, 0, 0}, 0.1));
    TriangleMesh shuffled = mesh;
    std::mt19937 random(5);
    std::shuffle(shuffled.triangles.begin(), shuffled.triangles.end(), random);
    const auto a = closedWithoutFinsAndHoles(mesh);
    const auto b = closedWithoutFinsAndHoles(shuffled);
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->withoutFins.finFaces, b->withoutFins.finFaces);
    // The areas are summed in another order.
    EXPECT_NEAR(a->withoutFins.finAreaShare, b->withoutFins.finAreaShare, 1e-12);
    EXPECT_EQ(a->capped.holes, b->capped.holes);
    EXPECT_EQ(a->capped.mesh.vertices.back(), b->capped.mesh.vertices.back());
}

}  // namespace
}  // namespace skelseg
