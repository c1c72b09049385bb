// Tests for io/volume/VdbIO.h. The only test file that includes OpenVDB headers
// (they are slow to compile): it builds its input grids with OpenVDB itself.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>

#include "io/volume/VdbIO.h"
#include "io/volume/VolumeReader.h"
#include "kernels/base/Error.h"
#include "tests/support/FileBytes.h"
#include "tests/support/InputErrorExpectation.h"
#include "tests/support/MaskCounts.h"
#include "tests/support/SmallTmpfs.h"
#include "tests/support/TempDir.h"

namespace fs = std::filesystem;
using namespace skelseg;
using namespace skelseg::test;

namespace {

void writeGrids(const fs::path& file, const openvdb::GridCPtrVec& grids) {
    openvdb::initialize();
    openvdb::io::File out(file.string());
    out.write(grids);
    out.close();
}

openvdb::BoolGrid::Ptr boolGridWith(const std::string& name,
                                    std::initializer_list<openvdb::Coord> voxels) {
    openvdb::initialize();
    auto grid = openvdb::BoolGrid::create(false);
    grid->setName(name);
    auto transform = openvdb::math::Transform::createLinearTransform(0.5);
    transform->postTranslate(openvdb::Vec3d(10.0, -4.0, 2.5));
    grid->setTransform(transform);
    for (const auto& voxel : voxels) grid->tree().setValueOn(voxel, true);
    return grid;
}

}  // namespace

TEST(VdbIO, BoolGridActiveVoxelsWithBoundingBoxAndGeometry) {
    test::TempDir dir;
    const auto grid = boolGridWith("shape", {openvdb::Coord(-3, 2, 5), openvdb::Coord(1, 4, 6)});
    // An active voxel whose value is false is still object: activity decides.
    grid->tree().setValueOn(openvdb::Coord(0, 3, 5), false);
    writeGrids(dir / "bool.vdb", {grid});
    const MaskVolume mask = readVdbMask(dir / "bool.vdb");
    ASSERT_EQ(mask.dims(), (Dims{5, 3, 2}));
    EXPECT_EQ(mask(0, 0, 0), 1);
    EXPECT_EQ(mask(4, 2, 1), 1);
    EXPECT_EQ(mask(3, 1, 0), 1);
    EXPECT_EQ(countNonzero(mask), 3u);
    // Our voxel (4, 2, 1) is VDB index (1, 4, 6).
    const auto world = mask.geometry.indexToWorld(4, 2, 1);
    const openvdb::Vec3d expected = grid->transform().indexToWorld(openvdb::Coord(1, 4, 6));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(world[c], expected[c], 1e-12);
    EXPECT_NEAR(mask.geometry.voxelSize(), 0.5, 1e-12);
}

TEST(VdbIO, ActiveTilesAreDensified) {
    test::TempDir dir;
    auto grid = boolGridWith("tiles", {});
    // A leaf-aligned 8^3 fill becomes an active tile, plus one loose voxel.
    grid->tree().fill(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(7)), true, true);
    grid->tree().setValueOn(openvdb::Coord(9, 0, 0), true);
    ASSERT_GT(grid->tree().activeTileCount(), 0u);
    writeGrids(dir / "tiles.vdb", {grid});
    const MaskVolume mask = readVdbMask(dir / "tiles.vdb");
    ASSERT_EQ(mask.dims(), (Dims{10, 8, 8}));
    EXPECT_EQ(countNonzero(mask), 8u * 8u * 8u + 1u);
    EXPECT_EQ(mask(8, 0, 0), 0);
}

TEST(VdbIO, MaskGrid) {
    test::TempDir dir;
    openvdb::initialize();
    auto grid = openvdb::MaskGrid::create();
    grid->setName("mask");
    grid->tree().setValueOn(openvdb::Coord(2, 2, 2));
    grid->tree().setValueOn(openvdb::Coord(2, 3, 2));
    writeGrids(dir / "mask.vdb", {grid});
    const MaskVolume mask = readVdbMask(dir / "mask.vdb");
    EXPECT_EQ(mask.dims(), (Dims{1, 2, 1}));
    EXPECT_EQ(countNonzero(mask), 2u);
}

