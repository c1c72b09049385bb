// The batch's memory estimate before reading an input (engine/batch/InputMemoryEstimate.h).
#include "engine/batch/InputMemoryEstimate.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include "tests/support/FileBytes.h"
#include "tests/support/TempDir.h"

namespace skelseg {
namespace {

TEST(InputMemoryEstimate, PeeksAtTheHeaderButNotIntoAFifoNamedLikeAVolume) {
    const test::TempDir dir;
    test::writeBytes(dir / "box.nrrd", "NRRD0004\nsizes: 3 4 5\n\n");
    const std::optional<Dims> dims = peekVolumeDims(dir / "box.nrrd");
    ASSERT_TRUE(dims.has_value());
    EXPECT_EQ(dims->x, 3);
    EXPECT_EQ(dims->y, 4);
    EXPECT_EQ(dims->z, 5);
    // Opening a FIFO for reading blocks until a writer comes: this returns
    // only because the type is checked first.
    ASSERT_EQ(::mkfifo((dir / "pipe.nrrd").c_str(), 0600), 0);
    EXPECT_FALSE(peekVolumeDims(dir / "pipe.nrrd").has_value());
    EXPECT_GT(estimateInputMemory(dir / "pipe.nrrd", SegmentCommandOptions{}, 1), 0u);
}

}  // namespace
}  // namespace skelseg
