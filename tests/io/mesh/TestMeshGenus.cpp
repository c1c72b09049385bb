#include "io/mesh/MeshGenus.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "io/mesh/MeshVoxelizer.h"
#include "kernels/VoxelGenus.h"
#include "tests/support/BoxMeshes.h"
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

/// Expects `t` to count these closed and other pieces, this Euler
/// characteristic and this genus.
void expectCounts(const MeshTopology& t, std::size_t closedPieces, std::size_t otherPieces,
                  std::int64_t eulerCharacteristic, std::int64_t genus) {
    EXPECT_EQ(t.closedPieces, closedPieces);
    EXPECT_EQ(t.otherPieces, otherPieces);
    EXPECT_EQ(t.eulerCharacteristic, eulerCharacteristic);
    EXPECT_EQ(t.genus, genus);
}

/// Appends triangle `t`, wound so that it faces away from `centre` (or
/// towards it, `outwards` false).
void appendFacing(TriangleMesh& mesh, std::array<std::uint32_t, 3> t, const Eigen::Vector3d& centre,
                  bool outwards = true) {
    const auto at = [&](std::uint32_t v) { return Eigen::Vector3d(mesh.vertices[v].data()); };
    const Eigen::Vector3d normal = (at(t[1]) - at(t[0])).cross(at(t[2]) - at(t[0]));
    if ((normal.dot((at(t[0]) + at(t[1]) + at(t[2])) / 3 - centre) > 0) != outwards)
        std::swap(t[1], t[2]);
    mesh.triangles.push_back(t);
    mesh.triangleFace.push_back(std::uint32_t(mesh.faceCount++));
}

/// Two unit cubes that share the edge from (1, 1, 0) to (1, 1, 1) and nothing else.
TriangleMesh cubesSharingAnEdge(bool outwards = true) {
    TriangleMesh mesh = test::unitCubes({{0, 0, 0}, {1, 1, 0}});
    if (!outwards)
        for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
    return mesh;
}

TEST(MeshGenus, ADoubleSidedFaceEnclosesNothing) {
    // A flap on one edge of a tetrahedron, written twice with opposite
    // windings (as writers of double-sided faces do): its edge is used by
    // four triangles, two of them at one angle, which no pairing tells apart.
    TriangleMesh mesh = tetrahedron();
    mesh.vertices.push_back({0.5, -1, -1});
    for (const std::array<std::uint32_t, 3> flap :
         {std::array<std::uint32_t, 3>{0, 1, 4}, {0, 4, 1}}) {
        mesh.triangles.push_back(flap);
        mesh.triangleFace.push_back(std::uint32_t(mesh.faceCount++));
    }
    expectCounts(meshTopology(mesh), 1, 0, 2, 0);
}

TEST(MeshGenus, AClosedSurfaceWrittenDoubleSidedHasNoKnownGenus) {
    // Every face twice, wound both ways: nothing is left once the pairs are
    // dropped, yet the voxel model holds the surface as a shell.
    TriangleMesh mesh = tetrahedron();
    for (const auto& t : tetrahedron().triangles) {
        mesh.triangles.push_back({t[0], t[2], t[1]});
        mesh.triangleFace.push_back(std::uint32_t(mesh.faceCount++));
    }
    const MeshTopology t = meshTopology(mesh);
    EXPECT_EQ(t.closedPieces, 0u);
    EXPECT_EQ(t.otherPieces, 1u);
    EXPECT_EQ(t.genus, 0);
}

TEST(MeshGenus, SolidsTouchingAlongAnEdgeAreTwoClosedPieces) {
    // Four triangles use the shared edge. Until they were paired round it
    // the two cubes were one non-manifold piece with no genus.
    // Turned off the axes too: the angles round the edge are measured in
    // no fixed frame.
    const Eigen::Matrix3d turns[] = {
        Eigen::Matrix3d::Identity(),
        Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix(),
        Eigen::AngleAxisd(2.9, Eigen::Vector3d(-3, 1, 0.5).normalized()).toRotationMatrix()};
    for (const bool outwards : {true, false})
        for (const Eigen::Matrix3d& turn : turns) {
            SCOPED_TRACE(outwards ? "facing outwards" : "facing inwards");
            TriangleMesh mesh = cubesSharingAnEdge(outwards);
            for (auto& v : mesh.vertices)
                Eigen::Vector3d::Map(v.data()) = turn * Eigen::Vector3d(v.data());
            expectCounts(meshTopology(mesh), 2, 0, 4, 0);
        }
}

