#include "io/mesh/ThinPartFill.h"

#include <gtest/gtest.h>

#include <cmath>

#include "io/mesh/MeshVoxelizer.h"
#include "kernels/VoxelGenus.h"
#include "tests/support/BoxMeshes.h"
#include "tests/support/CurledTube.h"
#include "tests/support/StopAtOnce.h"

namespace skelseg {
namespace {

using test::addBox;
using test::Rotation;
using test::rotation;

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

TEST(ThinPartFill, RaysMeetTheTrianglesOfTheirCellsAsTheyWouldMeetEveryTriangle) {
    // A UV sphere flattened into a closed disc under a voxel thick at its
    // centre and thinner towards its rim, turned obliquely: about 800
    // triangles of one to seven voxels, so a ray often ends in another cell
    // than it starts in and sees several triangles there. The reference
    // tests every ray exactly against every triangle; a cell list that
    // misses one, or a plane test that rejects a hit, changes the fill.
    for (const std::size_t orientation : {3u, 4u, 5u}) {
        const Rotation& r = kOrientations[orientation];
        TriangleMesh mesh = test::sphereMesh({0, 0, 0}, 20.0, 18, 24);
        for (auto& v : mesh.vertices) {
            const std::array<double, 3> flat{v[0], v[1], v[2] * 0.3 / 20.0};
            for (std::size_t i = 0; i < 3; ++i)
                v[i] = r[i][0] * flat[0] + r[i][1] * flat[1] + r[i][2] * flat[2];
        }
        const MaskVolume unfilled = voxelizeMesh(mesh, options(false, 48));
        MaskVolume byCells = unfilled, byEveryTriangle = unfilled;
        ThinPartOptions reference;
        reference.testEveryTriangle = true;
        const ThinPartFill cells = fillThinParts(mesh, byCells, {});
        const ThinPartFill every = fillThinParts(mesh, byEveryTriangle, reference);
        EXPECT_GT(cells.voxelsAdded, 100u) << "rotation " << orientation;
        EXPECT_EQ(cells.thinSamples, every.thinSamples) << "rotation " << orientation;
        EXPECT_EQ(cells.voxelsAdded, every.voxelsAdded) << "rotation " << orientation;
        EXPECT_TRUE(byCells.values() == byEveryTriangle.values()) << "rotation " << orientation;
    }
}

TEST(ThinPartFill, SecondVoxelisationFromTheKeptConversionIsTheSame) {
    // The engine voxelises without the fill, then again with it starting
    // from the kept conversion: both must equal a voxelisation from scratch.
    const TriangleMesh mesh = sheet(0.3, rotation({1, 2, 3}, 37));
    SignedVoxelization kept;
    const MeshVoxelization first =
        voxelizeMeshWithContacts(mesh, options(false, 64), nullInterrupter(), &kept);
    ASSERT_EQ(kept.mesh, &mesh);
    ASSERT_FALSE(kept.mask.empty());
    EXPECT_EQ(first.mask.values(), voxelizeMesh(mesh, options(false, 64)).values());
    for (bool threaded : {false, true}) {
        const MeshVoxelization again =
            voxelizeMeshWithContacts(mesh, options(true, 64, threaded), nullInterrupter(), &kept);
        const MeshVoxelization fresh = voxelizeMeshWithContacts(mesh, options(true, 64, threaded));
        EXPECT_GT(fresh.thinParts.voxelsAdded, 0u);
        EXPECT_EQ(again.thinParts.voxelsAdded, fresh.thinParts.voxelsAdded);
        EXPECT_EQ(again.thinParts.thinSamples, fresh.thinParts.thinSamples);
        EXPECT_EQ(again.mask.values(), fresh.mask.values());
    }
    // Another grid does not fit: converted anew, and kept for that grid.
    const MeshVoxelization other =
        voxelizeMeshWithContacts(mesh, options(true, 48), nullInterrupter(), &kept);
    EXPECT_EQ(other.mask.values(), voxelizeMesh(mesh, options(true, 48)).values());
    EXPECT_EQ(kept.dims, other.mask.dims());
}

TEST(ThinPartFill, AStopAnsweredOnceAtAnyPollThrows) {
    const TriangleMesh mesh = sheet(0.3, rotation({1, 2, 3}, 37));
    const MaskVolume unfilled = voxelizeMesh(mesh, options(false, 32));
    for (const bool threaded : {false, true}) {
        SCOPED_TRACE(threaded ? "threaded" : "serial");
        ThinPartOptions thin;
        thin.threaded = threaded;
        MaskVolume filled = unfilled;
        ASSERT_GT(fillThinParts(mesh, filled, thin).voxelsAdded, 0u);
        EXPECT_GT(test::expectAStopAtAnyPollThrows([&](Interrupter& interrupter) {
                      MaskVolume mask = unfilled;
                      fillThinParts(mesh, mask, thin, interrupter);
                  }),
                  1);
    }
}

}  // namespace
}  // namespace skelseg
