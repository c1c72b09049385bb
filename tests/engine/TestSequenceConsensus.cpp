#include "engine/SequenceConsensus.h"

#include <gtest/gtest.h>

#include "engine/SegmentationScore.h"
#include "kernels/base/Error.h"

namespace skelseg {
namespace {

using Labels = std::vector<std::int64_t>;

TEST(SequenceConsensus, TakesTheMostTypicalFrameOfTheModalPartCount) {
    // Frames 0 and 2 have 3 parts, frame 1 has 2. Frame 2's third part is a
    // sliver of frame 0's, so it lies nearer the others than frame 0.
    const std::vector<Labels> frames = {
        {0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2},
        {5, 5, 5, 5, 7, 7, 7, 7, 7, 7, 7, 7},
        {1, 3, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4},
    };
    const SequenceConsensus c = chooseSequenceConsensus(frames);
    EXPECT_EQ(c.parts, (std::vector<std::size_t>{3, 2, 3}));
    EXPECT_EQ(c.modalParts, 3u);
    EXPECT_EQ(c.reference, 2u);
    EXPECT_LT(c.meanErrorToOthers[2], c.meanErrorToOthers[0]);
    // Frame 1 is nearer the others still, but has the count fewer frames have.
    EXPECT_LT(c.meanErrorToOthers[1], c.meanErrorToOthers[2]);
}

TEST(SequenceConsensus, ErrorsAreTheScoresRandIndexOverFacesAndTheMeanCountsEachPairOnce) {
    const std::vector<Labels> frames = {{0, 0, 1, 1, 2, 2}, {0, 0, 0, 1, 2, 2}, {3, 3, 3, 3, 3, 4}};
    const SequenceConsensus c = chooseSequenceConsensus(frames);
    double sum = 0.0;
    for (std::size_t a = 0; a < 3; ++a)
        for (std::size_t b = 0; b < 3; ++b) {
            const double expected =
                a == b ? 0.0
                       : comparePartitions(frames[a], frames[b], nullptr, ScoreWeighting::Faces)
                             .randIndexError;
            EXPECT_DOUBLE_EQ(c.pairErrors[a * 3 + b], expected) << a << " " << b;
            if (a < b) sum += expected;
        }
    EXPECT_DOUBLE_EQ(c.meanPairError, sum / 3.0);
    EXPECT_DOUBLE_EQ(c.meanErrorToOthers[0], (c.pairErrors[1] + c.pairErrors[2]) / 2.0);
}

TEST(SequenceConsensus, ATieGoesToTheEarlierFrame) {
    // Two frames, two counts, one count each: both tie on count and error.
    const SequenceConsensus c = chooseSequenceConsensus({{0, 0, 1, 1}, {0, 1, 1, 2}});
    EXPECT_EQ(c.reference, 0u);
    EXPECT_EQ(c.modalParts, 2u);
    // Identical frames: the first.
    EXPECT_EQ(chooseSequenceConsensus({{0, 1}, {0, 1}, {0, 1}}).reference, 0u);
}

TEST(SequenceConsensus, FramesNotTrustedNeitherVoteNorAreChosen) {
    // Frames 0 and 1 have 3 parts and are not trusted; frame 2, the only
    // trusted one, has 2: its count is the vote and it is the reference,
    // though the untrusted frames are the majority and nearer each other.
    const std::vector<Labels> frames = {
        {0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2},
        {0, 0, 0, 1, 1, 1, 1, 1, 2, 2, 2, 2},
        {5, 5, 5, 5, 5, 5, 5, 5, 7, 7, 7, 7},
    };
    const SequenceConsensus everyFrame = chooseSequenceConsensus(frames);
    EXPECT_EQ(everyFrame.reference, 1u);
    EXPECT_EQ(everyFrame.modalParts, 3u);
    const SequenceConsensus c = chooseSequenceConsensus(frames, {false, false, true});
    EXPECT_EQ(c.reference, 2u);
    EXPECT_EQ(c.modalParts, 2u);
    EXPECT_EQ(c.voted, (std::vector<bool>{false, false, true}));
    // The errors are every frame's, whoever votes.
    EXPECT_EQ(c.pairErrors, everyFrame.pairErrors);
    EXPECT_EQ(c.meanErrorToOthers, everyFrame.meanErrorToOthers);
    // Of two trusted frames with 3 parts, the nearer to all frames is chosen.
    EXPECT_EQ(chooseSequenceConsensus(frames, {true, true, false}).reference, everyFrame.reference);
    // No frame trusted: every frame votes, as without trust.
    const SequenceConsensus none = chooseSequenceConsensus(frames, {false, false, false});
    EXPECT_EQ(none.reference, everyFrame.reference);
    EXPECT_EQ(none.voted, (std::vector<bool>{true, true, true}));
    EXPECT_THROW(chooseSequenceConsensus(frames, {true, false}), UsageError);
}

TEST(SequenceConsensus, RefusesFewerThanTwoFramesNoFacesAndFramesOfDifferentSizes) {
    EXPECT_THROW(chooseSequenceConsensus({}), UsageError);
    EXPECT_THROW(chooseSequenceConsensus({{0, 1}}), UsageError);
    EXPECT_THROW(chooseSequenceConsensus({{}, {}}), UsageError);
    EXPECT_THROW(chooseSequenceConsensus({{0, 1}, {0, 1, 2}}), UsageError);
}

}  // namespace
}  // namespace skelseg
