// Robustness of the CLI end for OpenVDB input (issue 5): see TestRobustness.cpp.
// The files are made with OpenVDB here; the mutated-byte cases that OpenVDB
// itself cannot survive are described in docs/robustness.md.
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <functional>
#include <ostream>

#include "tests/engine/RobustnessHelpers.h"

namespace fs = std::filesystem;
using namespace skelseg;
using namespace skelseg::test;

namespace {

void writeGrids(const fs::path& file, const openvdb::GridPtrVec& grids) {
    openvdb::initialize();
    openvdb::io::File out(file.string());
    out.write(grids);
    out.close();
}

openvdb::BoolGrid::Ptr cubeGrid() {
    openvdb::initialize();
    auto grid = openvdb::BoolGrid::create(false);
    grid->setName("cube");
    grid->fill(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(9)), true, true);
    return grid;
}

/// A valid one-grid file, cut to `keep(size)` bytes.
std::function<void(const fs::path&)> truncatedCube(std::function<std::size_t(std::size_t)> keep) {
    return [keep](const fs::path& file) {
        writeGrids(file, {cubeGrid()});
        const std::string bytes = fileBytes(file);
        writeBytes(file, bytes.substr(0, keep(bytes.size())));
    };
}

struct VdbCase {
    std::string name;
    std::function<void(const fs::path&)> make;
    std::string problem;
    std::vector<std::string> extraArguments = {};
};

void PrintTo(const VdbCase& c, std::ostream* os) {
    *os << c.name;
}

std::vector<VdbCase> vdbCases() {
    const std::string magic("\x20\x42\x44\x56\0\0\0\0", 8);
    auto raw = [](std::string content) {
        return [content](const fs::path& f) { writeBytes(f, content); };
    };
    return {
        {"empty", raw(""), "file is empty"},
        {"wrong_magic", raw("#binvox 1\ndim 1 1 1\ndata\n\1\1"), "wrong magic"},
        {"short_magic", raw("\x20\x42\x44"), "wrong magic"},
        {"magic_only", raw(magic), "truncated or corrupt"},
        {"magic_then_zeros", raw(magic + std::string(8, '\0')), ""},
        {"truncated_in_header", truncatedCube([](std::size_t) { return std::size_t(24); }), ""},
        {"truncated_in_metadata", truncatedCube([](std::size_t) { return std::size_t(200); }), ""},
        {"truncated_in_the_middle", truncatedCube([](std::size_t n) { return n / 2; }), ""},
        {"truncated_last_bytes", truncatedCube([](std::size_t n) { return n - 4; }), ""},
        {"no_grids", [](const fs::path& f) { writeGrids(f, {}); }, "holds no grids"},
        {"int32_grid",
         [](const fs::path& f) {
             auto grid = openvdb::Int32Grid::create(0);
             grid->tree().setValue(openvdb::Coord(1, 2, 3), 7);
             writeGrids(f, {grid});
         },
         "unsupported grid type"},
        {"vec3_grid",
         [](const fs::path& f) {
             auto grid = openvdb::Vec3SGrid::create();
             grid->tree().setValue(openvdb::Coord(1, 2, 3), openvdb::Vec3s(1, 0, 0));
             writeGrids(f, {grid});
         },
         "unsupported grid type"},
        {"frustum_transform",
         [](const fs::path& f) {
             auto grid = cubeGrid();
             grid->setTransform(openvdb::math::Transform::createFrustumTransform(
                 openvdb::BBoxd(openvdb::Vec3d(0), openvdb::Vec3d(10)), 0.5, 2.0, 1.0));
             writeGrids(f, {grid});
         },
         "non-linear"},
        {"bounding_box_over_axis_cap",
         [](const fs::path& f) {
             auto grid = openvdb::BoolGrid::create(false);
             grid->tree().setValueOn(openvdb::Coord(0, 0, 0), true);
             grid->tree().setValueOn(openvdb::Coord(100000, 0, 0), true);
             writeGrids(f, {grid});
         },
         "over the limit of 8192"},
        {"grid_too_far_for_its_voxel_size",
         [](const fs::path& f) {
             auto grid = cubeGrid();
             grid->transform().postTranslate(openvdb::Vec3d(1e15, 0, 0));
             writeGrids(f, {grid});
         },
         "2^-40 of them"},
        {"grid_name_not_found",
         [](const fs::path& f) { writeGrids(f, {cubeGrid()}); },
         "no grid named 'nope'",
         {"--grid", "nope"}},
    };
}

class BadVdbInput : public ::testing::TestWithParam<VdbCase> {};

TEST_P(BadVdbInput, ExitsTwoWithOneLineNamingTheFileAndWritesNothing) {
    TempDir dir;
    const fs::path file = dir / "input.vdb";
    GetParam().make(file);
    const std::string before = fileBytes(file);
    const CliResult result = runSegment(file, dir / "out", GetParam().extraArguments);
    EXPECT_TRUE(failsWithOneLine(result, 2, file.string(), GetParam().problem));
    EXPECT_TRUE(leftNothing(dir / "out"));
    EXPECT_EQ(fileBytes(file), before);
}

INSTANTIATE_TEST_SUITE_P(OpenVdb, BadVdbInput, ::testing::ValuesIn(vdbCases()),
                         [](const ::testing::TestParamInfo<VdbCase>& info) {
                             return info.param.name;
                         });

TEST(VdbInputCli, OwnLabelsOutputIsRefusedAsInput) {
    // labels.vdb is an Int32Grid of segment labels, not an object mask.
    TempDir dir;
    writeNrrdMask(dir / "box.nrrd", makeMask(Dims{10, 10, 10}, [](int x, int y, int z) {
                      return x > 1 && x < 8 && y > 1 && y < 8 && z > 1 && z < 8;
                  }));
    ASSERT_EQ(runSegment(dir / "box.nrrd", dir / "first", {"--no-preview"}).exitCode, 0);
    const CliResult result = runSegment(dir / "first" / "labels.vdb", dir / "second");
    EXPECT_TRUE(failsWithOneLine(result, 2, (dir / "first" / "labels.vdb").string(),
                                 "unsupported grid type"));
    EXPECT_TRUE(leftNothing(dir / "second"));
}

TEST(VdbInputCli, ValidCubeIsSegmented) {
    // The control for the cases above: the same file, untruncated, works.
    TempDir dir;
    writeGrids(dir / "cube.vdb", {cubeGrid()});
    const CliResult result = runSegment(dir / "cube.vdb", dir / "out", {"--no-preview"});
    ASSERT_EQ(result.exitCode, 0) << result.describe();
    EXPECT_EQ(readNrrdLabels(dir / "out" / "labels.nrrd").dims(), (Dims{10, 10, 10}));
}

}  // namespace
