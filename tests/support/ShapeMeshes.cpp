#include "tests/support/ShapeMeshes.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "io/render/SegmentSurfaces.h"

namespace skelseg::test {

TriangleMesh meshOfShape(const Shape& shape, const std::array<int, 3>& lo,
                         const std::array<int, 3>& hi) {
    // One empty voxel around the box so that every surface closes.
    const Dims dims{hi[0] - lo[0] + 3, hi[1] - lo[1] + 3, hi[2] - lo[2] + 3};
    LabelVolume labels(dims, 0);
    labels.geometry =
        VolumeGeometry::uniform(1.0, {double(lo[0] - 1), double(lo[1] - 1), double(lo[2] - 1)});
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x)
                if (shape.contains(
                        {double(x + lo[0] - 1), double(y + lo[1] - 1), double(z + lo[2] - 1)}))
                    labels(x, y, z) = 1;
    SegmentSurfaceOptions options;
    options.smoothingIterations = 0;
    const LabelledSurface surface = extractSegmentSurfaces(labels, options);
    TriangleMesh mesh;
    mesh.vertices = surface.vertices;
    mesh.triangles = surface.triangles;
    mesh.triangleFace.resize(mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) mesh.triangleFace[t] = std::uint32_t(t);
    mesh.faceCount = mesh.triangles.size();
    return mesh;
}

Shape figureWithHand(bool handOnHip) {
    Shape s;
    // Body faces at half-integers: x = -45.5 is the body's left side.
    s.box({0, 0, 0}, {45.5, 30.5, 72.5}, 9.0);
    s.capsule({0, 0, 60}, {0, 0, 95}, 12);  // neck
    s.sphere({0, 0, 122}, 30);              // head
    for (double sign : {-1.0, 1.0}) s.capsule({sign * 22, 0, -60}, {sign * 32, 0, -200}, 17);
    // Left arm, held away.
    s.capsule({36, 0, 50}, {88, 0, 5}, 13.5);
    s.capsule({88, 0, 5}, {110, 0, -35}, 13.5);
    s.box({114.5, 0, -45}, {6, 9, 12});
    // Right arm: elbow out; the hand's flat face at x = -46.5 leaves the
    // voxel column x = -46 empty between it and the body.
    s.capsule({-36, 0, 50}, {-88, 0, 5}, 13.5);
    if (handOnHip) {
        s.capsule({-88, 0, 5}, {-63, 0, -25}, 13.5);
        s.box({-52.5, 0, -25}, {6, 9, 12});
    } else {
        s.capsule({-88, 0, 5}, {-110, 0, -35}, 13.5);
        s.box({-114.5, 0, -45}, {6, 9, 12});
    }
    return s;
}

namespace {

/// meshOfShape over the bounding box of `shape`, one voxel wider.
TriangleMesh meshOverItsBounds(const Shape& shape) {
    const auto bounds = shape.bounds();
    std::array<int, 3> lo{}, hi{};
    for (std::size_t c = 0; c < 3; ++c) {
        lo[c] = int(std::floor(bounds[0][c])) - 1;
        hi[c] = int(std::ceil(bounds[1][c])) + 1;
    }
    return meshOfShape(shape, lo, hi);
}

}  // namespace

TriangleMesh figureMesh(bool handOnHip) {
    return meshOverItsBounds(figureWithHand(handOnHip));
}

TriangleMesh figureWithLegMesh(bool legFolded) {
    Shape s;
    s.box({0, 0, 0}, {45.5, 30.5, 72.5}, 9.0);
    s.capsule({0, 0, 60}, {0, 0, 95}, 12);
    s.sphere({0, 0, 122}, 30);
    s.capsule({-22, 0, -60}, {-32, 0, -200}, 17);
    for (double sign : {-1.0, 1.0}) {
        s.capsule({sign * 36, 0, 50}, {sign * 88, 0, 5}, 13.5);
        s.capsule({sign * 88, 0, 5}, {sign * 110, 0, -35}, 13.5);
        s.box({sign * 114.5, 0, -45}, {6, 9, 12});
    }
    if (legFolded) {
        // The thigh's top face at z = -73.5 leaves the layer z = -73 empty
        // under the body's bottom face (z = -72.5) but at the hip.
        s.box({22, -22, -86.5}, {13, 42, 13});
        s.capsule({22, 12, -60}, {22, 12, -86.5}, 11);
        s.capsule({22, -56, -86.5}, {26, -62, -200}, 13);
    } else {
        s.capsule({22, 0, -60}, {32, 0, -200}, 17);
    }
    return meshOverItsBounds(s);
}

TriangleMesh barsOnABase(int gap) {
    Shape s;
    // Fine voxel centres are integers, so faces lie at half-integers.
    const double left = -30.5, right = gap - 0.5;  // the left side, the right bar's inner face
    const double end = right + 30.0;
    s.box({0.5 * (left + end), 7.0, 0.0}, {0.5 * (end - left), 7.5, 30.5});
    s.box({-15.5, 127.0, 0.0}, {15.0, 112.5, 30.5});
    s.box({right + 15.0, 127.0, 0.0}, {15.0, 112.5, 30.5});
    return meshOfShape(s, {-32, -2, -32}, {32 + gap, 241, 32});
}

TriangleMesh reorderedTriangles(const TriangleMesh& mesh, unsigned seed) {
    std::vector<std::size_t> order(mesh.triangles.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::mt19937 random(seed);
    std::shuffle(order.begin(), order.end(), random);
    TriangleMesh out = mesh;
    for (std::size_t k = 0; k < order.size(); ++k) {
        const auto& t = mesh.triangles[order[k]];
        const std::size_t r = (k + seed) % 3;
        out.triangles[k] = {t[r], t[(r + 1) % 3], t[(r + 2) % 3]};
        if (!mesh.triangleFace.empty()) out.triangleFace[k] = mesh.triangleFace[order[k]];
    }
    return out;
}

}  // namespace skelseg::test
