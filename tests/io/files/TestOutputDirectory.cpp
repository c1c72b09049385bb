#include "io/files/OutputDirectory.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <memory>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "kernels/base/Error.h"
#include "tests/support/SmallTmpfs.h"
#include "tests/support/TempDir.h"

namespace skelseg {
namespace {

namespace fs = std::filesystem;

std::set<std::string> entries(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
    return names;
}

/// `files`, and the folder levels/ of folders of any name holding `levelFiles`.
OutputLayout layoutWithLevels(std::initializer_list<std::string> files,
                              std::initializer_list<std::string> levelFiles) {
    auto levels = std::make_shared<OutputLayout>();
    levels->folders.push_back(
        {"", [](const std::string&) { return true; }, std::make_shared<OutputLayout>(levelFiles)});
    OutputLayout layout(files);
    layout.folders.push_back({"levels", {}, levels});
    return layout;
}

TEST(OutputDirectory, ConcurrentWritersAllGetCommitted) {
    // The output flow graph stages files from several threads at once.
    test::TempDir tmp;
    const fs::path outdir = tmp / "out";
    constexpr int kThreads = 8, kFilesPerThread = 200;
    {
        OutputDirectory out(outdir, false, {"labels.nrrd"});
        std::vector<std::thread> threads;
        for (int t = 0; t < kThreads; ++t)
            threads.emplace_back([&out, t] {
                for (int i = 0; i < kFilesPerThread; ++i) {
                    const std::string name = "f" + std::to_string(t) + "_" + std::to_string(i);
                    // Each name twice: a repeated name is staged once.
                    out.stagingPath(name);
                    std::ofstream(out.stagingPath(name)) << name;
                }
            });
        for (auto& th : threads) th.join();
        out.commit();
    }
    const std::set<std::string> names = entries(outdir);
    EXPECT_EQ(names.size(), std::size_t(kThreads * kFilesPerThread));
    EXPECT_TRUE(names.count("f0_0"));
    EXPECT_TRUE(names.count("f7_199"));
}

TEST(OutputDirectory, NothingUnderAFinalNameWithoutCommit) {
    test::TempDir tmp;
    const fs::path outdir = tmp / "out";
    {
        OutputDirectory out(outdir, false, {"a.txt"});
        std::ofstream(out.stagingPath("a.txt")) << "half";
        EXPECT_FALSE(fs::exists(outdir / "a.txt"));
    }
    // Not committed: the directory this run created is gone again.
    EXPECT_FALSE(fs::exists(outdir));
}

TEST(OutputDirectory, EarlierResultsNeedForce) {
    test::TempDir tmp;
    const fs::path outdir = tmp / "out";
    fs::create_directories(outdir);
    std::ofstream(outdir / "a.txt") << "earlier";
    EXPECT_ANY_THROW(OutputDirectory(outdir, false, {"a.txt"}));
    {
        OutputDirectory out(outdir, true, {"a.txt"});
        std::ofstream(out.stagingPath("a.txt")) << "new";
        out.commit();
    }
    std::ifstream in(outdir / "a.txt");
    std::string text;
    in >> text;
    EXPECT_EQ(text, "new");
    EXPECT_EQ(entries(outdir), std::set<std::string>{"a.txt"});
}

TEST(OutputDirectory, StagedDirectoryReplacesTheEarlierOne) {
    test::TempDir tmp;
    const fs::path outdir = tmp / "out";
    fs::create_directories(outdir / "levels" / "5");
    std::ofstream(outdir / "levels" / "5" / "old.txt") << "earlier";
    {
        OutputDirectory out(outdir, true, layoutWithLevels({}, {"old.txt", "a.txt"}));
        const fs::path levels = out.stagingPath("levels");
        fs::create_directories(levels / "0");
        std::ofstream(levels / "0" / "a.txt") << "new";
        EXPECT_TRUE(fs::exists(outdir / "levels" / "5" / "old.txt")) << "replaced before commit";
        out.commit();
    }
    EXPECT_EQ(entries(outdir / "levels"), std::set<std::string>{"0"});
    EXPECT_TRUE(fs::exists(outdir / "levels" / "0" / "a.txt"));
}

TEST(OutputDirectory, ObsoleteOutputsGoOnlyOnCommit) {
    test::TempDir tmp;
    const fs::path outdir = tmp / "out";
    fs::create_directories(outdir / "levels" / "0");
    std::ofstream(outdir / "hierarchy.json") << "{}";
    {
        OutputDirectory out(outdir, true, layoutWithLevels({"a.txt", "hierarchy.json"}, {}));
        out.removeOnCommit("levels");
        out.removeOnCommit("hierarchy.json");
        std::ofstream(out.stagingPath("a.txt")) << "new";
        // Not committed (a failed run): the earlier outputs stay.
    }
    EXPECT_TRUE(fs::exists(outdir / "levels" / "0"));
    {
        OutputDirectory out(outdir, true, layoutWithLevels({"a.txt", "hierarchy.json"}, {}));
        out.removeOnCommit("levels");
        out.removeOnCommit("hierarchy.json");
        std::ofstream(out.stagingPath("a.txt")) << "new";
        out.commit();
    }
    EXPECT_EQ(entries(outdir), std::set<std::string>{"a.txt"});
}

std::string textOf(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// --force replaced any earlier output by its name: a user's folder named
// levels/ went with everything in it (finding 1 of the robustness hunt).
TEST(OutputDirectory, WhatNoRunWritesIsRefusedWithAndWithoutForce) {
    test::TempDir tmp;
    const fs::path outdir = tmp / "out";
    fs::create_directories(outdir / "levels" / "world1");
    std::ofstream(outdir / "levels" / "world1" / "map.txt") << "precious";
    const OutputLayout layout = layoutWithLevels({"a.txt"}, {"a.txt"});
    for (const bool force : {false, true}) {
        try {
            OutputDirectory out(outdir, force, layout);
            ADD_FAILURE() << "opened with force " << force;
        } catch (const UsageError& error) {
            EXPECT_EQ(std::string(error.what()),
                      (outdir / "levels" / "world1" / "map.txt").string() +
                          ": not written by skelseg, but inside levels/, which a run in " +
                          outdir.string() +
                          " replaces; move it away or choose another output directory");
        }
    }
    EXPECT_EQ(textOf(outdir / "levels" / "world1" / "map.txt"), "precious");
    EXPECT_EQ(entries(outdir), std::set<std::string>{"levels"});
}

// A run takes minutes: a file put into levels/ meanwhile stops the commit,
// which changes nothing.
TEST(OutputDirectory, ACommitRefusesWhatWasPutIntoAnOutputMeanwhile) {
    test::TempDir tmp;
    const fs::path outdir = tmp / "out";
    fs::create_directories(outdir / "levels" / "0");
    std::ofstream(outdir / "a.txt") << "earlier";
    {
        OutputDirectory out(outdir, true, layoutWithLevels({"a.txt"}, {}));
        out.removeOnCommit("levels");
        std::ofstream(out.stagingPath("a.txt")) << "new";
        std::ofstream(outdir / "levels" / "0" / "notes.txt") << "mine";
        EXPECT_THROW(out.commit(), UsageError);
    }
    EXPECT_EQ(textOf(outdir / "a.txt"), "earlier");
    EXPECT_EQ(textOf(outdir / "levels" / "0" / "notes.txt"), "mine");
    EXPECT_EQ(entries(outdir), (std::set<std::string>{"a.txt", "levels"}));
}

// A commit that fails half way leaves the earlier run's outputs whole, those
// already replaced and removed included. The failure: the earlier "tmpfs" is
// a mount point, which rename(2) cannot move (EBUSY).
TEST(OutputDirectory, AFailedCommitPutsTheEarlierOutputsBack) {
    test::SmallTmpfs mount(64 * 1024);
    if (!mount.mounted()) GTEST_SKIP() << mount.skipReason();
    const fs::path outdir = mount.path().parent_path();
    fs::create_directories(outdir / "levels" / "5");
    std::ofstream(outdir / "levels" / "5" / "old.txt") << "earlier";
    std::ofstream(outdir / "a.txt") << "earlier a";
    std::ofstream(outdir / "hierarchy.json") << "{}";
    std::ofstream(mount / "inside.txt") << "earlier tmpfs";
    const std::vector<std::string> names{"levels", "a.txt", "tmpfs", "hierarchy.json"};
    OutputLayout layout = layoutWithLevels({"a.txt", "hierarchy.json"}, {"old.txt", "new.txt"});
    layout.folders.push_back(
        {"tmpfs", {}, std::make_shared<OutputLayout>(OutputLayout{"inside.txt"})});
    {
        OutputDirectory out(outdir, true, layout);
        out.removeOnCommit("hierarchy.json");
        fs::create_directories(out.stagingPath("levels") / "0");
        std::ofstream(out.stagingPath("levels") / "0" / "new.txt") << "new";
        std::ofstream(out.stagingPath("a.txt")) << "new a";
        std::ofstream(out.stagingPath("tmpfs")) << "new tmpfs";
        try {
            out.commit();
            ADD_FAILURE() << "the commit did not fail";
        } catch (const OutputError& error) {
            EXPECT_NE(std::string(error.what()).find("tmpfs"), std::string::npos) << error.what();
        }
    }
    EXPECT_EQ(entries(outdir), std::set<std::string>(names.begin(), names.end()));
    EXPECT_EQ(entries(outdir / "levels"), std::set<std::string>{"5"});
    EXPECT_EQ(textOf(outdir / "levels" / "5" / "old.txt"), "earlier");
    EXPECT_EQ(textOf(outdir / "a.txt"), "earlier a");
    EXPECT_EQ(textOf(outdir / "hierarchy.json"), "{}");
    EXPECT_EQ(textOf(mount / "inside.txt"), "earlier tmpfs");
}

// --time-budget's finer pass stages a second set of outputs and falls back
// on the first when it is given up (engine/SegmentCommand.cpp).
TEST(OutputDirectory, ASetAsideAttemptIsPutBackWithItsMarks) {
    test::TempDir tmp;
    const fs::path outdir = tmp / "out";
    fs::create_directories(outdir);
    std::ofstream(outdir / "preview.png") << "earlier";
    std::ofstream(outdir / "hierarchy.json") << "{}";
    {
        OutputDirectory out(
            outdir, true,
            layoutWithLevels({"a.txt", "b.txt", "preview.png", "hierarchy.json"}, {"a.txt"}));
        out.removeOnCommit("hierarchy.json");
        std::ofstream(out.stagingPath("a.txt")) << "first";
        fs::create_directories(out.stagingPath("levels") / "0");
        std::ofstream(out.stagingPath("levels") / "0" / "a.txt") << "first level";
        out.setAside();
        // The second attempt writes other files and marks others.
        std::ofstream(out.stagingPath("a.txt")) << "second";
        std::ofstream(out.stagingPath("b.txt")) << "second only";
        out.removeOnCommit("preview.png");
        out.restoreSetAside();
        out.commit();
    }
    EXPECT_EQ(entries(outdir), (std::set<std::string>{"a.txt", "levels", "preview.png"}));
    EXPECT_EQ(textOf(outdir / "a.txt"), "first");
    EXPECT_EQ(textOf(outdir / "levels" / "0" / "a.txt"), "first level");
    EXPECT_EQ(textOf(outdir / "preview.png"), "earlier");  // the second attempt's mark is gone
}

TEST(OutputDirectory, ADroppedSetAsideLeavesTheSecondAttempt) {
    test::TempDir tmp;
    const fs::path outdir = tmp / "out";
    fs::create_directories(outdir);
    std::ofstream(outdir / "hierarchy.json") << "{}";
    {
        OutputDirectory out(outdir, true, {"a.txt", "b.txt", "hierarchy.json"});
        out.removeOnCommit("hierarchy.json");
        std::ofstream(out.stagingPath("a.txt")) << "first";
        std::ofstream(out.stagingPath("b.txt")) << "first only";
        out.setAside();
        std::ofstream(out.stagingPath("a.txt")) << "second";
        out.dropSetAside();
        out.commit();
    }
    // The first attempt's b.txt went with it; the marks made before stay.
    EXPECT_EQ(entries(outdir), std::set<std::string>{"a.txt"});
    EXPECT_EQ(textOf(outdir / "a.txt"), "second");
}

TEST(OutputDirectory, NothingOfASetAsideAttemptIsLeftWithoutCommit) {
    test::TempDir tmp;
    const fs::path outdir = tmp / "out";
    {
        OutputDirectory out(outdir, false, {"a.txt"});
        std::ofstream(out.stagingPath("a.txt")) << "first";
        out.setAside();
        std::ofstream(out.stagingPath("a.txt")) << "second";
    }
    EXPECT_FALSE(fs::exists(outdir));
}

TEST(WriteFileAtomically, FullDiskGivesTheSystemsReasonAndLeavesNoFile) {
    test::SmallTmpfs disk(64 * 1024);
    if (!disk.mounted()) GTEST_SKIP() << disk.skipReason();
    const fs::path file = disk / "big.bin";
    try {
        writeFileAtomically(file, std::string(256 * 1024, 'x'));
        FAIL() << "a 256 KiB file fitted on a 64 KiB file system";
    } catch (const OutputError& error) {
        const std::string message = error.what();
        EXPECT_NE(message.find(file.string() + ": "), std::string::npos) << message;
        // It said "write failed (disk full?)", a guess in place of errno.
        EXPECT_NE(message.find("no space left on device"), std::string::npos) << message;
    }
    EXPECT_TRUE(entries(disk.path()).empty());
}

TEST(OutputDirectory, FullDiskKeepsTheEarlierOutputWithForce) {
    test::SmallTmpfs disk(64 * 1024);
    if (!disk.mounted()) GTEST_SKIP() << disk.skipReason();
    const fs::path outdir = disk / "out";
    fs::create_directory(outdir);
    std::ofstream(outdir / "a.txt") << "earlier";
    {
        OutputDirectory out(outdir, true, {"a.txt"});
        EXPECT_THROW(writeFileAtomically(out.stagingPath("a.txt"), std::string(256 * 1024, 'x')),
                     OutputError);
    }
    EXPECT_EQ(textOf(outdir / "a.txt"), "earlier");
    EXPECT_EQ(entries(outdir), std::set<std::string>{"a.txt"});
}

TEST(OutputDirectory, ReadOnlyFileSystemIsOneOutputError) {
    test::SmallTmpfs disk(64 * 1024, /*readOnly=*/true);
    if (!disk.mounted()) GTEST_SKIP() << disk.skipReason();
    for (const fs::path& outdir : {disk.path(), disk / "new" / "deeper"}) {
        try {
            OutputDirectory out(outdir, false, {"a.txt"});
            FAIL() << outdir << " was opened on a read-only file system";
        } catch (const OutputError& error) {
            EXPECT_NE(std::string(error.what()).find("read-only file system"), std::string::npos)
                << error.what();
        }
    }
    EXPECT_TRUE(entries(disk.path()).empty());
}

TEST(OutputDirectory, SecondRunOnTheSameDirectoryIsRefused) {
    // Two runs committing file by file into one OUTDIR left a mix of both,
    // each exiting 0; the second did not even need --force.
    test::TempDir tmp;
    const fs::path outdir = tmp / "out";
    {
        OutputDirectory first(outdir, false, {"a.txt"});
        try {
            OutputDirectory second(outdir, true, {"a.txt"});
            FAIL() << "a second run opened a directory the first is writing to";
        } catch (const UsageError& error) {
            EXPECT_NE(std::string(error.what()).find(outdir.string() + ": another skelseg run"),
                      std::string::npos)
                << error.what();
        }
        std::ofstream(first.stagingPath("a.txt")) << "first";
        first.commit();
    }
    EXPECT_EQ(textOf(outdir / "a.txt"), "first");
    // The lock ends with the run; the earlier results then need --force.
    EXPECT_THROW(OutputDirectory(outdir, false, {"a.txt"}), UsageError);
    EXPECT_NO_THROW(OutputDirectory(outdir, true, {"a.txt"}));
}

TEST(OutputDirectory, AKilledRunsStagingDirectoryIsRemoved) {
    // SIGKILL leaves .skelseg-staging-PID-N with half-written files; no later
    // `segment` removed it.
    test::TempDir tmp;
    const fs::path outdir = tmp / "out";
    fs::create_directories(outdir / ".skelseg-staging-999999-0");
    std::ofstream(outdir / ".skelseg-staging-999999-0" / kStagingOwnerFileName)
        << stagingOwnerRecord(999999);
    std::ofstream(outdir / ".skelseg-staging-999999-0" / "labels.nrrd") << "half";
    std::ofstream(outdir / ".keep") << "the user's";
    {
        OutputDirectory out(outdir, false, {"labels.nrrd"});
        EXPECT_FALSE(fs::exists(outdir / ".skelseg-staging-999999-0"));
    }
    EXPECT_EQ(entries(outdir), std::set<std::string>{".keep"});
}

// Hunt 2, finding 11: a user's folder OUTDIR/.skelseg-staging-1-0 was removed
// with its files although PID 1 is alive; the name alone was taken as proof.
// Now a staging directory goes only when its owner record (or its emptiness)
// shows it skelseg's, and the run that made it is not alive.
TEST(OutputDirectory, OnlyADeadRunsStagingDirectoryIsRemoved) {
    test::TempDir tmp;
    const fs::path outdir = tmp / "out";
    const auto makeFolder = [&](const std::string& name, const std::string& record) {
        fs::create_directories(outdir / name);
        if (!record.empty()) std::ofstream(outdir / name / kStagingOwnerFileName) << record;
        std::ofstream(outdir / name / "mine.txt") << "the user's";
    };
    makeFolder(".skelseg-staging-1-0", "");       // the finding: no record, PID 1 alive
    makeFolder(".skelseg-staging-999999-1", "");  // no record: not proved skelseg's
    makeFolder(".skelseg-staging-x", stagingOwnerRecord(999999));  // not the name pattern
    const std::string live = ".skelseg-staging-" + std::to_string(::getpid()) + "-9999";
    makeFolder(live, stagingOwnerRecord(::getpid()));                     // a live run's
    makeFolder(".skelseg-staging-999999-2", stagingOwnerRecord(999999));  // a dead run's
    fs::create_directories(outdir / ".skelseg-staging-999999-3");  // killed before the record
    fs::create_directories(outdir / ".skelseg-staging-1-4");       // empty, but PID 1 is alive
    { OutputDirectory out(outdir, false, {"labels.nrrd"}); }
    EXPECT_EQ(entries(outdir),
              (std::set<std::string>{".skelseg-staging-1-0", ".skelseg-staging-1-4",
                                     ".skelseg-staging-999999-1", ".skelseg-staging-x", live}));
    EXPECT_EQ(textOf(outdir / ".skelseg-staging-1-0" / "mine.txt"), "the user's");
}

TEST(OutputDirectory, MessagesNameTheFinalPath) {
    test::TempDir tmp;
    const fs::path outdir = tmp / "out\nline";
    OutputDirectory out(outdir, false, {"a.txt"});
    const std::string staged = OutputError(out.stagingPath("a.txt").string() + ": no").what();
    EXPECT_EQ(out.withFinalPaths(staged), OutputError((outdir / "a.txt").string() + ": no").what());
    EXPECT_EQ(out.withFinalPaths("no path"), "no path");
}

TEST(OutputReplacing, PathOverPathMaxIsNoOutput) {
    // weakly_canonical() fails on it (ENAMETOOLONG) and gave empty paths,
    // which the comparison took for the output itself: "the input is
    // labels.nrrd in the output directory".
    std::string deep;
    for (int i = 0; i < 20; ++i) deep += std::string(250, 'a') + "/";
    const fs::path outdir = fs::path("/tmp") / deep;
    EXPECT_EQ(outputReplacing("/tmp/shape.off", outdir, {"labels.nrrd"}), "");
}

}  // namespace
}  // namespace skelseg
