// Done markers, input fingerprints and staging leftovers (engine/batch/DoneMarker.h,
// engine/batch/StagingCleanup.h).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include "engine/Version.h"
#include "engine/batch/DoneMarker.h"
#include "engine/batch/StagingCleanup.h"
#include "io/files/OutputDirectory.h"
#include "kernels/base/Error.h"
#include "tests/support/CliRunner.h"
#include "tests/support/TempDir.h"

namespace fs = std::filesystem;
using namespace skelseg;
using namespace skelseg::test;

TEST(DoneMarker, FingerprintSeesEveryByte) {
    TempDir dir;
    writeBytes(dir / "a", "0123456789");
    const InputFingerprint first = fingerprintFile(dir / "a");
    EXPECT_EQ(first.bytes, 10u);
    EXPECT_EQ(first.crc32, 0xa684c7c6u);  // CRC-32 of "0123456789"
    writeBytes(dir / "a", "0123456788");
    EXPECT_FALSE(fingerprintFile(dir / "a") == first);
    EXPECT_THROW(fingerprintFile(dir / "absent"), InputError);
}

// A detached NRRD header reads its data file: new data behind an unchanged
// header is a changed input (a batch skipped such an input and kept the old
// outputs), and a data file gone is an input that cannot be read.
TEST(DoneMarker, InputFingerprintSeesADetachedHeadersDataFile) {
    TempDir dir;
    writeBytes(dir / "a.off", "0123456789");
    EXPECT_TRUE(fingerprintInput(dir / "a.off") == fingerprintFile(dir / "a.off"));

    writeBytes(dir / "vol.nhdr",
               "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
               "data file: vol.raw\n");
    writeBytes(dir / "vol.raw", std::string(8, '\1'));
    const InputFingerprint first = fingerprintInput(dir / "vol.nhdr");
    EXPECT_EQ(first.bytes, fs::file_size(dir / "vol.nhdr") + 8u);
    EXPECT_FALSE(first == fingerprintFile(dir / "vol.nhdr"));
    writeBytes(dir / "vol.raw", std::string(7, '\1') + '\0');
    EXPECT_FALSE(fingerprintInput(dir / "vol.nhdr") == first);
    fs::remove(dir / "vol.raw");
    EXPECT_THROW(fingerprintInput(dir / "vol.nhdr"), InputError);
}

namespace {

/// The problem of the InputError `fingerprintFile(file)` throws ("" if none).
std::string fingerprintProblem(const fs::path& file) {
    try {
        fingerprintFile(file);
    } catch (const InputError& error) {
        return error.problem();
    }
    return "";
}

}  // namespace

TEST(DoneMarker, FingerprintRefusesAFifoWithoutOpeningItAndADirectory) {
    TempDir dir;
    // Opening a FIFO for reading blocks until a writer comes: this returns
    // only because the type is checked first.
    ASSERT_EQ(::mkfifo((dir / "pipe.off").c_str(), 0600), 0);
    EXPECT_EQ(fingerprintProblem(dir / "pipe.off"), "is not a regular file");
    fs::create_directories(dir / "folder.off");
    EXPECT_EQ(fingerprintProblem(dir / "folder.off"), "is a directory, not a file");
    EXPECT_EQ(fingerprintProblem(dir / "absent.off"), "no such file");
}

TEST(DoneMarker, RoundTripsAndMatchesOnlyTheSameInputOptionsAndVersion) {
    TempDir dir;
    SegmentCommandOptions options;
    DoneMarker marker;
    marker.skelsegVersion = versionString();
    marker.skelsegBuild = engineBuildId();
    marker.input = "/data/x.off";
    marker.fingerprint = {1234, 0xdeadbeef};
    marker.options = outputAffectingOptions(options);
    marker.finishedAt = utcTimestamp();
    marker.run = runIdentity();
    marker.parts = 7;
    marker.wallSeconds = 1.5;
    writeDoneMarker(dir.path(), marker);
    const auto read = readDoneMarker(dir.path());
    ASSERT_TRUE(read);
    EXPECT_EQ(read->input, marker.input);
    EXPECT_EQ(read->fingerprint.crc32, 0xdeadbeefu);
    EXPECT_EQ(read->parts, 7u);
    EXPECT_EQ(read->finishedAt, marker.finishedAt);
    EXPECT_TRUE(read->matches({1234, 0xdeadbeef}, outputAffectingOptions(options)));
    EXPECT_FALSE(read->matches({1235, 0xdeadbeef}, outputAffectingOptions(options)));
    EXPECT_FALSE(read->matches({1234, 0xdeadbeee}, outputAffectingOptions(options)));
    SegmentCommandOptions other = options;
    other.resolution = 128;
    EXPECT_FALSE(read->matches({1234, 0xdeadbeef}, outputAffectingOptions(other)));
    other = options;
    other.selfOverlapClearance = 2;
    EXPECT_FALSE(read->matches({1234, 0xdeadbeef}, outputAffectingOptions(other)));
    other = options;
    other.parameters.tau = TauSpec::parse("250");
    EXPECT_FALSE(read->matches({1234, 0xdeadbeef}, outputAffectingOptions(other)));
    // A hierarchy run (--tau 1%,3%) writes other outputs than --tau 3% alone.
    other = options;
    other.parameters.finerTaus = {TauSpec::parse("1%")};
    EXPECT_FALSE(read->matches({1234, 0xdeadbeef}, outputAffectingOptions(other)));
    EXPECT_NE(outputAffectingOptions(other).find("\"1%,3%\""), std::string::npos);
    // Options that do not change the outputs do not redo anything.
    other = options;
    other.threads = 3;
    other.timeLimitSeconds = 9;
    other.maxMemoryBytes = 1 << 30;
    EXPECT_TRUE(read->matches({1234, 0xdeadbeef}, outputAffectingOptions(other)));
    DoneMarker older = *read;
    older.skelsegVersion = "0.0.0-old";
    EXPECT_FALSE(older.matches({1234, 0xdeadbeef}, outputAffectingOptions(options)));
    // The same version from another build (any commit may move a cut), or
    // from a batch that recorded no build.
    EXPECT_EQ(read->skelsegBuild, engineBuildId());
    EXPECT_FALSE(engineBuildId().empty());
    for (const char* build : {"1234-00c0ffee", ""}) {
        DoneMarker otherBuild = *read;
        otherBuild.skelsegBuild = build;
        EXPECT_FALSE(otherBuild.matches({1234, 0xdeadbeef}, outputAffectingOptions(options)))
            << "build '" << build << "'";
    }

    removeDoneMarker(dir.path());
    EXPECT_FALSE(readDoneMarker(dir.path()));
    EXPECT_EQ(directoryEntries(dir.path()), std::vector<std::string>{});
}

