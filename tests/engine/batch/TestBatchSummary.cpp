// Batch summaries, their merge, and the memory admission rule
// (engine/batch/BatchSummary.h, engine/batch/MemoryBudget.h).
#include <gtest/gtest.h>

#include <atomic>
#include <functional>
#include <thread>

#include "engine/Version.h"
#include "engine/batch/BatchSummary.h"
#include "engine/batch/DoneMarker.h"
#include "engine/batch/MemoryBudget.h"
#include "kernels/base/Error.h"
#include "tests/support/CliRunner.h"
#include "tests/support/TempDir.h"
#include "tests/support/ThrownMessage.h"

namespace fs = std::filesystem;
using namespace skelseg;
using namespace skelseg::test;

namespace {

BatchEntry entry(const std::string& name, const std::string& status) {
    BatchEntry e;
    e.name = name;
    e.input = "/in/" + name + ".off";
    e.status = status;
    e.parts = status == "done" ? 4 : 0;
    if (status == "failed") e.error = "/in/" + name + ".off: bad header, \"quoted\"";
    return e;
}

BatchSummary shardSummary(int index, int count, std::vector<BatchEntry> entries) {
    BatchSummary s;
    s.skelsegVersion = versionString();
    s.skelsegBuild = engineBuildId();
    s.manifest = "/in/list.txt";
    s.shard = {index, count};
    s.options = outputAffectingOptions({});
    s.updatedAt = "2026-11-30T06:0" + std::to_string(index) + ":00Z";
    s.complete = true;
    s.manifestNames = {"a", "b", "c", "d", "e"};
    s.entries = std::move(entries);
    return s;
}

void markDone(const fs::path& outroot, const std::string& name) {
    fs::create_directories(outroot / name);
    DoneMarker marker;
    marker.skelsegVersion = versionString();
    marker.input = "/in/" + name + ".off";
    marker.options = outputAffectingOptions({});
    marker.finishedAt = "2026-11-30T06:00:00Z";
    marker.parts = 3;
    writeDoneMarker(outroot / name, marker);
}

}  // namespace

TEST(BatchSummary, WritesJsonAndCsvThatReadBack) {
    TempDir dir;
    BatchSummary s = shardSummary(1, 2, {entry("a", "done"), entry("b", "failed")});
    writeBatchSummary(dir.path(), s.shard.summaryStem(), s);
    const BatchSummary read = readBatchSummary(dir / "summary.shard-1-of-2.json");
    ASSERT_EQ(read.entries.size(), 2u);
    EXPECT_EQ(read.entries[1].status, "failed");
    EXPECT_EQ(read.entries[1].error, s.entries[1].error);
    EXPECT_EQ(read.manifestNames, s.manifestNames);
    EXPECT_EQ(read.shard.index, 1);
    const std::string csv = fileBytes(dir / "summary.shard-1-of-2.csv");
    EXPECT_EQ(csv.rfind("name,input,status,parts,", 0), 0u);
    // The error holds a comma and quotes: one quoted CSV field.
    EXPECT_NE(csv.find("\"/in/b.off: bad header, \"\"quoted\"\"\""), std::string::npos) << csv;
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3);
    writeBytes(dir / "other.json", "{\"not\": \"a summary\"}");
    EXPECT_THROW(readBatchSummary(dir / "other.json"), InputError);
}

