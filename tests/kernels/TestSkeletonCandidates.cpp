#include "kernels/SkeletonCandidates.h"

#include <gtest/gtest.h>

#include "io/shapes/SyntheticShapes.h"
#include "kernels/BoundaryGraph.h"
#include "kernels/FeatureTransform.h"
#include "tests/support/StopAtOnce.h"

namespace skelseg {
namespace {

TEST(SkeletonCandidates, AStopAnsweredOnceAtAnyPollThrows) {
    const MaskVolume mask = rasterise(makeShape("capsule"), {32, 2});
    const Volume<std::uint32_t> ft = featureTransform(boundaryVoxels(mask, {false}), {false});
    const BoundaryGraph graph = buildBoundaryGraph(mask, {false});
    for (const bool threaded : {false, true}) {
        SCOPED_TRACE(threaded ? "threaded" : "serial");
        CandidateOptions options;
        options.threaded = threaded;
        EXPECT_FALSE(selectSkeletonCandidates(mask, ft, graph, options).empty());
        EXPECT_GT(test::expectAStopAtAnyPollThrows([&](Interrupter& interrupter) {
                      selectSkeletonCandidates(mask, ft, graph, options, nullptr, interrupter);
                  }),
                  3);
    }
}

}  // namespace
}  // namespace skelseg
