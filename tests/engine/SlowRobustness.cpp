// Degenerate shapes through the CLI (issue 5), label slow: each has a checked
// outcome. Volumes are written with writeNrrdMask, meshes with writeOff, into a
// TempDir; `skelseg segment --quiet` runs as a child process and its exit code,
// stderr, report.json and labels.nrrd are checked. Each run takes well under a
// second to a few seconds, about 15 s in all, hence test_slow.
#include <fstream>
#include <set>

#include "io/mesh/MeshIO.h"
#include "io/shapes/SyntheticShapes.h"
#include "tests/engine/RobustnessHelpers.h"

namespace fs = std::filesystem;
using namespace skelseg;
using namespace skelseg::test;

namespace {

// --- checks --------------------------------------------------------------------------

/// Lines of stderr that are warnings ("skelseg: warning: ...").
std::vector<std::string> warningLines(const CliResult& result) {
    std::vector<std::string> warnings;
    for (const auto& line : result.errLines())
        if (line.rfind("skelseg: warning: ", 0) == 0) warnings.push_back(line);
    return warnings;
}

/// Checks a successful volume run on `mask` into `outdir` and returns its report:
///  - exit 0, every output file present, no staging directory left;
///  - labels.nrrd has the input's size; background voxels are 0, every object
///    voxel carries a label listed in report.json;
///  - the segments' voxel counts add up to the object voxels, and per label
///    match labels.nrrd;
///  - segment_count is the number of segments; every line on stderr is a warning.
nlohmann::json expectConsistentVolumeRun(const CliResult& result,
                                         const std::filesystem::path& outdir,
                                         const MaskVolume& mask) {
    EXPECT_EQ(result.exitCode, 0) << result.describe();
    EXPECT_EQ(warningLines(result).size(), result.errLines().size()) << result.describe();
    for (const char* name :
         {"labels.nrrd", "labels.vdb", "skeleton.ply", "cuts.ply", "segments.ply", "preview.png",
          "report.json", "segments.glb", "viewer.html"})
        EXPECT_TRUE(std::filesystem::exists(outdir / name))
            << name << " missing; " << result.describe();
    for (const auto& entry : directoryEntries(outdir))
        EXPECT_EQ(entry.rfind(".skelseg-staging", 0), std::string::npos)
            << "staging directory left behind";
    if (!std::filesystem::exists(outdir / "report.json")) return {};

    const nlohmann::json report = readReport(outdir);
    EXPECT_EQ(report["status"], "ok");
    EXPECT_EQ(report["segment_count"].get<std::size_t>(), report["segments"].size());
    const LabelVolume labels = readNrrdLabels(outdir / "labels.nrrd");
    EXPECT_EQ(labels.dims(), mask.dims());
    if (labels.dims() != mask.dims()) return report;

    std::map<std::uint32_t, std::uint64_t> reported;
    std::uint64_t reportedTotal = 0;
    for (const auto& segment : report["segments"]) {
        const auto id = segment["id"].get<std::uint32_t>();
        EXPECT_TRUE(reported.emplace(id, segment["voxels"].get<std::uint64_t>()).second)
            << "label " << id << " twice";
        reportedTotal += segment["voxels"].get<std::uint64_t>();
    }
    std::map<std::uint32_t, std::uint64_t> counted;
    std::uint64_t objectVoxels = 0, unlabelled = 0, labelledBackground = 0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (mask[i]) {
            ++objectVoxels;
            if (labels[i] == 0)
                ++unlabelled;
            else
                ++counted[labels[i]];
        } else if (labels[i] != 0) {
            ++labelledBackground;
        }
    }
    EXPECT_EQ(unlabelled, 0u) << "object voxels without a label";
    EXPECT_EQ(labelledBackground, 0u) << "background voxels with a label";
    EXPECT_EQ(reportedTotal, objectVoxels);
    EXPECT_EQ(counted, reported) << "labels.nrrd and report.json disagree";
    EXPECT_EQ(report["counts"]["object_voxels"].get<std::uint64_t>(), objectVoxels);
    return report;
}

// --- volumes -------------------------------------------------------------------------

nlohmann::json runVolume(const TempDir& dir, const MaskVolume& mask,
                         CliResult* resultOut = nullptr) {
    writeNrrdMask(dir / "input.nrrd", mask);
    const CliResult result = runSegment(dir / "input.nrrd", dir / "out");
    if (resultOut) *resultOut = result;
    return expectConsistentVolumeRun(result, dir / "out", mask);
}

bool inBox(int x, int y, int z, std::array<int, 3> lo, std::array<int, 3> hi) {
    return x >= lo[0] && x <= hi[0] && y >= lo[1] && y <= hi[1] && z >= lo[2] && z <= hi[2];
}

