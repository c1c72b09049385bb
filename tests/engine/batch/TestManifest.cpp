// Manifest parsing, output names and shards (engine/batch/Manifest.h).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <climits>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>

#include "engine/batch/DoneMarker.h"
#include "engine/batch/Manifest.h"
#include "kernels/base/Error.h"
#include "tests/support/CliRunner.h"
#include "tests/support/TempDir.h"
#include "tests/support/ThrownMessage.h"

namespace fs = std::filesystem;
using namespace skelseg;
using namespace skelseg::test;

namespace {

void touch(const fs::path& file, std::size_t bytes = 10) {
    fs::create_directories(file.parent_path());
    writeBytes(file, std::string(bytes, 'x'));
}

}  // namespace

TEST(Manifest, SkipsCommentsAndBlankLinesAndTrims) {
    TempDir dir;
    touch(dir / "a.nrrd");
    touch(dir / "b.off");
    writeBytes(dir / "list.txt", "# a comment\n\n   a.nrrd  \n\t# indented comment\nb.off\r\n");
    const Manifest m = readManifest(dir / "list.txt");
    ASSERT_EQ(m.entries.size(), 2u);
    EXPECT_EQ(m.entries[0].input, dir / "a.nrrd");
    EXPECT_EQ(m.entries[0].line, 3);
    EXPECT_EQ(m.entries[1].input, dir / "b.off");
    EXPECT_EQ(m.entries[1].line, 5);
    EXPECT_TRUE(m.warnings.empty());
}

// Paths quoted as a shell or a script quotes paths with spaces: the quotes
// are not part of the name, unless a file is named with them.
TEST(Manifest, QuotedPathsAreThePathsInsideTheQuotes) {
    TempDir dir;
    touch(dir / "my shapes" / "a.off");
    touch(dir / "b.nrrd");
    touch(dir / "\"c.off\"");
    writeBytes(dir / "list.txt", "\"my shapes/a.off\"\n  'b.nrrd'  \n\"c.off\"\n\"d.off'\n\"\"\n" +
                                     ("\"" + (dir / "b.nrrd").string() + "\"\n"));
    const Manifest m = readManifest(dir / "list.txt");
    ASSERT_EQ(m.entries.size(), 5u);
    EXPECT_EQ(m.entries[0].input, dir / "my shapes" / "a.off");
    EXPECT_TRUE(m.entries[0].exists);
    EXPECT_EQ(m.entries[0].name, "a");
    EXPECT_EQ(m.entries[1].input, dir / "b.nrrd");
    EXPECT_TRUE(m.entries[1].exists);
    // A file whose name holds the quotes is that file.
    EXPECT_EQ(m.entries[2].input, dir / "\"c.off\"");
    EXPECT_TRUE(m.entries[2].exists);
    // Quotes that do not match, and a pair of quotes alone, stay as written.
    EXPECT_EQ(m.entries[3].input, dir / "\"d.off'");
    EXPECT_FALSE(m.entries[3].exists);
    EXPECT_EQ(m.entries[4].input, dir / "\"\"");
    EXPECT_FALSE(m.entries[4].exists);
    // The absolute path in quotes is b.nrrd again: kept once.
    ASSERT_EQ(m.warnings.size(), 1u);
    EXPECT_NE(m.warnings[0].find("first on line 2"), std::string::npos) << m.warnings[0];
}

TEST(Manifest, RelativePathsAreRelativeToTheManifest) {
    TempDir dir;
    touch(dir / "data" / "shapes" / "x.binvox", 33);
    touch(dir / "elsewhere" / "y.nrrd");
    writeBytes(dir / "data" / "list.txt",
               "shapes/x.binvox\n" + (dir / "elsewhere" / "y.nrrd").string() + "\n");
    const Manifest m = readManifest(dir / "data" / "list.txt");
    ASSERT_EQ(m.entries.size(), 2u);
    EXPECT_EQ(m.entries[0].input, dir / "data" / "shapes" / "x.binvox");
    EXPECT_TRUE(m.entries[0].exists);
    EXPECT_EQ(m.entries[0].fileBytes, 33u);
    EXPECT_EQ(m.entries[1].input, dir / "elsewhere" / "y.nrrd");
    EXPECT_EQ(m.entries[0].name, "x");
    EXPECT_EQ(m.entries[1].name, "y");
}

TEST(Manifest, DuplicatesAreKeptOnceWithAWarning) {
    TempDir dir;
    touch(dir / "s" / "a.nrrd");
    writeBytes(dir / "list.txt", "s/a.nrrd\ns/../s/a.nrrd\n" + (dir / "s" / "a.nrrd").string());
    const Manifest m = readManifest(dir / "list.txt");
    ASSERT_EQ(m.entries.size(), 1u);
    ASSERT_EQ(m.warnings.size(), 2u);
    EXPECT_NE(m.warnings[0].find("list.txt:2"), std::string::npos) << m.warnings[0];
    EXPECT_NE(m.warnings[0].find("first on line 1"), std::string::npos) << m.warnings[0];
}

// A hard link was segmented twice under two names, although a symbolic link
// or another spelling of the same file was caught.
TEST(Manifest, AHardLinkIsTheSameFile) {
    TempDir dir;
    touch(dir / "s" / "a.nrrd");
    fs::create_hard_link(dir / "s" / "a.nrrd", dir / "s" / "linked.nrrd");
    writeBytes(dir / "list.txt", "s/a.nrrd\ns/linked.nrrd\n");
    const Manifest m = readManifest(dir / "list.txt");
    ASSERT_EQ(m.entries.size(), 1u);
    ASSERT_EQ(m.warnings.size(), 1u);
    EXPECT_NE(m.warnings[0].find("linked.nrrd is listed again (first on line 1)"),
              std::string::npos)
        << m.warnings[0];
}

