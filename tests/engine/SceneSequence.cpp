// `skelseg sequence` on generated frames: one mesh (the figure of
// tests/support/ShapeMeshes.h) moved rigidly and stretched, so the frames share
// their faces as an animated character's do.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "io/mesh/MeshIO.h"
#include "io/mesh/SegFile.h"
#include "tests/support/BoxMeshes.h"
#include "tests/support/CliRunner.h"
#include "tests/support/CurledTube.h"
#include "tests/support/FileBytes.h"
#include "tests/support/ShapeMeshes.h"
#include "tests/support/TempDir.h"

namespace skelseg {
namespace {

/// `mesh` turned by `degrees` about the z axis and stretched by `stretch`
/// along y: same faces, other positions.
TriangleMesh posed(TriangleMesh mesh, double degrees, double stretch) {
    const double a = degrees * M_PI / 180.0, c = std::cos(a), s = std::sin(a);
    for (auto& v : mesh.vertices) {
        const double x = v[0], y = v[1] * stretch;
        v = {c * x - s * y, s * x + c * y, v[2]};
    }
    return mesh;
}

std::size_t distinct(const std::vector<std::int64_t>& labels) {
    return std::set<std::int64_t>(labels.begin(), labels.end()).size();
}

/// Two arms (boxes of 1 x 1 x 3), the second centred at `second`; vertices
/// numbered in the order the triangles first use them, as the STL reader
/// numbers the corners it merges, so the mesh an STL file of it reads as is
/// this one wherever no corners of the two arms coincide.
TriangleMesh twoArms(const std::array<double, 3>& second) {
    TriangleMesh boxes;
    const test::Rotation none = test::rotation({0, 0, 1}, 0);
    test::addBox(boxes, {1, 1, 3}, none);
    test::addBox(boxes, {1, 1, 3}, none, second);
    TriangleMesh mesh = boxes;
    mesh.vertices.clear();
    std::map<std::uint32_t, std::uint32_t> renumbered;
    for (auto& triangle : mesh.triangles)
        for (std::uint32_t& v : triangle) {
            const auto [entry, added] = renumbered.emplace(v, std::uint32_t(mesh.vertices.size()));
            if (added) mesh.vertices.push_back(boxes.vertices[v]);
            v = entry->second;
        }
    return mesh;
}

/// A binary STL of `mesh` (its coordinates must be floats: these are).
void writeBinaryStl(const std::filesystem::path& path, const TriangleMesh& mesh) {
    std::string out(80, ' ');
    const auto append = [&](const void* bytes, std::size_t size) {
        out.append(static_cast<const char*>(bytes), size);
    };
    const auto count = std::uint32_t(mesh.triangles.size());
    append(&count, 4);
    for (const auto& triangle : mesh.triangles) {
        const float normal[3] = {0, 0, 0};
        append(normal, 12);
        for (std::uint32_t v : triangle)
            for (double coordinate : mesh.vertices[v]) {
                const auto value = float(coordinate);
                append(&value, 4);
            }
        out += std::string(2, '\0');
    }
    std::ofstream(path, std::ios::binary) << out;
}

void writeAsciiStl(const std::filesystem::path& path, const TriangleMesh& mesh) {
    std::ostringstream out;
    out.precision(17);
    out << "solid arms\n";
    for (const auto& triangle : mesh.triangles) {
        out << "facet normal 0 0 0\nouter loop\n";
        for (std::uint32_t v : triangle)
            out << "vertex " << mesh.vertices[v][0] << ' ' << mesh.vertices[v][1] << ' '
                << mesh.vertices[v][2] << '\n';
        out << "endloop\nendfacet\n";
    }
    out << "endsolid arms\n";
    std::ofstream(path) << out.str();
}

nlohmann::json reportInput(const std::filesystem::path& frameOutputs) {
    std::ifstream in(frameOutputs / "report.json");
    return nlohmann::json::parse(in).at("input");
}

class SceneSequence : public ::testing::Test {
protected:
    static void SetUpTestSuite() { figure = new TriangleMesh(test::figureMesh(false)); }
    static void TearDownTestSuite() { delete figure, figure = nullptr; }
    static TriangleMesh* figure;
    test::TempDir dir;
};
TriangleMesh* SceneSequence::figure = nullptr;

TEST_F(SceneSequence, EveryFrameIsSegmentedAndTheConsensusIsTheModalFramesLabels) {
    const std::vector<std::string> names = {"walk_1", "walk_2", "walk_3"};
    writeOff(dir / "walk_1.off", *figure);
    writeOff(dir / "walk_2.off", posed(*figure, 30.0, 1.0));
    writeOff(dir / "walk_3.off", posed(*figure, -20.0, 1.15));
    const auto out = dir / "out";
    const auto run =
        test::runSkelseg({"sequence", (dir / "walk_1.off").string(), (dir / "walk_2.off").string(),
                          (dir / "walk_3.off").string(), "-o", out.string(), "--resolution", "80",
                          "-q", "--no-preview"});
    ASSERT_EQ(run.exitCode, 0) << run.describe();
    EXPECT_TRUE(run.err.empty()) << run.err;

    std::ifstream in(out / "sequence.json");
    const nlohmann::json summary = nlohmann::json::parse(in);
    ASSERT_EQ(summary["frames"].size(), 3u);
    std::vector<std::size_t> parts;
    std::map<std::size_t, int> framesWith;
    for (std::size_t f = 0; f < 3; ++f) {
        const auto labels = readSeg(out / "frames" / names[f] / "segmentation.seg");
        ASSERT_EQ(labels.size(), figure->faceCount);
        parts.push_back(distinct(labels));
        ++framesWith[parts.back()];
        EXPECT_EQ(summary["frames"][f]["parts"].get<std::size_t>(), parts.back());
        EXPECT_EQ(summary["frames"][f]["outputs"], "frames/" + names[f]);
    }
    // A figure with two arms, two legs and a head: more than one part.
    EXPECT_GT(parts[0], 1u);
    const std::size_t reference = summary["reference_frame"];
    ASSERT_LT(reference, 3u);
    int most = 0;
    for (const auto& [count, frames] : framesWith) most = std::max(most, frames);
    EXPECT_EQ(framesWith[parts[reference]], most);
    EXPECT_EQ(summary["modal_parts"].get<std::size_t>(), parts[reference]);
    EXPECT_EQ(summary["frames"][reference]["rand_index_error_to_consensus"].get<double>(), 0.0);
    // The consensus is the reference frame's labels, byte for byte.
    EXPECT_EQ(test::fileBytes(out / "segmentation.seg"),
              test::fileBytes(out / "frames" / names[reference] / "segmentation.seg"));
}

// A frame whose voxel model keeps a handle its mesh lacks neither votes nor
// is chosen. Frame 0: a tube wound beyond a turn, its end sunk into its
// beginning, with the self-overlap clearing held to 2 voxels (the crossing
// stays fused at some of these shapes and resolutions); frame 1: the same
// faces wound three quarters of a turn, nothing touching. With both frames
// voting, two frames tie and the earlier would be chosen.
TEST_F(SceneSequence, AFrameWithHandlesItsMeshLacksIsNotChosen) {
    int fused = 0;
    for (double extraAngle : {1.2, 2.0}) {
        test::CurledTube tube;
        tube.endRadius = 0.3;
        tube.extraAngle = extraAngle;
        writeOff(dir / "wound.off", tube.mesh());
        tube.extraAngle = -1.5;
        writeOff(dir / "open.off", tube.mesh());
        for (const std::string resolution : {"64", "96"}) {
            const auto out = dir / ("out-" + std::to_string(extraAngle) + "-" + resolution);
            const auto run = test::runSkelseg(
                {"sequence", (dir / "wound.off").string(), (dir / "open.off").string(), "-o",
                 out.string(), "--resolution", resolution, "--self-overlap-clearance", "2", "-q",
                 "--no-preview"});
            ASSERT_EQ(run.exitCode, 0) << run.describe();
            std::ifstream in(out / "sequence.json");
            const nlohmann::json summary = nlohmann::json::parse(in);
            std::vector<std::int64_t> handles;
            for (const std::string name : {"wound", "open"}) {
                std::ifstream reportFile(out / "frames" / name / "report.json");
                const nlohmann::json input = nlohmann::json::parse(reportFile).at("input");
                handles.push_back(
                    std::max<std::int64_t>(0, input.at("voxel_genus").get<std::int64_t>() -
                                                  input.at("mesh_genus").get<std::int64_t>()));
            }
            ASSERT_EQ(handles[1], 0) << "the open tube must voxelise with its mesh's genus";
            for (std::size_t f = 0; f < 2; ++f) {
                EXPECT_EQ(summary["frames"][f]["voxel_handles_beyond_mesh"], handles[f]);
                EXPECT_EQ(summary["frames"][f]["voted"], handles[f] == 0);
            }
            if (handles[0] == 0) {
                EXPECT_EQ(summary["reference_frame"], 0) << "a tie goes to the earlier frame";
                continue;
            }
            ++fused;
            EXPECT_EQ(summary["reference_frame"], 1)
                << "extra angle " << extraAngle << ", resolution " << resolution;
            EXPECT_EQ(test::fileBytes(out / "segmentation.seg"),
                      test::fileBytes(out / "frames" / "open" / "segmentation.seg"));
        }
    }
    // Without a fused frame this test tests nothing.
    EXPECT_GE(fused, 1);
}

TEST_F(SceneSequence, FramesWithOtherFacesAreRefusedAndNothingIsWritten) {
    writeOff(dir / "a.off", *figure);
    writeOff(dir / "b.off", test::figureMesh(true));  // the hand on the hip: other faces
    const auto out = dir / "out";
    const auto run = test::runSkelseg(
        {"sequence", (dir / "a.off").string(), (dir / "b.off").string(), "-o", out.string(), "-q"});
    EXPECT_EQ(run.exitCode, 2) << run.describe();
    ASSERT_EQ(run.errLines().size(), 1u) << run.err;
    EXPECT_NE(run.err.find((dir / "b.off").string()), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("share their faces"), std::string::npos) << run.err;
    EXPECT_FALSE(std::filesystem::exists(out));
}

// STL has no shared vertices: its reader makes one vertex of the corners at
// one position, so the corners where the arms touch in the second frame only
// are one vertex there alone, and the frame's triangle list was not the
// others'. A valid sequence was refused ("its faces differ from those of
// apart_1.stl"). Each STL frame is segmented as the same pose written as OFF,
// whose touching corners stay two vertices: every check counts corners at
// one position as one.
TEST_F(SceneSequence, StlFramesWhoseCornersTouchInOnePoseOnlyShareTheirFaces) {
    const std::vector<std::string> names = {"apart_1", "touching", "apart_2"};
    const std::vector<TriangleMesh> poses = {twoArms({1.5, 1, 3}), twoArms({1, 1, 3}),
                                             twoArms({1, 1.5, 3})};
    const std::vector<std::string> arguments = {"--resolution", "40", "-q", "--no-preview"};
    const auto runSequence = [&](const std::string& kind,
                                 const std::vector<std::string>& extensions) {
        std::vector<std::string> command = {"sequence"};
        for (std::size_t f = 0; f < poses.size(); ++f) {
            const auto path = dir / (kind + "_" + names[f] + extensions[f]);
            if (extensions[f] == ".off")
                writeOff(path, poses[f]);
            else if (kind == "ascii" || kind == "mixed")
                writeAsciiStl(path, poses[f]);
            else
                writeBinaryStl(path, poses[f]);
            command.push_back(path.string());
        }
        const auto out = dir / ("out_" + kind);
        command.insert(command.end(), {"-o", out.string()});
        command.insert(command.end(), arguments.begin(), arguments.end());
        return std::make_pair(test::runSkelseg(command), out);
    };

    const auto [offRun, offOut] = runSequence("off", {".off", ".off", ".off"});
    ASSERT_EQ(offRun.exitCode, 0) << offRun.describe();
    const auto frameOutputs = [&](const std::filesystem::path& out, const std::string& kind,
                                  std::size_t f) {
        return out / "frames" / (kind + "_" + names[f]);
    };
    // The touching corners are two vertices in the OFF file and one read
    // from STL (below).
    EXPECT_EQ(reportInput(frameOutputs(offOut, "off", 1)).at("vertices"), 16);

    // Binary, ASCII, and STL between OFF frames (each frame's own vertices
    // are compared only with another file that has them).
    for (const auto& [kind, extensions] :
         std::vector<std::pair<std::string, std::vector<std::string>>>{
             {"binary", {".stl", ".stl", ".stl"}},
             {"ascii", {".stl", ".stl", ".stl"}},
             {"mixed", {".off", ".stl", ".off"}}}) {
        SCOPED_TRACE(kind);
        const auto [run, out] = runSequence(kind, extensions);
        ASSERT_EQ(run.exitCode, 0) << run.describe();
        // The apart frames' "2 separate pieces", as for OFF.
        EXPECT_EQ(run.errLines().size(), offRun.errLines().size()) << run.err;
        EXPECT_EQ(readSeg(out / "segmentation.seg").size(), 24u);
        for (std::size_t f = 0; f < poses.size(); ++f) {
            SCOPED_TRACE(names[f]);
            const auto own = frameOutputs(out, kind, f), off = frameOutputs(offOut, "off", f);
            EXPECT_EQ(readSeg(own / "segmentation.seg").size(), 24u);
            EXPECT_EQ(test::fileBytes(own / "segmentation.seg"),
                      test::fileBytes(off / "segmentation.seg"));
            const nlohmann::json input = reportInput(own), offInput = reportInput(off);
            for (const char* key :
                 {"mesh_closed", "mesh_pieces", "mesh_genus", "mesh_closed_pieces", "voxel_genus"})
                EXPECT_EQ(input.at(key), offInput.at(key)) << key;
            if (f == 1 && extensions[f] == ".stl") EXPECT_EQ(input.at("vertices"), 15);
        }
        EXPECT_EQ(test::fileBytes(out / "segmentation.seg"),
                  test::fileBytes(offOut / "segmentation.seg"));
        // Touching or apart, the arms are two parts of genus 0.
        std::ifstream in(out / "sequence.json");
        const nlohmann::json summary = nlohmann::json::parse(in);
        for (std::size_t f = 0; f < poses.size(); ++f) {
            EXPECT_EQ(summary["frames"][f]["parts"], 2) << names[f];
            EXPECT_EQ(reportInput(frameOutputs(out, kind, f)).at("mesh_genus"), 0) << names[f];
        }
    }
}

TEST_F(SceneSequence, StlFramesOfAnotherTriangleCountAreRefused) {
    writeBinaryStl(dir / "a.stl", twoArms({1.5, 1, 3}));
    TriangleMesh oneArm;
    test::addBox(oneArm, {1, 1, 3}, test::rotation({0, 0, 1}, 0));
    writeAsciiStl(dir / "b.stl", oneArm);
    const auto out = dir / "out";
    auto run = test::runSkelseg(
        {"sequence", (dir / "a.stl").string(), (dir / "b.stl").string(), "-o", out.string(), "-q"});
    EXPECT_EQ(run.exitCode, 2) << run.describe();
    EXPECT_EQ(run.errLines(),
              std::vector<std::string>{"skelseg: error: " + (dir / "b.stl").string() +
                                       ": has 12 faces, " + (dir / "a.stl").string() +
                                       " has 24; the frames of a sequence share their faces"});
    EXPECT_FALSE(std::filesystem::exists(out));

    // After an STL frame, a frame with vertices of its own is held to the
    // first such frame's.
    writeOff(dir / "c.off", twoArms({1.5, 1, 3}));
    TriangleMesh swapped = twoArms({1.5, 1, 3});
    std::swap(swapped.triangles[0], swapped.triangles[12]);
    writeOff(dir / "d.off", swapped);
    run = test::runSkelseg({"sequence", (dir / "a.stl").string(), (dir / "c.off").string(),
                            (dir / "d.off").string(), "-o", out.string(), "-q"});
    EXPECT_EQ(run.exitCode, 2) << run.describe();
    EXPECT_EQ(run.errLines(),
              std::vector<std::string>{
                  "skelseg: error: " + (dir / "d.off").string() +
                  ": its faces differ from those of " + (dir / "c.off").string() +
                  "; the frames of a sequence share their faces (same faces in the same order)"});
    EXPECT_FALSE(std::filesystem::exists(out));
}

TEST_F(SceneSequence, OneFrameAFrameInsideTheOutputsAndEarlierResultsAreRefused) {
    writeOff(dir / "a.off", *figure);
    writeOff(dir / "b.off", posed(*figure, 10.0, 1.0));
    auto run = test::runSkelseg(
        {"sequence", (dir / "a.off").string(), "-o", (dir / "one").string(), "-q"});
    EXPECT_EQ(run.exitCode, 2) << run.describe();
    EXPECT_EQ(run.errLines().size(), 1u) << run.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "one"));