TEST(BatchSummary, MergeTakesTheMarkersAsTruthAndListsWhatIsMissing) {
    TempDir dir;
    // Shard 0 finished a, b; shard 1 was killed after c (its summary still
    // says pending), failed d; e belongs to shard 2, which never ran.
    writeBatchSummary(dir.path(), "summary.shard-0-of-3",
                      shardSummary(0, 3, {entry("a", "done"), entry("b", "skipped")}));
    writeBatchSummary(dir.path(), "summary.shard-1-of-3",
                      shardSummary(1, 3, {entry("c", "pending"), entry("d", "failed")}));
    // A file from an earlier split into two is ignored.
    writeBatchSummary(dir.path(), "summary.shard-0-of-2", shardSummary(0, 2, {entry("e", "done")}));
    for (const char* name : {"a", "b", "c"}) markDone(dir.path(), name);
    const MergeResult result = mergeBatchSummaries(dir.path());
    EXPECT_EQ(result.shardFiles.size(), 2u);
    EXPECT_EQ(result.missingShards, std::vector<std::string>{"2/3"});
    EXPECT_EQ(result.failed, std::vector<std::string>{"d"});
    EXPECT_EQ(result.missing, (std::vector<std::string>{"d", "e"}));
    ASSERT_EQ(result.merged.entries.size(), 5u);
    EXPECT_EQ(result.merged.entries[2].status, "done");  // from its marker
    EXPECT_EQ(result.merged.entries[2].parts, 3u);
    EXPECT_EQ(result.merged.entries[4].status, "missing");
    EXPECT_FALSE(result.merged.complete);
    const BatchSummary written = readBatchSummary(dir / "summary.json");
    EXPECT_EQ(written.entries.size(), 5u);
    EXPECT_EQ(written.count("missing"), 1u);

    // The missing shard runs; a done entry whose marker was deleted is missing again.
    writeBatchSummary(dir.path(), "summary.shard-2-of-3", shardSummary(2, 3, {entry("e", "done")}));
    markDone(dir.path(), "e");
    markDone(dir.path(), "d");
    fs::remove(dir / "a" / kDoneMarkerName);
    const MergeResult again = mergeBatchSummaries(dir.path());
    EXPECT_TRUE(again.missingShards.empty());
    EXPECT_EQ(again.missing, std::vector<std::string>{"a"});
    EXPECT_EQ(again.merged.entries[3].status, "done");
}

TEST(BatchSummary, MergeListsRunsOfAbsentSharesOnce) {
    // Two inputs split into 10^9 shares (`--shard I/1000000000`): the merge
    // listed every absent share, a billion lines, and ran out of memory first.
    TempDir dir;
    const int count = 1000000000;
    writeBatchSummary(dir.path(), "summary.shard-0-of-1000000000",
                      shardSummary(0, count, {entry("a", "done")}));
    writeBatchSummary(dir.path(), "summary.shard-5-of-1000000000",
                      shardSummary(5, count, {entry("b", "done")}));
    writeBatchSummary(dir.path(), "summary.shard-6-of-1000000000", shardSummary(6, count, {}));
    markDone(dir.path(), "a");
    markDone(dir.path(), "b");
    const MergeResult result = mergeBatchSummaries(dir.path());
    EXPECT_EQ(result.missingShards,
              (std::vector<std::string>{"1-4/1000000000", "7-999999999/1000000000"}));
    EXPECT_EQ(result.missing, (std::vector<std::string>{"c", "d", "e"}));  // in no summary
    EXPECT_FALSE(result.merged.complete);
    // One absent share between two present ones is named alone.
    TempDir three;
    writeBatchSummary(three.path(), "summary.shard-0-of-3", shardSummary(0, 3, {}));
    writeBatchSummary(three.path(), "summary.shard-2-of-3", shardSummary(2, 3, {}));
    EXPECT_EQ(mergeBatchSummaries(three.path()).missingShards, std::vector<std::string>{"1/3"});
}

TEST(BatchSummary, MergeWithoutSummariesIsAnInputError) {
    TempDir dir;
    EXPECT_THROW(mergeBatchSummaries(dir.path()), InputError);
}

TEST(BatchSummary, MergeRefusesASummaryWhoseShardIsNotTheOneItsNameSays) {
    TempDir dir;
    writeBatchSummary(dir.path(), "summary.shard-1-of-2", shardSummary(1, 2, {entry("b", "done")}));
    // A damaged shard-0 file, the newest, claiming another count: the merge
    // took that count, ignored the real shards and listed the shares of the
    // claimed count as missing; with a count of 2^31 - 1 it listed two
    // billion of them until the memory ran out.
    BatchSummary damaged = shardSummary(0, 3, {entry("a", "done")});
    damaged.updatedAt = "2026-11-30T07:00:00Z";
    writeBatchSummary(dir.path(), "summary.shard-0-of-2", damaged);
    try {
        mergeBatchSummaries(dir.path());
        ADD_FAILURE() << "the damaged summary was merged";
    } catch (const InputError& error) {
        EXPECT_EQ(std::string(error.what()),
                  (dir / "summary.shard-0-of-2.json").string() +
                      ": not a skelseg batch summary: it holds shard 0/3 but is named for 0/2");
    }
    EXPECT_FALSE(fs::exists(dir / "summary.json"));
    // The single summary of an unsharded batch is share 0/1.
    TempDir single;
    writeBatchSummary(single.path(), "summary", shardSummary(3, 5, {entry("a", "done")}));
    EXPECT_THROW(mergeBatchSummaries(single.path()), InputError);
}

