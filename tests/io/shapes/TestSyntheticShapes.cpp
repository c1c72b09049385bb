#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "io/shapes/SyntheticShapes.h"

namespace skelseg {
namespace {

using Vec = std::array<double, 3>;

bool inAnyPrimitive(const Shape& shape, const Vec& p) {
    const auto& primitives = shape.primitives();
    return std::any_of(primitives.begin(), primitives.end(),
                       [&](const ShapePrimitive& s) { return primitiveContains(s, p); });
}

// Shape::contains tests each primitive's box before the primitive: the box
// must never be what decides. Every voxel centre of every named shape in
// every pose, rasterised finely enough to put centres on and beside its
// surfaces, gets the answer of the primitives themselves.
TEST(SyntheticShapes, ContainsIsTheUnionOfThePrimitivesAtEveryVoxelOfEveryShape) {
    for (const std::string& name : shapeNames())
        for (int pose = 0; pose <= 2; ++pose) {
            const Shape shape = makeShape(name, pose);
            const MaskVolume mask = rasterise(shape, {40, 2});
            std::size_t inside = 0;
            for (int z = 0; z < mask.dims().z; ++z)
                for (int y = 0; y < mask.dims().y; ++y)
                    for (int x = 0; x < mask.dims().x; ++x) {
                        const Vec centre = mask.geometry.indexToWorld(x, y, z);
                        const bool expected = inAnyPrimitive(shape, centre);
                        ASSERT_EQ(mask(x, y, z) != 0, expected)
                            << name << " pose " << pose << " voxel " << x << "," << y << "," << z;
                        inside += expected ? 1 : 0;
                    }
            EXPECT_GT(inside, 0u) << name << " pose " << pose;
        }
}

// The points a box test could lose are those on a primitive's extremes:
// each primitive's outermost points along each axis, which lie exactly on
// its box, are contained, also when the coordinates are far from 0.
TEST(SyntheticShapes, APrimitivesOutermostPointsAreContained) {
    for (const double offset : {0.0, 0.1, -3.7, 1e6 + 0.3}) {
        const Vec c{offset + 0.3, offset - 0.7, offset + 1.9};
        Shape sphere, ellipsoid, capsule, cylinder, box, torus;
        sphere.sphere(c, 0.7);
        ellipsoid.ellipsoid(c, {0.3, 1.1, 0.9});
        capsule.capsule(c, {c[0] + 2.0, c[1], c[2]}, 0.6);
        cylinder.cylinder(c, {c[0], c[1], c[2] + 2.5}, 0.45);
        box.box(c, {0.4, 0.8, 1.2});
        torus.torus(c, {0.0, 0.0, 1.0}, 1.5, 0.25);
        const std::array<std::pair<const Shape*, std::array<Vec, 2>>, 6> cases{{
            {&sphere, {Vec{c[0] + 0.7, c[1], c[2]}, Vec{c[0], c[1] - 0.7, c[2]}}},
            {&ellipsoid, {Vec{c[0] - 0.3, c[1], c[2]}, Vec{c[0], c[1] + 1.1, c[2]}}},
            {&capsule, {Vec{c[0] + 2.6, c[1], c[2]}, Vec{c[0] + 1.0, c[1], c[2] - 0.6}}},
            {&cylinder, {Vec{c[0] + 0.45, c[1], c[2] + 1.0}, Vec{c[0], c[1], c[2] + 2.5}}},
            {&box, {Vec{c[0] + 0.4, c[1] - 0.8, c[2] + 1.2}, Vec{c[0] - 0.4, c[1], c[2]}}},
            {&torus, {Vec{c[0] + 1.75, c[1], c[2]}, Vec{c[0], c[1] - 1.5, c[2] + 0.25}}},
        }};
        for (const auto& [shape, points] : cases)
            for (const Vec& p : points)
                EXPECT_EQ(shape->contains(p), inAnyPrimitive(*shape, p))
                    << "offset " << offset << " point " << p[0] << "," << p[1] << "," << p[2];
        // Beyond the box, nothing.
        EXPECT_FALSE(sphere.contains({c[0] + 0.71, c[1], c[2]}));
    }
}

}  // namespace
}  // namespace skelseg
