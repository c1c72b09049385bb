// Scene tests of the joint level (--joints, engine/SegmentationLevels.h): it
// is one more level below the finest junction-rule level, nested in it like
// any other level; the junction-rule levels are those of the same run
// without --joints, byte for byte; with a single tau the top-level result
// stays the joint level as a run without levels gives it.
#include <gtest/gtest.h>

#include "tests/engine/LevelNestingChecks.h"
#include "tests/engine/RobustnessHelpers.h"
#include "tests/support/SceneSupport.h"
#include "tests/support/TempDir.h"
#include "tests/support/TestPaths.h"

namespace skelseg::test {
namespace {

using json = nlohmann::json;

bool sameLabels(const LabelVolume& a, const LabelVolume& b) {
    return a.dims() == b.dims() && std::equal(a.data(), a.data() + a.size(), b.data());
}

TEST(SceneJointLevels, CapsuleChainJointLevelNestsInTheJunctionLevel) {
    SegmentationParameters p;
    p.joints = true;
    const SceneRun run = segmentShape("capsule-chain", kSceneSize, p);
    const SegmentationResult& r = run.result;
    ASSERT_FALSE(r.topIsCoarsestLevel);
    ASSERT_EQ(r.levelCount(), 2u);
    EXPECT_TRUE(r.levelIsJoints(0));
    EXPECT_FALSE(r.levelIsJoints(1));
    EXPECT_EQ(r.levelSegments(0).size(), 3u);
    EXPECT_EQ(r.levelSegments(1).size(), 1u);
    expectResultLevelsNest(r, "capsule-chain");
    // The junction-rule level is the run without --joints.
    const SceneRun plain = segmentShape("capsule-chain", kSceneSize);
    EXPECT_TRUE(sameLabels(r.levelLabels(1), plain.result.labels));
    // The top level is the joint level: the chain's three capsules.
    EXPECT_EQ(r.segments.size(), 3u);
    EXPECT_EQ(r.finerLevels[0].nestingMovedNodes, 0u);
    EXPECT_TRUE(sameLabels(r.labels, r.levelLabels(0)));
    ASSERT_EQ(r.objects.size(), 1u);
    EXPECT_EQ(r.objects[0].levelCutLoops(0), r.objects[0].cutLoops);
    EXPECT_EQ(r.objects[0].levelCutLoops(1).size(), 0u);
}

TEST(SceneJointLevels, CapsuleChainWithATauListAddsTheJointLevelBelowTheFinest) {
    SegmentationParameters p;
    p.joints = true;
    p.finerTaus = {TauSpec::parse("1%")};
    p.tau = TauSpec::parse("3%");
    const SceneRun run = segmentShape("capsule-chain", kSceneSize, p);
    const SegmentationResult& r = run.result;
    ASSERT_TRUE(r.topIsCoarsestLevel);
    ASSERT_EQ(r.levelCount(), 3u);
    EXPECT_TRUE(r.levelIsJoints(0));
    EXPECT_EQ(r.levelTau(0).toString(), "1%");
    EXPECT_EQ(r.levelSegments(0).size(), 3u);
    EXPECT_EQ(r.segments.size(), 1u);  // the top is the coarsest junction-rule level
    expectResultLevelsNest(r, "capsule-chain list");
    // Every cut of the finest junction-rule level is a joint-level cut.
    for (const ObjectSegmentation& object : r.objects)
        for (const auto& loop : object.levelCutLoops(1))
            EXPECT_NE(
                std::find(object.levelCutLoops(0).begin(), object.levelCutLoops(0).end(), loop),
                object.levelCutLoops(0).end());
}

TEST(SceneJointLevels, FigureJointLevelNestsAndKeepsTheJunctionLevels) {
    SegmentationParameters plain;
    plain.finerTaus = {TauSpec::parse("1%")};
    plain.tau = TauSpec::parse("9%");
    SegmentationParameters joints = plain;
    joints.joints = true;
    const SceneRun a = segmentShape("figure", kSceneSize, plain, 1);
    const SceneRun b = segmentShape("figure", kSceneSize, joints, 1);
    ASSERT_EQ(b.result.levelCount(), a.result.levelCount() + 1);
    expectResultLevelsNest(b.result, "figure");
    for (std::size_t k = 0; k < a.result.levelCount(); ++k)
        EXPECT_TRUE(sameLabels(a.result.levelLabels(k), b.result.levelLabels(k + 1))) << k;
}

/// The bytes of level `k`'s files of a CLI run (mesh input).
std::string levelFile(const std::filesystem::path& out, std::size_t k, const char* name) {
    return fileBytes(out / "levels" / std::to_string(k) / name);
}

TEST(SceneJointLevels, SharedPsbModelJointLevelNestsAndTheJunctionLevelsAreUnchanged) {
    if (!hasSharedData()) GTEST_SKIP() << sharedDataDir() << " absent";
    const std::filesystem::path mesh = sharedDataDir() / "psb" / "off" / "1.off";
    if (!std::filesystem::exists(mesh)) GTEST_SKIP() << mesh << " absent";
    TempDir dir;
    const std::vector<std::string> common = {"--no-preview", "--resolution", "128"};
    auto with = [&](std::vector<std::string> extra) {
        extra.insert(extra.begin(), common.begin(), common.end());
        return extra;
    };
    // A list: the joint level below 1%, the three junction-rule levels as
    // without --joints, byte for byte, and the top-level files too.
    ASSERT_EQ(runSegment(mesh, dir / "list", with({"--tau", "1%,3%,9%"})).exitCode, 0);
    const auto list =
        runSegment(mesh, dir / "list-joints", with({"--tau", "1%,3%,9%", "--joints"}));
    ASSERT_EQ(list.exitCode, 0) << list.describe();
    expectWrittenLevelsNest(dir / "list-joints", true, {"1%", "1%", "3%", "9%"});
    for (std::size_t k = 0; k < 3; ++k)
        for (const char* name : {"labels.nrrd", "cuts.ply", "segmentation.seg"})
            EXPECT_EQ(levelFile(dir / "list-joints", k + 1, name), levelFile(dir / "list", k, name))
                << "level " << k << " " << name;
    for (const char* name : {"labels.nrrd", "skeleton.ply", "cuts.ply", "segmentation.seg"})
        EXPECT_EQ(fileBytes(dir / "list-joints" / name), fileBytes(dir / "list" / name)) << name;
    const json hierarchy = json::parse(fileBytes(dir / "list-joints" / "hierarchy.json"));
    const json plainHierarchy = json::parse(fileBytes(dir / "list" / "hierarchy.json"));
    EXPECT_EQ(hierarchy["levels"][0]["joints"], true);
    for (std::size_t k = 0; k < 3; ++k) {
        json level = hierarchy["levels"][k + 1];
        level["level"] = k;
        EXPECT_EQ(level, plainHierarchy["levels"][k]) << k;
    }
    const json report = readReport(dir / "list-joints");
    ASSERT_EQ(report["levels"].size(), 4u);
    EXPECT_EQ(report["levels"][0]["joints"], true);
    EXPECT_GE(report["levels"][0]["segments"].get<int>(),
              report["levels"][1]["segments"].get<int>());

    // One tau: two levels, the junction-rule level as the run without
    // --joints and the top-level cuts those of the joint level.
    ASSERT_EQ(runSegment(mesh, dir / "one", with({})).exitCode, 0);
    const auto one = runSegment(mesh, dir / "one-joints", with({"--joints"}));
    ASSERT_EQ(one.exitCode, 0) << one.describe();
    expectWrittenLevelsNest(dir / "one-joints", true, {"3%", "3%"});
    for (const char* name : {"labels.nrrd", "cuts.ply", "segmentation.seg"})
        EXPECT_EQ(levelFile(dir / "one-joints", 1, name), fileBytes(dir / "one" / name)) << name;
    EXPECT_EQ(levelFile(dir / "one-joints", 0, "cuts.ply"),
              fileBytes(dir / "one-joints" / "cuts.ply"));
    EXPECT_EQ(fileBytes(dir / "one-joints" / "skeleton.ply"),
              fileBytes(dir / "one" / "skeleton.ply"));
    EXPECT_FALSE(std::filesystem::exists(dir / "one" / "hierarchy.json"));
}

}  // namespace
}  // namespace skelseg::test