namespace {

/// The message of the InputError `mergeBatchSummaries(outroot)` throws ("" if none).
std::string mergeError(const fs::path& outroot) {
    return thrownMessage<InputError>([&] { mergeBatchSummaries(outroot); });
}

}  // namespace

// Two manifests run as the shares of one OUTROOT: the second's input of the
// same output name replaced the first's, and the merge combined both
// summaries and called the input done (finding 3 of the robustness hunt).
TEST(BatchSummary, MergeRefusesTheShardsOfAnotherBatch) {
    const std::string advice =
        "; merge only the shards of one batch (same manifest, options and skelseg build)";
    struct Case {
        const char* what;
        std::function<void(BatchSummary&)> change;
        std::string difference;
    };
    SegmentCommandOptions otherSigma;
    otherSigma.parameters.sigmaMin = 0.7;
    const std::vector<Case> cases = {
        {"manifest", [](BatchSummary& s) { s.manifest = "/in/other.txt"; },
         "its manifest is /in/other.txt, not /in/list.txt"},
        {"names", [](BatchSummary& s) { s.manifestNames.push_back("f"); },
         "its manifest lists other inputs (manifest_names)"},
        {"options", [&](BatchSummary& s) { s.options = outputAffectingOptions(otherSigma); },
         "its options differ (sigma_min is 0.7, not 0.8)"},
        {"version", [](BatchSummary& s) { s.skelsegVersion = "0.0.1"; },
         "it was written by skelseg 0.0.1, not " + std::string(versionString())},
        // The same version, another build (a node with another binary).
        {"build", [](BatchSummary& s) { s.skelsegBuild = "1234-00c0ffee"; },
         "it was written by build 1234-00c0ffee, not build " + engineBuildId()},
        {"no build", [](BatchSummary& s) { s.skelsegBuild.clear(); },
         "it was written by a build it does not name, not build " + engineBuildId()},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.what);
        TempDir dir;
        BatchSummary other = shardSummary(0, 2, {entry("a", "done")});
        c.change(other);
        writeBatchSummary(dir.path(), "summary.shard-0-of-2", other);
        // The newest, the reference.
        writeBatchSummary(dir.path(), "summary.shard-1-of-2",
                          shardSummary(1, 2, {entry("b", "done")}));
        markDone(dir.path(), "a");
        markDone(dir.path(), "b");
        EXPECT_EQ(mergeError(dir.path()),
                  (dir / "summary.shard-0-of-2.json").string() + ": is of another batch than " +
                      (dir / "summary.shard-1-of-2.json").string() + ": " + c.difference + advice);
        EXPECT_FALSE(fs::exists(dir / "summary.json"));
    }
    // One manifest spelled two ways by two tasks is one batch.
    TempDir dir;
    BatchSummary first = shardSummary(0, 2, {entry("a", "done")});
    first.manifest = "/in/./list.txt";
    writeBatchSummary(dir.path(), "summary.shard-0-of-2", first);
    writeBatchSummary(dir.path(), "summary.shard-1-of-2", shardSummary(1, 2, {entry("b", "done")}));
    EXPECT_EQ(mergeError(dir.path()), "");
}

