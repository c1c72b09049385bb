#include "io/mesh/FaceLabelNesting.h"

#include <algorithm>
#include <array>

#include "kernels/base/Error.h"

namespace skelseg {

namespace {

/// Faces sharing an edge, as CSR (offset per face into neighbour).
struct FaceAdjacency {
    std::vector<std::uint32_t> offset, neighbour;
};

FaceAdjacency faceAdjacency(const TriangleMesh& mesh) {
    // (smaller vertex, larger vertex, face) per triangle edge; runs of one
    // edge connect their faces.
    std::vector<std::array<std::uint32_t, 3>> edges;
    edges.reserve(mesh.triangles.size() * 3);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int i = 0; i < 3; ++i) {
            const std::uint32_t a = mesh.triangles[t][i], b = mesh.triangles[t][(i + 1) % 3];
            edges.push_back({std::min(a, b), std::max(a, b), mesh.triangleFace[t]});
        }
    std::sort(edges.begin(), edges.end());
    std::vector<std::array<std::uint32_t, 2>> pairs;
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && edges[j][0] == edges[i][0] && edges[j][1] == edges[i][1]) ++j;
        for (std::size_t p = i; p < j; ++p)
            for (std::size_t q = i; q < j; ++q)
                if (edges[p][2] != edges[q][2]) pairs.push_back({edges[p][2], edges[q][2]});
        i = j;
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    FaceAdjacency adjacency;
    adjacency.offset.assign(mesh.faceCount + 1, 0);
    for (const auto& p : pairs) ++adjacency.offset[p[0] + 1];
    for (std::size_t f = 0; f < mesh.faceCount; ++f) adjacency.offset[f + 1] += adjacency.offset[f];
    for (const auto& p : pairs) adjacency.neighbour.push_back(p[1]);
    return adjacency;
}

}  // namespace

std::size_t nestFaceLabels(const TriangleMesh& mesh, std::vector<std::uint32_t>& fine,
                           const std::vector<std::uint32_t>& coarse,
                           const std::vector<std::uint16_t>& parentLabel,
                           const std::vector<std::uint16_t>& fallbackChild) {
    const std::size_t faceCount = mesh.faceCount;
    if (fine.size() != faceCount || coarse.size() != faceCount)
        throw UsageError("nestFaceLabels: the labels do not match the mesh's faces");
    auto parentOf = [&](std::uint32_t label) {
        if (label == 0 || label > parentLabel.size())
            throw UsageError("nestFaceLabels: fine label " + std::to_string(label) +
                             " has no parent");
        return std::uint32_t(parentLabel[label - 1u]);
    };
    std::vector<std::uint8_t> pending(faceCount, 0);
    std::size_t changed = 0;
    for (std::size_t f = 0; f < faceCount; ++f)
        if (fine[f] && coarse[f] && parentOf(fine[f]) != coarse[f]) pending[f] = 1, ++changed;
    if (!changed) return 0;

    const FaceAdjacency adjacency = faceAdjacency(mesh);
    std::vector<std::uint32_t> candidates, next(fine);
    for (bool progress = true; progress;) {
        progress = false;
        for (std::size_t f = 0; f < faceCount; ++f) {
            if (!pending[f]) continue;
            candidates.clear();
            for (std::uint32_t e = adjacency.offset[f]; e < adjacency.offset[f + 1]; ++e) {
                const std::uint32_t g = adjacency.neighbour[e];
                if (!pending[g] && fine[g] && parentOf(fine[g]) == coarse[f])
                    candidates.push_back(fine[g]);
            }
            if (candidates.empty()) continue;
            std::sort(candidates.begin(), candidates.end());
            std::uint32_t best = candidates[0];
            std::size_t bestCount = 0;
            for (std::size_t i = 0; i < candidates.size();) {
                std::size_t j = i;
                while (j < candidates.size() && candidates[j] == candidates[i]) ++j;
                if (j - i > bestCount) bestCount = j - i, best = candidates[i];
                i = j;
            }
            next[f] = best;
        }
        // Apply the round at once, so the result does not depend on face order.
        for (std::size_t f = 0; f < faceCount; ++f)
            if (pending[f] && next[f] != fine[f] && parentOf(next[f]) == coarse[f])
                fine[f] = next[f], pending[f] = 0, progress = true;
    }
    for (std::size_t f = 0; f < faceCount; ++f) {
        if (!pending[f]) continue;
        if (coarse[f] == 0 || coarse[f] > fallbackChild.size() || !fallbackChild[coarse[f] - 1u])
            throw UsageError("nestFaceLabels: coarse label " + std::to_string(coarse[f]) +
                             " has no child");
        fine[f] = fallbackChild[coarse[f] - 1u];
    }
    return changed;
}

std::vector<std::uint32_t> renumberFaceLabels(const std::vector<std::uint32_t>& voxelLabels) {
    std::vector<std::uint32_t> used(voxelLabels);
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    used.erase(std::remove(used.begin(), used.end(), 0u), used.end());
    std::vector<std::uint32_t> out(voxelLabels.size(), 0);
    for (std::size_t f = 0; f < voxelLabels.size(); ++f)
        if (voxelLabels[f])
            out[f] = std::uint32_t(std::lower_bound(used.begin(), used.end(), voxelLabels[f]) -
                                   used.begin());
    return out;
}

}  // namespace skelseg