TEST(Manifest, MissingFilesAreKeptAndMarked) {
    TempDir dir;
    touch(dir / "here.nrrd");
    writeBytes(dir / "list.txt", "gone.nrrd\nhere.nrrd\n");
    const Manifest m = readManifest(dir / "list.txt");
    ASSERT_EQ(m.entries.size(), 2u);
    EXPECT_FALSE(m.entries[0].exists);
    EXPECT_EQ(m.entries[0].fileBytes, 0u);
    EXPECT_TRUE(m.entries[1].exists);
}

TEST(Manifest, EmptyOrUnreadableManifestIsAnInputError) {
    TempDir dir;
    writeBytes(dir / "empty.txt", "# nothing here\n\n");
    try {
        readManifest(dir / "empty.txt");
        FAIL() << "an empty manifest was accepted";
    } catch (const InputError& error) {
        EXPECT_EQ(error.file(), (dir / "empty.txt").string());
    }
    EXPECT_THROW(readManifest(dir / "absent.txt"), InputError);
    fs::create_directories(dir / "nothing");
    touch(dir / "nothing" / "notes.txt");
    EXPECT_THROW(readManifest(dir / "nothing"), InputError);
}

TEST(Manifest, ByteOrderMarkIsSkipped) {
    TempDir dir;
    touch(dir / "a.nrrd");
    writeBytes(dir / "list.txt",
               "\xEF\xBB\xBF"
               "a.nrrd\n");
    const Manifest manifest = readManifest(dir / "list.txt");
    ASSERT_EQ(manifest.entries.size(), 1u);
    EXPECT_TRUE(manifest.entries[0].exists);
    EXPECT_EQ(manifest.entries[0].name, "a");
}

TEST(Manifest, AShapeOrBinaryDataIsNotAManifest) {
    TempDir dir;
    // Each line of these would otherwise become a missing input.
    writeBytes(dir / "shape.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    writeBytes(dir / "binary.txt", std::string("a.nrrd\nb\0c\n", 11));
    EXPECT_THROW(readManifest(dir / "shape.off"), InputError);
    EXPECT_THROW(readManifest(dir / "binary.txt"), InputError);
    // `dir /b > list.txt` in Windows PowerShell writes UTF-16: it was refused
    // for "a NUL byte", as if it were binary data.
    writeBytes(dir / "utf16.txt", std::string("\xFF\xFE"
                                              "a\0.\0n\0r\0r\0d\0\r\0\n\0",
                                              18));
    try {
        readManifest(dir / "utf16.txt");
        ADD_FAILURE() << "a UTF-16 manifest was read";
    } catch (const InputError& error) {
        EXPECT_EQ(
            std::string(error.what()),
            (dir / "utf16.txt").string() +
                ": is UTF-16 text (it starts with a UTF-16 byte order mark); save it as UTF-8");
    }
    // Classic Mac OS line ends made one input of the whole list.
    writeBytes(dir / "mac.txt", "a.nrrd\rb.nrrd\r");
    try {
        readManifest(dir / "mac.txt");
        ADD_FAILURE() << "a manifest with carriage returns alone was read";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("carriage return alone"), std::string::npos)
            << error.what();
    }
}

TEST(Manifest, ALineLongerThanAnyPathIsNotAManifest) {
    TempDir dir;
    writeBytes(dir / "list.txt", "a.off\n" + std::string(PATH_MAX, 'x') + ".off\n");
    EXPECT_EQ(thrownMessage<InputError>([&] { readManifest(dir / "list.txt"); }),
              (dir / "list.txt").string() + ": line 2 is " + std::to_string(PATH_MAX + 4) +
                  " bytes long, longer than any path (" + std::to_string(PATH_MAX - 1) +
                  " bytes): not a manifest");
    // The longest path the system takes is an input, missing or not.
    writeBytes(dir / "list.txt", "/" + std::string(PATH_MAX - 6, 'x') + ".off\n");
    EXPECT_EQ(readManifest(dir / "list.txt").entries.size(), 1u);
}

TEST(OutputNames, ThousandsOfEqualNamesGetDistinctFoldersOrCounters) {
    std::vector<fs::path> inputs;
    for (int i = 0; i < 3000; ++i)
        inputs.push_back(fs::path("d" + std::to_string(i)) / "x" / "m.off");
    const std::vector<std::string> names = uniqueOutputNames(inputs);
    EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), inputs.size());
    EXPECT_EQ(names[0], "d0-x-m");
    EXPECT_EQ(names[2999], "d2999-x-m");
    // Names no folder tells apart get counters, without a quadratic search.
    std::vector<fs::path> cut;
    for (int i = 0; i < 3000; ++i)
        cut.push_back(fs::path(std::string(260, 'd') + std::to_string(i)) / "m.off");
    const std::vector<std::string> cutNames = uniqueOutputNames(cut);
    EXPECT_EQ(std::set<std::string>(cutNames.begin(), cutNames.end()).size(), cut.size());
    EXPECT_EQ(cutNames[0], std::string(253, 'd') + "-m");
    EXPECT_EQ(cutNames[1], std::string(253, 'd') + "-2");
    EXPECT_EQ(cutNames[2999], std::string(250, 'd') + "-3000");
}

