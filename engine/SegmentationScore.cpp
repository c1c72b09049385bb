#include "engine/SegmentationScore.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "kernels/base/Error.h"

namespace skelseg {

namespace {

/// Segment labels renumbered 0..K-1 in order of first appearance.
std::vector<std::uint32_t> compactLabels(const std::vector<std::int64_t>& labels,
                                         std::size_t& segmentCount) {
    std::unordered_map<std::int64_t, std::uint32_t> numbers;
    std::vector<std::uint32_t> compact(labels.size());
    for (std::size_t f = 0; f < labels.size(); ++f)
        compact[f] = numbers.emplace(labels[f], std::uint32_t(numbers.size())).first->second;
    segmentCount = numbers.size();
    return compact;
}

/// Summed weight of a set of faces and of its squares: enough for the
/// weight of the pairs inside it.
struct SetWeight {
    double sum = 0.0, sumOfSquares = 0.0;
    void add(double w) noexcept {
        sum += w;
        sumOfSquares += w * w;
    }
    /// Weight of the unordered pairs of distinct faces: C(n, 2) for unit weights.
    double pairs() const noexcept { return 0.5 * (sum * sum - sumOfSquares); }
};

struct Cell {
    SetWeight pairWeight;  // Rand Index weights
    double overlap = 0.0;  // Hamming weights
};

void checkWeights(const std::vector<double>& weights, std::size_t faceCount) {
    if (weights.size() != faceCount)
        throw UsageError("face areas: " + std::to_string(weights.size()) + " values for " +
                         std::to_string(faceCount) + " faces");
    for (std::size_t f = 0; f < weights.size(); ++f)
        if (!(std::isfinite(weights[f]) && weights[f] >= 0.0))
            throw UsageError("face areas: face " + std::to_string(f) +
                             " has a negative or non-finite area");
}

/// One pass over the faces: Rand Index with randWeights, Hamming measures
/// with hammingWeights (null = unit weight).
PartitionScore score(const std::vector<std::int64_t>& candidate,
                     const std::vector<std::int64_t>& reference,
                     const std::vector<double>* randWeights,
                     const std::vector<double>* hammingWeights) {
    const std::size_t faceCount = candidate.size();
    std::size_t candidateSegments = 0, referenceSegments = 0;
    const std::vector<std::uint32_t> s1 = compactLabels(candidate, candidateSegments);
    const std::vector<std::uint32_t> s2 = compactLabels(reference, referenceSegments);

    // Contingency table: only the non-empty cells, at most one per face.
    std::unordered_map<std::uint64_t, Cell> cells;
    cells.reserve(std::min<std::size_t>(faceCount, candidateSegments * referenceSegments));
    std::vector<SetWeight> rows(candidateSegments), columns(referenceSegments);
    SetWeight all;
    double totalOverlap = 0.0;
    for (std::size_t f = 0; f < faceCount; ++f) {
        const double randWeight = randWeights ? (*randWeights)[f] : 1.0;
        const double hammingWeight = hammingWeights ? (*hammingWeights)[f] : 1.0;
        Cell& cell = cells[(std::uint64_t(s1[f]) << 32) | s2[f]];
        cell.pairWeight.add(randWeight);
        cell.overlap += hammingWeight;
        rows[s1[f]].add(randWeight);
        columns[s2[f]].add(randWeight);
        all.add(randWeight);
        totalOverlap += hammingWeight;
    }
    if (!(all.sum > 0.0) || !(totalOverlap > 0.0))
        throw UsageError("face areas: all faces have zero area");

    PartitionScore result;
    // Rand Index error: pairs together in exactly one of the two partitions.
    double together1 = 0.0, together2 = 0.0, togetherBoth = 0.0;
    for (const SetWeight& row : rows) together1 += row.pairs();
    for (const SetWeight& column : columns) together2 += column.pairs();
    std::vector<double> bestInRow(candidateSegments, 0.0), bestInColumn(referenceSegments, 0.0);
    for (const auto& [key, cell] : cells) {
        togetherBoth += cell.pairWeight.pairs();
        const std::uint32_t row = std::uint32_t(key >> 32),
                            column = std::uint32_t(key & 0xFFFFFFFFu);
        bestInRow[row] = std::max(bestInRow[row], cell.overlap);
        bestInColumn[column] = std::max(bestInColumn[column], cell.overlap);
    }
    const double allPairs = all.pairs();
    result.randIndexError =
        allPairs > 0.0 ? std::max(0.0, together1 + together2 - 2.0 * togetherBoth) / allPairs : 0.0;

    // D_H(S1 => S2) = sum over reference segments of what their best
    // candidate match misses; D_H(S2 => S1) the other way round.
    double matchedReference = 0.0, matchedCandidate = 0.0;
    for (double best : bestInColumn) matchedReference += best;
    for (double best : bestInRow) matchedCandidate += best;
    result.missingRate = std::max(0.0, totalOverlap - matchedReference) / totalOverlap;
    result.falseAlarmRate = std::max(0.0, totalOverlap - matchedCandidate) / totalOverlap;
    result.hammingDistance = 0.5 * (result.missingRate + result.falseAlarmRate);
    return result;
}

}  // namespace

PartitionScore comparePartitions(const std::vector<std::int64_t>& candidate,
                                 const std::vector<std::int64_t>& reference,
                                 const std::vector<double>* faceAreas, ScoreWeighting weighting) {
    if (candidate.size() != reference.size())
        throw UsageError("segmentations differ in size: " + std::to_string(candidate.size()) +
                         " and " + std::to_string(reference.size()) + " faces");
    if (candidate.empty()) throw UsageError("segmentations without faces cannot be compared");
    if (faceAreas) checkWeights(*faceAreas, candidate.size());
    const std::vector<double>* areas = weighting == ScoreWeighting::Faces ? nullptr : faceAreas;
    const std::vector<double>* randWeights = weighting == ScoreWeighting::Areas ? areas : nullptr;
    return score(candidate, reference, randWeights, areas);
}

ScoreSummary scoreAgainstHumans(const std::vector<std::int64_t>& candidate,
                                const std::vector<std::vector<std::int64_t>>& humans,
                                const std::vector<double>* faceAreas, ScoreWeighting weighting) {
    if (humans.empty()) throw UsageError("no human segmentation to score against");
    ScoreSummary summary;
    for (const auto& human : humans) {
        summary.perHuman.push_back(comparePartitions(candidate, human, faceAreas, weighting));
        const PartitionScore& s = summary.perHuman.back();
        summary.mean.randIndexError += s.randIndexError;
        summary.mean.hammingDistance += s.hammingDistance;
        summary.mean.missingRate += s.missingRate;
        summary.mean.falseAlarmRate += s.falseAlarmRate;
    }
    const double count = double(humans.size());
    summary.mean.randIndexError /= count;
    summary.mean.hammingDistance /= count;
    summary.mean.missingRate /= count;
    summary.mean.falseAlarmRate /= count;
    return summary;
}

}  // namespace skelseg
