// `skelseg batch` replaces only what a batch made for the same input
// (engine/BatchCommand.h, engine/batch/OutputFolderClaim.h), run as a child
// process as a user runs it. Findings 2 and 3 of the robustness hunt: a
// batch replaced a folder `skelseg segment` had written, a user's file in its
// levels/ with it, and the folder another manifest's input of the same name
// had written, all without --force and without a word.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <tuple>

#include "engine/batch/DoneMarker.h"
#include "io/files/OutputDirectory.h"
#include "tests/engine/RobustnessHelpers.h"

namespace fs = std::filesystem;
using namespace skelseg;
using namespace skelseg::test;

namespace {

/// `skelseg batch MANIFEST -o OUTROOT` with quick options and `extra`.
CliResult runBatch(const fs::path& manifest, const fs::path& outroot,
                   const std::vector<std::string>& extra = {}) {
    std::vector<std::string> arguments = {
        "batch",   manifest.string(), "-o",        outroot.string(),
        "--quiet", "--no-preview",    "--threads", "1"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return runSkelseg(arguments);
}

/// A bar `length` voxels long, with a two-voxel margin.
void writeBar(const fs::path& file, int length) {
    fs::create_directories(file.parent_path());
    writeNrrdMask(file, makeMask(Dims{length + 4, 10, 10}, [length](int x, int y, int z) {
                      return x > 1 && x < length + 2 && y > 1 && y < 8 && z > 1 && z < 8;
                  }));
}

bool mentions(const CliResult& result, const std::string& text) {
    return result.err.find(text) != std::string::npos;
}

/// The build id of the skelseg executable the tests run, computed here from
/// its file (engine/Version.h: size and CRC-32, hexadecimal).
std::string buildIdOfTheBinary() {
    const InputFingerprint binary = fingerprintFile(skelsegBinary());
    char id[48];
    std::snprintf(id, sizeof id, "%llx-%08x", static_cast<unsigned long long>(binary.bytes),
                  binary.crc32);
    return id;
}

}  // namespace

TEST(BatchCommand, EarlierResultsOfSegmentAreRefusedWithoutForce) {
    TempDir dir;
    writeBar(dir / "in" / "bar.nrrd", 10);
    writeBytes(dir / "list.txt", "in/bar.nrrd\n");
    const fs::path out = dir / "out";
    const CliResult segment = runSegment(dir / "in" / "bar.nrrd", out / "bar", {"--no-preview"});
    ASSERT_EQ(segment.exitCode, 0) << segment.describe();
    const auto before = snapshot(out / "bar");

    const CliResult refused = runBatch(dir / "list.txt", out);
    EXPECT_EQ(refused.exitCode, 5) << refused.describe();
    EXPECT_TRUE(mentions(refused, "bar (line 1): " + (out / "bar").string() +
                                      ": holds results of an earlier run (labels.nrrd); use "
                                      "--force to replace them"))
        << refused.err;
    EXPECT_EQ(snapshot(out / "bar"), before) << "the earlier results changed without --force";

    const CliResult forced = runBatch(dir / "list.txt", out, {"--force"});
    ASSERT_EQ(forced.exitCode, 0) << forced.describe();
    EXPECT_TRUE(fs::exists(out / "bar" / kDoneMarkerName));
    EXPECT_FALSE(fs::exists(out / "bar" / kPendingMarkerName));
}

// The version (0.2.0) stayed the same while the cuts changed from one commit
// to the next, so a batch re-run with a new build skipped every input an
// older build had done, and kept its outputs.
TEST(BatchCommand, AnotherBuildsResultsAreRedone) {
    TempDir dir;
    writeBar(dir / "in" / "bar.nrrd", 10);
    writeBytes(dir / "list.txt", "in/bar.nrrd\n");
    const fs::path out = dir / "out";
    const std::string build = buildIdOfTheBinary();
    ASSERT_EQ(runBatch(dir / "list.txt", out).exitCode, 0);
    const auto marker = readDoneMarker(out / "bar");
    ASSERT_TRUE(marker);
    EXPECT_EQ(marker->skelsegBuild, build);
    EXPECT_EQ(readReport(out / "bar").value("skelseg_build", ""), build);
    const CliResult version = runSkelseg({"--version"});
    EXPECT_NE(version.out.find("(build " + build + ")"), std::string::npos) << version.out;

    // The same build: nothing is redone (the marker is the first run's).
    const std::string doneBytes = fileBytes(out / "bar" / kDoneMarkerName);
    ASSERT_EQ(runBatch(dir / "list.txt", out).exitCode, 0);
    EXPECT_EQ(fileBytes(out / "bar" / kDoneMarkerName), doneBytes);

    // Another build's marker, and one from before markers had a build.
    for (const char* older :
         {static_cast<const char*>("1234-00c0ffee"), static_cast<const char*>(nullptr)}) {
        SCOPED_TRACE(older ? older : "no build recorded");
        auto json = nlohmann::json::parse(doneBytes);
        json["run"] = "another-host:1";
        if (older)
            json["skelseg_build"] = older;
        else
            json.erase("skelseg_build");
        writeBytes(out / "bar" / kDoneMarkerName, json.dump(2));
        const CliResult redo = runBatch(dir / "list.txt", out);
        ASSERT_EQ(redo.exitCode, 0) << redo.describe();
        const auto redone = readDoneMarker(out / "bar");
        ASSERT_TRUE(redone);
        EXPECT_EQ(redone->skelsegBuild, build);
        EXPECT_NE(redone->run, "another-host:1") << "the input was not redone";
    }
}

// A detached NRRD header whose data file was replaced by another shape was
// skipped (the marker fingerprinted the header alone), and its old outputs
// were kept; with the data file gone it was still "skipped".
TEST(BatchCommand, NewDataBehindAnUnchangedDetachedHeaderIsRedone) {
    TempDir dir;
    fs::create_directories(dir / "in");
    writeBytes(dir / "in" / "bar.nhdr",
               "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 24 10 10\nencoding: raw\n"
               "data file: bar.raw\n");
    // A bar from x = 2 to x = 1 + length, six voxels across.
    const auto writeData = [&](int length) {
        std::string bytes(24 * 10 * 10, '\0');
        for (int z = 2; z < 8; ++z)
            for (int y = 2; y < 8; ++y)
                for (int x = 2; x < 2 + length; ++x) bytes[std::size_t((z * 10 + y) * 24 + x)] = 1;
        writeBytes(dir / "in" / "bar.raw", bytes);
    };
    writeData(20);
    writeBytes(dir / "list.txt", "in/bar.nhdr\n");
    const fs::path out = dir / "out";
    ASSERT_EQ(runBatch(dir / "list.txt", out).exitCode, 0);
    const std::string firstLabels = fileBytes(out / "bar" / "labels.nrrd");

    writeData(12);
    const CliResult redo = runBatch(dir / "list.txt", out);
    ASSERT_EQ(redo.exitCode, 0) << redo.describe();
    const CliResult direct = runSegment(dir / "in" / "bar.nhdr", dir / "direct", {"--no-preview"});
    ASSERT_EQ(direct.exitCode, 0) << direct.describe();
    EXPECT_NE(fileBytes(out / "bar" / "labels.nrrd"), firstLabels) << "the input was skipped";
    EXPECT_EQ(fileBytes(out / "bar" / "labels.nrrd"), fileBytes(dir / "direct" / "labels.nrrd"));

    fs::remove(dir / "in" / "bar.raw");
    const CliResult gone = runBatch(dir / "list.txt", out);
    EXPECT_EQ(gone.exitCode, 5) << gone.describe();
    EXPECT_TRUE(mentions(gone, "bar.raw")) << gone.err;
}

TEST(BatchCommand, AUsersFileInLevelsIsNeverRemovedEvenWithForce) {
    TempDir dir;
    writeBar(dir / "in" / "bar.nrrd", 10);
    writeBytes(dir / "list.txt", "in/bar.nrrd\n");
    const fs::path out = dir / "out";
    const CliResult first = runBatch(dir / "list.txt", out, {"--tau", "1%,3%"});
    ASSERT_EQ(first.exitCode, 0) << first.describe();
    writeBytes(out / "bar" / "levels" / "my-notes.txt", "precious");
    const auto levels = snapshot(out / "bar" / "levels");
    const auto report = fileBytes(out / "bar" / "report.json");

    // Other options: the batch's own folder is redone, --force or not.
    for (const std::vector<std::string>& extra :
         {std::vector<std::string>{"--tau", "5%"},
          std::vector<std::string>{"--tau", "5%", "--force"}}) {
        SCOPED_TRACE(extra.size() == 3 ? "with --force" : "without --force");
        const CliResult result = runBatch(dir / "list.txt", out, extra);
        EXPECT_EQ(result.exitCode, 5) << result.describe();
        EXPECT_TRUE(mentions(result, (out / "bar" / "levels" / "my-notes.txt").string() +
                                         ": not written by skelseg, but inside levels/"))
            << result.err;
        EXPECT_EQ(snapshot(out / "bar" / "levels"), levels);
        EXPECT_EQ(fileBytes(out / "bar" / "report.json"), report);
    }
}

TEST(BatchCommand, AFolderAnotherInputsBatchWroteIsRefusedWithoutForce) {
    TempDir dir;
    writeBar(dir / "d1" / "a.nrrd", 10);
    writeBar(dir / "d2" / "a.nrrd", 12);
    writeBytes(dir / "first.txt", "d1/a.nrrd\n");
    writeBytes(dir / "second.txt", "d2/a.nrrd\n");
    const fs::path out = dir / "out";
    const CliResult first = runBatch(dir / "first.txt", out);
    ASSERT_EQ(first.exitCode, 0) << first.describe();
    const auto before = snapshot(out / "a");

    const CliResult refused = runBatch(dir / "second.txt", out);
    EXPECT_EQ(refused.exitCode, 5) << refused.describe();
    EXPECT_TRUE(mentions(refused, "a (line 1): " + (out / "a").string() +
                                      ": holds the results of another input (" +
                                      (dir / "d1" / "a.nrrd").string() +
                                      ", done.json); use --force to replace them"))
        << refused.err;
    EXPECT_EQ(snapshot(out / "a"), before);

    const CliResult forced = runBatch(dir / "second.txt", out, {"--force"});
    ASSERT_EQ(forced.exitCode, 0) << forced.describe();
    const auto marker = readDoneMarker(out / "a");
    ASSERT_TRUE(marker);
    EXPECT_EQ(marker->input, dir / "d2" / "a.nrrd");
}

// A redo that fails keeps the earlier outputs (segment's commit is all or
// nothing) and the record that they are the batch's: the next run redoes
// them without --force.
TEST(BatchCommand, AFailedRedoLeavesTheFolderTheBatchsToRedo) {
    TempDir dir;
    writeBar(dir / "in" / "bar.nrrd", 10);
    writeBytes(dir / "list.txt", "in/bar.nrrd\n");
    const fs::path out = dir / "out";
    ASSERT_EQ(runBatch(dir / "list.txt", out).exitCode, 0);
    const std::string labels = fileBytes(out / "bar" / "labels.nrrd");

    writeBytes(dir / "in" / "bar.nrrd", "not a volume any more\n");
    const CliResult failed = runBatch(dir / "list.txt", out);
    EXPECT_EQ(failed.exitCode, 5) << failed.describe();
    EXPECT_EQ(fileBytes(out / "bar" / "labels.nrrd"), labels);
    EXPECT_FALSE(fs::exists(out / "bar" / kDoneMarkerName));
    const auto pending = readDoneMarker(out / "bar", kPendingMarkerName);
    ASSERT_TRUE(pending) << "no record that the folder is the batch's";
    EXPECT_EQ(pending->input, dir / "in" / "bar.nrrd");

    writeBar(dir / "in" / "bar.nrrd", 12);
    const CliResult redone = runBatch(dir / "list.txt", out);
    ASSERT_EQ(redone.exitCode, 0) << redone.describe();
    EXPECT_NE(fileBytes(out / "bar" / "labels.nrrd"), labels);
    EXPECT_TRUE(fs::exists(out / "bar" / kDoneMarkerName));
    EXPECT_FALSE(fs::exists(out / "bar" / kPendingMarkerName));
}

// Hunt 2, finding 1: a second batch (another share, --force, or a batch while
// `skelseg segment` runs) deleted the running run's staging directory and
// done.json, and only then found the folder's lock taken; the running run
// then failed a valid input. The folder is now locked before anything in it
// is touched, and a locked folder is refused and left exactly as it was.
TEST(BatchCommand, AFolderAnotherRunIsWritingIsLeftAlone) {
    TempDir dir;
    writeBar(dir / "in" / "bar.nrrd", 10);
    writeBytes(dir / "list.txt", "in/bar.nrrd\n");
    const fs::path out = dir / "out";
    const CliResult first = runBatch(dir / "list.txt", out);
    ASSERT_EQ(first.exitCode, 0) << first.describe();
    const std::string doneMarker = fileBytes(out / "bar" / kDoneMarkerName);

    // A `segment --force` on out/bar, as it runs: it holds the folder's lock
    // and has staged a file.
    OutputDirectory running(out / "bar", true, segmentOutputLayout());
    const fs::path staged = running.stagingPath("labels.nrrd");
    writeBytes(staged, "being written");
    const auto before = snapshot(out / "bar");

    // Done and matching (skipped), redone with other options, forced, and
    // another share of another count: each is refused on the lock.
    for (const std::vector<std::string>& extra :
         {std::vector<std::string>{}, std::vector<std::string>{"--tau", "5%"},
          std::vector<std::string>{"--force"}, std::vector<std::string>{"--shard", "0/2"}}) {
        std::string options;
        for (const auto& word : extra) options += " " + word;
        SCOPED_TRACE("batch" + options);
        const CliResult refused = runBatch(dir / "list.txt", out, extra);
        EXPECT_EQ(refused.exitCode, 5) << refused.describe();
        EXPECT_TRUE(mentions(refused, "bar (line 1): " + (out / "bar").string() +
                                          ": another skelseg run is writing to it"))
            << refused.err;
        EXPECT_EQ(fileBytes(staged), "being written") << "the running run's staged file";
        EXPECT_EQ(fileBytes(out / "bar" / kDoneMarkerName), doneMarker);
        EXPECT_FALSE(fs::exists(out / "bar" / kPendingMarkerName));
        EXPECT_EQ(snapshot(out / "bar"), before);
    }
    running.commit();
    EXPECT_EQ(fileBytes(out / "bar" / "labels.nrrd"), "being written");
}

// Hunt 2, finding 2: `batch OUT/summary.csv -o OUT` replaced the manifest by
// its own summary without a word (rc 0), and a rerun read the summary as a
// manifest. It is refused now, before anything is read or written.
TEST(BatchCommand, AManifestThatIsOneOfItsSummariesIsRefused) {
    TempDir dir;
    writeBar(dir / "in" / "bar.nrrd", 10);
    const fs::path out = dir / "out";
    const std::string list = (dir / "in" / "bar.nrrd").string() + "\n";
    struct Case {
        std::string manifest;
        std::vector<std::string> extra;
    };
    for (const Case& c : {Case{"summary.csv", {}}, Case{"summary.json", {}},
                          Case{"summary.shard-0-of-2.csv", {"--shard", "0/2"}},
                          Case{"summary.shard-1-of-2.json", {"--shard", "0/2"}},
                          Case{"summary.csv", {"--shard", "1/2"}}}) {
        SCOPED_TRACE(c.manifest);
        fs::remove_all(out);
        fs::create_directories(out);
        writeBytes(out / c.manifest, list);
        const CliResult refused = runBatch(out / c.manifest, out, c.extra);
        EXPECT_TRUE(
            failsWithOneLine(refused, 2, (out / c.manifest).string(), "which the batch rewrites"));
        EXPECT_EQ(fileBytes(out / c.manifest), list);
        EXPECT_EQ(directoryEntries(out), std::vector<std::string>{c.manifest});
    }
    // The same file by another name: a hard link to OUT/summary.csv.
    fs::remove_all(out);
    fs::create_directories(out);
    writeBytes(out / "summary.csv", list);
    fs::create_hard_link(out / "summary.csv", dir / "list.txt");
    const CliResult linked = runBatch(dir / "list.txt", out);
    EXPECT_TRUE(failsWithOneLine(linked, 2, (dir / "list.txt").string(), "summary.csv"));
    EXPECT_EQ(fileBytes(out / "summary.csv"), list);
    // A manifest beside the summaries under another name is the user's file.
    fs::remove(dir / "list.txt");
    fs::rename(out / "summary.csv", out / "inputs.csv");
    const CliResult ran = runBatch(out / "inputs.csv", out);
    EXPECT_EQ(ran.exitCode, 0) << ran.describe();
    EXPECT_EQ(fileBytes(out / "inputs.csv"), list);
}

// A pattern line beside OUTROOT: `*` in data/list.txt with OUTROOT data/out,
// or data/*/* with OUTROOT data/out. The first run was fine; every run after
// it was refused (exit 2), `*` matching OUTROOT ("is OUTROOT, where the
// batch writes") and data/*/* the outputs of every done input ("is
// labels.nrrd in data/out/a, which the batch rewrites").
TEST(BatchCommand, APatternBesideOutrootIsRunAgainAndSkipsWhatIsDone) {
    TempDir dir;
    writeBar(dir / "data" / "a.nrrd", 10);
    writeBar(dir / "data" / "sub" / "b.nrrd", 12);
    writeBytes(dir / "data" / "list.txt", "*\n");
    writeBytes(dir / "nested.txt", "data/*/*\n");
    // data/*/* runs second: it also matches the first batch's outputs in
    // data/out/a/, another batch's, which were segmented as inputs.
    const std::vector<std::tuple<fs::path, fs::path, std::set<std::string>>> runs = {
        {dir / "data" / "list.txt", dir / "data" / "out", {"a.nrrd", "b.nrrd"}},
        {dir / "nested.txt", dir / "data" / "res", {"b.nrrd"}}};
    for (const auto& [manifest, out, shapes] : runs) {
        SCOPED_TRACE(manifest.string());
        const CliResult first = runBatch(manifest, out, {"--tau", "5%,10%"});
        ASSERT_EQ(first.exitCode, 0) << first.describe();
        const CliResult again = runBatch(manifest, out, {"--tau", "5%,10%"});
        ASSERT_EQ(again.exitCode, 0) << again.describe();
        std::ifstream in(out / "summary.json");
        const nlohmann::json summary = nlohmann::json::parse(in);
        ASSERT_FALSE(summary["entries"].empty());
        // The shapes only: no output of either run is among the inputs.
        std::set<std::string> inputs;
        for (const auto& entry : summary["entries"]) {
            EXPECT_EQ(entry["status"], "skipped") << entry.dump();
            inputs.insert(fs::path(entry["input"].get<std::string>()).filename().string());
        }
        EXPECT_EQ(inputs, shapes);
    }
}
