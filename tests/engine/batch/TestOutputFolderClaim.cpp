// Which output folders a batch may write (engine/batch/OutputFolderClaim.h).
#include "engine/batch/OutputFolderClaim.h"

#include <gtest/gtest.h>

#include "engine/SegmentCommand.h"
#include "engine/Version.h"
#include "io/files/OutputDirectory.h"
#include "kernels/base/Error.h"
#include "tests/support/CliRunner.h"
#include "tests/support/TempDir.h"
#include "tests/support/ThrownMessage.h"

namespace fs = std::filesystem;
using namespace skelseg;
using namespace skelseg::test;

namespace {

DoneMarker markerOf(const fs::path& input) {
    DoneMarker marker;
    marker.skelsegVersion = versionString();
    marker.input = input;
    marker.absoluteInput = fs::absolute(input);
    marker.options = outputAffectingOptions({});
    return marker;
}

/// The message of the UsageError claiming `outdir` throws ("" if none).
std::string claimRefusal(const fs::path& outdir, const DoneMarker& pending, bool force) {
    return thrownMessage<UsageError>([&] { claimOutputFolder(outdir, pending, force); });
}

/// DIR/a, done for DIR/a.off by an earlier batch.
fs::path doneFolder(const TempDir& dir) {
    const fs::path outdir = dir / "a";
    fs::create_directories(outdir);
    writeBytes(outdir / "report.json", "{}");
    writeDoneMarker(outdir, markerOf(dir / "a.off"));
    return outdir;
}

}  // namespace

TEST(OutputFolderClaim, ANewFolderHoldsThePendingMarkerAndGoesAgainOnFailure) {
    TempDir dir;
    const fs::path outdir = dir / "out" / "a";
    fs::create_directories(dir / "out");
    const OutputFolderClaim claim = claimOutputFolder(outdir, markerOf(dir / "a.off"), false);
    EXPECT_TRUE(claim.createdFolder);
    EXPECT_FALSE(claim.hadRecord);
    EXPECT_EQ(directoryEntries(outdir), std::vector<std::string>{kPendingMarkerName});
    const auto pending = readDoneMarker(outdir, kPendingMarkerName);
    ASSERT_TRUE(pending);
    EXPECT_EQ(pending->input, dir / "a.off");
    releaseOutputFolder(outdir, claim);
    EXPECT_FALSE(fs::exists(outdir));
}

// `skelseg segment` made them, or a user: a batch replaced them without a
// word (finding 2 of the robustness hunt).
TEST(OutputFolderClaim, OutputsWithoutAMarkerAreAnEarlierRunsAndNeedForce) {
    TempDir dir;
    const fs::path outdir = dir / "a";
    fs::create_directories(outdir);
    writeBytes(outdir / "report.json", "{}");
    EXPECT_EQ(claimRefusal(outdir, markerOf(dir / "a.off"), false),
              outdir.string() +
                  ": holds results of an earlier run (report.json); use --force to "
                  "replace them");
    EXPECT_EQ(directoryEntries(outdir), std::vector<std::string>{"report.json"});
    // A user's file in levels/ is refused even with --force.
    fs::create_directories(outdir / "levels" / "0");
    writeBytes(outdir / "levels" / "0" / "notes.txt", "mine");
    EXPECT_EQ(claimRefusal(outdir, markerOf(dir / "a.off"), true),
              (outdir / "levels" / "0" / "notes.txt").string() +
                  ": not written by skelseg, but inside levels/, which a run in " +
                  outdir.string() + " replaces; move it away or choose another output directory");
    fs::remove(outdir / "levels" / "0" / "notes.txt");
    // With --force the outputs are the batch's to replace; a failure leaves
    // them without a marker of the batch's, as they were.
    const OutputFolderClaim forced = claimOutputFolder(outdir, markerOf(dir / "a.off"), true);
    EXPECT_FALSE(forced.hadRecord);
    EXPECT_TRUE(fs::exists(outdir / kPendingMarkerName));
    releaseOutputFolder(outdir, forced);
    EXPECT_EQ(directoryEntries(outdir), (std::vector<std::string>{"levels", "report.json"}));
}

