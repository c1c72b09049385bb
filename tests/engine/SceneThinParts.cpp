// Scene: `skelseg segment` on meshes with parts thinner than a voxel. A
// perforated sheet (handles the mesh does not have) is voxelised again with
// the thin-part fill and keeps that model; a thin spike, whose voxel genus is
// already the mesh's, is left as it was (its broken tip is an island, not a
// part), so the fill cannot change parts that were right (docs/meshes.md,
// "Parts thinner than a voxel").
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "io/mesh/MeshIO.h"
#include "io/mesh/MeshVoxelizer.h"
#include "tests/support/BoxMeshes.h"
#include "tests/support/CliRunner.h"
#include "tests/support/TempDir.h"

namespace skelseg {
namespace {

constexpr int kResolution = 48;

nlohmann::json segmentMesh(const test::TempDir& dir, const TriangleMesh& mesh,
                           const std::string& name) {
    const auto input = dir / (name + ".off");
    writeOff(input, mesh);
    const auto out = dir / name;
    const auto run =
        test::runSkelseg({"segment", input.string(), "-o", out.string(), "--resolution",
                          std::to_string(kResolution), "-q", "--no-preview"});
    EXPECT_EQ(run.exitCode, 0) << run.describe();
    std::ifstream in(out / "report.json");
    return nlohmann::json::parse(in);
}

/// The voxel size of `build(voxel)` at kResolution (the thin dimension hardly
/// changes the bounding box).
template <typename Build>
double voxelOf(const Build& build) {
    VoxelizeOptions options;
    options.resolution = kResolution;
    return voxelGridFor(build(1.0), options).geometry.voxelSize();
}

TEST(SceneThinParts, APerforatedSheetIsFilledAndAThinSpikeLeftAlone) {
    test::TempDir dir;
    // Sheets 0.4 voxels thick at several orientations: where one comes out
    // perforated, the fill is kept and the voxel genus becomes the mesh's.
    int filled = 0, sheets = 0;
    for (const test::Rotation& tilted :
         {test::rotation({1, 0, 0}, 30), test::rotation({1, 1, 0}, 45),
          test::rotation({1, 2, 3}, 37), test::rotation({3, -1, 2}, 61),
          test::rotation({0, 1, 1}, 54.7356)}) {
        const auto sheet = [&](double voxel) {
            TriangleMesh mesh;
            test::addBox(mesh, {40, 40, 0.4 * voxel}, tilted);
            return mesh;
        };
        const nlohmann::json report =
            segmentMesh(dir, sheet(voxelOf(sheet)), "sheet" + std::to_string(sheets++));
        const nlohmann::json& input = report.at("input");
        if (input.at("thin_part_fill") == "not needed") continue;
        ++filled;
        EXPECT_EQ(input.at("thin_part_fill"), "kept");
        EXPECT_EQ(input.at("thin_part_fill_voxel_genus"), input.at("voxel_genus"));
        EXPECT_GT(input.at("thin_part_voxels_added").get<int>(), 0);
        EXPECT_EQ(input.at("voxel_genus"), input.at("mesh_genus"));
    }
    EXPECT_GT(filled, 0) << "some sheet must come out perforated without the fill";

    const test::Rotation spikeAxis = test::rotation({2, -1, 1}, 50);
    const auto spike = [&](double voxel) {
        TriangleMesh mesh;
        test::addBox(mesh, {20, 20, 20}, test::rotation({1, 0, 0}, 0));
        const std::array<double, 3> tip{spikeAxis[0][2] * 20, spikeAxis[1][2] * 20,
                                        spikeAxis[2][2] * 20};
        test::addBox(mesh, {0.3 * voxel, 0.3 * voxel, 40}, spikeAxis, tip);
        return mesh;
    };
    const nlohmann::json spikeReport = segmentMesh(dir, spike(voxelOf(spike)), "spike");
    const nlohmann::json& spikeInput = spikeReport.at("input");
    EXPECT_EQ(spikeInput.at("thin_part_fill"), "not needed");
    EXPECT_EQ(spikeInput.at("thin_part_voxels_added"), 0);
    EXPECT_EQ(spikeInput.at("voxel_genus"), spikeInput.at("mesh_genus"));
    EXPECT_EQ(spikeReport.at("segments").size(), 1u) << "the broken tip must not be a part";
}

}  // namespace
}  // namespace skelseg
