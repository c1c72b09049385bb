#include "kernels/NarrowTunnels.h"

#include <array>
#include <cstdlib>

namespace skelseg {

namespace {

/// The 3x3x3 neighbourhood of a voxel as bits: bit (dz + 1) * 9 + (dy + 1) * 3
/// + (dx + 1); the voxel itself is bit 13.
constexpr int kCentre = 13;

struct NeighbourhoodTables {
    std::array<std::uint32_t, 27>
        touching26{};  // per bit: the bits it shares a face, edge or corner with
    std::array<std::uint32_t, 27> touching6{};  // per bit: the bits it shares a face with
    std::uint32_t within18 = 0;                 // the 18-neighbourhood, centre excluded
    std::uint32_t faces = 0;                    // the centre's six face neighbours

    NeighbourhoodTables() {
        const auto offset = [](int bit) {
            return std::array<int, 3>{bit % 3 - 1, (bit / 3) % 3 - 1, bit / 9 - 1};
        };
        for (int a = 0; a < 27; ++a) {
            const auto p = offset(a);
            const int fromCentre = std::abs(p[0]) + std::abs(p[1]) + std::abs(p[2]);
            if (a != kCentre && fromCentre <= 2) within18 |= 1u << a;
            if (fromCentre == 1) faces |= 1u << a;
            for (int b = 0; b < 27; ++b) {
                if (a == b) continue;
                const auto q = offset(b);
                const int dx = std::abs(p[0] - q[0]), dy = std::abs(p[1] - q[1]),
                          dz = std::abs(p[2] - q[2]);
                if (dx <= 1 && dy <= 1 && dz <= 1) touching26[std::size_t(a)] |= 1u << b;
                if (dx + dy + dz == 1) touching6[std::size_t(a)] |= 1u << b;
            }
        }
    }
};

const NeighbourhoodTables& tables() {
    static const NeighbourhoodTables t;
    return t;
}

/// The connected piece of `set` that holds bit `seed`.
std::uint32_t pieceOf(std::uint32_t set, int seed, const std::array<std::uint32_t, 27>& touching) {
    std::uint32_t piece = 1u << seed, frontier = piece;
    while (frontier) {
        std::uint32_t grown = 0;
        for (std::uint32_t bits = frontier; bits; bits &= bits - 1)
            grown |= touching[std::size_t(__builtin_ctz(bits))];
        frontier = grown & set & ~piece;
        piece |= frontier;
    }
    return piece;
}

/// Bits of the 3x3x3 neighbourhood of (x, y, z) that are object voxels
/// (the voxel must not lie on the grid's outermost layer).
std::uint32_t objectBits(const MaskVolume& mask, int x, int y, int z) {
    std::uint32_t bits = 0;
    int bit = 0;
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy) {
            const std::uint8_t* row = &mask(x - 1, y + dy, z + dz);
            for (int dx = 0; dx < 3; ++dx, ++bit)
                if (row[dx]) bits |= 1u << bit;
        }
    return bits;
}

bool closesTunnel(std::uint32_t object) {
    const NeighbourhoodTables& t = tables();
    object &= ~(1u << kCentre);
    if (!(object & t.faces)) return false;
    // T26 = 1: the object voxels around are one piece.
    if (pieceOf(object, __builtin_ctz(object), t.touching26) != object) return false;
    // T6 >= 2: the background within the 18-neighbourhood that touches a
    // face of the centre falls into two or more pieces.
    const std::uint32_t background = ~object & t.within18;
    std::uint32_t faceBackground = background & t.faces;
    if (!faceBackground) return false;
    const std::uint32_t first = pieceOf(background, __builtin_ctz(faceBackground), t.touching6);
    return (faceBackground & ~first) != 0;
}

}  // namespace

bool closesNarrowTunnel(const MaskVolume& mask, int x, int y, int z) {
    if (mask(x, y, z)) return false;
    return closesTunnel(objectBits(mask, x, y, z));
}

std::vector<std::size_t> closeNarrowTunnels(MaskVolume& mask, Interrupter& interrupter) {
    std::vector<std::size_t> closed;
    const Dims d = mask.dims();
    for (int z = 1; z + 1 < d.z; ++z) {
        if (interrupter.wasInterrupted(double(z) / d.z)) {
            for (std::size_t i : closed) mask[i] = 0;
            throwIfInterrupted(interrupter);
        }
        for (int y = 1; y + 1 < d.y; ++y) {
            const std::uint8_t* row = &mask(0, y, z);
            for (int x = 1; x + 1 < d.x; ++x) {
                // Only background voxels with an object voxel beside them
                // (the face test of closesTunnel, read cheaply first).
                if (row[x] || !(row[x - 1] | row[x + 1] | mask(x, y - 1, z) | mask(x, y + 1, z) |
                                mask(x, y, z - 1) | mask(x, y, z + 1)))
                    continue;
                if (!closesTunnel(objectBits(mask, x, y, z))) continue;
                mask(x, y, z) = 1;
                closed.push_back(mask.index(x, y, z));
            }
        }
    }
    return closed;
}

}  // namespace skelseg
