// Scene: a figure whose hand rests on its hip with a gap of a third of a
// voxel, written as a mesh, keeps the mesh's topology in the voxel model and
// segments like the same figure with the hand held away, like itself with
// its faces in another order, and like itself with a fin on its head; one
// whose leg is folded under its body, pressed there with the same gap,
// segments like the leg hanging free.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "engine/SegmentCommand.h"
#include "engine/Segmenter.h"
#include "io/mesh/FaceLabels.h"
#include "io/mesh/MeshGenus.h"
#include "io/mesh/MeshVoxelizer.h"
#include "kernels/VoxelGenus.h"
#include "tests/support/MeshEdits.h"
#include "tests/support/SceneSupport.h"
#include "tests/support/ShapeMeshes.h"
#include "tests/support/TempDir.h"

namespace skelseg {
namespace {

/// The coarse resolution at which one fine voxel (the gap) is a third of a voxel.
VoxelizeOptions thirdOfAVoxelGap(const TriangleMesh& mesh, bool keepTopology) {
    double low = HUGE_VAL, high = -HUGE_VAL;
    for (const auto& p : mesh.vertices) {
        low = std::min(low, p[2]);
        high = std::max(high, p[2]);
    }
    VoxelizeOptions options;
    options.resolution = int(std::lround((high - low) / 3.0));  // z is the longest side
    options.keepMeshTopology = keepTopology;
    return options;
}

TEST(SceneMeshTopology, HandOnHipKeepsGenusAndParts) {
    const TriangleMesh touching = test::figureMesh(true);
    const TriangleMesh away = test::figureMesh(false);
    ASSERT_EQ(meshTopology(touching).genus, 0);
    ASSERT_EQ(meshTopology(touching).closedPieces, 1u);

    // Without the contact separation the hand fuses with the hip: a loop.
    const MaskVolume fused = voxelizeMesh(touching, thirdOfAVoxelGap(touching, false));
    ASSERT_EQ(voxelTopology(fused).genus, 1) << "the test figure must fuse when voxelised";

    const MeshVoxelization kept =
        voxelizeMeshWithContacts(touching, thirdOfAVoxelGap(touching, true));
    EXPECT_GE(kept.contacts.contacts, 1u)
        << "pairs " << kept.contacts.contactPairs << " kept " << kept.contacts.contactsKept;
    const VoxelTopology keptTopology = voxelTopology(kept.mask);
    EXPECT_EQ(keptTopology.genus, 0);
    EXPECT_EQ(keptTopology.objects, 1u);

    const MaskVolume apart = voxelizeMesh(away, thirdOfAVoxelGap(away, true));
    EXPECT_EQ(voxelTopology(apart).genus, 0);

    const SegmentationResult touchingResult = segmentVolume(kept.mask, {});
    const SegmentationResult awayResult = segmentVolume(apart, {});
    EXPECT_EQ(touchingResult.segments.size(), awayResult.segments.size());
    const auto touchingAdjacency = test::segmentAdjacency(touchingResult.labels);
    const auto awayAdjacency = test::segmentAdjacency(awayResult.labels);
    const int count = int(awayResult.segments.size());
    EXPECT_EQ(test::degreeSequence(touchingAdjacency, count),
              test::degreeSequence(awayAdjacency, count));
    EXPECT_GE(count, 6);  // body, head, two arms, two legs at least
}

TEST(SceneMeshTopology, ALegFoldedUnderTheBodyIsCutLikeTheLegHangingFree) {
    const TriangleMesh folded = test::figureWithLegMesh(true);
    const TriangleMesh hanging = test::figureWithLegMesh(false);
    ASSERT_EQ(meshTopology(folded).genus, 0);
    ASSERT_EQ(meshTopology(folded).closedPieces, 1u);
    const MeshVoxelization kept = voxelizeMeshWithContacts(folded, thirdOfAVoxelGap(folded, true));
    EXPECT_GE(kept.contacts.contacts, 1u);
    EXPECT_EQ(voxelTopology(kept.mask).genus, 0);
    const MaskVolume apart = voxelizeMesh(hanging, thirdOfAVoxelGap(hanging, true));
    const SegmentationResult foldedResult = segmentVolume(kept.mask, {});
    const SegmentationResult hangingResult = segmentVolume(apart, {});
    const int count = int(hangingResult.segments.size());
    EXPECT_GE(count, 6);  // body, head, two arms, two legs at least
    EXPECT_EQ(int(foldedResult.segments.size()), count);
    EXPECT_EQ(test::degreeSequence(test::segmentAdjacency(foldedResult.labels), count),
              test::degreeSequence(test::segmentAdjacency(hangingResult.labels), count));
}

TEST(SceneMeshTopology, BarsTouchingOverWholeOpenVdbLeavesSegmentLikeBarsApart) {
    // Two bars on one base, a third of a voxel apart over a contact that
    // crosses whole leaves of OpenVDB's grids, against the same bars three
    // voxels apart: parted over only part of the contact, the bars read
    // as joined there, and the U gained a junction and parts.
    VoxelizeOptions options;
    options.resolution = 80;
    const MeshVoxelization touching = voxelizeMeshWithContacts(test::barsOnABase(1), options);
    const MeshVoxelization apart = voxelizeMeshWithContacts(test::barsOnABase(10), options);
    ASSERT_EQ(apart.contacts.contacts, 0u) << "three voxels apart, the bars must not touch";
    const SegmentationResult touchingResult = segmentVolume(touching.mask, {});
    const SegmentationResult apartResult = segmentVolume(apart.mask, {});
    const int count = int(apartResult.segments.size());
    EXPECT_EQ(int(touchingResult.segments.size()), count);
    EXPECT_EQ(test::degreeSequence(test::segmentAdjacency(touchingResult.labels), count),
              test::degreeSequence(test::segmentAdjacency(apartResult.labels), count));
}

TEST(SceneMeshTopology, TheFaceOrderGivesTheSameFaceLabels) {
    // The same figure written by another exporter (its triangles in another
    // order, each started at another corner) must give the same parts, face
    // for face: the contact at the hip is where the order used to matter.
    const TriangleMesh mesh = test::figureMesh(true);
    const TriangleMesh shuffled = test::reorderedTriangles(mesh, 5);
    const VoxelizeOptions options = thirdOfAVoxelGap(mesh, true);
    const MeshVoxelization original = voxelizeMeshWithContacts(mesh, options);
    const MeshVoxelization again = voxelizeMeshWithContacts(shuffled, options);
    ASSERT_GE(original.contacts.contacts, 1u);
    EXPECT_TRUE(again.mask.values() == original.mask.values());
    const SegmentationResult originalResult = segmentVolume(original.mask, {});
    const SegmentationResult againResult = segmentVolume(again.mask, {});
    const std::vector<std::uint32_t> originalFaces = labelFaces(mesh, originalResult.labels);
    const std::vector<std::uint32_t> againFaces = labelFaces(shuffled, againResult.labels);
    EXPECT_GE(originalResult.segments.size(), 6u);
    EXPECT_EQ(againResult.segments.size(), originalResult.segments.size());
    EXPECT_TRUE(againFaces == originalFaces);
}

/// What `skelseg segment MESH -o OUT --resolution R` reports, and the face
/// labels it writes.
struct SegmentedMesh {
    nlohmann::json report;
    std::vector<int> faceLabels;
};

SegmentedMesh segmentMeshFile(const test::TempDir& dir, const std::string& name,
                              const TriangleMesh& mesh, int resolution) {
    const std::filesystem::path input = dir / (name + ".off");
    writeOff(input, mesh);
    SegmentCommandOptions options;
    options.input = input;
    options.outdir = dir / name;
    options.resolution = resolution;
    options.threads = 2;
    options.writePreview = false;
    ProgressReporter progress(ProgressReporter::Display::Quiet);
    runSegmentCommand(options, progress);
    SegmentedMesh result;
    std::ifstream(options.outdir / "report.json") >> result.report;
    std::ifstream labels(options.outdir / "segmentation.seg");
    for (int label; labels >> label;) result.faceLabels.push_back(label);
    return result;
}

/// `mesh` with a hole: its last face (one triangle) left out.
TriangleMesh withoutItsLastFace(const TriangleMesh& mesh) {
    TriangleMesh open = mesh;
    open.triangles.pop_back();
    open.triangleFace.pop_back();
    --open.faceCount;
    return open;
}

TEST(SceneMeshTopology, AMeshMissingAFaceSegmentsLikeTheClosedOne) {
    // The bars three voxels apart with one triangle missing: voxelised as an
    // open mesh, the shell method's closing filled the gap between them and
    // the U came out with more parts than the closed mesh gives. With the
    // hole capped, the mesh is voxelised as the closed one.
    const TriangleMesh closed = test::barsOnABase(10);
    const TriangleMesh open = withoutItsLastFace(closed);
    const test::TempDir dir;
    const SegmentedMesh closedRun = segmentMeshFile(dir, "closed", closed, 80);
    const SegmentedMesh openRun = segmentMeshFile(dir, "open", open, 80);
    EXPECT_EQ(openRun.report["input"]["mesh_holes_capped"], 1);
    EXPECT_EQ(openRun.report["input"]["mesh_closed"], true);
    EXPECT_EQ(openRun.report["segment_count"], closedRun.report["segment_count"]);
    EXPECT_EQ(openRun.report["counts"]["object_voxels"],
              closedRun.report["counts"]["object_voxels"]);
    ASSERT_EQ(openRun.faceLabels.size() + 1, closedRun.faceLabels.size());
    EXPECT_TRUE(std::equal(openRun.faceLabels.begin(), openRun.faceLabels.end(),
                           closedRun.faceLabels.begin()));
}

TEST(SceneMeshTopology, AMeshMissingAFaceWithAnOpenCupBesideItSegmentsLikeTheClosedOne) {
    // The same U with one triangle missing and, beside its base, a small cup
    // (a box without its top, as an eyelid or a tongue is often modelled):
    // neither the fin rule (the U's sheet is open too) nor the hole rule (the
    // cup's opening is a fifth of it) takes this mesh alone, and the shell
    // method filled the gap between the bars. With the cup dropped as a fin
    // and the hole capped, the U is voxelised as the closed one.
    const TriangleMesh closed = test::barsOnABase(10);
    TriangleMesh open = withoutItsLastFace(closed);
    test::appendPiece(open, test::openCup({60.0, 0.0, 0.0}, 4.0));
    const test::TempDir dir;
    const SegmentedMesh closedRun = segmentMeshFile(dir, "closed", closed, 80);
    const SegmentedMesh openRun = segmentMeshFile(dir, "open", open, 80);
    EXPECT_EQ(openRun.report["input"]["mesh_fin_faces"], 10);
    EXPECT_EQ(openRun.report["input"]["mesh_holes_capped"], 1);
    EXPECT_EQ(openRun.report["input"]["mesh_closed"], true);
    EXPECT_EQ(openRun.report["segment_count"], closedRun.report["segment_count"]);
    EXPECT_EQ(openRun.report["counts"]["object_voxels"],
              closedRun.report["counts"]["object_voxels"]);
    ASSERT_EQ(openRun.faceLabels.size(), closedRun.faceLabels.size() - 1 + 10);
    EXPECT_TRUE(std::equal(closedRun.faceLabels.begin(), closedRun.faceLabels.end() - 1,
                           openRun.faceLabels.begin()));
}

TEST(SceneMeshTopology, FlippedFacesAtTheHipAreTurnedAndTheFigureSegmentsAsWound) {
    // The figure with the faces round its hand and hip wound the wrong way,
    // as a hand edit can leave them: without a consistent outside there,
    // the contact separation could not tell the gap between hand and hip
    // from the solid. Turned back, the figure is the one wound right.
    const TriangleMesh wound = test::figureMesh(true);
    TriangleMesh flipped = wound;
    std::size_t patch = 0;
    for (auto& t : flipped.triangles) {
        double x = 0.0, z = 0.0;
        for (const std::uint32_t v : t) {
            x += flipped.vertices[v][0] / 3.0;
            z += flipped.vertices[v][2] / 3.0;
        }
        if (x > -40.0 || z < -50.0 || z > 0.0) continue;
        std::swap(t[1], t[2]);
        ++patch;
    }
    ASSERT_GT(patch, 100u);
    const int resolution = thirdOfAVoxelGap(wound, true).resolution;
    const test::TempDir dir;
    const SegmentedMesh woundRun = segmentMeshFile(dir, "wound", wound, resolution);
    const SegmentedMesh flippedRun = segmentMeshFile(dir, "flipped", flipped, resolution);
    EXPECT_EQ(flippedRun.report["input"]["mesh_faces_turned"], patch);
    EXPECT_EQ(woundRun.report["input"]["mesh_faces_turned"], 0);
    EXPECT_EQ(flippedRun.report["input"]["voxel_genus"], 0);
    EXPECT_EQ(flippedRun.report["counts"]["object_voxels"],
              woundRun.report["counts"]["object_voxels"]);
    EXPECT_EQ(flippedRun.report["segment_count"], woundRun.report["segment_count"]);
    EXPECT_TRUE(flippedRun.faceLabels == woundRun.faceLabels);
}

TEST(SceneMeshTopology, AFinOnTheFigureLeavesItClosed) {
    // A stray triangle standing on an edge at the top of the head, as
    // exporters leave them: the mesh as read is open (two free edges) and
    // was voxelised by the shell method, which does not keep the hand off
    // the hip. Without the fin the figure is closed, and is voxelised so.
    TriangleMesh withFin = test::figureMesh(true);
    std::size_t top = 0;
    const auto height = [&](std::size_t t) {
        const auto& c = withFin.triangles[t];
        return withFin.vertices[c[0]][2] + withFin.vertices[c[1]][2] + withFin.vertices[c[2]][2];
    };
    for (std::size_t t = 1; t < withFin.triangles.size(); ++t)
        if (height(t) > height(top)) top = t;
    const auto corners = withFin.triangles[top];
    const auto& a = withFin.vertices[corners[0]];
    const auto& b = withFin.vertices[corners[1]];
    withFin.vertices.push_back({(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2 + 2.0});
    withFin.triangles.push_back(
        {corners[0], corners[1], std::uint32_t(withFin.vertices.size() - 1)});
    withFin.triangleFace.push_back(std::uint32_t(withFin.faceCount++));

    const int resolution = thirdOfAVoxelGap(withFin, true).resolution;
    const test::TempDir dir;
    const SegmentedMesh finned = segmentMeshFile(dir, "fin", withFin, resolution);
    const SegmentedMesh away = segmentMeshFile(dir, "away", test::figureMesh(false), resolution);
    const nlohmann::json& input = finned.report.at("input");
    EXPECT_EQ(input.at("mesh_fin_faces"), 1);
    EXPECT_EQ(input.at("mesh_closed"), true);
    EXPECT_GE(input.at("contacts_separated").get<int>(), 1);
    EXPECT_EQ(input.at("voxel_genus"), 0);
    EXPECT_EQ(input.at("mesh_genus"), 0);
    EXPECT_EQ(finned.report.at("segment_count"), away.report.at("segment_count"));
    EXPECT_GE(finned.report.at("segment_count").get<int>(), 6);
    // Every face is labelled, the fin with the head it stands on.
    ASSERT_EQ(finned.faceLabels.size(), withFin.faceCount);
    EXPECT_EQ(finned.faceLabels.back(), finned.faceLabels[withFin.triangleFace[top]]);
    bool warned = false;
    for (const auto& warning : finned.report.at("warnings"))
        warned |= warning.get<std::string>().find("1 face lies on fins") != std::string::npos;
    EXPECT_TRUE(warned) << finned.report.at("warnings");
}

}  // namespace
}  // namespace skelseg
