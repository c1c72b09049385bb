// A batch creates a task arena per shape in flight, not per input: oneTBB
// 2021.8 never freed the arena a shape created inside a busy batch task, and
// the batch grew with every input (kernels/base/ArenaPool.h).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "engine/BatchCommand.h"
#include "io/shapes/SyntheticShapes.h"
#include "io/volume/NrrdIO.h"
#include "kernels/base/ArenaPool.h"
#include "tests/support/FileBytes.h"
#include "tests/support/TempDir.h"

namespace fs = std::filesystem;
using namespace skelseg;
using namespace skelseg::test;

TEST(BatchArenas, ThirtyInputsThreeInFlightCreateAtMostThreeArenas) {
    const TempDir dir;
    fs::create_directories(dir / "in");
    const MaskVolume mask = rasterise(makeShape("y-arms"), {24, 2});
    std::string manifest;
    const int inputs = 30;
    for (int i = 0; i < inputs; ++i) {
        const fs::path file = dir / "in" / ("v" + std::to_string(i) + ".nrrd");
        writeNrrdMask(file, mask);
        manifest += file.string() + "\n";
    }
    writeBytes(dir / "list.txt", manifest);

    BatchCommandOptions options;
    options.manifest = dir / "list.txt";
    options.outroot = dir / "out";
    options.segment.threads = 2;
    options.segment.writePreview = false;
    options.shapesInFlight = 3;
    options.display = BatchProgress::Display::Quiet;
    const std::size_t arenasBefore = ArenaPool::process().arenaCount();
    const std::size_t leasesBefore = ArenaPool::process().leaseCount();
    const BatchOutcome outcome = runBatchCommand(options, stdout);
    EXPECT_EQ(outcome.done, std::size_t(inputs));
    // Every input ran in a pooled arena...
    EXPECT_GE(ArenaPool::process().leaseCount() - leasesBefore, std::size_t(inputs));
    const std::size_t created = ArenaPool::process().arenaCount() - arenasBefore;
    // One per shape at once (none if an earlier test left idle ones), never
    // one per input.
    EXPECT_LE(created, outcome.peakShapesInFlight);
    EXPECT_LE(outcome.peakShapesInFlight, std::size_t(3));
}
