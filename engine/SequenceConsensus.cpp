#include "engine/SequenceConsensus.h"

#include <algorithm>
#include <map>
#include <string>
#include <unordered_set>

#include "engine/SegmentationScore.h"
#include "kernels/base/Error.h"

namespace skelseg {

SequenceConsensus chooseSequenceConsensus(const std::vector<std::vector<std::int64_t>>& frameLabels,
                                          const std::vector<bool>& trusted) {
    const std::size_t frames = frameLabels.size();
    if (frames < 2) throw UsageError("a pose sequence needs at least two frames");
    const std::size_t faces = frameLabels.front().size();
    if (faces == 0) throw UsageError("a pose sequence needs faces");
    for (std::size_t f = 1; f < frames; ++f)
        if (frameLabels[f].size() != faces)
            throw UsageError("frame " + std::to_string(f + 1) + " has " +
                             std::to_string(frameLabels[f].size()) + " faces, frame 1 has " +
                             std::to_string(faces));
    if (!trusted.empty() && trusted.size() != frames)
        throw UsageError("trust is given for " + std::to_string(trusted.size()) +
                         " frames, the sequence has " + std::to_string(frames));

    SequenceConsensus result;
    const bool anyTrusted = std::find(trusted.begin(), trusted.end(), true) != trusted.end();
    result.voted.assign(frames, true);
    if (anyTrusted) result.voted = trusted;
    result.parts.resize(frames);
    for (std::size_t f = 0; f < frames; ++f)
        result.parts[f] =
            std::unordered_set<std::int64_t>(frameLabels[f].begin(), frameLabels[f].end()).size();

    result.pairErrors.assign(frames * frames, 0.0);
    double sum = 0.0;
    for (std::size_t a = 0; a < frames; ++a)
        for (std::size_t b = a + 1; b < frames; ++b) {
            const double error =
                comparePartitions(frameLabels[a], frameLabels[b], nullptr, ScoreWeighting::Faces)
                    .randIndexError;
            result.pairErrors[a * frames + b] = result.pairErrors[b * frames + a] = error;
            sum += error;
        }
    result.meanPairError = sum / double(frames * (frames - 1) / 2);
    result.meanErrorToOthers.resize(frames);
    for (std::size_t a = 0; a < frames; ++a) {
        double row = 0.0;
        for (std::size_t b = 0; b < frames; ++b) row += result.pairErrors[a * frames + b];
        result.meanErrorToOthers[a] = row / double(frames - 1);
    }

    std::map<std::size_t, std::size_t> framesWithParts;
    for (std::size_t f = 0; f < frames; ++f)
        if (result.voted[f]) ++framesWithParts[result.parts[f]];
    std::size_t mostFrames = 0;
    for (const auto& [parts, count] : framesWithParts) mostFrames = std::max(mostFrames, count);
    bool chosen = false;
    for (std::size_t f = 0; f < frames; ++f) {
        if (!result.voted[f] || framesWithParts[result.parts[f]] != mostFrames) continue;
        if (!chosen || result.meanErrorToOthers[f] < result.meanErrorToOthers[result.reference]) {
            result.reference = f;
            chosen = true;
        }
    }
    result.modalParts = result.parts[result.reference];
    return result;
}

}  // namespace skelseg
