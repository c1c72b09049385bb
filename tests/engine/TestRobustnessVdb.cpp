// Robustness of the CLI end for OpenVDB input (issue 5): see TestRobustness.cpp.
// The files are made with OpenVDB here. Damaged files that OpenVDB itself
// cannot survive are found by damaging a file OpenVDB wrote until a plain
// OpenVDB parse crashes (docs/robustness.md, "Damaged OpenVDB files").
#include <fcntl.h>
#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <fstream>
#include <functional>
#include <optional>
#include <ostream>
#include <random>
#include <sstream>

#include "io/volume/VdbIO.h"
#include "tests/engine/RobustnessHelpers.h"
#include "tests/support/SanitizerAllocator.h"

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
        {"wrong_magic", raw("VDB 1\ndim 1 1 1\ndata\n\1\1"), "wrong magic"},
        // A shape of another format under the name: named, not "wrong magic".
        {"binvox_content", raw("#binvox 1\ndim 1 1 1\ndata\n\1\1"),
         "holds a binvox volume (it starts with '#binvox 1'), not an OpenVDB file as its name "
         "says; rename it to .binvox"},
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

/// The bytes OpenVDB writes for `grids` (the same for one OpenVDB version).
std::string vdbBytes(const openvdb::GridCPtrVec& grids) {
    openvdb::initialize();
    std::ostringstream out;
    openvdb::io::Stream(out).write(grids);
    return out.str();
}

