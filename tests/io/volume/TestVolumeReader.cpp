// Tests for io/volume/VolumeReader.h: format detection, dispatch and the file
// checks every reader shares.
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/volume/BinvoxIO.h"
#include "io/volume/NrrdIO.h"
#include "io/volume/VolumeReader.h"
#include "kernels/base/Error.h"
#include "tests/support/FileBytes.h"
#include "tests/support/InputErrorExpectation.h"
#include "tests/support/TempDir.h"

namespace fs = std::filesystem;
using namespace skelseg;
using namespace skelseg::test;

namespace {

MaskVolume sampleMask() {
    MaskVolume mask(Dims{5, 7, 3});
    mask(1, 2, 0) = 1;
    mask(4, 6, 2) = 1;
    mask(0, 5, 1) = 1;
    mask.geometry = VolumeGeometry::uniform(0.5, {1.0, 2.0, 3.0});
    return mask;
}

const std::string kCannotDropPrivileges = "<cannot drop privileges>";

/// The InputError message of `read` ("" if it throws none) where file modes
/// apply. root ignores file modes, so as root `read` runs in a child process
/// that first becomes user and group 65534 ("nobody").
std::string inputErrorWithoutPrivileges(const std::function<void()>& read) {
    const auto capture = [&]() -> std::string {
        try {
            read();
        } catch (const InputError& error) {
            return error.what();
        }
        return "";
    };
    if (::geteuid() != 0) return capture();
    int channel[2];
    if (::pipe(channel) != 0) return kCannotDropPrivileges;
    const pid_t child = ::fork();
    if (child < 0) {
        ::close(channel[0]);
        ::close(channel[1]);
        return kCannotDropPrivileges;
    }
    if (child == 0) {
        ::close(channel[0]);
        const std::string message =
            (::setgid(65534) == 0 && ::setuid(65534) == 0) ? capture() : kCannotDropPrivileges;
        const ssize_t written = ::write(channel[1], message.data(), message.size());
        ::_exit(written == ssize_t(message.size()) ? 0 : 1);
    }
    ::close(channel[1]);
    std::string message;
    char buffer[512];
    for (ssize_t got; (got = ::read(channel[0], buffer, sizeof buffer)) > 0;)
        message.append(buffer, std::size_t(got));
    ::close(channel[0]);
    int status = 0;
    ::waitpid(child, &status, 0);
    return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? message : kCannotDropPrivileges;
}

}  // namespace

TEST(VolumeReader, FormatFromExtensionIgnoresCase) {
    EXPECT_EQ(volumeFormatFromPath("a/b/shape.nrrd"), VolumeFormat::Nrrd);
    EXPECT_EQ(volumeFormatFromPath("shape.NRRD"), VolumeFormat::Nrrd);
    EXPECT_EQ(volumeFormatFromPath("shape.nhdr"), VolumeFormat::Nrrd);
    EXPECT_EQ(volumeFormatFromPath("shape.BinVox"), VolumeFormat::Binvox);
    EXPECT_EQ(volumeFormatFromPath("shape.vdb"), VolumeFormat::Vdb);
    EXPECT_EQ(volumeFormatFromPath("shape.Vdb"), VolumeFormat::Vdb);
    EXPECT_EQ(volumeFormatFromPath("shape.raw"), VolumeFormat::Unknown);
    EXPECT_EQ(volumeFormatFromPath("shape.nrrd.gz"), VolumeFormat::Unknown);
    EXPECT_EQ(volumeFormatFromPath("nrrd"), VolumeFormat::Unknown);
}

TEST(VolumeReader, DispatchesByExtension) {
    test::TempDir dir;
    const MaskVolume mask = sampleMask();
    writeNrrdMask(dir / "shape.nrrd", mask);
    writeBinvox(dir / "shape.BINVOX", mask);
    for (const char* name : {"shape.nrrd", "shape.BINVOX"}) {
        const MaskVolume back = readVolume(dir / name);
        ASSERT_EQ(back.dims(), mask.dims()) << name;
        EXPECT_EQ(back.values(), mask.values()) << name;
        EXPECT_NEAR(back.geometry.origin[1], 2.0, 1e-12) << name;
    }
    // The extension decides, not the content: binvox data named .nrrd is a NRRD error.
    fs::copy_file(dir / "shape.BINVOX", dir / "mislabelled.nrrd");
    expectInputError([&] { readVolume(dir / "mislabelled.nrrd"); }, "mislabelled.nrrd",
                     "not a NRRD file");
}

