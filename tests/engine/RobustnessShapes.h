// Checks shared by the degenerate-shape tests (TestRobustnessShapes.cpp,
// SlowRobustness.cpp): a successful run wrote every output, and report.json
// and labels.nrrd agree with each other and with the input.
#pragma once

#include <set>

#include "tests/engine/RobustnessHelpers.h"

namespace skelseg::test {

/// Lines of stderr that are warnings ("skelseg: warning: ...").
inline std::vector<std::string> warningLines(const CliResult& result) {
    std::vector<std::string> warnings;
    for (const auto& line : result.errLines())
        if (line.rfind("skelseg: warning: ", 0) == 0) warnings.push_back(line);
    return warnings;
}

/// Checks a successful volume run on `mask` into `outdir` and returns its report:
///  - exit 0, every output file present, no staging directory left;
///  - labels.nrrd has the input's size; background voxels are 0, every object
///    voxel carries a label listed in report.json;
///  - the segments' voxel counts add up to the object voxels, and per label
///    match labels.nrrd;
///  - segment_count is the number of segments; every line on stderr is a warning.
inline nlohmann::json expectConsistentVolumeRun(const CliResult& result, const std::filesystem::path& outdir,
                                                const MaskVolume& mask) {
    EXPECT_EQ(result.exitCode, 0) << result.describe();
    EXPECT_EQ(warningLines(result).size(), result.errLines().size()) << result.describe();
    for (const char* name :
         {"labels.nrrd", "labels.vdb", "skeleton.ply", "cuts.ply", "segments.ply", "preview.png", "report.json"})
        EXPECT_TRUE(std::filesystem::exists(outdir / name)) << name << " missing; " << result.describe();
    for (const auto& entry : directoryEntries(outdir))
        EXPECT_EQ(entry.rfind(".skelseg-staging", 0), std::string::npos) << "staging directory left behind";
    if (!std::filesystem::exists(outdir / "report.json")) return {};

    const nlohmann::json report = readReport(outdir);
    EXPECT_EQ(report["status"], "ok");
    EXPECT_EQ(report["segment_count"].get<std::size_t>(), report["segments"].size());
    const LabelVolume labels = readNrrdLabels(outdir / "labels.nrrd");
    EXPECT_EQ(labels.dims(), mask.dims());
    if (labels.dims() != mask.dims()) return report;

    std::map<std::uint32_t, std::uint64_t> reported;
    std::uint64_t reportedTotal = 0;
    for (const auto& segment : report["segments"]) {
        const auto id = segment["id"].get<std::uint32_t>();
        EXPECT_TRUE(reported.emplace(id, segment["voxels"].get<std::uint64_t>()).second) << "label " << id << " twice";
        reportedTotal += segment["voxels"].get<std::uint64_t>();
    }
    std::map<std::uint32_t, std::uint64_t> counted;
    std::uint64_t objectVoxels = 0, unlabelled = 0, labelledBackground = 0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (mask[i]) {
            ++objectVoxels;
            if (labels[i] == 0) ++unlabelled;
            else ++counted[labels[i]];
        } else if (labels[i] != 0) {
            ++labelledBackground;
        }
    }
    EXPECT_EQ(unlabelled, 0u) << "object voxels without a label";
    EXPECT_EQ(labelledBackground, 0u) << "background voxels with a label";
    EXPECT_EQ(reportedTotal, objectVoxels);
    EXPECT_EQ(counted, reported) << "labels.nrrd and report.json disagree";
    EXPECT_EQ(report["counts"]["object_voxels"].get<std::uint64_t>(), objectVoxels);
    return report;
}

}  // namespace skelseg::test