namespace {

/// Every order of `inputs` gives each input the name it has in `names`.
void expectTheSameNamesInEveryOrder(const std::vector<fs::path>& inputs,
                                    const std::vector<std::string>& names) {
    std::vector<std::size_t> order(inputs.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    while (std::next_permutation(order.begin(), order.end())) {
        std::vector<fs::path> shuffled;
        for (const std::size_t i : order) shuffled.push_back(inputs[i]);
        const auto shuffledNames = uniqueOutputNames(shuffled);
        for (std::size_t k = 0; k < order.size(); ++k)
            ASSERT_EQ(shuffledNames[k], names[order[k]]) << shuffled[k];
    }
}

}  // namespace

// Names came from a counter in manifest order, so the same inputs listed in
// another order (a regenerated manifest, a resumed batch) got each other's
// folders, and the resume refused them as another input's results.
TEST(OutputNames, DoNotDependOnTheOrderOfTheInputs) {
    std::vector<fs::path> inputs = {"in/e1/a.off", "in/e2/a.off", "in/e2/e1/a.off", "in/b.off",
                                    "in/x/b.ply"};
    const auto names = uniqueOutputNames(inputs);
    EXPECT_EQ(names, (std::vector<std::string>{"in-e1-a", "e2-a", "e2-e1-a", "in-b", "x-b"}));
    expectTheSameNamesInEveryOrder(inputs, names);
}

// A name made of folders ("b-c" for a/b/c.off beside a-b/c.off) that is
// another input's own stem (b-c.off): the counter went to whichever came
// later in the manifest, so a reordered manifest swapped b-c and b-c-2.
TEST(OutputNames, AFolderMadeNameEqualToAnotherStemDoesNotDependOnTheOrder) {
    const std::vector<fs::path> inputs = {"/in/a/b/c.off", "/in/a-b/c.off", "/in/b-c.off",
                                          "/in/x/b-c-2.off"};
    const auto names = uniqueOutputNames(inputs);
    EXPECT_EQ(names, (std::vector<std::string>{"b-c-3", "a-b-c", "b-c", "b-c-2"}));
    expectTheSameNamesInEveryOrder(inputs, names);
}

// `ls data/*.off > lists/all.txt` lists paths from the working directory;
// the batch reads them from the manifest's folder, and every input failed
// with "lists/data/a.off: no such file", a path nobody wrote. A line a shell
// would have expanded (~, $HOME) failed the same way.
TEST(Manifest, AMissingInputSaysWhyItsPathMayNameNoFile) {
    TempDir dir;
    touch(dir / "data" / "a.off");
    touch(dir / "lists" / "b.off");
    writeBytes(dir / "lists" / "all.txt",
               "data/a.off\nb.off\n~/c.off\n\"$HOME/d.off\"\nmissing.off\n");
    struct WorkingDirectory {
        fs::path before = fs::current_path();
        ~WorkingDirectory() { fs::current_path(before); }
    } restore;
    fs::current_path(dir.path());
    const Manifest m = readManifest("lists/all.txt");
    ASSERT_EQ(m.entries.size(), 5u);
    EXPECT_FALSE(m.entries[0].exists);
    EXPECT_EQ(m.entries[0].missingNote,
              "relative paths are read from the manifest's folder, lists; data/a.off is a file "
              "from the working directory: list it as " +
                  (fs::current_path() / "data" / "a.off").string());
    EXPECT_TRUE(m.entries[1].exists);
    EXPECT_EQ(m.entries[1].missingNote, "");
    for (const std::size_t i : {2, 3})
        EXPECT_NE(m.entries[i].missingNote.find("not expanded as a shell expands them"),
                  std::string::npos)
            << m.entries[i].input;
    EXPECT_EQ(m.entries[4].missingNote, "");
    // The batch's line for the input says it.
    const auto run = runSkelseg({"batch", "lists/all.txt", "-o", "out", "-q", "--no-preview"});
    EXPECT_EQ(run.exitCode, 5) << run.describe();
    EXPECT_NE(run.err.find("  a (line 1): lists/data/a.off: no such file (relative paths are "
                           "read from the manifest's folder, lists; data/a.off is a file"),
              std::string::npos)
        << run.err;
    EXPECT_NE(run.err.find("  missing (line 5): lists/missing.off: no such file\n"),
              std::string::npos)
        << run.err;
}

// What a batch wrote is no shape of a folder or a pattern: data/*/* matched
// the outputs of a batch with OUTROOT data/res (labels.nrrd, cuts.ply, ...),
// refused on the next run or segmented as inputs by another batch. A user's
// file of such a name, in a folder without a batch's marker, stays a shape.
TEST(Manifest, APatternOrAFolderLeavesOutWhatABatchWrote) {
    TempDir dir;
    touch(dir / "data" / "a" / "shape.off");
    touch(dir / "data" / "user" / "labels.nrrd");
    writeBytes(dir / "data" / "user" / "done.json", "{}");  // not a batch's marker
    const fs::path outputs = dir / "data" / "res" / "shape";
    for (const char* name : {"labels.nrrd", "cuts.ply", "segments.ply", "levels/0/labels.nrrd"})
        touch(outputs / name);
    DoneMarker marker;
    marker.input = dir / "data" / "a" / "shape.off";
    marker.options = "{}";
    writeDoneMarker(outputs, marker);
    writeBytes(dir / "list.txt", "data/*/*\ndata/res/shape/levels/*\n");
    const Manifest m = readManifest(dir / "list.txt");
    std::vector<fs::path> inputs;
    for (const auto& e : m.entries) inputs.push_back(e.input);
    EXPECT_EQ(inputs, (std::vector<fs::path>{dir / "data" / "a" / "shape.off",
                                             dir / "data" / "user" / "labels.nrrd"}));
    // The folders a pattern matched are not lines naming a folder.
    EXPECT_TRUE(m.listedFolders.empty());
    // A pending marker (a batch killed while redoing the input) is a batch's too.
    fs::rename(outputs / kDoneMarkerName, outputs / kPendingMarkerName);
    writeBytes(dir / "folder.txt", "data/res/shape\ndata/a\n");
    const Manifest folder = readManifest(dir / "folder.txt");
    ASSERT_EQ(folder.entries.size(), 1u);
    EXPECT_EQ(folder.entries[0].input, dir / "data" / "a" / "shape.off");
    EXPECT_EQ(folder.listedFolders.size(), 2u);
}

// `ls > list.txt` lists a shape named "#1.off" as it is; the line is a
// comment, and the shape was dropped without a word. A comment that only
// looks like a commented-out path ("#b.off" where b.off exists) says nothing.
TEST(Manifest, ACommentThatNamesAShapeIsSaidToBeOne) {
    TempDir dir;
    touch(dir / "#1.off");
    touch(dir / "b.off");
    writeBytes(dir / "list.txt", "#1.off\n#b.off\n# b.off\nb.off\n");
    const Manifest m = readManifest(dir / "list.txt");
    ASSERT_EQ(m.entries.size(), 1u);
    EXPECT_EQ(m.entries[0].input, dir / "b.off");
    EXPECT_EQ(m.warnings,
              std::vector<std::string>{(dir / "list.txt").string() +
                                       ":1: #1.off is a comment, though a shape of that name "
                                       "exists; write ./#1.off to segment it"});
    writeBytes(dir / "fixed.txt", "./#1.off\n");
    EXPECT_EQ(readManifest(dir / "fixed.txt").entries.at(0).input, dir / "#1.off");
}

// A JSON list of paths was half read: its lines in quotes without a comma
// were paths, the others missing files. Refused, as JSON lines are.
TEST(Manifest, AJsonListOfPathsIsNotAManifest) {
    TempDir dir;
    touch(dir / "a.off");
    touch(dir / "b.off");
    for (const std::string json :
         {"[\n  \"a.off\",\n  \"b.off\"\n]\n", "[\"a.off\", \"b.off\"]\n",
          "\xEF\xBB\xBF# made by a script\n{\"path\": \"a.off\"}\n{\"path\": \"b.off\"}\n"}) {
        writeBytes(dir / "list.json", json);
        const std::string message =
            thrownMessage<InputError>([&] { readManifest(dir / "list.json"); });
        EXPECT_NE(message.find("this looks like JSON, and a manifest is a text file with one "
                               "path per line"),
                  std::string::npos)
            << json << ": " << message;
    }
    // A pattern in brackets on the first line is a manifest's.
    writeBytes(dir / "list.txt", "[ab].off\n");
    EXPECT_EQ(readManifest(dir / "list.txt").entries.size(), 2u);
}

// `find . -name '*.off' | skelseg batch - -o OUT` said "-: no such file",
// `skelseg batch <(ls *.off) -o OUT` "/dev/fd/63: is not a regular file".
TEST(Manifest, StandardInputOrAPipeIsRefusedSayingToWriteAFile) {
    TempDir dir;
    ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
    const std::string advice =
        "; write the list to a file and give its path (a re-run and every shard read the "
        "manifest again)";
    EXPECT_EQ(thrownMessage<InputError>([&] { readManifest(dir / "fifo"); }),
              (dir / "fifo").string() + ": is a pipe or a device, not a file" + advice);
    EXPECT_EQ(thrownMessage<InputError>([&] { readManifest("/dev/null"); }),
              "/dev/null: is a pipe or a device, not a file" + advice);
    struct WorkingDirectory {
        fs::path before = fs::current_path();
        ~WorkingDirectory() { fs::current_path(before); }
    } restore;
    fs::current_path(dir.path());
    EXPECT_EQ(thrownMessage<InputError>([&] { readManifest("-"); }),
              "-: standard input is not read as a manifest" + advice);
    // A manifest named "-" is read.
    touch(dir / "a.off");
    writeBytes(dir / "-", "a.off\n");
    EXPECT_EQ(readManifest("-").entries.size(), 1u);
}

TEST(Manifest, DirectoryListsSupportedFilesByName) {
    TempDir dir;
    // Hidden files are left out as a shell's * leaves them: "._c.OFF" is the
    // resource fork a Mac writes beside c.OFF, and was a failed input.
    for (const char* name :
         {"c.OFF", "a.nrrd", "b.binvox", "readme.txt", "z.vdb", "m.nhdr", "._c.OFF", ".h.off"})
        touch(dir / "in" / name);
    fs::create_directories(dir / "in" / "sub.nrrd");  // a folder, not a file
    const Manifest m = readManifest(dir / "in");
    std::vector<std::string> names;
    for (const auto& e : m.entries) names.push_back(e.input.filename().string());
    EXPECT_EQ(names, (std::vector<std::string>{"a.nrrd", "b.binvox", "c.OFF", "m.nhdr", "z.vdb"}));
}

// A folder on a line was a failed input ("is a directory, not a file"),
// although the same folder given as the manifest was expanded.
TEST(Manifest, AFolderOnALineStandsForItsShapes) {
    TempDir dir;
    for (const char* name : {"b.off", "a.nrrd", "notes.txt"}) touch(dir / "chairs" / name);
    touch(dir / "chairs" / "deeper" / "c.off");  // not its subfolders
    touch(dir / "tables" / "a.off");
    fs::create_directories(dir / "empty");
    writeBytes(dir / "list.txt", "tables/a.off\nchairs\n\"empty\"\nchairs/b.off\n");
    const Manifest m = readManifest(dir / "list.txt");
    std::vector<std::string> inputs, names;
    std::vector<int> lines;
    for (const auto& e : m.entries) {
        inputs.push_back(e.input.lexically_relative(dir.path()).string());
        names.push_back(e.name);
        lines.push_back(e.line);
        EXPECT_TRUE(e.exists);
    }
    EXPECT_EQ(inputs, (std::vector<std::string>{"tables/a.off", "chairs/a.nrrd", "chairs/b.off"}));
    EXPECT_EQ(lines, (std::vector<int>{1, 2, 2}));
    EXPECT_EQ(names, (std::vector<std::string>{"tables-a", "chairs-a", "b"}));
    // The empty folder says so; chairs/b.off, listed again, is kept once.
    ASSERT_EQ(m.warnings.size(), 2u);
    EXPECT_EQ(m.warnings[0], (dir / "list.txt").string() + ":3: " + (dir / "empty").string() +
                                 " is a directory holding no supported input file; nothing to "
                                 "do for it");
    EXPECT_NE(m.warnings[1].find(":4: "), std::string::npos) << m.warnings[1];
    EXPECT_NE(m.warnings[1].find("is listed again (first on line 2)"), std::string::npos)
        << m.warnings[1];
    // A manifest whose only line is an empty folder lists no input.
    writeBytes(dir / "empty.txt", "empty\n");
    EXPECT_EQ(thrownMessage<InputError>([&] { readManifest(dir / "empty.txt"); }),
              (dir / "empty.txt").string() + ": the manifest lists no input");
}

// A manifest written by hand lists patterns as a shell would take them; a
// line "scans/*.off" was one missing file.
TEST(Manifest, AWildcardLineStandsForTheShapesItMatches) {
    TempDir dir;
    for (const char* name : {"a1.off", "a2.OBJ", "b.off", "a-notes.txt", "odd[1].off"})
        touch(dir / "in" / name);
    touch(dir / "in" / "sub" / "c.off");
    touch(dir / "in" / "sub2" / "d.ply");
    writeBytes(dir / "list.txt",
               "in/a*\nin/*.off\nin/sub*\nin/x*.ply\nin/odd[1].off\n\"in/b?.off\"\n");
    const Manifest m = readManifest(dir / "list.txt");
    std::vector<std::string> inputs;
    std::vector<int> lines;
    for (const auto& e : m.entries) {
        inputs.push_back(e.input.lexically_relative(dir / "in").string());
        lines.push_back(e.line);
        EXPECT_TRUE(e.exists) << e.input;
    }
    // By name within a line; a file matched again is kept once; a folder a
    // pattern matches stands for its shapes; "odd[1].off" exists, so it is
    // that file (line 2's pattern matched it first).
    EXPECT_EQ(inputs, (std::vector<std::string>{"a1.off", "a2.OBJ", "b.off", "odd[1].off",
                                                "sub/c.off", "sub2/d.ply"}));
    EXPECT_EQ(lines, (std::vector<int>{1, 1, 2, 2, 3, 3}));
    std::vector<std::string> nothing;
    for (const auto& warning : m.warnings)
        if (warning.find("matches no supported input file") != std::string::npos)
            nothing.push_back(warning);
    ASSERT_EQ(nothing.size(), 2u);
    EXPECT_EQ(nothing[0], (dir / "list.txt").string() + ":4: " + (dir / "in" / "x*.ply").string() +
                              " matches no supported input file; nothing to do for it");
    EXPECT_NE(nothing[1].find(":6: "), std::string::npos) << nothing[1];
    EXPECT_EQ(m.warnings.size(), 4u);  // and a1.off, odd[1].off listed again

    // The manifest's own folder is a name, not a pattern: "[1]" in it does
    // not turn a missing file into a pattern matching nothing.
    touch(dir / "set[1]" / "e.off");
    writeBytes(dir / "set[1]" / "list.txt", "*.off\nmissing.off\n");
    const Manifest inSet = readManifest(dir / "set[1]" / "list.txt");
    ASSERT_EQ(inSet.entries.size(), 2u);
    EXPECT_EQ(inSet.entries[0].input, dir / "set[1]" / "e.off");
    EXPECT_TRUE(inSet.entries[0].exists);
    EXPECT_EQ(inSet.entries[1].input, dir / "set[1]" / "missing.off");
    EXPECT_FALSE(inSet.entries[1].exists);
    EXPECT_TRUE(inSet.warnings.empty());
}

TEST(OutputNames, CollisionsGetFoldersThenACounter) {
    const std::vector<fs::path> inputs = {"chairs/1.off", "tables/1.off", "x/2.off",   "y/x/2.off",
                                          "3.off",        "3.obj",        "solo.nrrd", "3-2.off"};
    const auto names = uniqueOutputNames(inputs);
    EXPECT_EQ(names[0], "chairs-1");
    EXPECT_EQ(names[1], "tables-1");
    EXPECT_EQ(names[2], "x-2");
    EXPECT_EQ(names[3], "y-x-2");
    EXPECT_EQ(names[4], "3");
    EXPECT_EQ(names[5], "3-3");  // "3-2" belongs to another input
    EXPECT_EQ(names[6], "solo");
    EXPECT_EQ(names[7], "3-2");
    EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
}

TEST(OutputNames, TheBatchsOwnFileNamesGetACounter) {
    // OUTROOT/summary.json is the batch's file: a folder of that name could
    // not be made, and the input failed.
    const std::vector<fs::path> inputs = {"a/summary.json.off",
                                          "summary.csv.ply",
                                          "summary.shard-0-of-2.json.obj",
                                          "summary.off",
                                          "summary.shard-1-of-2.csv.stl",
                                          "summary.txt.off",
                                          ".summary.lock.off",
                                          ".summary.shard-0-of-2.lock.ply"};
    const auto names = uniqueOutputNames(inputs);
    EXPECT_EQ(names, (std::vector<std::string>{"summary.json-2", "summary.csv-2",
                                               "summary.shard-0-of-2.json-2", "summary",
                                               "summary.shard-1-of-2.csv-2", "summary.txt",
                                               ".summary.lock-2", ".summary.shard-0-of-2.lock-2"}));
}

TEST(OutputNames, NoNameIsLongerThanAFolderNameCanBe) {
    // A 251-byte stem (a 255-byte file name) in several folders:
    // "folder-stem" was over 255 bytes and the input failed with "File name
    // too long".
    const std::string stem(251, 'x');
    const std::string folder(200, 'p');
    const std::string accented = "a\xC3\xA9\xC3\xA9";  // a cut must not split a character
    const std::vector<fs::path> inputs = {
        fs::path(folder) / (stem + ".off"), fs::path("qq") / (stem + ".off"),
        fs::path(accented) / (stem + ".off"), fs::path("r") / "qq" / (stem + ".off")};
    const auto names = uniqueOutputNames(inputs);
    for (const auto& name : names) EXPECT_LE(name.size(), 255u) << name;
    EXPECT_EQ(names[0], "ppp-" + stem);  // the folder's name is cut, not the stem
    EXPECT_EQ(names[1], "qq-" + stem);
    EXPECT_EQ(names[2], "a\xC3\xA9-" + stem);
    EXPECT_EQ(names[3], "r-q-" + stem);  // "r-qq" cut
    EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
    // Cut names that become equal are told apart by the counter.
    std::vector<fs::path> many;
    for (int i = 0; i < 12; ++i)
        many.push_back(fs::path(std::string(240, 'd') + std::to_string(i)) / (stem + ".off"));
    const auto cut = uniqueOutputNames(many);
    EXPECT_EQ(std::set<std::string>(cut.begin(), cut.end()).size(), many.size());
    for (const auto& name : cut) EXPECT_LE(name.size(), 255u);
}

TEST(Shards, EveryInputInExactlyOneShardForOneToSevenShards) {
    std::mt19937 random(11);
    std::vector<std::uint64_t> sizes(41);
    for (auto& s : sizes) s = 1000 + random() % 200000;
    sizes[5] = sizes[6] = 0;  // missing files
    const std::uint64_t largest = *std::max_element(sizes.begin(), sizes.end());
    for (int n = 1; n <= 7; ++n) {
        SCOPED_TRACE("N = " + std::to_string(n));
        // The union over shards of each shard's share, as the shard processes compute it.
        std::vector<int> seen(sizes.size(), 0);
        std::vector<std::uint64_t> load(std::size_t(n), 0);
        for (int index = 0; index < n; ++index) {
            const std::vector<int> shardOf = assignShards(sizes, n);
            for (std::size_t i = 0; i < sizes.size(); ++i)
                if (shardOf[i] == index) {
                    ++seen[i];
                    load[std::size_t(index)] += sizes[i];
                }
        }
        for (std::size_t i = 0; i < sizes.size(); ++i) EXPECT_EQ(seen[i], 1) << "input " << i;
        const auto [lightest, heaviest] = std::minmax_element(load.begin(), load.end());
        EXPECT_GT(*lightest, 0u);
        // Largest-first greedy: no two shares differ by more than one input.
        EXPECT_LE(*heaviest - *lightest, largest);
    }
}

TEST(Shards, SplitIsDeterministicAndUsesOnlyTheSizes) {
    const std::vector<std::uint64_t> sizes = {5, 9, 9, 1, 7, 3, 3, 8};
    const auto first = assignShards(sizes, 3);
    EXPECT_EQ(first, assignShards(sizes, 3));
    // Equal sizes go to different shards, the earlier one to the lower index.
    EXPECT_EQ(first[1], 0);
    EXPECT_EQ(first[2], 1);
    EXPECT_THROW(assignShards(sizes, 0), UsageError);
    // More shards than inputs: each input alone, none twice.
    const auto wide = assignShards({4, 4, 4}, 5);
    EXPECT_EQ(std::set<int>(wide.begin(), wide.end()).size(), 3u);
}

TEST(Shards, AShareCountFarBeyondTheInputsCostsNoTablePerShare) {
    // `--shard 0/1000000000` on two inputs took three minutes and 16 GB (out
    // of memory, exit 4, under a smaller limit): a load per share. The k-th
    // largest input still goes to share k, as with a count just over the inputs.
    const std::vector<std::uint64_t> sizes = {5, 9, 0, 7};
    const std::vector<int> expected = {2, 0, 3, 1};
    EXPECT_EQ(assignShards(sizes, 5), expected);
    EXPECT_EQ(assignShards(sizes, 1000000000), expected);
    EXPECT_EQ(assignShards(sizes, std::numeric_limits<int>::max()), expected);
    EXPECT_TRUE(assignShards({}, 1000000000).empty());
}

TEST(Shards, SplitEqualsTheScanOfEveryShareOnTies) {
    // Every task of an array computes the split on its own, possibly with
    // another build of skelseg after a resubmission: the heap that picks the
    // least loaded share must pick the one the former scan of all shares
    // picked (least load, then fewest inputs, then lowest index).
    auto scanSplit = [](const std::vector<std::uint64_t>& sizes, std::size_t shares) {
        std::vector<std::size_t> order(sizes.size());
        std::iota(order.begin(), order.end(), std::size_t(0));
        std::stable_sort(order.begin(), order.end(),
                         [&](std::size_t a, std::size_t b) { return sizes[a] > sizes[b]; });
        const std::size_t weighed = std::max<std::size_t>(1, std::min(shares, sizes.size()));
        std::vector<std::uint64_t> load(weighed, 0);
        std::vector<std::size_t> count(weighed, 0);
        std::vector<int> shard(sizes.size(), 0);
        for (std::size_t i : order) {
            std::size_t best = 0;
            for (std::size_t s = 1; s < weighed; ++s)
                if (load[s] < load[best] || (load[s] == load[best] && count[s] < count[best]))
                    best = s;
            shard[i] = int(best);
            load[best] += sizes[i];
            ++count[best];
        }
        return shard;
    };
    std::mt19937 random(11);
    for (int trial = 0; trial < 40; ++trial) {
        // Few distinct sizes and zeros (missing files): many equal loads.
        std::vector<std::uint64_t> sizes(std::size_t(1 + random() % 300));
        for (auto& s : sizes) s = (random() % 4) * 1000 + (random() % 3 == 0 ? 0 : 7);
        const int shares = int(1 + random() % 80);
        SCOPED_TRACE(std::to_string(sizes.size()) + " inputs, " + std::to_string(shares) +
                     " shares");
        EXPECT_EQ(assignShards(sizes, shares), scanSplit(sizes, std::size_t(shares)));
    }
}

TEST(ShardSpec, ParsesIndexOfCount) {
    const ShardSpec spec = ShardSpec::parse("2/5");
    EXPECT_EQ(spec.index, 2);
    EXPECT_EQ(spec.count, 5);
    EXPECT_EQ(spec.summaryStem(), "summary.shard-2-of-5");
    EXPECT_EQ(ShardSpec::parse("0/1").summaryStem(), "summary");
    for (const char* bad : {"5/5", "-1/3", "1", "a/b", "1/0", "1/3x", "/3", "+1/3", "1 /3", " "})
        EXPECT_THROW(ShardSpec::parse(bad), UsageError) << bad;
    // Blanks around the value (a script's) either side: " 0/2" was taken
    // and "0/2 " refused.
    for (const char* padded : {" 1/2", "1/2 ", "\t1/2\n"})
        EXPECT_EQ(ShardSpec::parse(padded).toString(), "1/2") << padded;
}

TEST(ShardSpec, ComesFromSlurmOrKubernetes) {
    std::map<std::string, std::string> env;
    auto lookup = [&](const char* name) -> const char* {
        const auto found = env.find(name);
        return found == env.end() ? nullptr : found->second.c_str();
    };
    EXPECT_FALSE(shardFromEnvironment(lookup, 0).has_value());
    env = {{"SLURM_ARRAY_TASK_ID", "3"},
           {"SLURM_ARRAY_TASK_COUNT", "4"},
           {"SLURM_ARRAY_TASK_MIN", "0"},
           {"SLURM_ARRAY_TASK_MAX", "3"}};
    auto spec = shardFromEnvironment(lookup, 0);
    ASSERT_TRUE(spec);
    EXPECT_EQ(spec->index, 3);
    EXPECT_EQ(spec->count, 4);
    // --array=1-4: ids start at 1.
    env = {
        {"SLURM_ARRAY_TASK_ID", "1"}, {"SLURM_ARRAY_TASK_MIN", "1"}, {"SLURM_ARRAY_TASK_MAX", "4"}};
    spec = shardFromEnvironment(lookup, 0);
    ASSERT_TRUE(spec);
    EXPECT_EQ(spec->index, 0);
    EXPECT_EQ(spec->count, 4);
    // --array=0-6:2 -> ids 0 2 4 6.
    env = {{"SLURM_ARRAY_TASK_ID", "4"},
           {"SLURM_ARRAY_TASK_MIN", "0"},
           {"SLURM_ARRAY_TASK_MAX", "6"},
           {"SLURM_ARRAY_TASK_STEP", "2"}};
    spec = shardFromEnvironment(lookup, 0);
    ASSERT_TRUE(spec);
    EXPECT_EQ(spec->index, 2);
    EXPECT_EQ(spec->count, 4);
    env = {{"SLURM_ARRAY_TASK_ID", "7"}, {"SLURM_ARRAY_TASK_COUNT", "4"}};
    EXPECT_THROW(shardFromEnvironment(lookup, 0), UsageError);
    env = {{"SLURM_ARRAY_TASK_ID", "x"}, {"SLURM_ARRAY_TASK_COUNT", "4"}};
    EXPECT_THROW(shardFromEnvironment(lookup, 0), UsageError);
    // An array's variables without a task id ran the whole manifest.
    env = {{"SLURM_ARRAY_TASK_ID", ""}, {"SLURM_ARRAY_TASK_COUNT", "2"}};
    EXPECT_EQ(thrownMessage<UsageError>([&] { shardFromEnvironment(lookup, 0); }),
              "SLURM_ARRAY_TASK_ID is set but empty; pass --shard I/N");
    env = {{"SLURM_ARRAY_TASK_COUNT", "2"}};
    EXPECT_EQ(thrownMessage<UsageError>([&] { shardFromEnvironment(lookup, 0); }),
              "SLURM_ARRAY_TASK_COUNT is set but SLURM_ARRAY_TASK_ID is not; pass --shard I/N");
    env = {{"JOB_COMPLETION_INDEX", ""}};
    EXPECT_THROW(shardFromEnvironment(lookup, 3), UsageError);
    env = {{"JOB_COMPLETION_INDEX", "2"}};
    EXPECT_THROW(shardFromEnvironment(lookup, 0), UsageError);  // --shards missing
    spec = shardFromEnvironment(lookup, 3);
    ASSERT_TRUE(spec);
    EXPECT_EQ(spec->index, 2);
    EXPECT_EQ(spec->count, 3);
    EXPECT_THROW(shardFromEnvironment(lookup, 2), UsageError);
}

// A task id between two steps of the array (id 3 of --array=0-8:2) took the
// share of the id below it: ids 2 and 3 did share 1 and a share went undone.
TEST(ShardSpec, SlurmTaskIdBetweenTheArraysStepsIsRefused) {
    std::map<std::string, std::string> env = {{"SLURM_ARRAY_TASK_ID", "3"},
                                              {"SLURM_ARRAY_TASK_MIN", "0"},
                                              {"SLURM_ARRAY_TASK_MAX", "8"},
                                              {"SLURM_ARRAY_TASK_STEP", "2"}};
    auto lookup = [&](const char* name) -> const char* {
        const auto found = env.find(name);
        return found == env.end() ? nullptr : found->second.c_str();
    };
    try {
        shardFromEnvironment(lookup, 0);
        ADD_FAILURE() << "task 3 of 0-8:2 was given a share";
    } catch (const UsageError& error) {
        EXPECT_EQ(std::string(error.what()),
                  "SLURM_ARRAY_TASK_ID=3 is not on the array's steps (SLURM_ARRAY_TASK_MIN=0, "
                  "SLURM_ARRAY_TASK_STEP=2): the ids are MIN + k * STEP; pass --shard I/N");
    }
    // The ids on the steps keep their shares, from a MIN above 0 too.
    env["SLURM_ARRAY_TASK_ID"] = "8";
    const auto last = shardFromEnvironment(lookup, 0);
    ASSERT_TRUE(last);
    EXPECT_EQ(last->toString(), "4/5");
    env = {{"SLURM_ARRAY_TASK_ID", "7"},
           {"SLURM_ARRAY_TASK_MIN", "1"},
           {"SLURM_ARRAY_TASK_COUNT", "4"},
           {"SLURM_ARRAY_TASK_STEP", "3"}};
    const auto third = shardFromEnvironment(lookup, 0);
    ASSERT_TRUE(third);
    EXPECT_EQ(third->toString(), "2/4");
    env["SLURM_ARRAY_TASK_ID"] = "5";
    EXPECT_THROW(shardFromEnvironment(lookup, 0), UsageError);
}

// A spreadsheet's or a script's CSV: `path,label` with a header was every
// row a failed input (the whole line read as one path).
TEST(Manifest, ACsvManifestReadsItsPathColumn) {
    TempDir dir;
    touch(dir / "a.off");
    touch(dir / "my, shapes" / "b.nrrd");
    touch(dir / "c.obj");
    writeBytes(dir / "list.csv",
               "\xEF\xBB\xBF# exported\nlabel,Path,parts\r\ncat,a.off,4\r\n,,\r\n"
               "dog,\"my, shapes/b.nrrd\",5\r\n# ignored,c.obj\r\nfish,,2\r\nbird,c.obj\r\n");
    const Manifest m = readManifest(dir / "list.csv");
    ASSERT_EQ(m.entries.size(), 3u);
    EXPECT_EQ(m.entries[0].input, dir / "a.off");
    EXPECT_EQ(m.entries[0].line, 3);
    EXPECT_EQ(m.entries[1].input, dir / "my, shapes" / "b.nrrd");
    EXPECT_TRUE(m.entries[1].exists);
    EXPECT_EQ(m.entries[1].line, 5);
    EXPECT_EQ(m.entries[2].input, dir / "c.obj");
    EXPECT_EQ(m.entries[2].line, 8);
    ASSERT_EQ(m.warnings.size(), 1u);
    EXPECT_EQ(m.warnings[0],
              (dir / "list.csv").string() + ":7: no path in column 'Path'; row skipped");

    // An earlier batch's summary.csv lists its inputs in "input".
    fs::create_directories(dir / "old");
    writeBytes(dir / "old" / "summary.csv",
               "name,input,status,parts\na," + (dir / "a.off").string() + ",done,4\n");
    const Manifest again = readManifest(dir / "old" / "summary.csv");
    ASSERT_EQ(again.entries.size(), 1u);
    EXPECT_EQ(again.entries[0].input, dir / "a.off");

    // One path per line in a file named .csv is read as before.
    writeBytes(dir / "plain.csv", "a.off\nc.obj\n");
    EXPECT_EQ(readManifest(dir / "plain.csv").entries.size(), 2u);

    // Several columns, none of them named: refused on one line.
    writeBytes(dir / "unnamed.csv", "a.off,4\nc.obj,5\n");
    EXPECT_EQ(thrownMessage<InputError>([&] { readManifest(dir / "unnamed.csv"); }),
              (dir / "unnamed.csv").string() +
                  ": line 1: a CSV manifest's first line names its path column (path, input or "
                  "file); this one names none: a.off,4");
    writeBytes(dir / "unnamed.csv", "# exported\n\na.off,4\n");
    EXPECT_EQ(thrownMessage<InputError>([&] { readManifest(dir / "unnamed.csv"); }),
              (dir / "unnamed.csv").string() +
                  ": line 3: a CSV manifest's first line names its path column (path, input or "
                  "file); this one names none: a.off,4");
    // The same lines in a text manifest are paths with commas, as ever.
    touch(dir / "a.off,4");
    writeBytes(dir / "list.txt", "a.off,4\n");
    EXPECT_EQ(readManifest(dir / "list.txt").entries[0].input, dir / "a.off,4");
}
