// Determinism through the command line: any --threads value gives
// byte-identical label volumes (issue 2).
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "tests/support/FileBytes.h"
#include "tests/support/QuietCommand.h"
#include "tests/support/TempDir.h"
#include "tests/support/TestPaths.h"

namespace skelseg::test {
namespace {

TEST(SceneCli, OneAndTwoThreadsGiveByteIdenticalLabels) {
    TempDir dir;
    const std::string exe = skelsegBinary();
    const auto input = dir / "figure.nrrd";
    ASSERT_EQ(runQuietly(exe + " generate figure -o " + input.string() +
                         " --size 96 --pose 1 --noise 0.01"),
              0);
    ASSERT_EQ(runQuietly(exe + " segment " + input.string() + " -o " + (dir / "t1").string() +
                         " --threads 1 -q --no-preview"),
              0);
    ASSERT_EQ(runQuietly(exe + " segment " + input.string() + " -o " + (dir / "t2").string() +
                         " --threads 2 -q --no-preview"),
              0);
    const std::string a = fileBytes(dir / "t1" / "labels.nrrd"),
                      b = fileBytes(dir / "t2" / "labels.nrrd");
    ASSERT_FALSE(a.empty());
    EXPECT_EQ(a, b);
    EXPECT_EQ(fileBytes(dir / "t1" / "skeleton.ply"), fileBytes(dir / "t2" / "skeleton.ply"));
    EXPECT_EQ(fileBytes(dir / "t1" / "cuts.ply"), fileBytes(dir / "t2" / "cuts.ply"));
}

}  // namespace
}  // namespace skelseg::test
