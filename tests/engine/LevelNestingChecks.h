// Checks shared by the scene tests of hierarchy runs (SceneLevels.cpp,
// SceneJointLevels.cpp): a finer level nests in the next coarser one, voxel
// by voxel through the parents, and (meshes) face by face in the written
// levels/k/segmentation.seg.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "engine/Segmenter.h"
#include "io/mesh/SegFile.h"
#include "io/volume/NrrdIO.h"
#include "tests/engine/RobustnessHelpers.h"
#include "tests/support/FileBytes.h"

namespace skelseg::test {

/// Every voxel's fine label maps to its coarse label through the parents;
/// every coarse segment has a child.
inline void expectNested(const LabelVolume& fine, const std::vector<std::uint16_t>& parentLabel,
                         std::size_t fineSegments, const LabelVolume& coarse,
                         std::size_t coarseSegments, const std::string& what) {
    ASSERT_EQ(fine.dims(), coarse.dims()) << what;
    ASSERT_EQ(parentLabel.size(), fineSegments) << what;
    std::vector<std::uint8_t> hasChild(coarseSegments + 1, 0);
    std::size_t mismatches = 0;
    for (std::size_t v = 0; v < fine.size(); ++v) {
        const std::uint16_t f = fine[v], c = coarse[v];
        if ((f == 0) != (c == 0)) {
            ++mismatches;
            continue;
        }
        if (!f) continue;
        ASSERT_LE(f, fineSegments) << what;
        if (parentLabel[f - 1u] != c) ++mismatches;
        hasChild[c] = 1;
    }
    EXPECT_EQ(mismatches, 0u) << what
                              << ": voxels whose fine segment is not inside their coarse one";
    for (std::size_t c = 1; c <= coarseSegments; ++c)
        EXPECT_TRUE(hasChild[c]) << what << ": coarse segment " << c << " has no child";
}

/// Every level of a result nests in the next coarser one (SegmentationResult's
/// level accessors, so a joint level with one tau is covered too).
inline void expectResultLevelsNest(const SegmentationResult& r, const std::string& what) {
    for (std::size_t k = 0; k + 1 < r.levelCount(); ++k) {
        const SegmentationLevel& level = r.finerLevels[k];
        expectNested(level.labels, level.parentLabel, level.segments.size(), r.levelLabels(k + 1),
                     r.levelSegments(k + 1).size(), what + " level " + std::to_string(k));
        EXPECT_GE(level.segments.size(), r.levelSegments(k + 1).size()) << what;
    }
}

/// hierarchy.json, levels/k/labels.nrrd and (meshes) levels/k/segmentation.seg
/// of a CLI run agree: parents map every voxel and every face. `taus`: the
/// levels' taus as hierarchy.json gives them, finest first.
inline void expectWrittenLevelsNest(const std::filesystem::path& out, bool isMesh,
                                    const std::vector<std::string>& taus) {
    const nlohmann::json hierarchy = nlohmann::json::parse(fileBytes(out / "hierarchy.json"));
    const nlohmann::json& levels = hierarchy["levels"];
    ASSERT_EQ(levels.size(), taus.size());
    for (std::size_t k = 0; k < taus.size(); ++k) EXPECT_EQ(levels[k]["tau"], taus[k]) << k;
    for (std::size_t k = 0; k + 1 < levels.size(); ++k) {
        const std::string what = out.string() + " level " + std::to_string(k);
        const LabelVolume fine = readNrrdLabels(out / "levels" / std::to_string(k) / "labels.nrrd");
        const LabelVolume coarse =
            readNrrdLabels(out / "levels" / std::to_string(k + 1) / "labels.nrrd");
        std::vector<std::uint16_t> parent;
        std::map<std::int64_t, std::int64_t> parentOfSegLabel;
        std::map<std::int64_t, std::int64_t> coarseSegLabelOfId;
        for (const nlohmann::json& s : levels[k + 1]["segments"])
            if (isMesh && !s["seg_label"].is_null())
                coarseSegLabelOfId[s["id"].get<std::int64_t>()] = s["seg_label"];
        for (const nlohmann::json& s : levels[k]["segments"]) {
            EXPECT_EQ(s["id"].get<std::size_t>(), parent.size() + 1) << what;
            parent.push_back(s["parent"].get<std::uint16_t>());
            if (isMesh && !s["seg_label"].is_null())
                parentOfSegLabel[s["seg_label"]] = coarseSegLabelOfId.at(s["parent"]);
        }
        EXPECT_EQ(levels[k]["segment_count"].get<std::size_t>(), parent.size());
        expectNested(fine, parent, parent.size(), coarse, levels[k + 1]["segment_count"], what);
        if (!isMesh) continue;
        const std::vector<std::int64_t> fineFaces =
            readSeg(out / "levels" / std::to_string(k) / "segmentation.seg");
        const std::vector<std::int64_t> coarseFaces =
            readSeg(out / "levels" / std::to_string(k + 1) / "segmentation.seg");
        ASSERT_EQ(fineFaces.size(), coarseFaces.size()) << what;
        std::size_t mismatches = 0;
        for (std::size_t f = 0; f < fineFaces.size(); ++f)
            mismatches += parentOfSegLabel.at(fineFaces[f]) != coarseFaces[f];
        EXPECT_EQ(mismatches, 0u) << what
                                  << ": faces whose fine segment is not in their coarse one";
    }
    const nlohmann::json& coarsest = levels.back();
    for (const nlohmann::json& s : coarsest["segments"]) EXPECT_TRUE(s["parent"].is_null());
}

}  // namespace skelseg::test