TEST(DegenerateShapes, EmptyVolumeGivesNoSegmentsAndAWarning) {
    TempDir dir;
    CliResult result;
    const auto report = runVolume(dir, MaskVolume(Dims{16, 16, 16}), &result);
    EXPECT_EQ(report["segment_count"], 0);
    EXPECT_EQ(report["objects"].size(), 0u);
    const auto warnings = warningLines(result);
    ASSERT_EQ(warnings.size(), 1u) << result.describe();
    // Named: a batch printed the line once per empty input, naming none.
    EXPECT_EQ(warnings[0], "skelseg: warning: " + (dir / "input.nrrd").string() +
                               ": the volume holds no object voxels: no segments");
    EXPECT_EQ(report["warnings"].size(), 1u);
}

TEST(DegenerateShapes, SingleVoxelIsOneSegment) {
    TempDir dir;
    const MaskVolume mask =
        makeMask(Dims{9, 9, 9}, [](int x, int y, int z) { return x == 4 && y == 4 && z == 4; });
    const auto report = runVolume(dir, mask);
    EXPECT_EQ(report["segment_count"], 1);
    EXPECT_EQ(report["objects"].size(), 1u);
}

TEST(DegenerateShapes, SingleVoxelInACornerIsOneSegment) {
    TempDir dir;
    const MaskVolume mask =
        makeMask(Dims{5, 5, 5}, [](int x, int y, int z) { return x == 0 && y == 0 && z == 0; });
    const auto report = runVolume(dir, mask);
    EXPECT_EQ(report["segment_count"], 1);
}

TEST(DegenerateShapes, OneVoxelThinSheet) {
    TempDir dir;
    const MaskVolume mask = makeMask(Dims{32, 32, 5}, [](int x, int y, int z) {
        return inBox(x, y, z, {3, 3, 2}, {28, 28, 2});
    });
    const auto report = runVolume(dir, mask);
    EXPECT_GE(report["segment_count"].get<int>(), 1);
    EXPECT_EQ(report["objects"].size(), 1u);
}

TEST(DegenerateShapes, OneVoxelThinLine) {
    TempDir dir;
    const MaskVolume mask = makeMask(Dims{40, 5, 5}, [](int x, int y, int z) {
        return inBox(x, y, z, {2, 2, 2}, {37, 2, 2});
    });
    const auto report = runVolume(dir, mask);
    EXPECT_EQ(report["segment_count"], 1) << "a straight line has no parts";
    EXPECT_EQ(report["objects"].size(), 1u);
}

TEST(DegenerateShapes, OneVoxelThinLineWithABranch) {
    TempDir dir;
    // A "T" of one-voxel lines: a junction with no thickness at all.
    const MaskVolume mask = makeMask(Dims{41, 24, 5}, [](int x, int y, int z) {
        return inBox(x, y, z, {2, 2, 2}, {38, 2, 2}) || inBox(x, y, z, {20, 2, 2}, {20, 21, 2});
    });
    const auto report = runVolume(dir, mask);
    EXPECT_GE(report["segment_count"].get<int>(), 1);
}

TEST(DegenerateShapes, BoxFillingTheWholeGrid) {
    TempDir dir;
    const MaskVolume mask = makeMask(Dims{12, 12, 12}, [](int, int, int) { return true; });
    const auto report = runVolume(dir, mask);
    EXPECT_EQ(report["segment_count"], 1) << "a box has no parts";
}

TEST(DegenerateShapes, ObjectTouchingTheGridBorder) {
    TempDir dir;
    // A capsule cut open by the grid's faces at x = 0 and z = max.
    const MaskVolume mask = makeMask(Dims{40, 16, 16}, [](int x, int y, int z) {
        const double dy = y - 7.5, dz = z - 12.0;
        return x <= 30 && dy * dy + dz * dz <= 36.0;
    });
    const auto report = runVolume(dir, mask);
    EXPECT_GE(report["segment_count"].get<int>(), 1);
    EXPECT_EQ(report["objects"].size(), 1u);
}

TEST(DegenerateShapes, TwoDisjointObjectsGetDisjointLabels) {
    TempDir dir;
    const MaskVolume mask = makeMask(Dims{30, 12, 12}, [](int x, int y, int z) {
        return inBox(x, y, z, {1, 1, 1}, {10, 10, 10}) || inBox(x, y, z, {16, 2, 2}, {28, 9, 9});
    });
    const auto report = runVolume(dir, mask);
    ASSERT_EQ(report["objects"].size(), 2u);
    const LabelVolume labels = readNrrdLabels(dir / "out" / "labels.nrrd");
    std::set<std::uint16_t> first, second;
    for (int z = 0; z < 12; ++z)
        for (int y = 0; y < 12; ++y)
            for (int x = 0; x < 30; ++x) {
                if (!mask(x, y, z)) continue;
                (x <= 10 ? first : second).insert(labels(x, y, z));
            }
    for (std::uint16_t label : first)
        EXPECT_EQ(second.count(label), 0u) << "label " << label << " in both objects";
    std::set<int> objectsOfSegments;
    for (const auto& s : report["segments"]) objectsOfSegments.insert(s["object"].get<int>());
    EXPECT_EQ(objectsOfSegments, (std::set<int>{0, 1}));
}

