#include "io/files/OutputDirectory.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/TempDir.h"

namespace skelseg {
namespace {

namespace fs = std::filesystem;

std::set<std::string> entries(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
    return names;
}

TEST(OutputDirectory, ConcurrentWritersAllGetCommitted) {
    // The output flow graph stages files from several threads at once.
    test::TempDir tmp;
    const fs::path outdir = tmp / "out";
    constexpr int kThreads = 8, kFilesPerThread = 200;
    {
        OutputDirectory out(outdir, false, {"labels.nrrd"});
        std::vector<std::thread> threads;
        for (int t = 0; t < kThreads; ++t)
            threads.emplace_back([&out, t] {
                for (int i = 0; i < kFilesPerThread; ++i) {
                    const std::string name = "f" + std::to_string(t) + "_" + std::to_string(i);
                    // Each name twice: a repeated name is staged once.
                    out.stagingPath(name);
                    std::ofstream(out.stagingPath(name)) << name;
                }
            });
        for (auto& th : threads) th.join();
        out.commit();
    }
    const std::set<std::string> names = entries(outdir);
    EXPECT_EQ(names.size(), std::size_t(kThreads * kFilesPerThread));
    EXPECT_TRUE(names.count("f0_0"));
    EXPECT_TRUE(names.count("f7_199"));
}

TEST(OutputDirectory, NothingUnderAFinalNameWithoutCommit) {
    test::TempDir tmp;
    const fs::path outdir = tmp / "out";
    {
        OutputDirectory out(outdir, false, {"a.txt"});
        std::ofstream(out.stagingPath("a.txt")) << "half";
        EXPECT_FALSE(fs::exists(outdir / "a.txt"));
    }
    // Not committed: the directory this run created is gone again.
    EXPECT_FALSE(fs::exists(outdir));
}

TEST(OutputDirectory, EarlierResultsNeedForce) {
    test::TempDir tmp;
    const fs::path outdir = tmp / "out";
    fs::create_directories(outdir);
    std::ofstream(outdir / "a.txt") << "earlier";
    EXPECT_ANY_THROW(OutputDirectory(outdir, false, {"a.txt"}));
    {
        OutputDirectory out(outdir, true, {"a.txt"});
        std::ofstream(out.stagingPath("a.txt")) << "new";
        out.commit();
    }
    std::ifstream in(outdir / "a.txt");
    std::string text;
    in >> text;
    EXPECT_EQ(text, "new");
    EXPECT_EQ(entries(outdir), std::set<std::string>{"a.txt"});
}

TEST(OutputDirectory, StagedDirectoryReplacesTheEarlierOne) {
    test::TempDir tmp;
    const fs::path outdir = tmp / "out";
    fs::create_directories(outdir / "levels" / "5");
    std::ofstream(outdir / "levels" / "5" / "old.txt") << "earlier";
    {
        OutputDirectory out(outdir, true, {"levels"});
        const fs::path levels = out.stagingPath("levels");
        fs::create_directories(levels / "0");
        std::ofstream(levels / "0" / "a.txt") << "new";
        EXPECT_TRUE(fs::exists(outdir / "levels" / "5" / "old.txt")) << "replaced before commit";
        out.commit();
    }
    EXPECT_EQ(entries(outdir / "levels"), std::set<std::string>{"0"});
    EXPECT_TRUE(fs::exists(outdir / "levels" / "0" / "a.txt"));
}

TEST(OutputDirectory, ObsoleteOutputsGoOnlyOnCommit) {
    test::TempDir tmp;
    const fs::path outdir = tmp / "out";
    fs::create_directories(outdir / "levels" / "0");
    std::ofstream(outdir / "hierarchy.json") << "{}";
    {
        OutputDirectory out(outdir, true, {"a.txt", "levels", "hierarchy.json"});
        out.removeOnCommit("levels");
        out.removeOnCommit("hierarchy.json");
        std::ofstream(out.stagingPath("a.txt")) << "new";
        // Not committed (a failed run): the earlier outputs stay.
    }
    EXPECT_TRUE(fs::exists(outdir / "levels" / "0"));
    {
        OutputDirectory out(outdir, true, {"a.txt", "levels", "hierarchy.json"});
        out.removeOnCommit("levels");
        out.removeOnCommit("hierarchy.json");
        std::ofstream(out.stagingPath("a.txt")) << "new";
        out.commit();
    }
    EXPECT_EQ(entries(outdir), std::set<std::string>{"a.txt"});
}

}  // namespace
}  // namespace skelseg
