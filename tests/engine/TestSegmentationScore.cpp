#include "engine/SegmentationScore.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <sstream>

#include "engine/ScoreCommand.h"
#include "io/mesh/MeshIO.h"
#include "io/mesh/SegFile.h"
#include "kernels/base/Error.h"
#include "tests/support/TempDir.h"
#include "tests/support/TestPaths.h"

namespace skelseg {
namespace {

using Labels = std::vector<std::int64_t>;

TEST(SegmentationScore, IdenticalPartitionsScoreZeroWhateverTheLabels) {
    const Labels a = {0, 0, 1, 1, 2, 2, 2};
    const Labels renamed = {9, 9, -4, -4, 7, 7, 7};
    for (const Labels* other : {&a, &renamed}) {
        const PartitionScore s = comparePartitions(a, *other);
        EXPECT_EQ(s.randIndexError, 0.0);
        EXPECT_EQ(s.hammingDistance, 0.0);
        EXPECT_EQ(s.missingRate, 0.0);
        EXPECT_EQ(s.falseAlarmRate, 0.0);
    }
    // Renaming either side changes nothing.
    const Labels b = {0, 1, 1, 1, 2, 0, 2};
    const Labels bRenamed = {5, 3, 3, 3, 8, 5, 8};
    const PartitionScore s1 = comparePartitions(a, b), s2 = comparePartitions(renamed, bRenamed);
    EXPECT_DOUBLE_EQ(s1.randIndexError, s2.randIndexError);
    EXPECT_DOUBLE_EQ(s1.hammingDistance, s2.hammingDistance);
    EXPECT_GT(s1.randIndexError, 0.0);
}

TEST(SegmentationScore, HandComputedFourFaces) {
    // candidate [0,0,1,1], reference [0,1,1,1]. The 6 face pairs:
    //   (1,2) same/different  -> disagree    (1,3) diff/diff -> agree
    //   (1,4) diff/diff       -> agree       (2,3) diff/same -> disagree
    //   (2,4) diff/same       -> disagree    (3,4) same/same -> agree
    // Rand Index error = 3/6.
    // D_H(cand => ref): ref {1}: best cand {1,2} misses 0; ref {2,3,4}: best
    //   cand {3,4} misses face 2 -> 1. Rm = 1/4.
    // D_H(ref => cand): cand {1,2}: best ref ({1} or {2,3,4}, overlap 1)
    //   misses 1; cand {3,4}: best ref {2,3,4} misses 0. Rf = 1/4.
    const Labels candidate = {0, 0, 1, 1}, reference = {0, 1, 1, 1};
    const PartitionScore s = comparePartitions(candidate, reference);
    EXPECT_DOUBLE_EQ(s.randIndexError, 0.5);
    EXPECT_DOUBLE_EQ(s.missingRate, 0.25);
    EXPECT_DOUBLE_EQ(s.falseAlarmRate, 0.25);
    EXPECT_DOUBLE_EQ(s.hammingDistance, 0.25);
}

TEST(SegmentationScore, TextbookBaselines) {
    // Reference: segments of 3, 2 and 1 faces (6 faces, 15 pairs, 3 + 1 + 0
    // pairs inside segments).
    const Labels reference = {0, 0, 0, 1, 1, 2};
    const Labels oneSegment(6, 0);
    const Labels everyFace = {0, 1, 2, 3, 4, 5};

    // One segment: disagrees on the 11 pairs the reference separates. It
    // misses nothing of any reference segment (Rm = 0) and its one segment is
    // half outside the largest reference segment (Rf = 1 - 3/6).
    PartitionScore s = comparePartitions(oneSegment, reference);
    EXPECT_DOUBLE_EQ(s.randIndexError, 11.0 / 15.0);
    EXPECT_DOUBLE_EQ(s.missingRate, 0.0);
    EXPECT_DOUBLE_EQ(s.falseAlarmRate, 0.5);
    EXPECT_DOUBLE_EQ(s.hammingDistance, 0.25);

    // Every face its own segment: disagrees on the 4 pairs the reference
    // joins; keeps one face of each reference segment (Rm = 1 - 3/6), never
    // crosses a reference boundary (Rf = 0).
    s = comparePartitions(everyFace, reference);
    EXPECT_DOUBLE_EQ(s.randIndexError, 4.0 / 15.0);
    EXPECT_DOUBLE_EQ(s.missingRate, 0.5);
    EXPECT_DOUBLE_EQ(s.falseAlarmRate, 0.0);

    // The directions swap with the roles.
    s = comparePartitions(reference, oneSegment);
    EXPECT_DOUBLE_EQ(s.missingRate, 0.5);
    EXPECT_DOUBLE_EQ(s.falseAlarmRate, 0.0);
}

TEST(SegmentationScore, AreaWeights) {
    const Labels candidate = {0, 0, 1, 1}, reference = {0, 1, 1, 1};
    const std::vector<double> areas = {1, 10, 1, 1};
    // Pair weights w_i w_j; the disagreeing pairs (1,2), (2,3), (2,4) weigh
    // 10 each; all pairs weigh ((13^2) - (1 + 100 + 1 + 1)) / 2 = 33.
    // Hamming, total 13: ref {2,3,4} (12) is matched by cand {1,2} (10)
    // and misses 2 -> Rm = 2/13; cand {1,2} (11) is matched by ref {2,3,4}
    // (10) and misses 1 -> Rf = 1/13.
    PartitionScore s = comparePartitions(candidate, reference, &areas);
    EXPECT_DOUBLE_EQ(s.randIndexError, 30.0 / 33.0);
    EXPECT_DOUBLE_EQ(s.missingRate, 2.0 / 13.0);
    EXPECT_DOUBLE_EQ(s.falseAlarmRate, 1.0 / 13.0);
    EXPECT_DOUBLE_EQ(s.hammingDistance, 1.5 / 13.0);

    // Benchmark: Rand Index by faces (as unweighted), Hamming by area.
    s = comparePartitions(candidate, reference, &areas, ScoreWeighting::Benchmark);
    EXPECT_DOUBLE_EQ(s.randIndexError, 0.5);
    EXPECT_DOUBLE_EQ(s.hammingDistance, 1.5 / 13.0);
    // Faces: areas ignored.
    s = comparePartitions(candidate, reference, &areas, ScoreWeighting::Faces);
    EXPECT_DOUBLE_EQ(s.hammingDistance, 0.25);

    // Unit areas give the unweighted numbers.
    const std::vector<double> unit(4, 1.0);
    EXPECT_DOUBLE_EQ(comparePartitions(candidate, reference, &unit).randIndexError, 0.5);
}

TEST(SegmentationScore, RejectsMismatchedInput) {
    EXPECT_THROW(comparePartitions({0, 1}, {0, 1, 2}), UsageError);
    EXPECT_THROW(comparePartitions({}, {}), UsageError);
    const std::vector<double> negative = {1.0, -1.0};
    EXPECT_THROW(comparePartitions({0, 1}, {0, 1}, &negative), UsageError);
    const std::vector<double> zero = {0.0, 0.0};
    EXPECT_THROW(comparePartitions({0, 1}, {0, 1}, &zero), UsageError);
    const std::vector<double> shortAreas = {1.0};
    EXPECT_THROW(comparePartitions({0, 1}, {0, 1}, &shortAreas), UsageError);
    EXPECT_THROW(scoreAgainstHumans({0, 1}, {}, nullptr), UsageError);
}

TEST(SegmentationScore, LinearTimeOnLargeInputs) {
    // A quadratic pair count would take minutes here.
    const std::size_t faces = 2000000;
    Labels everyFace(faces), tenSegments(faces);
    for (std::size_t f = 0; f < faces; ++f) {
        everyFace[f] = std::int64_t(f);
        tenSegments[f] = std::int64_t(f % 10);
    }
    const auto start = std::chrono::steady_clock::now();
    const PartitionScore s = comparePartitions(everyFace, tenSegments);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(seconds, 20.0);
    EXPECT_NEAR(s.missingRate, 1.0 - 10.0 / double(faces), 1e-12);
    EXPECT_EQ(s.falseAlarmRate, 0.0);
    // 1 - RI = pairs inside the ten segments / all pairs ~ 1/10.
    const double inside = 10.0 * (faces / 10.0) * (faces / 10.0 - 1) / 2,
                 all = double(faces) * (faces - 1) / 2;
    EXPECT_NEAR(s.randIndexError, inside / all, 1e-12);
}

TEST(SegmentationScore, ScoreAgainstHumansAverages) {
    const Labels candidate = {0, 0, 1, 1};
    const ScoreSummary summary =
        scoreAgainstHumans(candidate, {{0, 1, 1, 1}, {0, 0, 1, 1}}, nullptr);
    ASSERT_EQ(summary.perHuman.size(), 2u);
    EXPECT_DOUBLE_EQ(summary.perHuman[0].randIndexError, 0.5);
    EXPECT_DOUBLE_EQ(summary.perHuman[1].randIndexError, 0.0);
    EXPECT_DOUBLE_EQ(summary.mean.randIndexError, 0.25);
    EXPECT_DOUBLE_EQ(summary.mean.hammingDistance, 0.125);
}

const char* kCubeOff =
    "OFF\n8 6 0\n0 0 0\n2 0 0\n2 2 0\n0 2 0\n0 0 2\n2 0 2\n2 2 2\n0 2 2\n"
    "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";

TEST(ScoreCommand, PrintsJsonAndTable) {
    test::TempDir dir;
    std::ofstream(dir / "cube.off") << kCubeOff;
    writeSeg(dir / "candidate.seg", {0, 0, 1, 1, 2, 2});
    writeSeg(dir / "human1.seg.gz", {0, 0, 1, 1, 2, 2});
    writeSeg(dir / "human2.seg", {0, 0, 0, 0, 0, 0});
    std::ostringstream json;
    EXPECT_EQ(runScoreCommand(dir / "cube.off", dir / "candidate.seg",
                              {dir / "human1.seg.gz", dir / "human2.seg"}, true, json),
              0);
    const auto document = nlohmann::json::parse(json.str());
    EXPECT_EQ(document["faces"], 6);
    ASSERT_EQ(document["humans"].size(), 2u);
    EXPECT_EQ(document["humans"][0]["rand_index_error"].get<double>(), 0.0);
    // Against one segment: the candidate's 3 pairs-together of 15 agree.
    EXPECT_DOUBLE_EQ(document["humans"][1]["rand_index_error"].get<double>(), 12.0 / 15.0);
    EXPECT_DOUBLE_EQ(document["humans"][1]["missing_rate"].get<double>(), 2.0 / 3.0);
    EXPECT_DOUBLE_EQ(document["mean"]["rand_index_error"].get<double>(), 6.0 / 15.0);
    EXPECT_TRUE(document["humans"][1].contains("file"));
    EXPECT_TRUE(document["mean"].contains("false_alarm_rate"));

    std::ostringstream table;
    runScoreCommand(dir / "cube.off", dir / "candidate.seg", {dir / "human1.seg.gz"}, false, table);
    EXPECT_NE(table.str().find("human1.seg.gz"), std::string::npos);
    EXPECT_NE(table.str().find("mean"), std::string::npos);

    // A file name's newline stays inside its row: 3 header lines, 2 rows.
    writeSeg(dir / "human\n3.seg", {0, 0, 1, 1, 2, 2});
    std::ostringstream escaped;
    runScoreCommand(dir / "cube.off", dir / "candidate.seg", {dir / "human\n3.seg"}, false,
                    escaped);
    const std::string text = escaped.str();
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 5) << text;
    EXPECT_NE(text.find("\nhuman\\n3.seg "), std::string::npos) << text;

