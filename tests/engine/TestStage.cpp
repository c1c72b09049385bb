// Stage: one name for the timer and the interrupter, on every path; the
// progress display announces a kernel's scope inside a Stage of the same
// name once.
#include "engine/Stage.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/ProgressReporter.h"

using namespace skelseg;

namespace {

class RecordingInterrupter final : public Interrupter {
public:
    void start(const char* name) override { started.push_back(name); }
    void end() override { ++ended; }
    std::vector<std::string> started;
    int ended = 0;
};

std::string readAll(std::FILE* file) {
    std::rewind(file);
    std::string text;
    char buffer[256];
    while (std::fgets(buffer, sizeof buffer, file)) text += buffer;
    return text;
}

}  // namespace

TEST(Stage, TimesAndAnnouncesUnderOneName) {
    StageTimer timer;
    RecordingInterrupter interrupter;
    {
        Stage stage(timer, interrupter, "boundary graph", true);
        ASSERT_EQ(interrupter.started, std::vector<std::string>{"boundary graph"});
        EXPECT_EQ(interrupter.ended, 0);
    }
    EXPECT_EQ(interrupter.ended, 1);
    { Stage again(timer, interrupter, "boundary graph", true); }
    const std::vector<StageTiming> timings = timer.timings();
    ASSERT_EQ(timings.size(), 1u);
    EXPECT_EQ(timings[0].name, "boundary graph");
    EXPECT_TRUE(timings[0].parallel);
    EXPECT_EQ(timings[0].calls, 2);
    EXPECT_GE(timings[0].wallSeconds, 0.0);
}

TEST(Stage, EndsAndCountsWhenTheStageThrows) {
    StageTimer timer;
    RecordingInterrupter interrupter;
    EXPECT_THROW(
        {
            Stage stage(timer, interrupter, "labelling", false);
            throw std::runtime_error("stop");
        },
        std::runtime_error);
    EXPECT_EQ(interrupter.ended, 1);
    const std::vector<StageTiming> timings = timer.timings();
    ASSERT_EQ(timings.size(), 1u);
    EXPECT_EQ(timings[0].name, "labelling");
    EXPECT_FALSE(timings[0].parallel);
    EXPECT_EQ(timings[0].calls, 1);
}

TEST(Stage, ProgressLinesNameANestedKernelScopeOnce) {
    std::FILE* stream = std::tmpfile();
    ASSERT_NE(stream, nullptr);
    {
        ProgressReporter progress(ProgressReporter::Display::Lines, 0.0, stream);
        StageTimer timer;
        {
            Stage stage(timer, progress, "feature transform", true);
            InterrupterScope kernel(progress, "feature transform");
        }
        Stage next(timer, progress, "boundary graph", true);
    }
    const std::string text = readAll(stream);
    std::fclose(stream);
    auto count = [&](const std::string& what) {
        std::size_t n = 0;
        for (std::size_t at = text.find(what); at != std::string::npos;
             at = text.find(what, at + 1))
            ++n;
        return n;
    };
    EXPECT_EQ(count("skelseg: feature transform ("), 1u) << text;
    EXPECT_EQ(count("skelseg: boundary graph ("), 1u) << text;
}