TEST(MeshGenus, WindingsThatDoNotAlternateRoundAnEdgeLeaveItsPieceOut) {
    TriangleMesh mesh = cubesSharingAnEdge();
    // Turn one triangle of the second cube that uses the shared edge: round
    // the edge the windings no longer say which wedges are inside.
    const Eigen::Vector3d a(1, 1, 0), b(1, 1, 1);
    std::size_t turned = 0;
    for (std::size_t i = 12; i < mesh.triangles.size() && turned == 0; ++i) {
        int onEdge = 0;
        for (const std::uint32_t v : mesh.triangles[i]) {
            const Eigen::Vector3d p(mesh.vertices[v].data());
            onEdge += p == a || p == b;
        }
        if (onEdge == 2) std::swap(mesh.triangles[i][1], mesh.triangles[i][2]), ++turned;
    }
    ASSERT_EQ(turned, 1u);
    const MeshTopology t = meshTopology(mesh);
    EXPECT_EQ(t.closedPieces, 0u);
    EXPECT_EQ(t.otherPieces, 1u);
    EXPECT_EQ(t.genus, 0);
}

TEST(MeshGenus, CubesSharingWholeFacesAreTheirUnion) {
    // Each shared face is written twice, once per cube with opposite
    // windings: dropped as a double-sided face, it leaves the union's
    // surface, whose edges round the shared faces had four triangles.
    const TriangleMesh ring = test::ringOfUnitCubes();
    const MeshTopology t = meshTopology(ring);
    EXPECT_EQ(t.closedPieces, 1u);
    EXPECT_EQ(t.otherPieces, 0u);
    EXPECT_EQ(t.genus, 1);
    VoxelizeOptions options;
    options.resolution = 48;
    EXPECT_EQ(voxelTopology(voxelizeMesh(ring, options)).genus, 1);
    // One shared face split along its other diagonal in one of its cubes:
    // the two copies no longer cancel, and round its border edges two
    // triangles leave in one plane. The genus is not known.
    const MeshTopology u = meshTopology(test::ringOfUnitCubes(true));
    EXPECT_EQ(u.closedPieces, 0u);
    EXPECT_EQ(u.otherPieces, 1u);
}

TEST(MeshGenus, ATorusWithATetrahedronOnOneOfItsEdgesKeepsItsHandle) {
    TriangleMesh mesh = meshOfShape(torusShape(), {-42, -42, -12}, {42, 42, 12});
    ASSERT_EQ(meshTopology(mesh).genus, 1);
    // The edge at the outer equator (largest x), where the surface is convex:
    // a small tetrahedron standing on it lies outside the torus.
    std::size_t outermost = 0;
    for (std::size_t v = 1; v < mesh.vertices.size(); ++v)
        if (mesh.vertices[v][0] > mesh.vertices[outermost][0]) outermost = v;
    std::array<std::uint32_t, 3> facing{};
    for (const auto& t : mesh.triangles)
        if (std::find(t.begin(), t.end(), outermost) != t.end()) {
            facing = t;
            break;
        }
    const auto at = [&](std::uint32_t v) { return Eigen::Vector3d(mesh.vertices[v].data()); };
    const std::size_t k = std::find(facing.begin(), facing.end(), outermost) - facing.begin();
    const std::uint32_t a = facing[k], b = facing[(k + 1) % 3];
    const Eigen::Vector3d edge = at(b) - at(a);
    const Eigen::Vector3d outward(1, 0, 0);
    const Eigen::Vector3d side = edge.cross(outward).normalized() * 0.3 * edge.norm();
    const Eigen::Vector3d top = (at(a) + at(b)) / 2 + outward * 2.0;
    const auto base = std::uint32_t(mesh.vertices.size());
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(top + side), Eigen::Vector3d(top - side)})
        mesh.vertices.push_back({p.x(), p.y(), p.z()});
    const Eigen::Vector3d centre = (at(a) + at(b) + at(base) + at(base + 1)) / 4;
    for (const std::array<std::uint32_t, 3>& t : {std::array<std::uint32_t, 3>{a, b, base},
                                                  {a, b, base + 1},
                                                  {a, base, base + 1},
                                                  {b, base, base + 1}})
        appendFacing(mesh, t, centre);
    // The torus and the tetrahedron, pulled apart along their edge. Counted
    // as one non-manifold piece the handle was lost: genus 0, so a voxel
    // model of genus 1 read as one with a handle the mesh lacks.
    const MeshTopology t = meshTopology(mesh);
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
