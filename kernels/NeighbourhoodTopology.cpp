#include "kernels/NeighbourhoodTopology.h"

#include <array>
#include <cstdlib>

namespace skelseg {

namespace {

struct NeighbourhoodTables {
    std::array<std::uint32_t, 27>
        touching26{};  // per bit: the bits it shares a face, edge or corner with
    std::array<std::uint32_t, 27> touching6{};  // per bit: the bits it shares a face with
    std::uint32_t within26 = 0;                 // the 26-neighbourhood, centre excluded
    std::uint32_t within18 = 0;                 // the 18-neighbourhood, centre excluded
    std::uint32_t faces = 0;                    // the centre's six face neighbours

    NeighbourhoodTables() {
        const auto offset = [](int bit) {
            return std::array<int, 3>{bit % 3 - 1, (bit / 3) % 3 - 1, bit / 9 - 1};
        };
        for (int a = 0; a < 27; ++a) {
            const auto p = offset(a);
            const int fromCentre = std::abs(p[0]) + std::abs(p[1]) + std::abs(p[2]);
            if (a != kNeighbourhoodCentre) within26 |= 1u << a;
            if (a != kNeighbourhoodCentre && fromCentre <= 2) within18 |= 1u << a;
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

/// The pieces of `set` (connected by `touching`) that hold a bit of `seeds`.
int piecesHolding(std::uint32_t set, std::uint32_t seeds,
                  const std::array<std::uint32_t, 27>& touching) {
    int pieces = 0;
    while (seeds) {
        seeds &= ~pieceOf(set, __builtin_ctz(seeds), touching);
        ++pieces;
    }
    return pieces;
}

}  // namespace

std::uint32_t neighbourhoodBits(const MaskVolume& mask, int x, int y, int z) {
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

std::uint32_t faceNeighbourBits() {
    return tables().faces;
}

int objectPieces26(std::uint32_t bits) {
    const NeighbourhoodTables& t = tables();
    const std::uint32_t object = bits & t.within26;
    return piecesHolding(object, object, t.touching26);
}

int backgroundPieces6(std::uint32_t bits) {
    const NeighbourhoodTables& t = tables();
    const std::uint32_t background = ~bits & t.within18;
    return piecesHolding(background, background & t.faces, t.touching6);
}

}  // namespace skelseg