// d1/a.off and d2/a.obj both go to a/: the second replaced the first's
// results (finding 3 of the robustness hunt).
TEST(OutputFolderClaim, AFolderOfAnotherInputNeedsForce) {
    TempDir dir;
    const fs::path outdir = dir / "a";
    fs::create_directories(outdir);
    writeBytes(outdir / "report.json", "{}");
    writeDoneMarker(outdir, markerOf(dir / "d1" / "a.off"));
    for (const char* marker : {kDoneMarkerName, kPendingMarkerName}) {
        SCOPED_TRACE(marker);
        if (std::string(marker) == kPendingMarkerName) {
            fs::rename(outdir / kDoneMarkerName, outdir / kPendingMarkerName);
        }
        EXPECT_EQ(claimRefusal(outdir, markerOf(dir / "d2" / "a.obj"), false),
                  outdir.string() + ": holds the results of another input (" +
                      (dir / "d1" / "a.off").string() + ", " + marker +
                      "); use --force to replace them");
        EXPECT_EQ(fileBytes(outdir / marker).empty(), false);
        EXPECT_EQ(readDoneMarker(outdir, marker)->input, dir / "d1" / "a.off");
    }
    const OutputFolderClaim forced =
        claimOutputFolder(outdir, markerOf(dir / "d2" / "a.obj"), true);
    EXPECT_TRUE(forced.hadRecord);
    EXPECT_EQ(readDoneMarker(outdir, kPendingMarkerName)->input, dir / "d2" / "a.obj");
}

// Its own input's folder, done or left pending by a killed batch, is the
// batch's to redo; after a failed redo the pending marker stays, so that the
// next run redoes it still.
TEST(OutputFolderClaim, ItsOwnInputsFolderIsRedoneAndStaysPendingAfterAFailure) {
    TempDir dir;
    const fs::path outdir = doneFolder(dir);
    {
        const OutputFolderClaim claim = claimOutputFolder(outdir, markerOf(dir / "a.off"), false);
        EXPECT_TRUE(claim.hadRecord);
        EXPECT_FALSE(fs::exists(outdir / kDoneMarkerName));
        // Claimed, the folder is locked until the claim ends.
        EXPECT_NE(claimRefusal(outdir, markerOf(dir / "a.off"), false)
                      .find("another skelseg run is writing to it"),
                  std::string::npos);
        releaseOutputFolder(outdir, claim);
        EXPECT_EQ(directoryEntries(outdir),
                  (std::vector<std::string>{kPendingMarkerName, "report.json"}));
    }
    // The same file by another path.
    EXPECT_EQ(claimRefusal(outdir, markerOf(dir / "." / "a.off"), false), "");
}

// Hunt 2, finding 1: the claim removed done.json and the staging directory of
// a run writing to the folder before that run's lock refused the batch. A
// folder another run has locked is now refused with nothing in it changed.
TEST(OutputFolderClaim, AFolderAnotherRunHasLockedIsRefusedAndLeftAlone) {
    TempDir dir;
    const fs::path outdir = doneFolder(dir);
    const std::string doneMarker = fileBytes(outdir / kDoneMarkerName);
    // A `segment --force` writing to the folder, as it runs.
    OutputDirectory running(outdir, true, segmentOutputLayout());
    writeBytes(running.stagingPath("labels.nrrd"), "being written");
    const auto before = directoryEntries(outdir);
    for (const bool force : {false, true}) {
        EXPECT_EQ(claimRefusal(outdir, markerOf(dir / "a.off"), force),
                  outdir.string() +
                      ": another skelseg run is writing to it; wait for it to end "
                      "or choose another output directory");
        EXPECT_EQ(directoryEntries(outdir), before);
        EXPECT_EQ(fileBytes(outdir / kDoneMarkerName), doneMarker);
        EXPECT_EQ(fileBytes(running.stagingPath("labels.nrrd")), "being written");
    }
}