TEST(DoneMarker, CorruptMarkerMeansNotDone) {
    TempDir dir;
    writeBytes(dir / kDoneMarkerName, "{\"skelseg_version\": \"0.1");
    EXPECT_FALSE(readDoneMarker(dir.path()));
    writeBytes(dir / kDoneMarkerName, "{}");
    EXPECT_FALSE(readDoneMarker(dir.path()));
}

TEST(StagingCleanup, RemovesOnlyWhatAKilledRunLeaves) {
    TempDir dir;
    // Killed runs' (PIDs no process has), proved skelseg's by the owner record.
    fs::create_directories(dir / ".skelseg-staging-999999-0");
    writeBytes(dir / ".skelseg-staging-999999-0" / kStagingOwnerFileName,
               stagingOwnerRecord(999999));
    writeBytes(dir / ".skelseg-staging-999999-0" / "labels.nrrd", "partial");
    writeBytes(dir / ".report.json.tmp-999999-4", "partial");
    // A live process's (this one's) and a user's folder of that name stay.
    const std::string live = ".done.json.tmp-" + std::to_string(::getpid()) + "-0";
    writeBytes(dir / live, "being written");
    fs::create_directories(dir / ".skelseg-staging-1-0");
    writeBytes(dir / ".skelseg-staging-1-0" / "mine.txt", "user file");
    writeBytes(dir / "labels.nrrd", "final");
    writeBytes(dir / "notes.tmp-keep", "user file");
    writeBytes(dir / ".hidden-user-file", "user file");
    EXPECT_EQ(removeStagingLeftovers(dir.path()), 2u);
    EXPECT_EQ(directoryEntries(dir.path()),
              (std::vector<std::string>{live, ".hidden-user-file", ".skelseg-staging-1-0",
                                        "labels.nrrd", "notes.tmp-keep"}));
    EXPECT_EQ(removeStagingLeftovers(dir / "absent"), 0u);
}

// The same input file by any path, from any working directory; another file
// is another input.
TEST(DoneMarker, IsOfTheSameFileByAnyPath) {
    TempDir dir;
    fs::create_directories(dir / "d1");
    fs::create_directories(dir / "d2");
    writeBytes(dir / "d1" / "a.off", "OFF\n");
    writeBytes(dir / "d2" / "a.off", "OFF\n");
    DoneMarker marker;
    marker.input = "some/relative/path/of/another/working/directory/a.off";
    marker.absoluteInput = dir / "d1" / "a.off";
    EXPECT_TRUE(marker.isOf(dir / "d1" / "a.off"));
    EXPECT_TRUE(marker.isOf(dir / "d2" / ".." / "d1" / "a.off"));
    EXPECT_TRUE(marker.isOf(marker.input));
    EXPECT_FALSE(marker.isOf(dir / "d2" / "a.off"));
    fs::create_symlink(dir / "d1" / "a.off", dir / "link.off");
    EXPECT_TRUE(marker.isOf(dir / "link.off"));
    // Written and read back with both paths.
    marker.skelsegVersion = versionString();
    marker.options = outputAffectingOptions({});
    writeDoneMarker(dir.path(), marker);
    const auto read = readDoneMarker(dir.path());
    ASSERT_TRUE(read);
    EXPECT_EQ(read->absoluteInput, dir / "d1" / "a.off");
    EXPECT_FALSE(read->isOf(dir / "d2" / "a.off"));
}
