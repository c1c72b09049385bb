#include "tests/support/SceneSupport.h"

#include <algorithm>

namespace skelseg::test {

SceneRun segmentShape(const std::string& name, int size, const SegmentationParameters& parameters,
                      int pose, double noise, std::uint64_t seed) {
    SceneRun run;
    run.mask = rasterise(makeShape(name, pose), {size, 3});
    if (noise > 0) addBoundaryNoise(run.mask, noise, seed);
    run.result = segmentVolume(run.mask, parameters);
    return run;
}

std::set<std::pair<int, int>> segmentAdjacency(const LabelVolume& labels) {
    std::set<std::pair<int, int>> pairs;
    const Dims d = labels.dims();
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) {
                const int a = labels(x, y, z);
                if (!a) continue;
                for (int dz = 0; dz <= 1; ++dz)
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx) {
                            if (dz == 0 && (dy < 0 || (dy == 0 && dx <= 0)))
                                continue;  // each pair once
                            if (!labels.contains(x + dx, y + dy, z + dz)) continue;
                            const int b = labels(x + dx, y + dy, z + dz);
                            if (b && b != a) pairs.insert({std::min(a, b), std::max(a, b)});
                        }
            }
    return pairs;
}

std::vector<int> degreeSequence(const std::set<std::pair<int, int>>& adjacency, int count) {
    std::vector<int> degree(std::size_t(count) + 1, 0);
    for (const auto& [a, b] : adjacency) ++degree[std::size_t(a)], ++degree[std::size_t(b)];
    degree.erase(degree.begin());
    std::sort(degree.begin(), degree.end());
    return degree;
}

std::array<double, 3> modelToVoxel(const VolumeGeometry& geometry,
                                   const std::array<double, 3>& model) {
    const double s = geometry.directions[0][0];
    return {(model[0] - geometry.origin[0]) / s, (model[1] - geometry.origin[1]) / s,
            (model[2] - geometry.origin[2]) / s};
}

}  // namespace skelseg::test
