// Scene tests: islands are not parts (issue 12). Stray voxels and small
// pieces beside a shape, in a volume or a mesh, add no segments.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "io/mesh/FaceLabels.h"
#include "io/mesh/MeshCheck.h"
#include "io/mesh/MeshVoxelizer.h"
#include "kernels/ConnectedObjects.h"
#include "tests/support/SceneSupport.h"
#include "tests/support/ShapeMeshes.h"

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

/// figureWithHand with the left hand held away and, when `claw` is set, a
/// rod one fine voxel across hanging from the hand with a small box at its
/// end: one closed mesh piece whose rod is a third of a voxel wide at
/// resolution 123 (3 fine voxels a voxel).
TriangleMesh figureWithClaw(bool claw) {
    Shape shape = figureWithHand(false);
    if (claw) {
        shape.box({114, 0, -72}, {0.4, 0.4, 15.4});  // the rod: z -87 to -57
        shape.box({114, 0, -93}, {6, 6, 6});
    }
    const auto bounds = figureWithHand(false).bounds();  // the same grid either way
    std::array<int, 3> lo{}, hi{};
    for (std::size_t c = 0; c < 3; ++c) {
        lo[c] = int(std::floor(bounds[0][c])) - 1;
        hi[c] = int(std::ceil(bounds[1][c])) + 1;
    }
    return meshOfShape(shape, lo, hi);
}

// A closed mesh piece thinner than a voxel breaks in the voxel model, and
// the part beyond was one more segment (held-out cats: a claw or a tip of
// 1500 voxels beside 650,000). Too small to be a part, it is a fragment:
// the same segments as without it, its faces labelled as the part nearest.
TEST(SceneIslands, APieceBrokenOffAMeshPartIsNoSegment) {
    VoxelizeOptions options;
    options.resolution = 123;
    const TriangleMesh plain = figureWithClaw(false);
    const TriangleMesh clawed = figureWithClaw(true);
    ASSERT_EQ(checkMesh(clawed).pieces, 1u);
    ASSERT_TRUE(checkMesh(clawed).closed);

    const MeshVoxelization plainModel = voxelizeMeshWithContacts(plain, options);
    const MeshVoxelization clawedModel = voxelizeMeshWithContacts(clawed, options);
    ASSERT_EQ(findConnectedObjects(clawedModel.mask).objects.size(), 2u)
        << "the rod must break at this resolution for the test";
    ASSERT_EQ(clawedModel.objectSources.size(), 2u);
    EXPECT_EQ(clawedModel.objectSources[0].piece, clawedModel.objectSources[1].piece);
    EXPECT_TRUE(plainModel.objectSources.empty());  // one object: nothing to tell

    SegmentationParameters parameters;
    const SegmentationResult clean = segmentVolume(plainModel.mask, parameters);
    // Without the voxeliser's sources the claw is an object and a segment.
    const SegmentationResult unsourced = segmentVolume(clawedModel.mask, parameters);
    EXPECT_EQ(unsourced.segments.size(), clean.segments.size() + 1);
    parameters.objectSources = clawedModel.objectSources;
    const SegmentationResult clawedResult = segmentVolume(clawedModel.mask, parameters);
    EXPECT_EQ(clawedResult.islands.fragments, 1u);
    EXPECT_GT(clawedResult.islands.fragmentVoxels, 27u);
    EXPECT_EQ(clawedResult.segments.size(), clean.segments.size());
    EXPECT_EQ(clawedResult.objects.size(), 1u);

    // Faces of the claw take labels of the figure's parts: no more labels
    // than the figure has segments (0..K-1).
    const std::vector<std::uint32_t> faceLabels = labelFaces(clawed, clawedResult.labels);
    const std::set<std::uint32_t> labels(faceLabels.begin(), faceLabels.end());
    EXPECT_EQ(labels.size(), clean.segments.size());
    EXPECT_EQ(*labels.rbegin() + 1, clean.segments.size());
}

}  // namespace
}  // namespace skelseg::test
