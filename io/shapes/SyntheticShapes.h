// skelseg: synthetic test shapes, rasterised from unions of simple solids.
//
// The scene tests, the benchmarks and the README's example run on shapes the
// project makes itself, so they need no data files. A shape is a union of
// primitives (spheres, ellipsoids, capsules, rounded/chamfered boxes,
// cylinders, tori) in model units; rasterising it at `size` makes its longest
// side span size - 2*margin voxels. Named shapes (shapeNames()):
//   disc-limbs   a flat disc with three thin limbs in its plane   (4 parts)
//   y-arms       three equally thick arms meeting at 120 degrees (3 parts)
//   t-body       a thick body with one thin limb                  (2 parts)
//   slab         a flat rectangular slab                          (1 part)
//   box-tubes    a chamfered box with three attached tubes        (4 parts)
//   torus-limb   a torus with one limb                            (2 parts)
//   figure       body, head on a neck, two arms, two legs; pose 0..2
//   capsule, cylinder, sphere, box, torus   single solids
//   capsule-chain three capsules end to end, two narrowings (1 part; 3 with joints)
//   bent-tube     a uniform tube with one 90 degree bend    (1 part; 2 with joints)
//   bent-capsule-chain  the capsule chain flexed by 45 degrees at both waists
//                       (1 part; 3 with joints)
// The limb shapes take a pose too: 0 along the grid axes, 1 and 2 oblique.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/base/Volume.h"

namespace skelseg {

struct ShapePrimitive {
    enum class Kind { Sphere, Ellipsoid, Capsule, Box, Cylinder, Torus } kind = Kind::Sphere;
    std::array<double, 3> a{}, b{};  // centre / segment ends / box half sizes (b) ...
    double radius = 0.0;   // sphere, capsule, cylinder radius; torus tube radius; box rounding
    double radius2 = 0.0;  // torus ring radius; box chamfer
    std::array<double, 3> axes{};  // ellipsoid semi-axes; torus normal
};

/// Whether `p` lies in the primitive `s` (its boundary included).
bool primitiveContains(const ShapePrimitive& s, const std::array<double, 3>& p);

class Shape {
public:
    Shape& sphere(std::array<double, 3> centre, double radius);
    Shape& ellipsoid(std::array<double, 3> centre, std::array<double, 3> semiAxes);
    Shape& capsule(std::array<double, 3> from, std::array<double, 3> to, double radius);
    Shape& cylinder(std::array<double, 3> from, std::array<double, 3> to, double radius);
    /// Axis-aligned box; `chamfer` cuts its edges at 45 degrees by that length.
    Shape& box(std::array<double, 3> centre, std::array<double, 3> halfSize, double chamfer = 0.0);
    /// Torus around `centre` with ring radius `ringRadius` and tube radius
    /// `tubeRadius`, ring in the plane normal to `normal` (unit vector).
    Shape& torus(std::array<double, 3> centre, std::array<double, 3> normal, double ringRadius,
                 double tubeRadius);

    /// Whether `p` lies in any primitive: primitiveContains of each, after
    /// a test against the primitive's box (widened by far more than a
    /// rounding error, so that it never decides alone).
    bool contains(const std::array<double, 3>& p) const;
    /// Bounding box (min, max) of the union.
    std::array<std::array<double, 3>, 2> bounds() const;
    const std::vector<ShapePrimitive>& primitives() const { return mPrimitives; }

private:
    void add(const ShapePrimitive& primitive);

    std::vector<ShapePrimitive> mPrimitives;
    std::vector<std::array<std::array<double, 3>, 2>> mBoxes;  // per primitive, a little widened
};

struct RasterOptions {
    int size = 128;  // voxels along the longest side, margins included
    int margin = 3;  // empty voxels around the shape
};

/// Rasterises `shape`: a voxel is inside when its centre is. Geometry maps
/// voxel centres back to model units.
MaskVolume rasterise(const Shape& shape, const RasterOptions& options);

/// Names accepted by makeShape().
std::vector<std::string> shapeNames();
/// A named shape (see the list above). pose selects the figure's pose or the
/// limb shapes' orientation (0..2).
/// Throws UsageError for unknown names.
Shape makeShape(const std::string& name, int pose = 0);

/// Flips `fraction` of the boundary voxels of `mask` (object <-> background
/// by removing boundary voxels and adding background voxels next to the
/// boundary in equal numbers), deterministically from `seed`.
void addBoundaryNoise(MaskVolume& mask, double fraction, std::uint64_t seed);

}  // namespace skelseg
