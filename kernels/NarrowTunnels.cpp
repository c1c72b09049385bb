#include "kernels/NarrowTunnels.h"

#include "kernels/NeighbourhoodTopology.h"

namespace skelseg {

namespace {

bool closesTunnel(std::uint32_t neighbourhood) {
    if (!(neighbourhood & faceNeighbourBits())) return false;
    // T26 = 1 (the object voxels around are one piece) and T6 >= 2 (the
    // background touching a face of the centre falls into two or more).
    return objectPieces26(neighbourhood) == 1 && backgroundPieces6(neighbourhood) >= 2;
}

}  // namespace

bool closesNarrowTunnel(const MaskVolume& mask, int x, int y, int z) {
    if (mask(x, y, z)) return false;
    return closesTunnel(neighbourhoodBits(mask, x, y, z));
}

std::vector<std::size_t> closeNarrowTunnels(MaskVolume& mask, Interrupter& interrupter) {
    std::vector<std::size_t> closed;
    const Dims d = mask.dims();
    for (int z = 1; z + 1 < d.z; ++z) {
        if (interrupter.wasInterrupted(double(z) / d.z)) {
            for (std::size_t i : closed) mask[i] = 0;
            throwInterrupted(interrupter);
        }
        for (int y = 1; y + 1 < d.y; ++y) {
            const std::uint8_t* row = &mask(0, y, z);
            for (int x = 1; x + 1 < d.x; ++x) {
                // Only background voxels with an object voxel beside them
                // (the face test of closesTunnel, read cheaply first).
                if (row[x] || !(row[x - 1] | row[x + 1] | mask(x, y - 1, z) | mask(x, y + 1, z) |
                                mask(x, y, z - 1) | mask(x, y, z + 1)))
                    continue;
                if (!closesTunnel(neighbourhoodBits(mask, x, y, z))) continue;
                mask(x, y, z) = 1;
                closed.push_back(mask.index(x, y, z));
            }
        }
    }
    return closed;
}

}  // namespace skelseg