// The readers hand the grid to the caller's check after their own checks of
// the file and before they allocate it: what the check throws passes through,
// and a file that cannot hold its grid never reaches it.
TEST(VolumeReader, GridCheckSeesTheGridBeforeItIsAllocated) {
    struct Refused {
        Dims dims;
    };
    test::TempDir dir;
    const MaskVolume mask = sampleMask();
    writeNrrdMask(dir / "shape.nrrd", mask);
    writeBinvox(dir / "shape.binvox", mask);
    VolumeReadOptions refusing;
    refusing.guards.checkGrid = [](const Dims& dims) { throw Refused{dims}; };
    for (const char* name : {"shape.nrrd", "shape.binvox"}) {
        try {
            readVolume(dir / name, refusing);
            ADD_FAILURE() << name << ": the check was not called";
        } catch (const Refused& refused) {
            EXPECT_EQ(refused.dims, mask.dims()) << name;
        }
        int calls = 0;
        VolumeReadOptions accepting;
        accepting.guards.checkGrid = [&](const Dims&) { ++calls; };
        EXPECT_EQ(readVolume(dir / name, accepting).values(), mask.values()) << name;
        EXPECT_EQ(calls, 1) << name;
    }
    // Data too short for the grid: the reader's error, and no call.
    const std::string header =
        "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 64 64 64\nencoding: raw\n\n";
    std::ofstream(dir / "short.nrrd", std::ios::binary) << header << "abc";
    expectInputError([&] { readVolume(dir / "short.nrrd", refusing); }, "short.nrrd",
                     "data is too short");
}

TEST(VolumeReader, FileChecks) {
    test::TempDir dir;
    expectInputError([&] { readVolume(dir / "absent.nrrd"); }, "absent.nrrd", "no such file");
    fs::create_directories(dir / "folder.vdb");
    expectInputError([&] { readVolume(dir / "folder.vdb"); }, "folder.vdb", "is a directory");
    writeBytes(dir / "shape.stl", "solid nothing\nendsolid nothing\n");
    expectInputError([&] { readVolume(dir / "shape.stl"); }, "shape.stl",
                     ".nrrd, .nhdr, .binvox, .vdb");
    // A missing file is reported as missing even with an unknown extension.
    expectInputError([&] { readVolume(dir / "absent.xyz"); }, "absent.xyz", "no such file");
}

TEST(VolumeReader, NonRegularFileIsRejected) {
    test::TempDir dir;
    const fs::path fifo = dir / "pipe.nrrd";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    expectInputError([&] { readVolume(fifo); }, "pipe.nrrd", "not a regular file");
}

TEST(VolumeReader, UnreadableFile) {
    test::TempDir dir;
    const fs::path file = dir / "locked.binvox";
    writeBinvox(file, sampleMask());
    ASSERT_EQ(::chmod(file.c_str(), 0), 0);
    for (const auto& read : std::vector<std::function<void()>>{[&] { readVolume(file); },
                                                               [&] { readFileBytes(file); }}) {
        const std::string message = inputErrorWithoutPrivileges(read);
        if (message == kCannotDropPrivileges) GTEST_SKIP() << "cannot run as an unprivileged user";
        EXPECT_NE(message.find("locked.binvox"), std::string::npos) << message;
        EXPECT_NE(message.find("cannot be read: permission denied"), std::string::npos) << message;
    }
}

TEST(VolumeReader, GridNameOnlyForVdb) {
    test::TempDir dir;
    writeNrrdMask(dir / "shape.nrrd", sampleMask());
    VolumeReadOptions options;
    options.gridName = "density";
    EXPECT_THROW(readVolume(dir / "shape.nrrd", options), UsageError);
}

TEST(VolumeReader, ReadFileBytes) {
    test::TempDir dir;
    std::string content("binary\0data\n\xff", 13);
    content.push_back('\0');
    writeBytes(dir / "bytes.bin", content);
    EXPECT_EQ(readFileBytes(dir / "bytes.bin"), content);
    writeBytes(dir / "empty.bin", "");
    EXPECT_EQ(readFileBytes(dir / "empty.bin"), "");
    expectInputError([&] { readFileBytes(dir / "absent.bin"); }, "absent.bin", "no such file");
    expectInputError([&] { readFileBytes(dir.path()); }, dir.path().string(), "is a directory");
}
