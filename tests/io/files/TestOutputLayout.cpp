// What a command writes into its output directory (io/files/OutputLayout.h).
#include "io/files/OutputLayout.h"

#include <gtest/gtest.h>

#include <fstream>
#include <memory>

#include "tests/support/TempDir.h"

namespace skelseg {
namespace {

namespace fs = std::filesystem;

/// report.json and levels/, whose folders 0, 1, ... hold labels.nrrd.
OutputLayout levelsLayout() {
    auto levels = std::make_shared<OutputLayout>();
    levels->folders.push_back({"",
                               [](const std::string& name) {
                                   return name.find_first_not_of("0123456789") == std::string::npos;
                               },
                               std::make_shared<OutputLayout>(OutputLayout{"labels.nrrd"})});
    OutputLayout layout{"report.json"};
    layout.folders.push_back({"levels", {}, levels});
    return layout;
}

void touch(const fs::path& file) {
    fs::create_directories(file.parent_path());
    std::ofstream(file) << "x";
}

TEST(OutputLayout, NamesAreTheFilesThenTheFixedFolders) {
    EXPECT_EQ(levelsLayout().names(), (std::vector<std::string>{"report.json", "levels"}));
}

TEST(OutputLayout, WhatARunWritesIsNotForeign) {
    test::TempDir dir;
    const OutputLayout layout = levelsLayout();
    EXPECT_FALSE(foreignEntry(dir.path(), "levels", layout));  // nothing there
    touch(dir / "report.json");
    touch(dir / "levels" / "0" / "labels.nrrd");
    touch(dir / "levels" / "12" / "labels.nrrd");
    fs::create_directories(dir / "levels" / "3");
    EXPECT_FALSE(foreignEntry(dir.path(), "report.json", layout));
    EXPECT_FALSE(foreignEntry(dir.path(), "levels", layout));
    // A name the layout does not list is not the layout's to judge.
    touch(dir / "notes.txt");
    EXPECT_FALSE(foreignEntry(dir.path(), "notes.txt", layout));
}

TEST(OutputLayout, TheFirstUnknownEntryInNameOrderIsForeign) {
    test::TempDir dir;
    const OutputLayout layout = levelsLayout();
    touch(dir / "levels" / "0" / "labels.nrrd");
    touch(dir / "levels" / "1" / "notes.txt");
    touch(dir / "levels" / "world" / "map.txt");
    EXPECT_EQ(foreignEntry(dir.path(), "levels", layout), dir / "levels" / "1" / "notes.txt");
    fs::remove(dir / "levels" / "1" / "notes.txt");
    EXPECT_EQ(foreignEntry(dir.path(), "levels", layout), dir / "levels" / "world");
}

TEST(OutputLayout, AnEntryOfAnotherKindIsForeign) {
    test::TempDir dir;
    const OutputLayout layout = levelsLayout();
    fs::create_directories(dir / "report.json");  // a folder where a run writes a file
    EXPECT_EQ(foreignEntry(dir.path(), "report.json", layout), dir / "report.json");
    touch(dir / "levels");  // a file where a run writes a folder
    EXPECT_EQ(foreignEntry(dir.path(), "levels", layout), dir / "levels");
    fs::remove(dir / "levels");
    // A link to a folder elsewhere: what it leads to is not a run's.
    fs::create_directories(dir / "elsewhere");
    fs::create_directory_symlink(dir / "elsewhere", dir / "levels");
    EXPECT_EQ(foreignEntry(dir.path(), "levels", layout), dir / "levels");
    fs::remove(dir / "levels");
    fs::create_directories(dir / "levels" / "0" / "labels.nrrd");
    EXPECT_EQ(foreignEntry(dir.path(), "levels", layout), dir / "levels" / "0" / "labels.nrrd");
}

}  // namespace
}  // namespace skelseg
