#include "io/mesh/MeshGenus.h"

#include <gtest/gtest.h>

#include "io/mesh/MeshVoxelizer.h"
#include "kernels/VoxelGenus.h"
#include "tests/support/ShapeMeshes.h"

namespace skelseg {
namespace {

using test::meshOfShape;

TriangleMesh tetrahedron() {
    TriangleMesh mesh;
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    mesh.triangleFace = {0, 1, 2, 3};
    mesh.faceCount = 4;
    return mesh;
}

Shape torusShape() {
    Shape s;
    s.torus({0, 0, 0}, {0, 0, 1}, 30, 10);
    return s;
}

Shape doubleTorusShape() {
    Shape s;
    s.torus({-26, 0, 0}, {0, 0, 1}, 30, 10);
    s.torus({26, 0, 0}, {0, 0, 1}, 30, 10);
    return s;
}

TEST(MeshGenus, Tetrahedron) {
    const MeshTopology t = meshTopology(tetrahedron());
    EXPECT_EQ(t.closedPieces, 1u);
    EXPECT_EQ(t.eulerCharacteristic, 2);
    EXPECT_EQ(t.genus, 0);
}

TEST(MeshGenus, OpenPieceHasNoGenus) {
    TriangleMesh mesh = tetrahedron();
    mesh.triangles.pop_back();
    mesh.triangleFace.pop_back();
    mesh.faceCount = 3;
    const MeshTopology t = meshTopology(mesh);
    EXPECT_EQ(t.closedPieces, 0u);
    EXPECT_EQ(t.otherPieces, 1u);
    EXPECT_EQ(t.genus, 0);
}

TEST(MeshGenus, DuplicatedVerticesAreOneVertex) {
    TriangleMesh mesh = tetrahedron();
    // The last face uses copies of its vertices, as a writer splitting seams would.
    mesh.vertices.push_back(mesh.vertices[1]);
    mesh.vertices.push_back(mesh.vertices[2]);
    mesh.vertices.push_back(mesh.vertices[3]);
    mesh.triangles[3] = {4, 5, 6};
    const MeshTopology t = meshTopology(mesh);
    EXPECT_EQ(t.closedPieces, 1u);
    EXPECT_EQ(t.genus, 0);
}

/// `mesh` and a tetrahedron one of whose corners lies on `mesh`'s vertex
/// `at` (the same position, so one vertex once positions are merged) and
/// the others away from it: the two touch in that vertex only.
TriangleMesh withTetrahedronTouchingAt(TriangleMesh mesh, std::size_t at) {
    const auto base = std::uint32_t(mesh.vertices.size());
    const auto p = mesh.vertices[at];
    for (const auto& q : tetrahedron().vertices)
        mesh.vertices.push_back({p[0] + 5 * q[0], p[1] + 5 * q[1], p[2] + 5 * q[2] + 1});
    mesh.vertices[base] = p;  // corner 0 of the tetrahedron sits on vertex `at`
    for (const auto& t : tetrahedron().triangles) {
        mesh.triangles.push_back({base + t[0], base + t[1], base + t[2]});
        mesh.triangleFace.push_back(std::uint32_t(mesh.faceCount++));
    }
    return mesh;
}

TEST(MeshGenus, PiecesTouchingInOneVertexAreTwoClosedPieces) {
    // Two tetrahedra sharing one vertex: counted as one vertex it made
    // V - E + F = 7 - 12 + 8 = 3, odd, and no closed piece at all.
    const MeshTopology t = meshTopology(withTetrahedronTouchingAt(tetrahedron(), 3));
    EXPECT_EQ(t.closedPieces, 2u);
    EXPECT_EQ(t.otherPieces, 0u);
    EXPECT_EQ(t.eulerCharacteristic, 4);
    EXPECT_EQ(t.genus, 0);
}

TEST(MeshGenus, ATorusTouchedInOneVertexKeepsItsHandle) {
    const TriangleMesh torus = meshOfShape(torusShape(), {-42, -42, -12}, {42, 42, 12});
    ASSERT_EQ(meshTopology(torus).genus, 1);
    // The handle counted (genus 1, not 0) is what keeps a voxel model of
    // genus 1 from being read as one with a handle the mesh lacks.
    const MeshTopology t = meshTopology(withTetrahedronTouchingAt(torus, 0));
    EXPECT_EQ(t.closedPieces, 2u);
    EXPECT_EQ(t.otherPieces, 0u);
    EXPECT_EQ(t.genus, 1);
}

TEST(MeshGenus, SphereTorusAndDoubleTorusMeshesAndTheirVoxels) {
    Shape sphere;
    sphere.sphere({0, 0, 0}, 30);
    struct Case {
        const char* name;
        Shape shape;
        std::array<int, 3> lo, hi;
        std::int64_t genus;
    };
    const Case cases[] = {{"sphere", sphere, {-32, -32, -32}, {32, 32, 32}, 0},
                          {"torus", torusShape(), {-42, -42, -12}, {42, 42, 12}, 1},
                          {"double torus", doubleTorusShape(), {-68, -42, -12}, {68, 42, 12}, 2}};
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const TriangleMesh mesh = meshOfShape(c.shape, c.lo, c.hi);
        const MeshTopology t = meshTopology(mesh);
        EXPECT_EQ(t.closedPieces, 1u);
        EXPECT_EQ(t.otherPieces, 0u);
        EXPECT_EQ(t.genus, c.genus);
        VoxelizeOptions options;
        options.resolution = 48;
        EXPECT_EQ(voxelTopology(voxelizeMesh(mesh, options)).genus, c.genus);
    }
}

}  // namespace
}  // namespace skelseg
