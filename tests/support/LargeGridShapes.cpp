#include "tests/support/LargeGridShapes.h"

#include "io/shapes/SyntheticShapes.h"

namespace skelseg::test {

MaskVolume figureInALargeGrid() {
    const MaskVolume figure = rasterise(makeShape("figure"), {64, 2});
    constexpr int kSide = 160;
    MaskVolume grid(Dims{kSide, kSide, kSide}, 0);
    grid.geometry = figure.geometry;
    const Dims d = figure.dims();
    const int ox = (kSide - d.x) / 2, oy = (kSide - d.y) / 2, oz = (kSide - d.z) / 2;
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) grid(ox + x, oy + y, oz + z) = figure(x, y, z);
    return grid;
}

}  // namespace skelseg::test