    // A volume is no frame: the consensus labels mesh faces.
    std::ofstream(dir / "v.nrrd") << "NRRD0004\n";
    run = test::runSkelseg({"sequence", (dir / "a.off").string(), (dir / "v.nrrd").string(), "-o",
                            (dir / "vol").string(), "-q"});
    EXPECT_EQ(run.exitCode, 2) << run.describe();
    EXPECT_EQ(run.errLines().size(), 1u) << run.err;
    EXPECT_NE(run.err.find((dir / "v.nrrd").string() + ": the frames of a sequence are meshes"),
              std::string::npos)
        << run.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "vol"));
    // A folder is said to be one (it was "the frames of a sequence are meshes").
    std::filesystem::create_directories(dir / "folder.off");
    run = test::runSkelseg({"sequence", (dir / "a.off").string(), (dir / "folder.off").string(),
                            "-o", (dir / "vol").string(), "-q"});
    EXPECT_EQ(run.exitCode, 2) << run.describe();
    EXPECT_EQ(run.errLines(),
              std::vector<std::string>{"skelseg: error: " + (dir / "folder.off").string() +
                                       ": is a directory, not a file"});
    EXPECT_FALSE(std::filesystem::exists(dir / "vol"));

    // A frame kept in OUTDIR/frames would be replaced by the run's frames/.
    std::filesystem::create_directories(dir / "out" / "frames");
    writeOff(dir / "out" / "frames" / "c.off", posed(*figure, 5.0, 1.0));
    const std::string kept = test::fileBytes(dir / "out" / "frames" / "c.off");
    run = test::runSkelseg({"sequence", (dir / "a.off").string(),
                            (dir / "out" / "frames" / "c.off").string(), "-o",
                            (dir / "out").string(), "-q", "--force"});
    EXPECT_EQ(run.exitCode, 2) << run.describe();
    EXPECT_NE(run.err.find("would be replaced"), std::string::npos) << run.err;
    EXPECT_EQ(test::fileBytes(dir / "out" / "frames" / "c.off"), kept);

    // Earlier results without --force: refused, left as they were.
    std::filesystem::create_directories(dir / "earlier");
    std::ofstream(dir / "earlier" / "sequence.json") << "{}";
    run = test::runSkelseg({"sequence", (dir / "a.off").string(), (dir / "b.off").string(), "-o",
                            (dir / "earlier").string(), "-q", "--resolution", "48"});
    EXPECT_EQ(run.exitCode, 2) << run.describe();
    EXPECT_EQ(test::directoryEntries(dir / "earlier"), std::vector<std::string>{"sequence.json"});
    EXPECT_EQ(test::fileBytes(dir / "earlier" / "sequence.json"), "{}");
}

