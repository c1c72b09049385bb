#include "kernels/SeveredObjects.h"

#include <algorithm>
#include <cstdint>

#include "kernels/ConnectedObjects.h"
#include "kernels/DisjointSets.h"

namespace skelseg {

std::vector<bool> rejoinSeveredObjects(MaskVolume& mask, const std::vector<ClearedGroup>& cleared,
                                       const SeveredObjectsOptions& options,
                                       Interrupter& interrupter) {
    std::vector<bool> setBack(cleared.size(), false);
    if (cleared.empty() || mask.empty()) return setBack;
    ConnectedObjectsOptions objectOptions;
    objectOptions.threaded = options.threaded;
    const ConnectedObjects objects = findConnectedObjects(mask, objectOptions, interrupter);
    DisjointSets joined(objects.objects.size());
    std::vector<std::uint32_t> around;  // objects next to one group
    for (std::size_t g = 0; g < cleared.size(); ++g) {
        if ((g & 63) == 0) throwIfInterrupted(interrupter);
        around.clear();
        for (const auto& c : cleared[g])
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
                        if (!mask.contains(x, y, z) || !mask(x, y, z)) continue;
                        const std::uint32_t object = objects.componentAt(x, y, z);
                        if (object > 0) around.push_back(joined.find(object - 1));
                    }
        std::sort(around.begin(), around.end());
        around.erase(std::unique(around.begin(), around.end()), around.end());
        if (around.size() < 2) continue;
        // The group's voxels are 26-connected and touch each of these
        // objects: set back, it joins them all again.
        if (options.setBack)
            for (const auto& c : cleared[g]) mask(c[0], c[1], c[2]) = 1;
        for (std::size_t k = 1; k < around.size(); ++k) joined.unite(around[0], around[k]);
        setBack[g] = true;
    }
    return setBack;
}

}  // namespace skelseg
