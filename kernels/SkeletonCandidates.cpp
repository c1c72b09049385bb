#include "kernels/SkeletonCandidates.h"

#include <algorithm>
#include <atomic>

#include "kernels/FeatureTransform.h"
#include "kernels/base/HugePages.h"
#include "kernels/base/ParallelFor.h"

namespace skelseg {

std::uint32_t extendedFeatureSet(const MaskVolume& mask,
                                 const Volume<std::uint32_t>& featureTransform,
                                 const BoundaryGraph& graph, int x, int y, int z,
                                 std::array<std::uint32_t, 8>& out) {
    std::uint32_t count = 0;
    for (int dz = 0; dz <= 1; ++dz)
        for (int dy = 0; dy <= 1; ++dy)
            for (int dx = 0; dx <= 1; ++dx) {
                const int qx = x + dx, qy = y + dy, qz = z + dz;
                if (!mask.contains(qx, qy, qz)) continue;
                const std::size_t q = mask.index(qx, qy, qz);
                if (!mask[q]) continue;
                const std::uint32_t f = featureTransform[q];
                if (f == kNoFeature) continue;
                const std::uint32_t node = graph.nodeOfVoxel[f];
                if (node == kNoNode) continue;
                bool seen = false;
                for (std::uint32_t i = 0; i < count; ++i) seen |= out[i] == node;
                if (!seen) out[count++] = node;
            }
    std::sort(out.begin(), out.begin() + count);
    return count;
}

std::vector<SkeletonCandidate> selectSkeletonCandidates(
    const MaskVolume& mask, const Volume<std::uint32_t>& featureTransform,
    const BoundaryGraph& graph, const CandidateOptions& options, CandidateStats* stats,
    Interrupter& interrupter) {
    InterrupterScope scope(interrupter, "skeleton candidates");
    const Dims d = mask.dims();
    const std::uint32_t nx = std::uint32_t(d.x), ny = std::uint32_t(d.y);
    std::vector<std::vector<SkeletonCandidate>> perSlice(std::size_t(d.z));
    std::atomic<std::uint64_t> objectVoxels{0}, withThree{0};
    std::atomic<bool> stop{false};
    const double minGap2 = options.minimumGap * options.minimumGap;
    const double ratio2 = options.gapRatio * options.gapRatio;

    auto slice = [&](int z) {
        if (stop.load(std::memory_order_relaxed)) return;
        if (interrupter.wasInterrupted(double(z) / d.z)) {
            stop = true;
            return;
        }
        std::uint64_t objects = 0, three = 0;
        auto& out = perSlice[std::size_t(z)];
        SkeletonCandidate c;
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) {
                const std::size_t p = mask.index(x, y, z);
                if (!mask[p]) continue;
                ++objects;
                const std::uint32_t n =
                    extendedFeatureSet(mask, featureTransform, graph, x, y, z, c.feature);
                if (n < 3) continue;
                ++three;
                // squaredDistance(d, p, fp) with p's coordinates known.
                const std::uint32_t fp = featureTransform[p];
                double depth2 = 0.0;
                if (fp != kNoFeature) {
                    const std::uint32_t fyz = fp / nx;
                    const std::int64_t dx = std::int64_t(fp - fyz * nx) - x,
                                       dy = std::int64_t(fyz % ny) - y,
                                       dz = std::int64_t(fyz / ny) - z;
                    depth2 = double(dx * dx + dy * dy + dz * dz);
                }
                const double threshold2 = std::max(ratio2 * depth2, minGap2);
                double maxGap2 = 0.0;
                for (std::uint32_t i = 0; i < n; ++i)
                    for (std::uint32_t j = i + 1; j < n; ++j) {
                        const Coord a = graph.coord[c.feature[i]], b = graph.coord[c.feature[j]];
                        const double dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
                        maxGap2 = std::max(maxGap2, dx * dx + dy * dy + dz * dz);
                    }
                if (maxGap2 <= threshold2) continue;
                c.voxel = std::uint32_t(p);
                c.featureCount = std::uint8_t(n);
                out.push_back(c);
            }
        objectVoxels += objects;
        withThree += three;
    };
    parallelForEach(d.z, slice, options.threaded);
    if (stop) throwInterrupted(interrupter);

    std::vector<SkeletonCandidate> all;
    std::size_t total = 0;
    for (const auto& s : perSlice) total += s.size();
    reserveWithHugePages(all, total);
    for (auto& s : perSlice) all.insert(all.end(), s.begin(), s.end());
    if (stats) {
        stats->objectVoxels = objectVoxels;
        stats->withThreeFeatures = withThree;
        stats->candidates = all.size();
    }
    return all;
}

}  // namespace skelseg
