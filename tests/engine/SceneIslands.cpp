// Scene tests: islands are not parts (issue 12). Stray voxels and small
// pieces beside a shape, in a volume or a mesh, add no segments.
#include <gtest/gtest.h>

#include <set>

#include "io/mesh/FaceLabels.h"
#include "io/mesh/MeshVoxelizer.h"
#include "tests/support/SceneSupport.h"

namespace skelseg::test {
namespace {

TEST(SceneIslands, StrayVoxelsInAVolumeAddNoSegments) {
    const SceneRun clean = segmentShape("t-body", 112);
    ASSERT_EQ(clean.result.islands.count, 0u);
    // Three single voxels and two small clumps in empty corners of the grid.
    MaskVolume mask = clean.mask;
    const Dims d = mask.dims();
    std::vector<std::array<int, 3>> stray = {{1, 1, 1}, {d.x - 2, 1, d.z - 2}, {1, d.y - 2, 1}};
    for (const auto& v : stray) ASSERT_EQ(mask(v[0], v[1], v[2]), 0);
    for (const auto& v : stray) mask(v[0], v[1], v[2]) = 1;
    for (int z = 1; z <= 2; ++z)
        for (int y = d.y - 3; y <= d.y - 2; ++y)
            for (int x = d.x - 3; x <= d.x - 2; ++x) {
                ASSERT_EQ(mask(x, y, z), 0);
                mask(x, y, z) = 1;
            }
    mask(d.x - 2, d.y - 2, d.z - 2) = mask(d.x - 3, d.y - 2, d.z - 2) = 1;
    const SegmentationResult noisy = segmentVolume(mask, {});

    EXPECT_EQ(noisy.islands.count, 5u);
    EXPECT_EQ(noisy.islands.voxels, 3u + 8u + 2u);
    ASSERT_EQ(noisy.segments.size(), clean.result.segments.size());
    ASSERT_EQ(noisy.objects.size(), clean.result.objects.size());
    // The shape is segmented exactly as without the islands; the islands keep label 0.
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (clean.mask[i])
            ASSERT_EQ(noisy.labels[i], clean.result.labels[i]) << "voxel " << i;
        else
            ASSERT_EQ(noisy.labels[i], 0) << "voxel " << i;
    }
}

/// Appends a closed axis-aligned box [lo, hi] (12 triangles, one face each).
void addAxisAlignedBox(TriangleMesh& mesh, std::array<double, 3> lo, std::array<double, 3> hi) {
    const auto base = std::uint32_t(mesh.vertices.size());
    for (int k = 0; k < 8; ++k)
        mesh.vertices.push_back({(k & 1) ^ ((k >> 1) & 1) ? hi[0] : lo[0], (k & 2) ? hi[1] : lo[1],
                                 (k & 4) ? hi[2] : lo[2]});
    // Vertices 0..3 go around the bottom (z = lo), 4..7 around the top.
    static const std::uint32_t faces[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7},
                                               {0, 1, 5}, {0, 5, 4}, {3, 7, 6}, {3, 6, 2},
                                               {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};
    for (const auto& f : faces) {
        mesh.triangles.push_back({base + f[0], base + f[1], base + f[2]});
        mesh.triangleFace.push_back(std::uint32_t(mesh.faceCount++));
    }
}

struct MeshRun {
    SegmentationResult result;
    std::vector<std::uint32_t> faceLabels;
};

MeshRun segmentMesh(const TriangleMesh& mesh) {
    VoxelizeOptions options;
    options.resolution = 96;
    MeshRun run;
    run.result = segmentVolume(voxelizeMesh(mesh, options), {});
    run.faceLabels = labelFaces(mesh, run.result.labels);
    return run;
}

TEST(SceneIslands, SmallPiecesOfAMeshTakeTheLabelOfARealPart) {
    // A body with a limb, then three boxes of 1.5 voxels a side away from
    // them (inside the bounding box, so the grid does not change).
    TriangleMesh mesh;
    addAxisAlignedBox(mesh, {-0.5, -0.15, -0.15}, {0.5, 0.15, 0.15});
    addAxisAlignedBox(mesh, {-0.05, 0.1, -0.05}, {0.05, 0.6, 0.05});
    const std::size_t shapeFaces = mesh.faceCount;
    const MeshRun clean = segmentMesh(mesh);
    const double side = 1.5 / 96.0;
    for (const std::array<double, 3>& at :
         {std::array<double, 3>{0.35, 0.4, 0.0}, {-0.35, 0.45, 0.05}, {0.2, 0.3, -0.1}})
        addAxisAlignedBox(mesh, at, {at[0] + side, at[1] + side, at[2] + side});
    const MeshRun noisy = segmentMesh(mesh);

    EXPECT_EQ(noisy.result.islands.count, 3u);
    EXPECT_EQ(noisy.result.segments.size(), clean.result.segments.size());
    // Same face labels on the shape; the islands' faces use labels of the shape.
    std::set<std::uint32_t> shapeLabels;
    for (std::size_t f = 0; f < shapeFaces; ++f) {
        EXPECT_EQ(noisy.faceLabels[f], clean.faceLabels[f]) << "face " << f;
        shapeLabels.insert(noisy.faceLabels[f]);
    }
    for (std::size_t f = shapeFaces; f < mesh.faceCount; ++f)
        EXPECT_TRUE(shapeLabels.count(noisy.faceLabels[f])) << "island face " << f;
    EXPECT_EQ(std::set<std::uint32_t>(noisy.faceLabels.begin(), noisy.faceLabels.end()).size(),
              shapeLabels.size());
}

}  // namespace
}  // namespace skelseg::test