TEST(DegenerateShapes, ManyTinyObjects) {
    TempDir dir;
    // 64 isolated voxels: each its own object and segment, labels unique.
    const MaskVolume mask = makeMask(Dims{16, 16, 16}, [](int x, int y, int z) {
        return x % 4 == 1 && y % 4 == 1 && z % 4 == 1;
    });
    const auto report = runVolume(dir, mask);
    EXPECT_EQ(report["objects"].size(), 64u);
    EXPECT_EQ(report["segment_count"], 64);
}

TEST(DegenerateShapes, TorusHasATunnel) {
    TempDir dir;
    const MaskVolume mask = rasterise(makeShape("torus"), {64, 3});
    const auto report = runVolume(dir, mask);
    EXPECT_GE(report["segment_count"].get<int>(), 1);
    EXPECT_EQ(report["objects"].size(), 1u);
}

TEST(DegenerateShapes, TorusWithALimb) {
    TempDir dir;
    const MaskVolume mask = rasterise(makeShape("torus-limb"), {64, 3});
    const auto report = runVolume(dir, mask);
    EXPECT_GE(report["segment_count"].get<int>(), 1);
}

// --- meshes ---------------------------------------------------------------------

TriangleMesh cubeMesh(bool withoutTopFace) {
    TriangleMesh mesh;
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                     {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    const std::vector<std::array<std::uint32_t, 4>> quads = {
        {0, 3, 2, 1}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}, {4, 5, 6, 7}};
    for (std::size_t q = 0; q < quads.size(); ++q) {
        if (withoutTopFace && q == 5) continue;
        const auto& f = quads[q];
        mesh.triangles.push_back({f[0], f[1], f[2]});
        mesh.triangles.push_back({f[0], f[2], f[3]});
        mesh.triangleFace.push_back(std::uint32_t(mesh.faceCount));
        mesh.triangleFace.push_back(std::uint32_t(mesh.faceCount));
        ++mesh.faceCount;
    }
    return mesh;
}

std::size_t lineCount(const fs::path& file) {
    std::ifstream in(file);
    std::size_t lines = 0;
    for (std::string line; std::getline(in, line);) ++lines;
    return lines;
}

/// Runs a mesh and checks what every successful mesh run must have written.
nlohmann::json runMesh(const TempDir& dir, const TriangleMesh& mesh, CliResult& result) {
    writeOff(dir / "input.off", mesh);
    result = runSegment(dir / "input.off", dir / "out", {"--resolution", "32"});
    EXPECT_EQ(result.exitCode, 0) << result.describe();
    EXPECT_EQ(warningLines(result).size(), result.errLines().size()) << result.describe();
    for (const char* name :
         {"labels.nrrd", "labels.vdb", "skeleton.ply", "cuts.ply", "segments.ply", "preview.png",
          "report.json", "segmentation.seg", "segments.glb", "viewer.html"})
        EXPECT_TRUE(fs::exists(dir / "out" / name)) << name << " missing; " << result.describe();
    if (!fs::exists(dir / "out" / "report.json")) return {};
    EXPECT_EQ(lineCount(dir / "out" / "segmentation.seg"), mesh.faceCount)
        << "one label per input face";
    const nlohmann::json report = readReport(dir / "out");
    EXPECT_EQ(report["status"], "ok");
    EXPECT_EQ(report["input"]["faces"].get<std::size_t>(), mesh.faceCount);
    return report;
}

bool anyLineHas(const std::vector<std::string>& lines, const std::string& a, const std::string& b) {
    for (const auto& line : lines)
        if (line.find(a) != std::string::npos && line.find(b) != std::string::npos) return true;
    return false;
}

TEST(DegenerateMeshes, ClosedCubeHasNoWarnings) {
    TempDir dir;
    CliResult result;
    const auto report = runMesh(dir, cubeMesh(false), result);
    EXPECT_TRUE(result.err.empty()) << result.describe();
    EXPECT_EQ(report["input"]["mesh_closed"], true);
    EXPECT_EQ(report["segment_count"], 1);
}