TEST(VdbIO, LevelSetSphereInteriorMatchesBallVolume) {
    test::TempDir dir;
    openvdb::initialize();
    const float radius = 12.0f;
    auto sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
        radius, openvdb::Vec3f(3, -2, 1), 1.0f);
    sphere->setName("sphere");
    auto doubleSphere = openvdb::tools::createLevelSetSphere<openvdb::DoubleGrid>(
        radius, openvdb::Vec3f(3, -2, 1), 1.0f);
    doubleSphere->setName("double sphere");
    writeGrids(dir / "sphere.vdb", {sphere, doubleSphere});
    const double ball = 4.0 / 3.0 * M_PI * radius * radius * radius;
    for (const char* name : {"sphere", "double sphere"}) {
        const MaskVolume mask = readVdbMask(dir / "sphere.vdb", name);
        const double interior = double(countNonzero(mask));
        // The inactive interior (beyond the narrow band) counts too.
        EXPECT_NEAR(interior, ball, 0.03 * ball) << name;
        EXPECT_GE(mask.dims().x, 23) << name;
        EXPECT_LE(mask.dims().x, 25) << name;
        // The centre of the ball is object.
        const auto& g = mask.geometry;
        const int cx = int(std::lround(3 - g.origin[0])), cy = int(std::lround(-2 - g.origin[1])),
                  cz = int(std::lround(1 - g.origin[2]));
        EXPECT_EQ(mask(cx, cy, cz), 1) << name;
    }
}

TEST(VdbIO, FogVolumeUsesPositiveActiveValues) {
    test::TempDir dir;
    openvdb::initialize();
    auto fog = openvdb::FloatGrid::create(0.0f);
    fog->setGridClass(openvdb::GRID_FOG_VOLUME);
    fog->tree().setValueOn(openvdb::Coord(1, 1, 1), 0.5f);
    fog->tree().setValueOn(openvdb::Coord(4, 1, 1), 0.0f);  // active but empty
    fog->tree().setValueOn(openvdb::Coord(5, 1, 1), 1.0f);
    writeGrids(dir / "fog.vdb", {fog});
    const MaskVolume mask = readVdbMask(dir / "fog.vdb");
    EXPECT_EQ(mask.dims(), (Dims{5, 1, 1}));
    EXPECT_EQ(countNonzero(mask), 2u);
    EXPECT_EQ(mask(3, 0, 0), 0);
}

TEST(VdbIO, NamedGridSelectionAndMissingNameListsGrids) {
    test::TempDir dir;
    const auto a = boolGridWith("alpha", {openvdb::Coord(0, 0, 0)});
    const auto b = boolGridWith("beta", {openvdb::Coord(0, 0, 0), openvdb::Coord(0, 0, 1)});
    writeGrids(dir / "two.vdb", {a, b});
    EXPECT_EQ(countNonzero(readVdbMask(dir / "two.vdb")), 1u);
    EXPECT_EQ(countNonzero(readVdbMask(dir / "two.vdb", "beta")), 2u);
    VolumeReadOptions options;
    options.gridName = "beta";
    EXPECT_EQ(countNonzero(readVolume(dir / "two.vdb", options)), 2u);
    expectInputError([&] { readVdbMask(dir / "two.vdb", "gamma"); }, "two.vdb", "'alpha', 'beta'");
}

TEST(VdbIO, EmptyGridGivesOneEmptyVoxel) {
    test::TempDir dir;
    writeGrids(dir / "empty.vdb", {boolGridWith("nothing", {})});
    const MaskVolume mask = readVdbMask(dir / "empty.vdb");
    EXPECT_EQ(mask.dims(), (Dims{1, 1, 1}));
    EXPECT_EQ(countNonzero(mask), 0u);
}

