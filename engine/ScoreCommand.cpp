#include "engine/ScoreCommand.h"

#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "engine/SegmentationScore.h"
#include "io/mesh/MeshCheck.h"
#include "io/mesh/MeshIO.h"
#include "io/mesh/SegFile.h"
#include "kernels/base/Error.h"

namespace skelseg {

namespace {

std::vector<std::int64_t> readSegFor(const std::filesystem::path& path, std::size_t faceCount) {
    std::vector<std::int64_t> labels = readSeg(path);
    if (labels.size() != faceCount)
        throw InputError(path.string(), "has " + std::to_string(labels.size()) +
                                            " labels but the mesh has " +
                                            std::to_string(faceCount) + " faces");
    return labels;
}

nlohmann::json scoreJson(const PartitionScore& score) {
    return {{"rand_index_error", score.randIndexError},
            {"hamming_distance", score.hammingDistance},
            {"missing_rate", score.missingRate},
            {"false_alarm_rate", score.falseAlarmRate}};
}

}  // namespace

int runScoreCommand(const std::filesystem::path& meshPath,
                    const std::filesystem::path& candidatePath,
                    const std::vector<std::filesystem::path>& humanPaths, bool json,
                    std::ostream& out) {
    if (humanPaths.empty()) throw UsageError("score: give at least one human segmentation file");
    const TriangleMesh mesh = readMesh(meshPath);
    const std::vector<double> areas = faceAreas(mesh);
    // The benchmark weights faces by area: a mesh without any cannot be scored.
    if (std::none_of(areas.begin(), areas.end(), [](double area) { return area > 0.0; }))
        throw InputError(meshPath.string(),
                         noFaceHasArea(mesh.faceCount) + "; the scores weight faces by area");
    const std::vector<std::int64_t> candidate = readSegFor(candidatePath, mesh.faceCount);
    std::vector<std::vector<std::int64_t>> humans;
    for (const auto& path : humanPaths) humans.push_back(readSegFor(path, mesh.faceCount));
    const ScoreSummary summary =
        scoreAgainstHumans(candidate, humans, &areas, ScoreWeighting::Benchmark);

    if (json) {
        nlohmann::json document;
        document["mesh"] = meshPath.string();
        document["candidate"] = candidatePath.string();
        document["faces"] = mesh.faceCount;
        document["weighting"] = "benchmark";
        nlohmann::json perHuman = nlohmann::json::array();
        for (std::size_t h = 0; h < humanPaths.size(); ++h) {
            nlohmann::json entry = scoreJson(summary.perHuman[h]);
            entry["file"] = humanPaths[h].string();
            perHuman.push_back(std::move(entry));
        }
        document["humans"] = std::move(perHuman);
        document["mean"] = scoreJson(summary.mean);
        out << document.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
        return 0;
    }

    // A row per file: a name's newline would break the table.
    out << fmt::format("{} ({} faces) scored against {} human segmentation(s)\n",
                       escapeControlCharacters(candidatePath.string()), mesh.faceCount,
                       humanPaths.size());
    out << "Rand Index error over faces; Hamming distance weighted by face area (as the Princeton "
           "benchmark)\n";
    out << fmt::format("{:<40} {:>10} {:>10} {:>10} {:>10}\n", "human", "rand_err", "hamming",
                       "missing", "false_al");
    for (std::size_t h = 0; h < humanPaths.size(); ++h) {
        const PartitionScore& s = summary.perHuman[h];
        out << fmt::format("{:<40} {:>10.4f} {:>10.4f} {:>10.4f} {:>10.4f}\n",
                           escapeControlCharacters(humanPaths[h].filename().string()),
                           s.randIndexError, s.hammingDistance, s.missingRate, s.falseAlarmRate);
    }
    const PartitionScore& m = summary.mean;
    out << fmt::format("{:<40} {:>10.4f} {:>10.4f} {:>10.4f} {:>10.4f}\n", "mean", m.randIndexError,
                       m.hammingDistance, m.missingRate, m.falseAlarmRate);
    return 0;
}

}  // namespace skelseg