// A damaged summary was described in nlohmann::json's and libstdc++'s words
// ("[json.exception.type_error.304] cannot use at() with array",
// "basic_filebuf::underflow error reading the file: Is a directory").
TEST(BatchSummary, ADamagedSummaryIsDescribedInPlainWords) {
    const std::string good = [] {
        TempDir dir;
        writeBatchSummary(dir.path(), "summary.shard-0-of-2",
                          shardSummary(0, 2, {entry("a", "done"), entry("b", "failed")}));
        return fileBytes(dir / "summary.shard-0-of-2.json");
    }();
    const auto replaced = [&](const std::string& from, const std::string& to) {
        std::string text = good;
        const auto at = text.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        if (at != std::string::npos) text.replace(at, from.size(), to);
        return text;
    };
    const std::string prefix = "not a skelseg batch summary: ";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"[]", prefix + "it is not a JSON object"},
        {"{\"skelseg", prefix + "not JSON (it ends in the middle)"},
        {"{\"a\": x}", prefix + "not JSON (syntax error at byte 7)"},
        {replaced("\"skelseg_version\"", "\"version\""), prefix + "'skelseg_version' is missing"},
        {replaced("\"index\": 0", "\"index\": \"0\""), prefix + "'shard.index' is not an integer"},
        {replaced("\"shard\": {", "\"shard\": [], \"x\": {"),
         prefix + "'shard' is not a JSON object"},
        {replaced("\"manifest_names\": [", "\"manifest_names\": [1,"),
         prefix + "'manifest_names' item 1 is not a string"},
        {replaced("\"entries\": [", "\"entries\": {\"a\": 1}, \"x\": ["),
         prefix + "'entries' is not a list"},
        {replaced("\"status\": \"failed\",\n      \"wall_seconds\": 0.0",
                  "\"status\": \"failed\",\n      \"wall_seconds\": \"0\""),
         prefix + "entry 2: 'wall_seconds' is not a number"},
        {replaced("\"parts\": 4", "\"parts\": -4"),
         prefix + "entry 1: 'parts' is not a count (a whole number of at least 0)"},
    };
    for (const auto& [text, problem] : cases) {
        SCOPED_TRACE(problem);
        TempDir dir;
        writeBytes(dir / "summary.shard-0-of-2.json", text);
        EXPECT_EQ(mergeError(dir.path()),
                  (dir / "summary.shard-0-of-2.json").string() + ": " + problem);
    }
    TempDir dir;
    fs::create_directory(dir / "summary.shard-0-of-2.json");
    EXPECT_EQ(mergeError(dir.path()),
              (dir / "summary.shard-0-of-2.json").string() + ": is a directory, not a file");
}

TEST(MemoryBudget, AdmitsWhatFitsAndOneOversizedShapeAlone) {
    MemoryBudget budget(100, 3);
    EXPECT_TRUE(budget.acquire(60));
    EXPECT_TRUE(budget.acquire(40));
    EXPECT_EQ(budget.bytesInFlight(), 100u);
    // Does not fit: with a stop request, acquire gives up without acquiring.
    EXPECT_FALSE(budget.acquire(1, [] { return true; }));
    EXPECT_EQ(budget.shapesInFlight(), 2u);
    budget.release(60);
    budget.release(40);
    EXPECT_TRUE(budget.acquire(500));  // alone: admitted, segment's own check reports it
    EXPECT_FALSE(budget.acquire(1, [] { return true; }));
    budget.release(500);
    EXPECT_EQ(budget.peakShapesInFlight(), 2u);
}

TEST(MemoryBudget, BoundsTheShapesInFlightAcrossThreads) {
    MemoryBudget budget(1000, 2);
    std::atomic<int> inFlight{0}, peak{0};
    std::vector<std::thread> workers;
    for (int t = 0; t < 6; ++t)
        workers.emplace_back([&] {
            for (int i = 0; i < 20; ++i) {
                ASSERT_TRUE(budget.acquire(10));
                const int now = ++inFlight;
                int seen = peak.load();
                while (now > seen && !peak.compare_exchange_weak(seen, now)) {
                }
                std::this_thread::yield();
                --inFlight;
                budget.release(10);
            }
        });
    for (auto& w : workers) w.join();
    EXPECT_LE(peak.load(), 2);
    EXPECT_EQ(budget.shapesInFlight(), 0u);
    EXPECT_EQ(budget.bytesInFlight(), 0u);
}
