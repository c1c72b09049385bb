// Tests for io/volume/BinvoxIO.h: binvox axis order, geometry, round trips and a
// table of malformed files.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/volume/BinvoxIO.h"
#include "io/volume/VolumeReader.h"
#include "kernels/base/Error.h"
#include "tests/support/FileBytes.h"
#include "tests/support/InputErrorExpectation.h"
#include "tests/support/MaskCounts.h"
#include "tests/support/TempDir.h"

namespace fs = std::filesystem;
using namespace skelseg;
using namespace skelseg::test;

namespace {

/// Run-length data from (value, count) pairs.
std::string runs(const std::vector<std::pair<int, int>>& pairs) {
    std::string data;
    for (const auto& [value, count] : pairs) {
        data += char(value);
        data += char(count);
    }
    return data;
}

// "dim 4 3 5": binvox x extent 4, z extent 3, y extent 5, so our dims are
// 4 x 5 x 3. binvox voxel (x, y, z) = (2, 4, 1) sits at x*3*5 + z*5 + y = 39.
const std::string kSingleVoxelHeader = "#binvox 1\ndim 4 3 5\ntranslate 1 2 3\nscale 10\ndata\n";
const std::string kSingleVoxelRuns = runs({{0, 39}, {1, 1}, {0, 20}});

}  // namespace

TEST(BinvoxIO, BinvoxVoxelLandsAtSameXyz) {
    test::TempDir dir;
    writeBytes(dir / "one.binvox", kSingleVoxelHeader + kSingleVoxelRuns);
    const MaskVolume mask = readBinvox(dir / "one.binvox");
    ASSERT_EQ(mask.dims(), (Dims{4, 5, 3}));
    EXPECT_EQ(mask(2, 4, 1), 1);
    EXPECT_EQ(countNonzero(mask), 1u);
}

TEST(BinvoxIO, GeometryIsVoxelCentres) {
    test::TempDir dir;
    writeBytes(dir / "one.binvox", kSingleVoxelHeader + kSingleVoxelRuns);
    const VolumeGeometry geometry = readBinvox(dir / "one.binvox").geometry;
    // voxel size = scale / max(dim) = 10 / 5 = 2; centre of voxel 0 = translate + 1.
    EXPECT_DOUBLE_EQ(geometry.voxelSize(), 2.0);
    const auto centre = geometry.indexToWorld(2, 4, 1);
    EXPECT_DOUBLE_EQ(centre[0], 1 + 2 * 2.5);
    EXPECT_DOUBLE_EQ(centre[1], 2 + 2 * 4.5);
    EXPECT_DOUBLE_EQ(centre[2], 3 + 2 * 1.5);
}

TEST(BinvoxIO, WriterUsesBinvoxOrder) {
    test::TempDir dir;
    MaskVolume mask(Dims{4, 5, 3});
    mask(2, 4, 1) = 1;
    mask.geometry = VolumeGeometry::uniform(2.0, {2.0, 3.0, 4.0});
    writeBinvox(dir / "out.binvox", mask);
    const std::string text = fileBytes(dir / "out.binvox");
    const std::string header = "#binvox 1\ndim 4 3 5\ntranslate 1 2 3\nscale 10\ndata\n";
    ASSERT_EQ(text.substr(0, header.size()), header);
    EXPECT_EQ(text.substr(header.size()), kSingleVoxelRuns);
}

TEST(BinvoxIO, RoundTripNonCubicWithLongRuns) {
    test::TempDir dir;
    MaskVolume mask(Dims{5, 7, 3});
    for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = (i * 7919u) % 5 < 2;
    mask.geometry = VolumeGeometry::uniform(0.25, {1.0, -2.0, 3.0});
    writeBinvox(dir / "mask.binvox", mask);
    const MaskVolume back = readBinvox(dir / "mask.binvox");
    ASSERT_EQ(back.dims(), mask.dims());
    EXPECT_EQ(back.values(), mask.values());
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(back.geometry.origin[c], mask.geometry.origin[c], 1e-12);
    EXPECT_NEAR(back.geometry.voxelSize(), 0.25, 1e-12);

    MaskVolume full(Dims{20, 20, 20}, 1);  // 8000 voxels: runs split at 255
    full(19, 19, 19) = 0;
    writeBinvox(dir / "full.binvox", full);
    const MaskVolume fullBack = readVolume(dir / "full.binvox");
    EXPECT_EQ(fullBack.values(), full.values());
}

TEST(BinvoxIO, VersionTwoValuesZeroCountsAndDefaults) {
    test::TempDir dir;
    // No translate/scale: unit cube, voxel size 1/max(dim). A 0-count run is a no-op.
    writeBytes(dir / "v2.binvox", "#binvox 2\ndim 2 2 2\nsome future line\ndata\n" +
                                      runs({{0, 3}, {1, 0}, {7, 1}, {0, 4}}));
    const MaskVolume mask = readBinvox(dir / "v2.binvox");
    // binvox index 3 = x 0, z 1, y 1.
    EXPECT_EQ(mask(0, 1, 1), 1);
    EXPECT_EQ(countNonzero(mask), 1u);
    EXPECT_DOUBLE_EQ(mask.geometry.voxelSize(), 0.5);
    EXPECT_DOUBLE_EQ(mask.geometry.origin[0], 0.25);
}

