// Scene tests for --joints (issue 13): generated limbs with known joints,
// segmented end to end with and without joint cuts (kernels/JointDetection.h).
#include <gtest/gtest.h>

#include <cmath>

#include "tests/support/SceneSupport.h"

namespace skelseg::test {
namespace {

SegmentationParameters withJoints() {
    SegmentationParameters p;
    p.joints = true;
    return p;
}

std::size_t cutsOfKind(const SceneRun& run, CutKind kind) {
    std::size_t count = 0;
    for (const auto& object : run.result.objects) {
        EXPECT_EQ(object.cuts.size(), object.cutLoops.size());
        for (const auto& c : object.cuts) count += c.kind == kind;
    }
    return count;
}

TEST(SceneJoints, CapsuleChainHasThreePartsWithJointsAndOneWithout) {
    const SceneRun plain = segmentShape("capsule-chain", kSceneSize);
    EXPECT_EQ(partCount(plain), 1u);
    const SceneRun joints = segmentShape("capsule-chain", kSceneSize, withJoints());
    ASSERT_EQ(partCount(joints), 3u);
    EXPECT_EQ(cutsOfKind(joints, CutKind::Joint), 2u);
    EXPECT_EQ(cutsOfKind(joints, CutKind::Junction), 0u);
    // The three capsules are the parts: the outer two alike, the middle one
    // (shorter) smaller than either.
    const auto& s = joints.result.segments;
    EXPECT_NEAR(double(s[0].voxelCount), double(s[1].voxelCount), 0.15 * double(s[0].voxelCount));
    EXPECT_LT(s[2].voxelCount, s[1].voxelCount);
    EXPECT_GT(s[2].voxelCount, s[1].voxelCount / 3);
}

TEST(SceneJoints, CapsuleChainAtOtherOrientationsAndSizes) {
    for (int pose : {1, 2})
        EXPECT_EQ(partCount(segmentShape("capsule-chain", kSceneSize, withJoints(), pose)), 3u)
            << "orientation " << pose;
    EXPECT_EQ(partCount(segmentShape("capsule-chain", 160, withJoints(), 1)), 3u) << "size 160";
}

TEST(SceneJoints, FlexedCapsuleChainKeepsItsJoints) {
    // The chain flexed by 45 degrees at both waists (a knee and an ankle
    // flexing): the joints are measured against the limb on each side, which
    // the flexing leaves as it was, so the same two cuts part the capsules.
    for (int pose : {0, 1, 2}) {
        EXPECT_EQ(partCount(segmentShape("bent-capsule-chain", kSceneSize, {}, pose)), 1u)
            << "orientation " << pose;
        const SceneRun joints = segmentShape("bent-capsule-chain", kSceneSize, withJoints(), pose);
        ASSERT_EQ(partCount(joints), 3u) << "orientation " << pose;
        EXPECT_EQ(cutsOfKind(joints, CutKind::Joint), 2u) << "orientation " << pose;
        const auto& s = joints.result.segments;
        EXPECT_NEAR(double(s[0].voxelCount), double(s[1].voxelCount),
                    0.15 * double(s[0].voxelCount))
            << "orientation " << pose;
        EXPECT_LT(s[2].voxelCount, s[1].voxelCount) << "orientation " << pose;
        EXPECT_GT(s[2].voxelCount, s[1].voxelCount / 3) << "orientation " << pose;
    }
}

TEST(SceneJoints, StraightUniformTubesStayOnePart) {
    for (const char* name : {"capsule", "cylinder"}) {
        EXPECT_EQ(partCount(segmentShape(name, kSceneSize)), 1u) << name;
        const SceneRun joints = segmentShape(name, kSceneSize, withJoints());
        EXPECT_EQ(partCount(joints), 1u) << name;
        EXPECT_EQ(cutsOfKind(joints, CutKind::Joint), 0u) << name;
    }
}

TEST(SceneJoints, BentTubeIsCutAtItsBendWhenBendsAreOn) {
    EXPECT_EQ(partCount(segmentShape("bent-tube", kSceneSize)), 1u);
    // Bends are off by default: narrowings alone leave the uniform tube whole.
    EXPECT_EQ(partCount(segmentShape("bent-tube", kSceneSize, withJoints())), 1u);
    SegmentationParameters bends = withJoints();
    bends.jointOptions.bendAngleDegrees = 30.0;
    for (int pose : {0, 1, 2}) {
        const SceneRun run = segmentShape("bent-tube", kSceneSize, bends, pose);
        ASSERT_EQ(partCount(run), 2u) << "orientation " << pose;
        // The two legs are equally long: the cut sits at the corner.
        const auto& s = run.result.segments;
        EXPECT_NEAR(double(s[0].voxelCount), double(s[1].voxelCount),
                    0.25 * double(s[0].voxelCount))
            << "orientation " << pose;
    }
}

TEST(SceneJoints, JunctionShapesKeepTheirPartsWhenLimbsAreStraight) {
    // Straight uniform arms have no joint, and no joint lands on a junction
    // rule cut.
    const SceneRun run = segmentShape("y-arms", kSceneSize, withJoints());
    EXPECT_EQ(partCount(run), 3u);
    EXPECT_EQ(cutsOfKind(run, CutKind::Joint), 0u);
}

TEST(SceneJoints, SerialAndParallelAgree) {
    SegmentationParameters serial = withJoints();
    serial.threaded = false;
    const SceneRun a = segmentShape("capsule-chain", kSceneSize, withJoints(), 2);
    const SceneRun b = segmentShape("capsule-chain", kSceneSize, serial, 2);
    ASSERT_EQ(a.result.labels.size(), b.result.labels.size());
    std::size_t differing = 0;
    for (std::size_t i = 0; i < a.result.labels.size(); ++i)
        differing += a.result.labels[i] != b.result.labels[i];
    EXPECT_EQ(differing, 0u);
    EXPECT_EQ(a.result.segments.size(), 3u);
    ASSERT_EQ(a.result.objects.size(), b.result.objects.size());
    EXPECT_EQ(a.result.objects[0].cutLoops, b.result.objects[0].cutLoops);
}

}  // namespace
}  // namespace skelseg::test
