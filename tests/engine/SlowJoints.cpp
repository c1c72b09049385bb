// Slow: with --joints, every pose sequence of ../shared/data/poses keeps the
// same joint cuts in all its frames (issue 13), segmented as
// `skelseg segment MESH -o OUT --resolution 192 --joints`. A joint is a
// property of the limb, not of its pose, so a narrowing must not come and go,
// nor move to another joint, as the limb moves. Skipped where the data is
// absent.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "io/mesh/MeshIO.h"
#include "tests/support/PoseSequences.h"
#include "tests/support/TempDir.h"
#include "tests/support/TestPaths.h"

namespace skelseg {
namespace {

namespace fs = std::filesystem;
using Point = std::array<double, 3>;

/// The loops of cuts.ply (binary: float x, y, z, int cut per vertex), by loop index.
std::map<int, std::vector<Point>> readCutLoops(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::string line, header;
    std::size_t vertices = 0;
    while (std::getline(in, line) && line != "end_header") {
        std::istringstream words(line);
        std::string a, b;
        words >> a >> b;
        if (a == "element" && b == "vertex") words >> vertices;
    }
    std::map<int, std::vector<Point>> loops;
    for (std::size_t v = 0; v < vertices && in; ++v) {
        char record[16];
        in.read(record, sizeof record);
        float xyz[3];
        std::int32_t cut = 0;
        std::memcpy(xyz, record, sizeof xyz);
        std::memcpy(&cut, record + 12, sizeof cut);
        loops[cut].push_back({xyz[0], xyz[1], xyz[2]});
    }
    return loops;
}

/// Faces of `mesh` with a vertex within `reach` of a point of `loop`: the
/// ring of faces the loop cuts through.
std::set<std::uint32_t> facesNextTo(const TriangleMesh& mesh, const std::vector<Point>& loop,
                                    double reach) {
    std::set<std::uint32_t> faces;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (std::uint32_t v : mesh.triangles[t]) {
            bool near = false;
            for (const Point& p : loop) {
                double d2 = 0.0;
                for (int k = 0; k < 3; ++k) {
                    const double d = mesh.vertices[v][std::size_t(k)] - p[std::size_t(k)];
                    d2 += d * d;
                }
                near = near || d2 <= reach * reach;
            }
            if (near) {
                faces.insert(mesh.triangleFace[t]);
                break;
            }
        }
    return faces;
}

std::size_t sharedCount(const std::set<std::uint32_t>& a, const std::set<std::uint32_t>& b) {
    std::size_t shared = 0;
    for (std::uint32_t f : a) shared += b.count(f);
    return shared;
}

// The same joints: the frames of a sequence share their faces, so a joint
// cut is named by the faces next to its loop (a vertex within two voxels of
// a loop point). A joint cut of one frame is the same joint as a joint cut of
// another frame when at least a quarter of the smaller face ring is shared:
// a loop at the same joint crosses the same band of faces whatever the pose
// (the voxelisation moves it by a voxel or so), a loop at another joint, or
// one slid along the limb by more than its band, shares none. Every joint cut
// of every frame must be matched in every other frame, and the counts agree.
//
// And no decision is marginal: every narrowing candidate's ratio is at least
// kRatioMargin from --joint-ratio, so which joints these figures get does not
// hinge on the last hundredths of the threshold (docs/algorithm.md §14.5).
TEST(Joints, EveryPoseSequenceKeepsItsJointCuts) {
    constexpr double kRatioMargin = 0.02;
    const fs::path poses = test::sharedDataDir() / "poses";
    if (!fs::is_directory(poses)) GTEST_SKIP() << "no pose data at " << poses << ": skipped";
    const auto sequences = test::poseSequences(poses);
    if (sequences.empty()) GTEST_SKIP() << "no pose sequence in " << poses;
    test::TempDir dir;
    for (const auto& [name, outputs] : test::segmentPoseFrames(poses, dir.path(), {"--joints"})) {
        const std::vector<fs::path>& frames = sequences.at(name);
        ASSERT_EQ(frames.size(), outputs.size()) << name;
        std::vector<std::size_t> jointCuts;
        std::vector<std::vector<std::set<std::uint32_t>>> rings(outputs.size());
        for (std::size_t f = 0; f < outputs.size(); ++f) {
            const fs::path& out = outputs[f];
            std::ifstream in(out / "report.json");
            const nlohmann::json report = nlohmann::json::parse(in);
            const auto loops = readCutLoops(out / "cuts.ply");
            ASSERT_EQ(loops.size(), report.at("cuts").size()) << out;
            const TriangleMesh mesh = readMesh(frames[f]);
            const double reach = 2.0 * report.at("grid").at("voxel_size").get<double>();
            std::size_t kinds = 0, index = 0;
            for (const auto& cut : report.at("cuts")) {
                if (cut.at("kind") == "joint") {
                    ++kinds;
                    rings[f].push_back(facesNextTo(mesh, loops.at(int(index)), reach));
                    EXPECT_FALSE(rings[f].back().empty()) << out << ": joint cut " << index;
                }
                ++index;
            }
            EXPECT_EQ(kinds, report.at("joint_cuts").get<std::size_t>()) << out;
            const double threshold =
                report.at("parameters").at("joint_options").at("narrowing_ratio").get<double>();
            for (const auto& candidate : report.at("joint_candidates")) {
                if (candidate.at("kind") != "narrowing") continue;
                EXPECT_GE(std::fabs(candidate.at("ratio").get<double>() - threshold), kRatioMargin)
                    << out << ": narrowing at " << candidate.at("voxel").dump() << " with ratio "
                    << candidate.at("ratio").get<double>() << " (" << candidate.at("status") << ")";
            }
            jointCuts.push_back(kinds);
        }
        EXPECT_EQ(std::set<std::size_t>(jointCuts.begin(), jointCuts.end()).size(), 1u)
            << name << ": joint cuts per frame " << test::countList(jointCuts);
        for (std::size_t f = 0; f < rings.size(); ++f)
            for (std::size_t j = 0; j < rings[f].size(); ++j)
                for (std::size_t g = 0; g < rings.size(); ++g) {
                    if (g == f) continue;
                    bool matched = false;
                    for (const auto& other : rings[g])
                        matched = matched || 4 * sharedCount(rings[f][j], other) >=
                                                 std::min(rings[f][j].size(), other.size());
                    EXPECT_TRUE(matched)
                        << name << ": joint cut " << j << " of " << outputs[f].filename()
                        << " is no joint cut of " << outputs[g].filename();
                }
    }
}

}  // namespace
}  // namespace skelseg