TEST(DegenerateMeshes, CubeWithAHoleGivesAResultAndAWarning) {
    TempDir dir;
    CliResult result;
    const auto report = runMesh(dir, cubeMesh(true), result);
    const std::string file = (dir / "input.off").string();
    EXPECT_TRUE(anyLineHas(warningLines(result), file, "not closed")) << result.describe();
    EXPECT_EQ(report["input"]["mesh_closed"], false);
    EXPECT_EQ(report["input"]["mesh_boundary_edges"], 4);
    EXPECT_GE(report["segment_count"].get<int>(), 1)
        << "the open cube is still voxelised as a solid";
}

TEST(DegenerateMeshes, ZeroAreaFacesGiveAResultAndAWarning) {
    TempDir dir;
    TriangleMesh mesh = cubeMesh(false);
    // A face with a repeated vertex on an edge of the cube: zero area; it
    // uses that edge twice more, so the surface stays closed.
    mesh.triangles.push_back({0, 1, 1});
    mesh.triangleFace.push_back(std::uint32_t(mesh.faceCount++));
    CliResult result;
    const auto report = runMesh(dir, mesh, result);
    EXPECT_TRUE(anyLineHas(warningLines(result), (dir / "input.off").string(), "zero area"))
        << result.describe();
    EXPECT_EQ(report["input"]["mesh_degenerate_faces"], 1);
}

TEST(DegenerateMeshes, AFlatMeshIsRefusedAThinClosedPlateIsNot) {
    TempDir dir;
    TriangleMesh mesh;
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.triangles = {{0, 1, 2}};
    mesh.triangleFace = {0};
    mesh.faceCount = 1;
    writeOff(dir / "input.off", mesh);
    const CliResult result = runSegment(dir / "input.off", dir / "out", {"--resolution", "32"});
    // One plane bounds no volume: refused with one line, where it used to
    // become a sheet one voxel thick labelled as one part.
    EXPECT_TRUE(failsWithOneLine(result, 2, (dir / "input.off").string(), "the mesh is flat"));
    EXPECT_TRUE(leftNothing(dir / "out"));
    // A closed plate a thousandth of its size thick is a solid, however thin.
    TriangleMesh plate = cubeMesh(false);
    for (auto& v : plate.vertices) v[2] *= 1e-3;
    CliResult plateResult;
    const auto report = runMesh(dir, plate, plateResult);
    EXPECT_EQ(report["segment_count"], 1) << plateResult.describe();
}

TEST(DegenerateMeshes, AllFacesDegenerate) {
    TempDir dir;
    TriangleMesh mesh;
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
    mesh.triangles = {{0, 1, 2}, {1, 2, 3}, {0, 2, 3}, {0, 1, 3}};
    mesh.triangleFace = {0, 1, 2, 3};
    mesh.faceCount = 4;
    writeOff(dir / "input.off", mesh);
    const CliResult result = runSegment(dir / "input.off", dir / "out", {"--resolution", "32"});
    // No surface at all: refused with one line (docs/robustness.md), where it
    // used to become a wire of voxels labelled as one part.
    EXPECT_TRUE(failsWithOneLine(result, 2, (dir / "input.off").string(), "zero area"));
    EXPECT_TRUE(leftNothing(dir / "out"));
}

// --- a scanned mesh with tunnels ------------------------------------------------------

TEST(SlowDegenerateShapes, FertilityHasTunnels) {
    const fs::path input = sharedDataDir() / "shapes" / "fertility.off";
    if (!fs::exists(input)) GTEST_SKIP() << input << " is absent (shared data not installed)";
    TempDir dir;
    const CliResult result = runSegment(input, dir / "out", {"--resolution", "96"});
    ASSERT_EQ(result.exitCode, 0) << result.describe();
    EXPECT_EQ(warningLines(result).size(), result.errLines().size()) << result.describe();
    const nlohmann::json report = readReport(dir / "out");
    EXPECT_EQ(report["status"], "ok");
    EXPECT_EQ(report["input"]["mesh_closed"], true);
    EXPECT_EQ(report["objects"].size(), 1u);
    EXPECT_GE(report["segment_count"].get<int>(), 2);
    // One label per input face, all of them segments that exist.
    const TriangleMesh mesh = readMesh(input);
    std::ifstream seg(dir / "out" / "segmentation.seg");
    std::size_t lines = 0;
    for (std::string line; std::getline(seg, line);) {
        ++lines;
        EXPECT_LT(std::stoul(line), report["face_segments"].get<std::size_t>());
    }
    EXPECT_EQ(lines, mesh.faceCount);
    EXPECT_EQ(readNrrdLabels(dir / "out" / "labels.nrrd").dims().x,
              report["grid"]["size"][0].get<int>());
}

}  // namespace