TEST(VdbIO, MemoryReaderMatchesFileReader) {
    test::TempDir dir;
    writeGrids(dir / "bool.vdb",
               {boolGridWith("shape", {openvdb::Coord(1, 2, 3), openvdb::Coord(4, 2, 3)})});
    const std::string bytes = fileBytes(dir / "bool.vdb");
    const MaskVolume fromMemory = readVdbMaskFromMemory(
        "buffer", reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    const MaskVolume fromFile = readVdbMask(dir / "bool.vdb");
    EXPECT_EQ(fromMemory.dims(), fromFile.dims());
    EXPECT_EQ(fromMemory.values(), fromFile.values());
    EXPECT_EQ(countNonzero(fromMemory), 2u);
}

TEST(VdbIO, WriteLabelsUniformAndAffineGeometry) {
    test::TempDir dir;
    LabelVolume labels(Dims{5, 7, 3});
    std::size_t nonzero = 0;
    for (int z = 0; z < 3; ++z)
        for (int y = 0; y < 7; ++y)
            for (int x = 0; x < 5; ++x) {
                const int value = (x + 2 * y + 3 * z) % 4 == 0 ? 0 : 1 + x + 5 * y + 35 * z;
                labels(x, y, z) = std::uint16_t(value);
                nonzero += value != 0;
            }
    labels(4, 6, 2) = 60000;

    VolumeGeometry uniform = VolumeGeometry::uniform(0.5, {1.0, 2.0, 3.0});
    VolumeGeometry affine;
    affine.origin = {-1.0, 0.5, 7.0};
    affine.directions = {{{0.5, 0.1, 0.0}, {-0.1, 0.75, 0.0}, {0.0, 0.0, 1.2}}};
    for (const VolumeGeometry& geometry : {uniform, affine}) {
        labels.geometry = geometry;
        writeVdbLabels(dir / "labels.vdb", labels);
        openvdb::io::File in((dir / "labels.vdb").string());
        in.open();
        auto grid = openvdb::gridPtrCast<openvdb::Int32Grid>(in.readGrid("labels"));
        in.close();
        ASSERT_TRUE(grid);
        EXPECT_EQ(grid->background(), 0);
        EXPECT_EQ(grid->activeVoxelCount(), openvdb::Index64(nonzero));
        auto accessor = grid->getConstAccessor();
        for (int z = 0; z < 3; ++z)
            for (int y = 0; y < 7; ++y)
                for (int x = 0; x < 5; ++x) {
                    const openvdb::Coord c(x, y, z);
                    ASSERT_EQ(accessor.getValue(c), int(labels(x, y, z)));
                    ASSERT_EQ(accessor.isValueOn(c), labels(x, y, z) > 0);
                }
        const auto expected = geometry.indexToWorld(4, 6, 2);
        const auto world = grid->transform().indexToWorld(openvdb::Coord(4, 6, 2));
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(world[c], expected[c], 1e-9);
    }
    // labels.vdb is an Int32Grid, which is not an input grid type.
    expectInputError([&] { readVdbMask(dir / "labels.vdb"); }, "labels.vdb",
                     "unsupported grid type int32");
}

// OpenVDB's writer puts a random file ID in every file: labels.vdb differed
// between two runs of the same input, the one output that did.
TEST(VdbIO, WriteLabelsGivesTheSameBytesForTheSameLabels) {
    test::TempDir dir;
    LabelVolume labels(Dims{6, 5, 4});
    for (int z = 0; z < 4; ++z)
        for (int y = 0; y < 5; ++y)
            for (int x = 0; x < 6; ++x) labels(x, y, z) = std::uint16_t((x + y * z) % 3);
    labels.geometry = VolumeGeometry::uniform(0.25, {1.0, -2.0, 0.5});
    writeVdbLabels(dir / "a.vdb", labels);
    writeVdbLabels(dir / "b.vdb", labels);
    const std::string a = fileBytes(dir / "a.vdb");
    EXPECT_EQ(a, fileBytes(dir / "b.vdb"));
    // The ID is still a UUID OpenVDB reads, and other labels get another.
    openvdb::io::File in((dir / "a.vdb").string());
    in.open();
    const std::string id = in.getUniqueTag();
    in.close();
    EXPECT_EQ(id, a.substr(21, 36));
    labels(0, 0, 0) = 7;
    writeVdbLabels(dir / "c.vdb", labels);
    EXPECT_NE(fileBytes(dir / "c.vdb").substr(21, 36), id);
}

TEST(VdbIO, WriteLabelsOnAFullDiskThrowsAndLeavesNoFile) {
    // openvdb::io::File::write() never checks its stream: labels.vdb came out
    // empty on a full disk and `segment` exited 0.
    SmallTmpfs disk(16 * 1024);
    if (!disk.mounted()) GTEST_SKIP() << disk.skipReason();
    LabelVolume labels(Dims{64, 64, 64});
    std::uint32_t state = 1;  // noise, which no compression shrinks below 16 KiB
    for (std::size_t i = 0; i < labels.size(); ++i) {
        state = state * 1664525u + 1013904223u;
        labels.data()[i] = std::uint16_t(state >> 16);
    }
    const fs::path file = disk / "labels.vdb";
    try {
        writeVdbLabels(file, labels);
        FAIL() << "wrote " << fs::file_size(file) << " bytes of labels.vdb on a 16 KiB disk";
    } catch (const OutputError& error) {
        EXPECT_NE(std::string(error.what()).find(file.string() + ": "), std::string::npos)
            << error.what();
        EXPECT_NE(std::string(error.what()).find("no space left on device"), std::string::npos)
            << error.what();
    }
    EXPECT_TRUE(fs::is_empty(disk.path()));
}

namespace {

/// The smallest factor t for which OpenVDB writes a grid with the transform
/// `transformFor(t)`, to the last bit: asked of OpenVDB itself, never of skelseg.
double smallestFactorOpenVdbWrites(
    const std::function<openvdb::math::Transform::Ptr(double)>& transformFor) {
    openvdb::initialize();
    const auto writes = [&](double t) {
        try {
            auto grid = openvdb::Int32Grid::create(0);
            grid->tree().setValueOn(openvdb::Coord(1, 1, 1), 7);
            grid->setTransform(transformFor(t));
            std::ostringstream out;
            openvdb::io::Stream(out).write(openvdb::GridCPtrVec{grid});
            return true;
        } catch (const openvdb::ArithmeticError&) {
            return false;
        }
    };
    double low = 1e-12, high = 1.0;  // refused and written
    EXPECT_FALSE(writes(low));
    EXPECT_TRUE(writes(high));
    for (;;) {
        const double middle = low + (high - low) / 2;
        if (middle <= low || middle >= high) break;
        (writes(middle) ? high : low) = middle;
    }
    return high;
}

}  // namespace

TEST(VdbIO, VoxelVolumeBoundIsOpenVdbsOwn) {
    test::TempDir dir;
    LabelVolume labels(Dims{3, 2, 2}, 1);
    // The two kinds of transform labels.vdb gets (see writeVdbLabels): a
    // uniform scale and translation, and an affine map (rotated, anisotropic).
    const double oblique[3][3] = {{0.5, 0.1, 0.0}, {-0.1, 0.75, 0.0}, {0.0, 0.2, 1.2}};
    struct Kind {
        std::function<openvdb::math::Transform::Ptr(double)> transformFor;
        std::function<VolumeGeometry(double)> geometryFor;
    };
    const Kind kinds[] = {
        {[](double size) {
             auto transform = openvdb::math::Transform::createLinearTransform(size);
             transform->postTranslate(openvdb::Vec3d(1.0, 2.0, 3.0));
             return transform;
         },
         [](double size) {
             return VolumeGeometry::uniform(size, {1.0, 2.0, 3.0});
         }},
        {[&](double t) {
             openvdb::Mat4d matrix = openvdb::Mat4d::identity();
             for (int axis = 0; axis < 3; ++axis)
                 for (int c = 0; c < 3; ++c) matrix[axis][c] = t * oblique[axis][c];
             matrix.setTranslation(openvdb::Vec3d(-1.0, 0.5, 7.0));
             return openvdb::math::Transform::createLinearTransform(matrix);
         },
         [&](double t) {
             VolumeGeometry geometry;
             geometry.origin = {-1.0, 0.5, 7.0};
             for (int axis = 0; axis < 3; ++axis)
                 for (int c = 0; c < 3; ++c) geometry.directions[axis][c] = t * oblique[axis][c];
             return geometry;
         }},
    };
    for (const Kind& kind : kinds) {
        const double inside = smallestFactorOpenVdbWrites(kind.transformFor);
        const double outside = std::nextafter(inside, 0.0);
        // OpenVDB's bound: a voxel volume of 3e-15 world units cubed.
        const double volume = kind.transformFor(inside)->voxelVolume();
        EXPECT_GT(volume, 2.99e-15);
        EXPECT_LT(volume, 3.01e-15);

        labels.geometry = kind.geometryFor(inside);
        EXPECT_TRUE(vdbCanHoldVoxelVolume(labels.dims(), labels.geometry)) << inside;
        writeVdbLabels(dir / "inside.vdb", labels);
        EXPECT_TRUE(fs::is_regular_file(dir / "inside.vdb"));
        fs::remove(dir / "inside.vdb");

        labels.geometry = kind.geometryFor(outside);
        EXPECT_FALSE(vdbCanHoldVoxelVolume(labels.dims(), labels.geometry)) << outside;
        EXPECT_THROW(writeVdbLabels(dir / "outside.vdb", labels), OutputError);
        EXPECT_FALSE(fs::exists(dir / "outside.vdb"));
    }
}

TEST(VdbIO, MalformedFilesGiveOneLineErrors) {
    test::TempDir dir;
    writeGrids(dir / "good.vdb",
               {boolGridWith("shape", {openvdb::Coord(1, 2, 3), openvdb::Coord(40, 2, 3)})});
    const std::string good = fileBytes(dir / "good.vdb");
    writeBytes(dir / "empty.vdb", "");
    writeBytes(dir / "text.vdb", "this is not a vdb file at all");
    writeBytes(dir / "truncated.vdb", good.substr(0, good.size() / 2));
    writeBytes(dir / "header-only.vdb", good.substr(0, 12));
    writeGrids(dir / "nogrids.vdb", {});
    writeGrids(dir / "huge.vdb",
               {boolGridWith("far", {openvdb::Coord(0, 0, 0), openvdb::Coord(100000, 0, 0)})});
    expectInputError([&] { readVdbMask(dir / "empty.vdb"); }, "empty.vdb", "empty");
    expectInputError([&] { readVdbMask(dir / "text.vdb"); }, "text.vdb", "not an OpenVDB file");
    expectInputError([&] { readVdbMask(dir / "truncated.vdb"); }, "truncated.vdb", "truncated");
    expectInputError([&] { readVdbMask(dir / "header-only.vdb"); }, "header-only.vdb", "truncated");
    expectInputError([&] { readVdbMask(dir / "nogrids.vdb"); }, "nogrids.vdb", "no grids");
    expectInputError([&] { readVdbMask(dir / "huge.vdb"); }, "huge.vdb", "limit");
    expectInputError([&] { readVdbMask(dir / "absent.vdb"); }, "absent.vdb", "no such file");
    fs::create_directories(dir / "folder.vdb");
    expectInputError([&] { readVdbMask(dir / "folder.vdb"); }, "folder.vdb", "is a directory");
}