/// How a plain OpenVDB parse of `bytes` ends in a forked child: the tests'
/// own oracle, independent of skelseg's isolation. The signal that ended it;
/// 0 when it returned, threw, or ran over 2 s; -1 when it threw
/// std::bad_alloc under a limit of `memoryLimit` bytes beyond what it
/// inherited (0: none).
int plainParseEnding(const std::string& bytes, std::uint64_t memoryLimit) {
    const pid_t child = ::fork();
    if (child == 0) {
        const int devNull = ::open("/dev/null", O_WRONLY);
        ::dup2(devNull, STDERR_FILENO);
        ::alarm(2);
        if (memoryLimit > 0) {
            std::ifstream status("/proc/self/status");
            std::uint64_t inherited = 0;
            for (std::string line; std::getline(status, line);)
                if (line.rfind("VmData:", 0) == 0) inherited = std::stoull(line.substr(7)) * 1024;
            const rlimit limit{inherited + memoryLimit, inherited + memoryLimit};
            ::setrlimit(RLIMIT_DATA, &limit);
        }
        try {
            std::istringstream in(bytes);
            in.exceptions(std::ios::failbit | std::ios::badbit);
            openvdb::io::Stream stream(in, false);
            stream.getGrids();
        } catch (const std::bad_alloc&) {
            ::_exit(3);
        } catch (...) {
        }
        ::_exit(0);
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    if (WIFSIGNALED(status)) return WTERMSIG(status) == SIGALRM ? 0 : WTERMSIG(status);
    return WIFEXITED(status) && WEXITSTATUS(status) == 3 ? -1 : 0;
}

/// The first of up to `tries` damaged copies of `base` (one to three bytes
/// after the magic number replaced, from the fixed `seed`) that `wanted`
/// accepts; nullopt when none does.
std::optional<std::string> damagedCopy(const std::string& base, unsigned seed, int tries,
                                       const std::function<bool(const std::string&)>& wanted) {
    std::mt19937 random(seed);
    for (int trial = 0; trial < tries; ++trial) {
        std::string bytes = base;
        const unsigned changes = 1 + random() % 3;
        for (unsigned c = 0; c < changes; ++c)
            bytes[8 + random() % (bytes.size() - 8)] = char(random());
        if (wanted(bytes)) return bytes;
    }
    return std::nullopt;
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

// OpenVDB 10 trusts the sizes stored in a file: on some damaged files its
// reader corrupts the heap and glibc aborts the process. skelseg parses in a
// child process first, so the damage is one line and exit code 2.
TEST(VdbInputCli, DamagedFileOnWhichOpenVdbCrashesIsBadInput) {
#if SKELSEG_TEST_SANITIZER_ALLOCATOR
    GTEST_SKIP() << "AddressSanitizer's heap reports the damage instead of glibc's abort";
#endif
    auto ball =
        openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(5.0f, openvdb::Vec3f(0), 1.0f);
    ball->setName("ball");
    const std::optional<std::string> crashing =
        damagedCopy(vdbBytes({ball}), 162, 6000, [](const std::string& bytes) {
            const int ending = plainParseEnding(bytes, 0);
            return ending == SIGABRT || ending == SIGSEGV || ending == SIGBUS;
        });
    if (!crashing) GTEST_SKIP() << "no damaged copy crashed this OpenVDB's reader";
    TempDir dir;
    const fs::path file = dir / "damaged.vdb";
    writeBytes(file, *crashing);
    const CliResult result = runSegment(file, dir / "out");
    EXPECT_TRUE(failsWithOneLine(result, 2, file.string(), "OpenVDB's reader crashed on it"));
    EXPECT_TRUE(leftNothing(dir / "out"));
    EXPECT_EQ(fileBytes(file), *crashing);
    // The library call too: an InputError naming the file, and this process
    // lives on. Whether the parse crashes depends on the heap it starts
    // from, which the child process inherits from this one: after some
    // other tests in the same process (a shuffled order) the damage reads
    // past the end of the data instead, a corrupt-file error.
    try {
        readVdbMask(file);
        ADD_FAILURE() << "no error";
    } catch (const InputError& error) {
        const std::string message = error.what();
        EXPECT_EQ(error.file(), file.string());
        EXPECT_TRUE(message.find("crashed") != std::string::npos ||
                    message.find("corrupt") != std::string::npos)
            << message;
    }
}

// Other damaged files make OpenVDB allocate gigabytes for kilobytes: the parse
// runs under --max-memory (exit 4) and stops at --time-limit (exit 3).
TEST(VdbInputCli, DamagedFileThatClaimsGigabytesIsBoundedByTheLimits) {
    SKELSEG_SKIP_WHERE_FAILED_ALLOCATIONS_ABORT();
    const std::optional<std::string> hungry = damagedCopy(
        vdbBytes({cubeGrid()}), 11, 2000,
        [](const std::string& bytes) { return plainParseEnding(bytes, 256u << 20) == -1; });
    if (!hungry) GTEST_SKIP() << "no damaged copy made this OpenVDB's reader allocate 256 MB";
    TempDir dir;
    const fs::path file = dir / "hungry.vdb";
    writeBytes(file, *hungry);
    // It asks for its gigabytes at once, which no valid file's nodes do: a
    // damaged file under any limit, not a file that needs more memory.
    const CliResult limited = runSegment(file, dir / "out", {"--max-memory", "300M"});
    EXPECT_TRUE(failsWithOneLine(limited, 2, file.string(),
                                 "corrupt OpenVDB file (implausible allocation while reading)"));
    EXPECT_TRUE(leftNothing(dir / "out"));
    const CliResult stopped = runSegment(file, dir / "out", {"--time-limit", "0.2"});
    EXPECT_TRUE(failsWithOneLine(stopped, 3, file.string(), "time limit reached"));
    EXPECT_TRUE(leftNothing(dir / "out"));
}

// A valid file whose parse needs more than --max-memory is refused for the
// memory, with exit code 4, wherever the parse runs out: OpenVDB's reader
// turns a failed allocation into a stream error, and c-blosc's into a null
// pointer (a crash); neither makes the file corrupt.
TEST(VdbInputCli, ValidFileWhoseParseNeedsMoreThanMaxMemoryIsTheLimitNotCorrupt) {
    SKELSEG_SKIP_WHERE_FAILED_ALLOCATIONS_ABORT();
    TempDir dir;
    openvdb::initialize();
    auto sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
        90.0f, openvdb::Vec3f(0.0f), 1.0f, 3.0f);
    writeGrids(dir / "sphere.vdb", {sphere});
    const std::uintmax_t fileBytes = fs::file_size(dir / "sphere.vdb");
    // From just over the file (which the memory check reads whole first) to
    // well over what the parse of its leaves needs at the smallest step.
    for (const double factor : {1.2, 1.6, 2.0, 2.5, 3.0, 4.0}) {
        const std::string limit =
            std::to_string(std::uint64_t(double(fileBytes) * factor / 1000.0)) + "K";
        const CliResult result =
            runSegment(dir / "sphere.vdb", dir / "out", {"--max-memory", limit});
        EXPECT_EQ(result.exitCode, 4) << "--max-memory " << limit << ": " << result.err;
        EXPECT_TRUE(leftNothing(dir / "out"));
    }
}

// A .vdb holds its object sparsely: two voxels far apart span a dense grid of
// billions. The grid is checked against --max-memory before it is allocated.
TEST(VdbInputCli, DenseGridOverMaxMemoryIsRefusedBeforeItIsAllocated) {
    TempDir dir;
    auto grid = openvdb::BoolGrid::create(false);
    grid->tree().setValueOn(openvdb::Coord(0, 0, 0), true);
    grid->tree().setValueOn(openvdb::Coord(1499, 1499, 1499), true);
    writeGrids(dir / "far.vdb", {grid});
    const CliResult result = runSegment(dir / "far.vdb", dir / "out", {"--max-memory", "1G"});
    EXPECT_TRUE(failsWithOneLine(result, 4, (dir / "far.vdb").string(),
                                 "its grid of 1500 x 1500 x 1500 voxels needs at least"));
    EXPECT_TRUE(leftNothing(dir / "out"));
    const CliResult budgeted =
        runSegment(dir / "far.vdb", dir / "out", {"--max-memory", "1G", "--time-budget", "5"});
    EXPECT_TRUE(
        failsWithOneLine(budgeted, 4, (dir / "far.vdb").string(), "needs at least 3.38 GB"));
}

}  // namespace
