#include "io/mesh/MeshFins.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "io/mesh/MeshCheck.h"
#include "tests/support/BoxMeshes.h"

namespace skelseg {
namespace {

/// The unit cube [0, 1]^3, one face per triangle.
TriangleMesh unitCubeOfTwelveFaces() {
    TriangleMesh mesh = test::unitCubes({{0, 0, 0}});
    std::iota(mesh.triangleFace.begin(), mesh.triangleFace.end(), 0u);
    return mesh;
}

/// Appends a triangle standing on the edge (a, b) of `mesh`, its third corner
/// `apex`; `ownCorners`: a, b written again as new vertices at the same
/// positions, as exporters that split vertices per face do.
void addFinTriangle(TriangleMesh& mesh, std::uint32_t a, std::uint32_t b,
                    const std::array<double, 3>& apex, bool ownCorners = false) {
    if (ownCorners) {
        mesh.vertices.push_back(mesh.vertices[a]);
        mesh.vertices.push_back(mesh.vertices[b]);
        a = std::uint32_t(mesh.vertices.size() - 2);
        b = std::uint32_t(mesh.vertices.size() - 1);
    }
    mesh.vertices.push_back(apex);
    mesh.triangles.push_back({a, b, std::uint32_t(mesh.vertices.size() - 1)});
    mesh.triangleFace.push_back(std::uint32_t(mesh.faceCount++));
}

/// The vertices of the cube's corners at (0, 0, 0) and (1, 0, 0).
struct CubeEdge {
    std::uint32_t a = 0, b = 0;
};
CubeEdge lowerFrontEdge(const TriangleMesh& mesh) {
    CubeEdge edge;
    for (std::uint32_t v = 0; v < std::uint32_t(mesh.vertices.size()); ++v) {
        const auto& p = mesh.vertices[v];
        if (p == std::array<double, 3>{0, 0, 0}) edge.a = v;
        if (p == std::array<double, 3>{1, 0, 0}) edge.b = v;
    }
    return edge;
}

TEST(MeshFins, AClosedMeshHasNone) {
    const TriangleMesh mesh = unitCubeOfTwelveFaces();
    const std::vector<char> fins = finTriangles(mesh);
    EXPECT_EQ(std::count(fins.begin(), fins.end(), 1), 0);
    EXPECT_FALSE(closedWithoutFins(mesh).has_value());
}

TEST(MeshFins, ATriangleStandingOnAnEdgeIsDroppedAndTheRestIsClosed) {
    for (const bool ownCorners : {false, true}) {
        SCOPED_TRACE(ownCorners ? "corners written again" : "corners shared");
        TriangleMesh mesh = unitCubeOfTwelveFaces();
        const CubeEdge edge = lowerFrontEdge(mesh);
        addFinTriangle(mesh, edge.a, edge.b, {0.5, -0.05, -0.05}, ownCorners);
        const MeshDiagnostics asRead = checkMesh(mesh);
        ASSERT_FALSE(asRead.closed);
        ASSERT_EQ(asRead.boundaryEdges, 2u);
        ASSERT_EQ(asRead.nonManifoldEdges, 1u);

        const std::vector<char> fins = finTriangles(mesh);
        EXPECT_EQ(std::count(fins.begin(), fins.end(), 1), 1);
        EXPECT_EQ(fins.back(), 1);
        const auto withoutFins = closedWithoutFins(mesh);
        ASSERT_TRUE(withoutFins.has_value());
        EXPECT_EQ(withoutFins->finFaces, 1u);
        EXPECT_EQ(withoutFins->mesh.triangles.size(), 12u);
        EXPECT_EQ(withoutFins->mesh.faceCount, 12u);
        EXPECT_TRUE(checkMesh(withoutFins->mesh).closed);
        // The fin: base 1, height 0.05 * sqrt(2), against the cube's 6.
        const double finArea = 0.5 * 0.05 * std::sqrt(2.0);
        EXPECT_NEAR(withoutFins->finAreaShare, finArea / (6.0 + finArea), 1e-12);
    }
}

TEST(MeshFins, OpenSheetsAreNumberedInTheOrderOfTheirFirstTriangles) {
    // Two fins on the cube, written before it and after it: the cube's
    // sheet is closed, and each fin is its own open sheet.
    TriangleMesh mesh;
    mesh.vertices = {{5, 0, 0}, {6, 0, 0}, {5, 1, 0}};
    mesh.triangles = {{0, 1, 2}};
    mesh.triangleFace = {0};
    mesh.faceCount = 1;
    const TriangleMesh cube = unitCubeOfTwelveFaces();
    const auto offset = std::uint32_t(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(), cube.vertices.begin(), cube.vertices.end());
    for (const auto& t : cube.triangles) {
        mesh.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
        mesh.triangleFace.push_back(std::uint32_t(mesh.faceCount++));
    }
    const CubeEdge edge = lowerFrontEdge(mesh);
    addFinTriangle(mesh, edge.a, edge.b, {0.5, -0.05, -0.05});
    const std::vector<std::uint32_t> sheets = openSheets(mesh);
    ASSERT_EQ(sheets.size(), 14u);
    EXPECT_EQ(sheets.front(), 0u);
    EXPECT_EQ(sheets.back(), 1u);
    for (std::size_t t = 1; t < 13; ++t) EXPECT_EQ(sheets[t], kNotInOpenSheet);
}

TEST(MeshFins, AFlapOfOnePolygonIsOneFinFaceAndTheOtherFacesAreRenumbered) {
    // The flap (a quad, two triangles) comes first in the file: the cube's
    // faces keep their order and are numbered from 0.
    const TriangleMesh box = unitCubeOfTwelveFaces();
    const CubeEdge edge = lowerFrontEdge(box);
    TriangleMesh mesh;
    mesh.vertices = box.vertices;
    mesh.vertices.push_back({1, -0.05, 0});
    mesh.vertices.push_back({0, -0.05, 0});
    const auto c = std::uint32_t(box.vertices.size()), d = c + 1;
    mesh.triangles = {{edge.a, edge.b, c}, {edge.a, c, d}};
    mesh.triangleFace = {0, 0};
    for (std::size_t t = 0; t < box.triangles.size(); ++t) {
        mesh.triangles.push_back(box.triangles[t]);
        mesh.triangleFace.push_back(std::uint32_t(1 + t));
    }
    mesh.faceCount = 1 + box.faceCount;

    const std::vector<char> fins = finTriangles(mesh);
    EXPECT_EQ(fins[0], 1);
    EXPECT_EQ(fins[1], 1);
    EXPECT_EQ(std::count(fins.begin(), fins.end(), 1), 2);
    const auto withoutFins = closedWithoutFins(mesh);
    ASSERT_TRUE(withoutFins.has_value());
    EXPECT_EQ(withoutFins->finFaces, 1u);
    EXPECT_EQ(withoutFins->mesh.faceCount, 12u);
    std::vector<std::uint32_t> inOrder(12);
    std::iota(inOrder.begin(), inOrder.end(), 0u);
    EXPECT_EQ(withoutFins->mesh.triangleFace, inOrder);
    EXPECT_EQ(withoutFins->mesh.triangles, box.triangles);
}

TEST(MeshFins, LooseFacesAreFinsToo) {
    // A triangle touching the cube at one corner, and one floating beside
    // it: both open sheets, neither joined along an edge.
    for (const bool touching : {true, false}) {
        SCOPED_TRACE(touching ? "at a corner" : "floating");
        TriangleMesh mesh = unitCubeOfTwelveFaces();
        const CubeEdge edge = lowerFrontEdge(mesh);
        std::uint32_t corner = edge.a;  // the cube's (0, 0, 0)
        if (!touching) {
            corner = std::uint32_t(mesh.vertices.size());
            mesh.vertices.push_back({-0.02, -0.02, -0.02});
        }
        mesh.vertices.push_back({-0.05, -0.1, 0});
        mesh.vertices.push_back({0, -0.1, -0.05});
        const auto last = std::uint32_t(mesh.vertices.size() - 1);
        mesh.triangles.push_back({corner, last - 1, last});
        mesh.triangleFace.push_back(std::uint32_t(mesh.faceCount++));
        const MeshDiagnostics asRead = checkMesh(mesh);
        ASSERT_EQ(asRead.boundaryEdges, 3u);
        ASSERT_EQ(asRead.nonManifoldEdges, 0u);
        const auto withoutFins = closedWithoutFins(mesh);
        ASSERT_TRUE(withoutFins.has_value());
        EXPECT_EQ(withoutFins->finFaces, 1u);
        EXPECT_EQ(withoutFins->mesh.triangles.size(), 12u);
    }
}

TEST(MeshFins, AMeshWithAHoleHasNoneToDrop) {
    // The sheet round the hole is the whole surface: far over the limit.
    TriangleMesh mesh = unitCubeOfTwelveFaces();
    mesh.triangles.pop_back();
    mesh.triangleFace.pop_back();
    const std::vector<char> fins = finTriangles(mesh);
    EXPECT_EQ(std::count(fins.begin(), fins.end(), 1), 11);
    EXPECT_FALSE(closedWithoutFins(mesh).has_value());
}

TEST(MeshFins, AnOpenMeshWithAFinStaysOpen) {
    // A hole elsewhere: the surface without the fin is still open.
    TriangleMesh mesh = unitCubeOfTwelveFaces();
    const CubeEdge edge = lowerFrontEdge(mesh);
    addFinTriangle(mesh, edge.a, edge.b, {0.5, -0.05, -0.05});
    // The cube's +z face (addBox's triangles 2 and 3) removed.
    mesh.triangles.erase(mesh.triangles.begin() + 2, mesh.triangles.begin() + 4);
    mesh.triangleFace.erase(mesh.triangleFace.begin() + 2, mesh.triangleFace.begin() + 4);
    ASSERT_GT(checkMesh(mesh).boundaryEdges, 2u);
    EXPECT_FALSE(closedWithoutFins(mesh).has_value());
}

TEST(MeshFins, ALargeSheetKeepsTheMeshOpen) {
    // A flap of 2.4% of the area could be a part: the shell method keeps it.
    TriangleMesh mesh = unitCubeOfTwelveFaces();
    const CubeEdge edge = lowerFrontEdge(mesh);
    addFinTriangle(mesh, edge.a, edge.b, {0.5, -0.3, 0});
    const std::vector<char> fins = finTriangles(mesh);
    EXPECT_EQ(fins.back(), 1);
    EXPECT_FALSE(closedWithoutFins(mesh).has_value());
}

TEST(MeshFins, AnAreaBeyondADoubleGivesNoShare) {
    // At 1e160 every area overflows: the fins' share is inf / inf, which
    // was taken for "under 1 %" (found by FuzzPly).
    TriangleMesh mesh = unitCubeOfTwelveFaces();
    const CubeEdge edge = lowerFrontEdge(mesh);
    addFinTriangle(mesh, edge.a, edge.b, {0.5, -0.05, -0.05});
    for (auto& vertex : mesh.vertices)
        for (double& c : vertex) c *= 1e160;
    const auto withoutFins = closedWithoutFins(mesh);
    if (withoutFins) EXPECT_LE(withoutFins->finAreaShare, kMaxFinAreaShare);
}

TEST(MeshFins, SolidsTouchingAlongAnEdgeHaveNone) {
    // Four triangles on one edge, none with a free border.
    const TriangleMesh mesh = test::unitCubes({{0, 0, 0}, {1, 1, 0}});
    ASSERT_GT(checkMesh(mesh).nonManifoldEdges, 0u);
    const std::vector<char> fins = finTriangles(mesh);
    EXPECT_EQ(std::count(fins.begin(), fins.end(), 1), 0);
    EXPECT_FALSE(closedWithoutFins(mesh).has_value());
}

TEST(MeshFins, TheWarningCountsFacesInNumber) {
    MeshWithoutFins one;
    one.finFaces = 1;
    one.finAreaShare = 0.0017;
    EXPECT_EQ(finsWarning("cat.obj", one).rfind("cat.obj: 1 face lies on fins (", 0), 0u)
        << finsWarning("cat.obj", one);
    EXPECT_NE(finsWarning("cat.obj", one).find("; 0.17% of its area)"), std::string::npos)
        << finsWarning("cat.obj", one);
    MeshWithoutFins two = one;
    two.finFaces = 2;
    EXPECT_EQ(finsWarning("cat.obj", two).rfind("cat.obj: 2 faces lie on fins (", 0), 0u);
    // Fin triangles of quads whose other triangle is kept (a fuzzed file):
    // no whole face is a fin's, and the warning does not say "0 faces".
    MeshWithoutFins partly = one;
    partly.finFaces = 0;
    EXPECT_EQ(finsWarning("cat.obj", partly).rfind("cat.obj: parts of faces lie on fins (", 0), 0u);
}

}  // namespace
}  // namespace skelseg