TEST_F(SceneSequence, FramesNamedOnlyDotsBeforeTheExtensionAreRefusedAndNothingIsWritten) {
    // frames/NAME would be frames/. or frames/.., the frames folder itself or
    // OUTDIR's staging folder.
    writeOff(dir / "a.off", *figure);
    for (const std::string name : {"..off", "...off", "....OFF"}) {
        SCOPED_TRACE(name);
        writeOff(dir / name, posed(*figure, 10.0, 1.0));
        const auto before = test::directoryEntries(dir.path());
        const auto run =
            test::runSkelseg({"sequence", (dir / "a.off").string(), (dir / name).string(), "-o",
                              (dir / "out").string(), "-q", "--resolution", "48"});
        EXPECT_EQ(run.exitCode, 2) << run.describe();
        ASSERT_EQ(run.errLines().size(), 1u) << run.err;
        EXPECT_EQ(run.errLines()[0].rfind("skelseg: error: " + (dir / name).string() +
                                              ": the frame's name has nothing but dots before",
                                          0),
                  0u)
            << run.err;
        EXPECT_FALSE(std::filesystem::exists(dir / "out"));
        EXPECT_EQ(test::directoryEntries(dir.path()), before);
    }
}

// Frames exported one per folder share their file name (take_1/mesh.off,
// take_2/mesh.off): they were refused ("two frames are named 'mesh'"), and
// get the folder that tells them apart in front, as a batch names its inputs.
TEST_F(SceneSequence, FramesOfOneNameInTheirOwnFoldersAreToldApartByTheFolder) {
    std::filesystem::create_directories(dir / "take_1");
    std::filesystem::create_directories(dir / "take_2");
    writeOff(dir / "take_1" / "mesh.off", *figure);
    writeOff(dir / "take_2" / "mesh.off", posed(*figure, 20.0, 1.0));
    const auto out = dir / "out";
    const auto run = test::runSkelseg({"sequence", (dir / "take_1" / "mesh.off").string(),
                                       (dir / "take_2" / "mesh.off").string(), "-o", out.string(),
                                       "-q", "--no-preview", "--resolution", "48"});
    ASSERT_EQ(run.exitCode, 0) << run.describe();
    EXPECT_EQ(test::directoryEntries(out / "frames"),
              (std::vector<std::string>{"take_1-mesh", "take_2-mesh"}));
    std::ifstream in(out / "sequence.json");
    const nlohmann::json summary = nlohmann::json::parse(in);
    ASSERT_EQ(summary["frames"].size(), 2u);
    EXPECT_EQ(summary["frames"][0]["outputs"], "frames/take_1-mesh");
    EXPECT_EQ(summary["frames"][1]["outputs"], "frames/take_2-mesh");
    for (const char* name : {"take_1-mesh", "take_2-mesh"})
        EXPECT_EQ(readSeg(out / "frames" / name / "segmentation.seg").size(), figure->faceCount);
    // One file twice, by another path, is still refused: it would vote twice.
    const auto twice = test::runSkelseg({"sequence", (dir / "take_1" / "mesh.off").string(),
                                         (dir / "take_1" / ".." / "take_1" / "mesh.off").string(),
                                         "-o", (dir / "twice").string(), "-q"});
    EXPECT_EQ(twice.exitCode, 2) << twice.describe();
    EXPECT_EQ(twice.errLines(),
              std::vector<std::string>{
                  "skelseg: error: " + (dir / "take_1" / ".." / "take_1" / "mesh.off").string() +
                  ": is frame 1 again (" + (dir / "take_1" / "mesh.off").string() +
                  "); give each frame once"});
    EXPECT_FALSE(std::filesystem::exists(dir / "twice"));
}

}  // namespace
}  // namespace skelseg