TEST(BinvoxIO, MemoryReader) {
    const std::string bytes = kSingleVoxelHeader + kSingleVoxelRuns;
    const MaskVolume mask = readBinvoxFromMemory(
        "buffer", reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    EXPECT_EQ(mask(2, 4, 1), 1);
}

TEST(BinvoxIO, MalformedFilesGiveOneLineErrorsNamingFileAndProblem) {
    test::TempDir dir;
    const std::string eight = runs({{1, 8}});
    struct Case {
        const char* name;
        std::string content;
        const char* keyword;
    };
    const std::vector<Case> cases = {
        {"empty", "", "empty"},
        {"wrong-magic", "#voxels 1\ndim 2 2 2\ndata\n" + eight, "magic"},
        {"version-3", "#binvox 3\ndim 2 2 2\ndata\n" + eight, "version"},
        {"no-version", "#binvox\ndim 2 2 2\ndata\n" + eight, "version"},
        {"no-dim", "#binvox 1\ndata\n" + eight, "missing 'dim'"},
        {"no-data", "#binvox 1\ndim 2 2 2\n", "missing 'data'"},
        {"dim-count", "#binvox 1\ndim 2 2\ndata\n" + eight, "3 sizes"},
        {"dim-negative", "#binvox 1\ndim 2 -2 2\ndata\n" + eight, "not positive"},
        {"dim-zero", "#binvox 1\ndim 0 2 2\ndata\n" + eight, "not positive"},
        {"dim-huge", "#binvox 1\ndim 2 2 9000\ndata\n" + eight, "limit"},
        {"dim-overflow", "#binvox 1\ndim 2 2 123456789012345678901234\ndata\n" + eight,
         "too large"},
        {"dim-text", "#binvox 1\ndim 2 two 2\ndata\n" + eight, "not an integer"},
        {"dim-twice", "#binvox 1\ndim 2 2 2\ndim 2 2 2\ndata\n" + eight, "twice"},
        {"scale-zero", "#binvox 1\ndim 2 2 2\nscale 0\ndata\n" + eight, "not positive"},
        {"scale-text", "#binvox 1\ndim 2 2 2\nscale big\ndata\n" + eight, "finite number"},
        {"translate-count", "#binvox 1\ndim 2 2 2\ntranslate 1 2\ndata\n" + eight, "translate"},
        {"run-overflow", "#binvox 1\ndim 2 2 2\ndata\n" + runs({{1, 5}, {0, 4}}), "overflows"},
        {"data-short", "#binvox 1\ndim 2 2 2\ndata\n" + runs({{1, 5}}), "too short"},
        {"data-none", "#binvox 1\ndim 2 2 2\ndata\n", "too short"},
        {"data-truncated-run",
         "#binvox 1\ndim 2 2 2\ndata\n" + runs({{1, 5}, {0, 2}}) + std::string(1, '\0'),
         "truncated run"},
        {"trailing-garbage", "#binvox 1\ndim 2 2 2\ndata\n" + eight + "xyz", "too long"},
        {"implausible-size", "#binvox 1\ndim 8000 8000 60\ndata\n" + eight, "cannot cover"},
        // Geometry that doubles cannot represent (VolumeGeometry::problemOver);
        // a voxel is scale / 2.
        {"subnormal-scale", "#binvox 1\ndim 2 2 2\nscale 1e-320\ndata\n" + eight,
         ") is a subnormal number: the voxels have no usable size"},
        {"tiny-scale", "#binvox 1\ndim 2 2 2\nscale 2e-200\ndata\n" + eight,
         "the voxel volume (1e-200 x 1e-200 x 1e-200) is outside the range of doubles"},
        {"far", "#binvox 1\ndim 2 2 2\ntranslate 1e15 0 0\nscale 2\ndata\n" + eight,
         "world coordinates reach 1e+15, where the voxel step along axis 0 (1) is below 2^-40 of "
         "them"},
    };
    for (const auto& c : cases) {
        const std::string fileName = std::string(c.name) + ".binvox";
        writeBytes(dir / fileName, c.content);
        expectInputError([&] { readBinvox(dir / fileName); }, fileName, c.keyword);
        expectInputError(
            [&] {
                readBinvoxFromMemory(fileName,
                                     reinterpret_cast<const std::uint8_t*>(c.content.data()),
                                     c.content.size());
            },
            fileName, c.keyword);
    }
}

TEST(BinvoxIO, FileSystemErrors) {
    test::TempDir dir;
    expectInputError([&] { readBinvox(dir / "absent.binvox"); }, "absent.binvox", "no such file");
    fs::create_directories(dir / "folder.binvox");
    expectInputError([&] { readBinvox(dir / "folder.binvox"); }, "folder.binvox", "is a directory");
}