    writeSeg(dir / "short.seg", {0, 0, 1});
    try {
        std::ostringstream ignored;
        runScoreCommand(dir / "cube.off", dir / "candidate.seg",
                        {dir / "human1.seg.gz", dir / "short.seg"}, true, ignored);
        ADD_FAILURE() << "mismatching face count accepted";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("short.seg"), std::string::npos);
        EXPECT_NE(std::string(error.what()).find("3 labels but the mesh has 6 faces"),
                  std::string::npos);
    }
    std::ostringstream ignored;
    EXPECT_THROW(runScoreCommand(dir / "cube.off", dir / "candidate.seg", {}, false, ignored),
                 UsageError);
}

TEST(SegmentationScore, PrincetonHumansAgreeWithEachOtherMoreThanBaselines) {
    if (!test::hasSharedData())
        GTEST_SKIP() << "shared data folder " << test::sharedDataDir() << " is absent";
    const auto meshPath = test::sharedDataDir() / "psb" / "off" / "1.off";
    const auto segDir = test::sharedDataDir() / "psb" / "seg" / "1";
    if (!std::filesystem::exists(meshPath) || !std::filesystem::exists(segDir / "1_0.seg.gz"))
        GTEST_SKIP() << "psb model 1 is absent";
    const TriangleMesh mesh = readMesh(meshPath);
    const std::vector<double> areas = faceAreas(mesh);
    std::vector<Labels> humans;
    for (const auto& entry : std::filesystem::directory_iterator(segDir))
        humans.push_back(readSeg(entry.path()));
    ASSERT_GE(humans.size(), 2u);
    const Labels first = humans.front();
    humans.erase(humans.begin());
    const ScoreSummary human = scoreAgainstHumans(first, humans, &areas);
    const ScoreSummary oneSegment = scoreAgainstHumans(Labels(mesh.faceCount, 0), humans, &areas);
    Labels everyFace(mesh.faceCount);
    for (std::size_t f = 0; f < everyFace.size(); ++f) everyFace[f] = std::int64_t(f);
    const ScoreSummary each = scoreAgainstHumans(everyFace, humans, &areas);
    EXPECT_LT(human.mean.randIndexError, oneSegment.mean.randIndexError);
    EXPECT_LT(human.mean.hammingDistance, oneSegment.mean.hammingDistance);
    EXPECT_LT(human.mean.hammingDistance, each.mean.hammingDistance);
    EXPECT_EQ(oneSegment.mean.missingRate, 0.0);
    EXPECT_EQ(each.mean.falseAlarmRate, 0.0);
    EXPECT_GT(each.mean.missingRate, 0.99);  // every face its own segment: HD about 0.5
}

}  // namespace
}  // namespace skelseg
