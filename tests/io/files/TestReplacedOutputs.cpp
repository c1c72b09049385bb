#include "io/files/ReplacedOutputs.h"

#include <gtest/gtest.h>

#include "tests/support/FileBytes.h"
#include "tests/support/TempDir.h"

namespace skelseg {
namespace {

namespace fs = std::filesystem;

TEST(ReplacedOutputs, FindsEveryNameOfAnOutputOrOfAnEntryInsideAnOutputFolder) {
    test::TempDir dir;
    const fs::path out = dir / "out";
    fs::create_directories(out / "levels" / "0");
    test::writeBytes(out / "report.json", "{}");
    test::writeBytes(out / "levels" / "0" / "labels.nrrd", "x");
    test::writeBytes(dir / "outside.nrrd", "y");
    fs::create_hard_link(out / "report.json", dir / "report-link.json");
    fs::create_hard_link(out / "levels" / "0" / "labels.nrrd", dir / "level-link.nrrd");
    // A link inside an output folder is removed with it; its target is not.
    fs::create_symlink(dir / "outside.nrrd", out / "levels" / "0" / "outside.nrrd");

    ReplacedOutputs replaced;
    replaced.add(out, {"report.json", "levels", "hierarchy.json"}, "a");
    const ReplacedOutputs::Entry* report = replaced.find(dir / "report-link.json");
    ASSERT_NE(report, nullptr);
    EXPECT_EQ(report->output, "report.json");
    EXPECT_EQ(report->owner, "a");
    const ReplacedOutputs::Entry* level = replaced.find(dir / "level-link.nrrd");
    ASSERT_NE(level, nullptr);
    EXPECT_EQ(level->output, "levels/0/labels.nrrd");
    ASSERT_NE(replaced.find(out / "levels" / "0"), nullptr);
    EXPECT_EQ(replaced.find(out / "levels" / "0")->output, "levels/0");
    EXPECT_EQ(replaced.find(dir / "outside.nrrd"), nullptr);
    EXPECT_EQ(replaced.find(out / "levels" / "0" / "outside.nrrd"), nullptr);
    EXPECT_EQ(replaced.find(dir / "missing.nrrd"), nullptr);
    EXPECT_EQ(replaced.find(out), nullptr);  // OUTDIR itself is no output
}

TEST(ReplacedOutputs, AnOutputDirectoryThatDoesNotExistReplacesNothing) {
    test::TempDir dir;
    test::writeBytes(dir / "shape.off", "OFF\n");
    ReplacedOutputs replaced;
    replaced.add(dir / "absent", {"levels", "report.json"});
    EXPECT_EQ(replaced.find(dir / "shape.off"), nullptr);
    EXPECT_FALSE(fileIdentity(dir / "absent").has_value());
    ASSERT_TRUE(fileIdentity(dir / "shape.off").has_value());
}

}  // namespace
}  // namespace skelseg
