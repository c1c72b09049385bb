#include "io/mesh/FlippedFaces.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>

#include "io/mesh/MeshCheck.h"
#include "tests/support/CurledTube.h"
#include "tests/support/MeshEdits.h"

namespace skelseg {
namespace {

double centroidX(const TriangleMesh& mesh, std::size_t t) {
    const auto& c = mesh.triangles[t];
    return (mesh.vertices[c[0]][0] + mesh.vertices[c[1]][0] + mesh.vertices[c[2]][0]) / 3.0;
}

/// `mesh` with the triangles `flip(t)` picks wound the other way; their count.
template <typename Flip>
std::pair<TriangleMesh, std::size_t> withFlipped(const TriangleMesh& mesh, Flip flip) {
    TriangleMesh out = mesh;
    std::size_t flipped = 0;
    for (std::size_t t = 0; t < out.triangles.size(); ++t) {
        if (!flip(t)) continue;
        std::swap(out.triangles[t][1], out.triangles[t][2]);
        ++flipped;
    }
    return {out, flipped};
}

TEST(FlippedFaces, AConsistentMeshHasNone) {
    EXPECT_FALSE(withFlippedFacesTurned(test::sphereMesh({0, 0, 0}, 1.0)).has_value());
    // Wound inward all over is consistent too (a hollow's inner wall): kept.
    const auto inward =
        withFlipped(test::sphereMesh({0, 0, 0}, 1.0), [](std::size_t) { return true; });
    EXPECT_FALSE(withFlippedFacesTurned(inward.first).has_value());
}

TEST(FlippedFaces, APatchWoundTheWrongWayIsTurnedBack) {
    const TriangleMesh sphere = test::sphereMesh({0, 0, 0}, 1.0);
    const auto [flipped, count] =
        withFlipped(sphere, [&](std::size_t t) { return centroidX(sphere, t) > 0.6; });
    ASSERT_GT(count, 10u);
    ASSERT_GT(checkMesh(flipped).misorientedEdges, 0u);
    const auto turned = withFlippedFacesTurned(flipped);
    ASSERT_TRUE(turned.has_value());
    EXPECT_EQ(turned->turnedFaces, count);
    EXPECT_GT(turned->turnedAreaShare, 0.0);
    EXPECT_LT(turned->turnedAreaShare, 0.5);
    EXPECT_EQ(turned->diagnostics.misorientedEdges, 0u);
    EXPECT_TRUE(turned->diagnostics.closed);
    EXPECT_TRUE(turned->mesh.triangles == sphere.triangles);
    EXPECT_TRUE(turned->mesh.vertices == flipped.vertices);
    EXPECT_TRUE(turned->mesh.triangleFace == flipped.triangleFace);
}

TEST(FlippedFaces, TheLargerShareOfTheAreaKeepsItsWinding) {
    // Most of the sphere flipped: the rest is turned to agree with it.
    const TriangleMesh sphere = test::sphereMesh({0, 0, 0}, 1.0);
    const auto [flipped, count] =
        withFlipped(sphere, [&](std::size_t t) { return centroidX(sphere, t) > -0.5; });
    const auto turned = withFlippedFacesTurned(flipped);
    ASSERT_TRUE(turned.has_value());
    EXPECT_EQ(turned->turnedFaces, sphere.triangles.size() - count);
    EXPECT_EQ(turned->diagnostics.misorientedEdges, 0u);
    const auto inward = withFlipped(sphere, [](std::size_t) { return true; }).first;
    EXPECT_TRUE(turned->mesh.triangles == inward.triangles);
}

TEST(FlippedFaces, EachPieceIsWoundOnItsOwn) {
    // A sphere wound right beside one wound inward with a patch flipped:
    // the second keeps its inward winding, and only its patch is turned.
    TriangleMesh mesh = test::sphereMesh({0, 0, 0}, 1.0);
    const TriangleMesh second = test::sphereMesh({3, 0, 0}, 1.0);
    const auto inwardWithPatch = withFlipped(second, [&](std::size_t t) {
        return centroidX(second, t) < 3.6;  // all but the patch at x > 3.6
    });
    test::appendPiece(mesh, inwardWithPatch.first);
    const auto turned = withFlippedFacesTurned(mesh);
    ASSERT_TRUE(turned.has_value());
    EXPECT_EQ(turned->turnedFaces, second.triangles.size() - inwardWithPatch.second);
    EXPECT_EQ(turned->diagnostics.misorientedEdges, 0u);
    const std::size_t first = test::sphereMesh({0, 0, 0}, 1.0).triangles.size();
    for (std::size_t t = 0; t < first; ++t) EXPECT_EQ(turned->mesh.triangles[t], mesh.triangles[t]);
}

TEST(FlippedFaces, AMoebiusStripIsLeftAsItIs) {
    // No winding makes a Moebius strip consistent: nothing is turned.
    TriangleMesh strip;
    const int segments = 24;
    const double pi = std::acos(-1.0);
    for (int k = 0; k < segments; ++k) {
        const double a = 2.0 * pi * k / segments, half = a / 2.0;
        for (const double w : {-0.3, 0.3}) {
            const double r = 1.0 + w * std::cos(half);
            strip.vertices.push_back({r * std::cos(a), r * std::sin(a), w * std::sin(half)});
        }
    }
    for (int k = 0; k < segments; ++k) {
        const auto i = std::uint32_t(2 * k), j = std::uint32_t(2 * ((k + 1) % segments));
        // The last quad joins the strip's ends with its sides exchanged.
        const bool twist = k + 1 == segments;
        const std::uint32_t j0 = twist ? j + 1 : j, j1 = twist ? j : j + 1;
        strip.triangles.push_back({i, j0, j1});
        strip.triangles.push_back({i, j1, i + 1});
    }
    for (std::uint32_t t = 0; t < strip.triangles.size(); ++t) strip.triangleFace.push_back(t);
    strip.faceCount = strip.triangles.size();
    ASSERT_GT(checkMesh(strip).misorientedEdges, 0u);
    EXPECT_FALSE(withFlippedFacesTurned(strip).has_value());
}

TEST(FlippedFaces, APolygonIsTurnedAsOneFace) {
    // The sphere's triangles paired into quads (two triangles per face): a
    // flipped quad counts as one face turned.
    TriangleMesh sphere = test::sphereMesh({0, 0, 0}, 1.0);
    sphere.faceCount = 0;
    sphere.triangleFace.clear();
    for (std::size_t t = 0; t < sphere.triangles.size(); ++t)
        sphere.triangleFace.push_back(std::uint32_t(t / 2));
    sphere.faceCount = (sphere.triangles.size() + 1) / 2;
    const auto flipped = withFlipped(sphere, [](std::size_t t) { return t == 200 || t == 201; });
    const auto turned = withFlippedFacesTurned(flipped.first);
    ASSERT_TRUE(turned.has_value());
    EXPECT_EQ(turned->turnedFaces, 1u);
    EXPECT_TRUE(turned->mesh.triangles == sphere.triangles);
}

TEST(FlippedFaces, TheFaceOrderGivesTheSameTurns) {
    const TriangleMesh sphere = test::sphereMesh({0, 0, 0}, 1.0);
    const TriangleMesh flipped =
        withFlipped(sphere, [&](std::size_t t) { return centroidX(sphere, t) > 0.3; }).first;
    std::vector<std::size_t> order(flipped.triangles.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::mt19937 random(7);
    std::shuffle(order.begin(), order.end(), random);
    TriangleMesh shuffled = flipped;
    for (std::size_t k = 0; k < order.size(); ++k)
        shuffled.triangles[k] = flipped.triangles[order[k]];
    const auto a = withFlippedFacesTurned(flipped);
    const auto b = withFlippedFacesTurned(shuffled);
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->turnedFaces, b->turnedFaces);
    for (std::size_t k = 0; k < order.size(); ++k)
        EXPECT_EQ(b->mesh.triangles[k], a->mesh.triangles[order[k]]);
}

TEST(FlippedFaces, TheWarningSaysHowManyAndWhy) {
    MeshWithFlippedFacesTurned one;
    one.turnedFaces = 1;
    one.turnedAreaShare = 0.0004;
    EXPECT_EQ(flippedFacesWarning("homer.obj", one)
                  .rfind("homer.obj: 1 face was wound against the faces around it (flipped; "
                         "0.04% of its area): it is turned",
                         0),
              0u)
        << flippedFacesWarning("homer.obj", one);
    MeshWithFlippedFacesTurned many = one;
    many.turnedFaces = 1594;
    EXPECT_EQ(flippedFacesWarning("michael.off", many).rfind("michael.off: 1594 faces were", 0),
              0u);
}

}  // namespace
}  // namespace skelseg
