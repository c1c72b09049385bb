#include "io/mesh/FaceLabels.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <random>
#include <set>

#include "io/mesh/MeshVoxelizer.h"
#include "io/mesh/SegFile.h"
#include "kernels/base/Error.h"
#include "tests/support/StopAtOnce.h"
#include "tests/support/TempDir.h"

namespace skelseg {
namespace {

/// Box [-1,1] x [-0.5,0.5] x [-0.5,0.5] whose sides are grids of quads
/// (8 x 4 x 4 cells), so that x = 0 runs along quad edges: every face lies on
/// one side of it. Faces are shuffled (with a fixed seed) before the mesh is
/// built, and each quad is fan-triangulated as readMesh would.
TriangleMesh shuffledSplitBox() {
    const int cells[3] = {8, 4, 4};
    const double low[3] = {-1, -0.5, -0.5}, high[3] = {1, 0.5, 0.5};
    TriangleMesh mesh;
    std::vector<std::array<std::uint32_t, 4>> quads;
    std::map<std::array<int, 3>, std::uint32_t> vertexOf;
    auto vertex = [&](std::array<int, 3> grid) {
        const auto found = vertexOf.find(grid);
        if (found != vertexOf.end()) return found->second;
        std::array<double, 3> p{};
        for (int c = 0; c < 3; ++c) p[c] = low[c] + (high[c] - low[c]) * grid[c] / cells[c];
        mesh.vertices.push_back(p);
        vertexOf.emplace(grid, std::uint32_t(mesh.vertices.size() - 1));
        return std::uint32_t(mesh.vertices.size() - 1);
    };
    for (int axis = 0; axis < 3; ++axis) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        for (int side = 0; side < 2; ++side)
            for (int i = 0; i < cells[u]; ++i)
                for (int j = 0; j < cells[v]; ++j) {
                    std::array<std::array<int, 3>, 4> corners{};
                    const int offsets[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
                    for (int k = 0; k < 4; ++k) {
                        corners[k][axis] = side * cells[axis];
                        corners[k][u] = i + offsets[side ? k : 3 - k][0];
                        corners[k][v] = j + offsets[side ? k : 3 - k][1];
                    }
                    quads.push_back({vertex(corners[0]), vertex(corners[1]), vertex(corners[2]),
                                     vertex(corners[3])});
                }
    }
    std::mt19937 random(12345);
    std::shuffle(quads.begin(), quads.end(), random);
    for (std::size_t f = 0; f < quads.size(); ++f) {
        const auto& q = quads[f];
        mesh.triangles.push_back({q[0], q[1], q[2]});
        mesh.triangles.push_back({q[0], q[2], q[3]});
        mesh.triangleFace.push_back(std::uint32_t(f));
        mesh.triangleFace.push_back(std::uint32_t(f));
    }
    mesh.faceCount = quads.size();
    return mesh;
}

std::array<double, 3> faceCentroid(const TriangleMesh& mesh, std::size_t face) {
    std::array<double, 3> sum{0, 0, 0};
    int count = 0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        if (mesh.triangleFace[t] == face)
            for (auto v : mesh.triangles[t]) {
                for (int c = 0; c < 3; ++c) sum[c] += mesh.vertices[v][c];
                ++count;
            }
    for (double& s : sum) s /= count;
    return sum;
}

/// Labels solid voxels by the geometry of their centre: x < 0 -> left, else
/// right; voxels with x > rightLimit stay background.
LabelVolume labelsByGeometry(const MaskVolume& mask, std::uint16_t left, std::uint16_t right,
                             double rightLimit = 1e9) {
    LabelVolume labels(mask.dims(), 0);
    labels.geometry = mask.geometry;
    for (int z = 0; z < mask.dims().z; ++z)
        for (int y = 0; y < mask.dims().y; ++y)
            for (int x = 0; x < mask.dims().x; ++x) {
                if (!mask(x, y, z)) continue;
                const double worldX = mask.geometry.indexToWorld(x, y, z)[0];
                if (worldX > rightLimit) continue;
                labels(x, y, z) = worldX < 0 ? left : right;
            }
    return labels;
}

TEST(FaceLabels, ShuffledFacesGetTheLabelOfTheirOwnPosition) {
    const TriangleMesh mesh = shuffledSplitBox();
    ASSERT_EQ(mesh.faceCount, 2u * (8 * 4 + 4 * 4 + 4 * 8));
    VoxelizeOptions voxelize;
    voxelize.resolution = 48;
    const MaskVolume mask = voxelizeMesh(mesh, voxelize);
    // Voxel labels 7 and 3: the output is compacted by ascending voxel label,
    // so right (3) becomes 0 and left (7) becomes 1.
    const LabelVolume labels = labelsByGeometry(mask, 7, 3);
    FaceLabelStatistics statistics;
    const std::vector<std::uint32_t> faceLabels =
        labelFaces(mesh, labels, {}, nullInterrupter(), &statistics);
    ASSERT_EQ(faceLabels.size(), mesh.faceCount);
    for (std::size_t f = 0; f < mesh.faceCount; ++f)
        EXPECT_EQ(faceLabels[f], faceCentroid(mesh, f)[0] < 0 ? 1u : 0u) << "face " << f;
    EXPECT_EQ(statistics.votedFaces, mesh.faceCount);
    EXPECT_EQ(statistics.segments, 2u);

    FaceLabelOptions serial;
    serial.threaded = false;
    EXPECT_EQ(labelFaces(mesh, labels, serial), faceLabels);
}

TEST(FaceLabels, FacesFarFromLabelsTakeTheirNeighboursLabel) {
    const TriangleMesh mesh = shuffledSplitBox();
    VoxelizeOptions voxelize;
    voxelize.resolution = 48;
    const MaskVolume mask = voxelizeMesh(mesh, voxelize);
    // Leave the right end of the box (x > 0.7) unlabelled: the faces of the
    // end cap at x = 1 are more than 3 voxels from any labelled voxel.
    const LabelVolume labels = labelsByGeometry(mask, 1, 2, 0.7);
    FaceLabelStatistics statistics;
    FaceLabelOptions options;
    const std::vector<std::uint32_t> faceLabels =
        labelFaces(mesh, labels, options, nullInterrupter(), &statistics);
    EXPECT_GE(statistics.propagatedFaces, 16u);  // at least the 4 x 4 end cap
    EXPECT_EQ(statistics.nearestVoxelFaces, 0u);
    for (std::size_t f = 0; f < mesh.faceCount; ++f)
        EXPECT_EQ(faceLabels[f], faceCentroid(mesh, f)[0] < 0 ? 0u : 1u) << "face " << f;
    options.threaded = false;
    EXPECT_EQ(labelFaces(mesh, labels, options), faceLabels);
}

TEST(FaceLabels, APieceWithoutLabelsTakesTheNearestVoxelsLabel) {
    TriangleMesh mesh = shuffledSplitBox();
    VoxelizeOptions voxelize;
    voxelize.resolution = 32;
    const MaskVolume mask = voxelizeMesh(mesh, voxelize);
    const LabelVolume labels = labelsByGeometry(mask, 1, 2);
    // A lone triangle far beyond the right end, outside the volume.
    const std::uint32_t first = std::uint32_t(mesh.vertices.size());
    mesh.vertices.push_back({5, 0, 0});
    mesh.vertices.push_back({5, 0.1, 0});
    mesh.vertices.push_back({5, 0, 0.1});
    mesh.triangles.push_back({first, first + 1, first + 2});
    mesh.triangleFace.push_back(std::uint32_t(mesh.faceCount));
    ++mesh.faceCount;
    FaceLabelStatistics statistics;
    const auto faceLabels = labelFaces(mesh, labels, {}, nullInterrupter(), &statistics);
    EXPECT_EQ(statistics.nearestVoxelFaces, 1u);
    EXPECT_EQ(faceLabels.back(), 1u);  // right half
}

TEST(FaceLabels, EmptyLabelVolumeGivesOneSegment) {
    const TriangleMesh mesh = shuffledSplitBox();
    VoxelizeOptions voxelize;
    voxelize.resolution = 16;
    const MaskVolume mask = voxelizeMesh(mesh, voxelize);
    LabelVolume labels(mask.dims(), 0);
    labels.geometry = mask.geometry;
    const auto faceLabels = labelFaces(mesh, labels);
    EXPECT_EQ(faceLabels, std::vector<std::uint32_t>(mesh.faceCount, 0));
    FaceLabelOptions bad;
    bad.searchRadius = -1;
    EXPECT_THROW(labelFaces(mesh, labels, bad), UsageError);
}

TEST(FaceLabels, SegFileHasOneLabelPerFaceWithoutGaps) {
    const TriangleMesh mesh = shuffledSplitBox();
    VoxelizeOptions voxelize;
    voxelize.resolution = 40;
    const MaskVolume mask = voxelizeMesh(mesh, voxelize);
    // Four voxel labels with gaps (2, 5, 9, 40) by quadrant of (x, y).
    LabelVolume labels(mask.dims(), 0);
    labels.geometry = mask.geometry;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (!mask[i]) continue;
        const int x = int(i % std::size_t(mask.dims().x));
        const int y = int((i / std::size_t(mask.dims().x)) % std::size_t(mask.dims().y));
        const int z = int(i / (std::size_t(mask.dims().x) * std::size_t(mask.dims().y)));
        const auto w = mask.geometry.indexToWorld(x, y, z);
        static const std::uint16_t quadrantLabel[4] = {2, 5, 9, 40};
        labels[i] = quadrantLabel[(w[0] < 0 ? 0 : 1) + (w[1] < 0 ? 0 : 2)];
    }
    const auto faceLabels = labelFaces(mesh, labels);
    test::TempDir dir;
    writeSeg(dir / "box.seg", faceLabels);
    const std::vector<std::int64_t> read = readSeg(dir / "box.seg");
    ASSERT_EQ(read.size(), mesh.faceCount);
    const std::set<std::int64_t> distinct(read.begin(), read.end());
    EXPECT_EQ(distinct, (std::set<std::int64_t>{0, 1, 2, 3}));
}

TEST(FaceLabels, AStopAnsweredOnceAtAnyPollThrows) {
    const TriangleMesh mesh = shuffledSplitBox();
    VoxelizeOptions voxelize;
    voxelize.resolution = 48;
    const LabelVolume labels = labelsByGeometry(voxelizeMesh(mesh, voxelize), 7, 3);
    for (const bool threaded : {false, true}) {
        SCOPED_TRACE(threaded ? "threaded" : "serial");
        FaceLabelOptions options;
        options.threaded = threaded;
        EXPECT_GT(test::expectAStopAtAnyPollThrows([&](Interrupter& interrupter) {
                      labelFaces(mesh, labels, options, interrupter);
                  }),
                  0);
    }
}

}  // namespace
}  // namespace skelseg
