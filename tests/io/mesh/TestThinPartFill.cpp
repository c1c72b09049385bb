#include "io/mesh/ThinPartFill.h"

#include <gtest/gtest.h>

#include <cmath>

#include "io/mesh/MeshVoxelizer.h"
#include "kernels/VoxelGenus.h"

namespace skelseg {
namespace {

constexpr double kPi = 3.14159265358979323846;
using Rotation = std::array<std::array<double, 3>, 3>;

/// Rotation by `degrees` about the (normalised) axis.
Rotation rotation(std::array<double, 3> axis, double degrees) {
    const double length = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    for (double& a : axis) a /= length;
    const double c = std::cos(degrees * kPi / 180), s = std::sin(degrees * kPi / 180);
    const double x = axis[0], y = axis[1], z = axis[2];
    return {{{c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s},
             {y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s},
             {z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)}}};
}

/// Appends the closed box [-size/2, size/2] (outward normals), rotated and
/// moved to `centre`.
void addBox(TriangleMesh& mesh, const std::array<double, 3>& size, const Rotation& r,
            const std::array<double, 3>& centre = {0, 0, 0}) {
    const auto first = std::uint32_t(mesh.vertices.size());
    for (int corner = 0; corner < 8; ++corner) {
        const double p[3] = {(corner & 1 ? 0.5 : -0.5) * size[0],
                             (corner & 2 ? 0.5 : -0.5) * size[1],
                             (corner & 4 ? 0.5 : -0.5) * size[2]};
        std::array<double, 3> q{};
        for (std::size_t i = 0; i < 3; ++i)
            q[i] = centre[i] + r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2];
        mesh.vertices.push_back(q);
    }
    const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                       {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        mesh.triangles.push_back({first + q[0], first + q[1], first + q[2]});
        mesh.triangles.push_back({first + q[0], first + q[2], first + q[3]});
    }
    mesh.triangleFace.resize(mesh.triangles.size());
    mesh.faceCount = mesh.triangles.size();
}

/// A square sheet 40 units wide and `thickness` thick, rotated by r.
TriangleMesh sheet(double thickness, const Rotation& r) {
    TriangleMesh mesh;
    addBox(mesh, {40, 40, thickness}, r);
    return mesh;
}

VoxelizeOptions options(bool fill, int resolution, bool threaded = true) {
    VoxelizeOptions o;
    o.resolution = resolution;
    o.fillThinParts = fill;
    o.threaded = threaded;
    return o;
}

const Rotation kOrientations[] = {rotation({1, 0, 0}, 0),   rotation({1, 0, 0}, 30),
                                  rotation({1, 1, 0}, 45),  rotation({1, 2, 3}, 37),
                                  rotation({3, -1, 2}, 61), rotation({0, 1, 1}, 54.7356)};

TEST(ThinPartFill, SheetThinnerThanAVoxelIsOneObjectOfGenusZero) {
    constexpr int kResolution = 48;
    int perforatedWithoutFill = 0;
    for (const Rotation& r : kOrientations) {
        // The voxel size comes from the bounding box, which the thickness
        // hardly changes: measure it on a sheet without thickness first.
        const double voxel =
            voxelGridFor(sheet(0.0, r), options(true, kResolution)).geometry.voxelSize();
        const TriangleMesh mesh = sheet(0.4 * voxel, r);
        const VoxelTopology without =
            voxelTopology(voxelizeMesh(mesh, options(false, kResolution)));
        perforatedWithoutFill += without.genus != 0 || without.objects != 1;
        const MeshVoxelization with = voxelizeMeshWithContacts(mesh, options(true, kResolution));
        const VoxelTopology topology = voxelTopology(with.mask);
        EXPECT_EQ(topology.genus, 0) << "rotation " << &r - kOrientations;
        EXPECT_EQ(topology.objects, 1u) << "rotation " << &r - kOrientations;
        EXPECT_EQ(topology.cavities, 0u) << "rotation " << &r - kOrientations;
        EXPECT_GT(with.thinParts.voxelsAdded, 0u);
    }
    EXPECT_GT(perforatedWithoutFill, 0) << "the sheets must break without the fill";
}

TEST(ThinPartFill, ThinSpikeGivesNoIsland) {
    // A cube with a spike of 0.3 x 0.3 voxels sticking out of it at an angle
    // to every axis: its few voxel centres would be islands.
    constexpr int kResolution = 40;
    int brokenWithoutFill = 0;
    for (const Rotation& r : {rotation({1, 2, 3}, 37), rotation({2, -1, 1}, 50)}) {
        auto build = [&](double voxel) {
            TriangleMesh mesh;
            addBox(mesh, {20, 20, 20}, rotation({1, 0, 0}, 0));
            const std::array<double, 3> tip{r[0][2] * 20, r[1][2] * 20, r[2][2] * 20};
            addBox(mesh, {0.3 * voxel, 0.3 * voxel, 40}, r, tip);
            return mesh;
        };
        const double voxel =
            voxelGridFor(build(1.0), options(true, kResolution)).geometry.voxelSize();
        const TriangleMesh mesh = build(voxel);
        brokenWithoutFill +=
            voxelTopology(voxelizeMesh(mesh, options(false, kResolution))).objects != 1;
        const VoxelTopology topology =
            voxelTopology(voxelizeMesh(mesh, options(true, kResolution)));
        EXPECT_EQ(topology.objects, 1u);
        EXPECT_EQ(topology.genus, 0);
    }
    EXPECT_GT(brokenWithoutFill, 0) << "the spike must break into islands without the fill";
}

TEST(ThinPartFill, ThickShapesAreLeftAlone) {
    // A box 6 voxels thick at an angle: no chord is thin, nothing is added.
    const TriangleMesh mesh = sheet(6.0, rotation({1, 2, 3}, 37));
    const MeshVoxelization with = voxelizeMeshWithContacts(mesh, options(true, 40));
    EXPECT_EQ(with.thinParts.voxelsAdded, 0u);
    EXPECT_EQ(with.mask.values(), voxelizeMesh(mesh, options(false, 40)).values());
}

TEST(ThinPartFill, SerialEqualsParallel) {
    const TriangleMesh mesh = sheet(0.3, rotation({1, 2, 3}, 37));
    const MeshVoxelization serial = voxelizeMeshWithContacts(mesh, options(true, 64, false));
    const MeshVoxelization threaded = voxelizeMeshWithContacts(mesh, options(true, 64, true));
    EXPECT_GT(serial.thinParts.voxelsAdded, 0u);
    EXPECT_EQ(serial.thinParts.voxelsAdded, threaded.thinParts.voxelsAdded);
    EXPECT_EQ(serial.thinParts.thinSamples, threaded.thinParts.thinSamples);
    EXPECT_EQ(serial.mask.values(), threaded.mask.values());
}

}  // namespace
}  // namespace skelseg
