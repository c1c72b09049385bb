// The machine misbehaving under `skelseg segment` and `skelseg batch`: a full
// disk, a second run on the same output folder (docs/robustness.md, "The
// machine misbehaves (hunt4)"). The tests that mount a small tmpfs skip
// where mounting is not allowed (not root, a container without the right).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "tests/engine/RobustnessHelpers.h"
#include "tests/support/SmallTmpfs.h"

namespace fs = std::filesystem;
using namespace skelseg;
using namespace skelseg::test;

TEST(MachineFailures, FullDiskNamesTheFinalFileAndKeepsTheEarlierOutput) {
    TempDir dir;
    const fs::path input = dir / "tetra.off";
    writeBytes(input, kTetraOff);
    SmallTmpfs disk(48 * 1024);
    if (!disk.mounted()) GTEST_SKIP() << disk.skipReason();
    const fs::path outdir = disk / "out";
    // A new folder: nothing is left, not even the folder.
    const CliResult fresh = runSegment(input, outdir, {"--resolution", "48"});
    EXPECT_TRUE(failsWithOneLine(fresh, 1, outdir.string() + "/", "no space left on device"));
    // The line named the hidden staging folder, gone when it was read.
    EXPECT_EQ(fresh.err.find(".skelseg-staging"), std::string::npos) << fresh.err;
    EXPECT_TRUE(directoryEntries(disk.path()).empty());
    // An earlier output replaced with --force: a failed run keeps it whole.
    fs::create_directory(outdir);
    writeBytes(outdir / "labels.nrrd", "earlier");
    const CliResult forced = runSegment(input, outdir, {"--resolution", "48", "--force"});
    EXPECT_TRUE(failsWithOneLine(forced, 1, outdir.string() + "/", "no space left on device"));
    EXPECT_EQ(directoryEntries(outdir), std::vector<std::string>{"labels.nrrd"});
    EXPECT_EQ(fileBytes(outdir / "labels.nrrd"), "earlier");
}

// `sequence` creates OUTDIR/frames/ in its staging folder first: out of
// inodes, that was an "internal error" naming the staging folder, gone when
// the line was read.
TEST(MachineFailures, SequenceOutOfInodesNamesTheFinalFolder) {
    TempDir dir;
    writeBytes(dir / "a.off", kTetraOff);
    writeBytes(dir / "b.off", kTetraOff);
    SmallTmpfs disk(1024 * 1024, false, 4);
    if (!disk.mounted()) GTEST_SKIP() << disk.skipReason();
    const fs::path outdir = disk / "out";
    const CliResult result =
        runSkelseg({"sequence", (dir / "a.off").string(), (dir / "b.off").string(), "-o",
                    outdir.string(), "--resolution", "48", "-q"});
    EXPECT_TRUE(failsWithOneLine(result, 1, (outdir / "frames").string(),
                                 "cannot create directory: no space left on device"));
    EXPECT_EQ(result.err.find(".skelseg-staging"), std::string::npos) << result.err;
    EXPECT_TRUE(directoryEntries(disk.path()).empty());
}

TEST(MachineFailures, SecondSegmentOnTheSameOutdirIsRefused) {
    TempDir dir;
    const fs::path input = dir / "tetra.off";
    writeBytes(input, kTetraOff);
    const fs::path outdir = dir / "out";
    fs::create_directory(outdir);
    // The lock a run holds on its OUTDIR from start to end (OutputDirectory);
    // held here, as by a run still under way.
    const int fd = ::open(outdir.c_str(), O_RDONLY | O_DIRECTORY);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
    writeBytes(outdir / "report.json", "the other run's");
    const CliResult second = runSegment(input, outdir, {"--resolution", "16", "--force"});
    ::close(fd);
    EXPECT_TRUE(failsWithOneLine(second, 2, outdir.string(), "another skelseg run is writing"));
    EXPECT_EQ(fileBytes(outdir / "report.json"), "the other run's");
}

TEST(MachineFailures, SecondBatchOnTheSameOutrootIsRefused) {
    // Both batches segmented every input and rewrote summary.json, the last
    // to end winning; a shard of its own still runs beside the other.
    TempDir dir;
    writeBytes(dir / "tetra.off", kTetraOff);
    writeBytes(dir / "list.txt", "tetra.off\n");
    const fs::path outroot = dir / "out";
    fs::create_directory(outroot);
    const int fd = ::open((outroot / ".summary.lock").c_str(), O_RDWR | O_CREAT, 0666);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
    const std::vector<std::string> batch = {
        "batch", (dir / "list.txt").string(), "-o", outroot.string(), "--quiet", "--resolution",
        "16"};
    const CliResult second = runSkelseg(batch);
    EXPECT_TRUE(failsWithOneLine(second, 2, outroot.string(), "another skelseg batch"));
    EXPECT_EQ(directoryEntries(outroot), std::vector<std::string>{".summary.lock"});
    std::vector<std::string> shard = batch;
    shard.insert(shard.end(), {"--shard", "0/2"});
    const CliResult sharded = runSkelseg(shard);
    ::close(fd);
    EXPECT_NE(sharded.exitCode, 2) << sharded.describe();
    EXPECT_TRUE(fs::exists(outroot / "summary.shard-0-of-2.json")) << sharded.describe();
}

TEST(MachineFailures, BatchThatFailsAsAWholeLeavesNoOutroot) {
    TempDir dir;
    writeBytes(dir / "tetra.off", kTetraOff);
    writeBytes(dir / "list.txt", "tetra.off\n");
    SmallTmpfs disk(8 * 1024);
    if (!disk.mounted()) GTEST_SKIP() << disk.skipReason();
    // Fill the disk: the summary cannot be written.
    writeBytes(disk / "filler", std::string(4096, 'x'));
    for (int i = 0; fs::space(disk.path()).available > 0 && i < 64; ++i)
        writeBytes(disk / ("filler" + std::to_string(i)), std::string(1024, 'x'));
    const fs::path outroot = disk / "out";
    const CliResult result = runSkelseg({"batch", (dir / "list.txt").string(), "-o",
                                         outroot.string(), "--quiet", "--resolution", "16"});
    EXPECT_EQ(result.exitCode, 1) << result.describe();
    EXPECT_NE(result.err.find("no space left on device"), std::string::npos) << result.describe();
    EXPECT_FALSE(fs::exists(outroot)) << result.describe();
}
