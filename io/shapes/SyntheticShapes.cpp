#include "io/shapes/SyntheticShapes.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "kernels/BoundaryGraph.h"
#include "kernels/base/Error.h"

namespace skelseg {

namespace {

using Vec = std::array<double, 3>;

Eigen::Vector3d point(const Vec& p) {
    return {p[0], p[1], p[2]};
}

double segmentDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                       const Eigen::Vector3d& b) {
    const Eigen::Vector3d ab = b - a, ap = p - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0 ? std::clamp(ap.dot(ab) / len2, 0.0, 1.0) : 0.0;
    return (p - (a + t * ab)).norm();
}

/// `v` turned by `degrees` about +z.
Vec rotateZ(const Vec& v, double degrees) {
    const double angle = degrees * M_PI / 180.0, c = std::cos(angle), s = std::sin(angle);
    return {c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]};
}
Vec add(const Vec& a, const Vec& b) {
    const Eigen::Vector3d sum = point(a) + point(b);
    return {sum[0], sum[1], sum[2]};
}
Vec scale(const Vec& a, double k) {
    const Eigen::Vector3d scaled = point(a) * k;
    return {scaled[0], scaled[1], scaled[2]};
}

/// The box (min, max) that holds every point of `s`.
std::array<Vec, 2> primitiveBounds(const ShapePrimitive& s) {
    Vec lo = {1e300, 1e300, 1e300}, hi = {-1e300, -1e300, -1e300};
    auto grow = [&](Vec c, Vec h) {
        for (int i = 0; i < 3; ++i)
            lo[i] = std::min(lo[i], c[i] - h[i]), hi[i] = std::max(hi[i], c[i] + h[i]);
    };
    switch (s.kind) {
        case ShapePrimitive::Kind::Sphere:
            grow(s.a, {s.radius, s.radius, s.radius});
            break;
        case ShapePrimitive::Kind::Ellipsoid:
            grow(s.a, {std::abs(s.axes[0]), std::abs(s.axes[1]), std::abs(s.axes[2])});
            break;
        case ShapePrimitive::Kind::Capsule:
        case ShapePrimitive::Kind::Cylinder:
            grow(s.a, {s.radius, s.radius, s.radius});
            grow(s.b, {s.radius, s.radius, s.radius});
            break;
        case ShapePrimitive::Kind::Box:
            grow(s.a, {std::abs(s.b[0]), std::abs(s.b[1]), std::abs(s.b[2])});
            break;
        case ShapePrimitive::Kind::Torus: {
            const double r = s.radius + s.radius2;
            grow(s.a, {r, r, r});
            break;
        }
    }
    return {lo, hi};
}

}  // namespace

bool primitiveContains(const ShapePrimitive& s, const Vec& position) {
    const Eigen::Vector3d p = point(position), a = point(s.a);
    switch (s.kind) {
        case ShapePrimitive::Kind::Sphere:
            return (p - a).norm() <= s.radius;
        case ShapePrimitive::Kind::Ellipsoid: {
            double sum = 0;
            for (int i = 0; i < 3; ++i)
                sum += (p[i] - a[i]) * (p[i] - a[i]) / (s.axes[i] * s.axes[i]);
            return sum <= 1.0;
        }
        case ShapePrimitive::Kind::Capsule:
            return segmentDistance(p, a, point(s.b)) <= s.radius;
        case ShapePrimitive::Kind::Cylinder: {
            const Eigen::Vector3d ab = point(s.b) - a;
            const double len = ab.norm();
            const double t = (p - a).dot(ab) / (len * len);
            if (t < 0 || t > 1) return false;
            return (p - (a + t * ab)).norm() <= s.radius;
        }
        case ShapePrimitive::Kind::Box: {
            const Eigen::Vector3d d = (p - a).cwiseAbs();
            const Eigen::Vector3d halfSize = point(s.b);
            if (d[0] > halfSize[0] || d[1] > halfSize[1] || d[2] > halfSize[2]) return false;
            // Chamfer: cut each edge where the distances to two faces sum below c.
            const double c = s.radius2;
            if (c <= 0) return true;
            const Eigen::Vector3d m = halfSize - d;  // distance to each face pair
            return m[0] + m[1] >= c && m[1] + m[2] >= c && m[0] + m[2] >= c;
        }
        case ShapePrimitive::Kind::Torus: {
            const Eigen::Vector3d q = p - a, normal = point(s.axes);
            const double h = q.dot(normal);
            const double r = (q - h * normal).norm() - s.radius2;
            return r * r + h * h <= s.radius * s.radius;
        }
    }
    return false;
}

Shape& Shape::sphere(Vec centre, double radius) {
    ShapePrimitive p;
    p.kind = ShapePrimitive::Kind::Sphere, p.a = centre, p.radius = radius;
    add(p);
    return *this;
}
Shape& Shape::ellipsoid(Vec centre, Vec semiAxes) {
    ShapePrimitive p;
    p.kind = ShapePrimitive::Kind::Ellipsoid, p.a = centre, p.axes = semiAxes;
    add(p);
    return *this;
}
Shape& Shape::capsule(Vec from, Vec to, double radius) {
    ShapePrimitive p;
    p.kind = ShapePrimitive::Kind::Capsule, p.a = from, p.b = to, p.radius = radius;
    add(p);
    return *this;
}
Shape& Shape::cylinder(Vec from, Vec to, double radius) {
    ShapePrimitive p;
    p.kind = ShapePrimitive::Kind::Cylinder, p.a = from, p.b = to, p.radius = radius;
    add(p);
    return *this;
}
Shape& Shape::box(Vec centre, Vec halfSize, double chamfer) {
    ShapePrimitive p;
    p.kind = ShapePrimitive::Kind::Box, p.a = centre, p.b = halfSize, p.radius2 = chamfer;
    add(p);
    return *this;
}
Shape& Shape::torus(Vec centre, Vec normal, double ringRadius, double tubeRadius) {
    ShapePrimitive p;
    p.kind = ShapePrimitive::Kind::Torus, p.a = centre,
    p.axes = scale(normal, 1.0 / point(normal).norm());
    p.radius = tubeRadius, p.radius2 = ringRadius;
    add(p);
    return *this;
}

bool Shape::contains(const Vec& p) const {
    for (std::size_t k = 0; k < mPrimitives.size(); ++k) {
        // Most points of a shape's box lie outside most of its primitives:
        // six comparisons settle them before any distance is computed.
        const auto& box = mBoxes[k];
        if (p[0] < box[0][0] || p[1] < box[0][1] || p[2] < box[0][2] || p[0] > box[1][0] ||
            p[1] > box[1][1] || p[2] > box[1][2])
            continue;
        if (primitiveContains(mPrimitives[k], p)) return true;
    }
    return false;
}

void Shape::add(const ShapePrimitive& primitive) {
    auto box = primitiveBounds(primitive);
    // A point whose rounded distance is within reach can lie a rounding
    // error outside the exact box: widen it by far more than that.
    for (int i = 0; i < 3; ++i) {
        const double slack = 1e-9 * (1.0 + std::abs(box[0][i]) + std::abs(box[1][i]));
        box[0][i] -= slack, box[1][i] += slack;
    }
    mPrimitives.push_back(primitive);
    mBoxes.push_back(box);
}

std::array<Vec, 2> Shape::bounds() const {
    Vec lo = {1e300, 1e300, 1e300}, hi = {-1e300, -1e300, -1e300};
    for (const auto& s : mPrimitives) {
        const auto box = primitiveBounds(s);
        for (int i = 0; i < 3; ++i)
            lo[i] = std::min(lo[i], box[0][i]), hi[i] = std::max(hi[i], box[1][i]);
    }
    return {lo, hi};
}

MaskVolume rasterise(const Shape& shape, const RasterOptions& options) {
    if (shape.primitives().empty()) throw UsageError("shape has no primitives");
    if (options.size < 2 * options.margin + 4 || options.size > 2048)
        throw UsageError("shape size " + std::to_string(options.size) + " out of range [" +
                         std::to_string(2 * options.margin + 4) + ", 2048]");
    const auto [lo, hi] = shape.bounds();
    const double longest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    const double voxel = longest / double(options.size - 2 * options.margin);
    Dims dims;
    int* extent[3] = {&dims.x, &dims.y, &dims.z};
    Vec origin{};
    for (int i = 0; i < 3; ++i) {
        *extent[i] = int(std::ceil((hi[i] - lo[i]) / voxel)) + 2 * options.margin;
        origin[i] = lo[i] - (options.margin - 0.5) * voxel;  // centre of voxel 0
    }
    MaskVolume mask(dims, 0);
    mask.geometry = VolumeGeometry::uniform(voxel, origin);
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x)
                mask(x, y, z) = shape.contains(mask.geometry.indexToWorld(x, y, z)) ? 1 : 0;
    return mask;
}

std::vector<std::string> shapeNames() {
    return {"disc-limbs", "y-arms", "t-body",        "slab",      "box-tubes",
            "torus-limb", "figure", "capsule",       "cylinder",  "sphere",
            "box",        "torus",  "capsule-chain", "bent-tube", "bent-capsule-chain"};
}

namespace {

/// The limb shapes' orientations: pose 0 along the grid axes, 1 and 2
/// oblique to them (the joint thresholds must not depend on the grid).
Vec orient(const Vec& v, int pose) {
    if (pose < 0 || pose > 2) throw UsageError("pose must be 0, 1 or 2");
    if (pose == 0) return v;
    const Eigen::Vector3d axis = pose == 1 ? Eigen::Vector3d(0.3, 1.0, 0.2).normalized()
                                           : Eigen::Vector3d(1.0, -1.0, 1.0).normalized();
    const double degrees = pose == 1 ? 35.0 : 50.0;
    const Eigen::Vector3d r = Eigen::AngleAxisd(degrees * M_PI / 180.0, axis) * point(v);
    return {r.x(), r.y(), r.z()};
}

}  // namespace

Shape makeShape(const std::string& name, int pose) {
    Shape s;
    if (name == "disc-limbs") {
        s.cylinder({0, 0, -0.07}, {0, 0, 0.07}, 0.42);
        for (int i = 0; i < 3; ++i) {
            const Vec dir = rotateZ({1, 0, 0}, 90.0 + 120.0 * i);
            s.capsule(scale(dir, 0.3), scale(dir, 0.95), 0.075);
        }
    } else if (name == "y-arms") {
        for (int i = 0; i < 3; ++i)
            s.capsule({0, 0, 0}, scale(rotateZ({1, 0, 0}, 90.0 + 120.0 * i), 0.8), 0.13);
    } else if (name == "t-body") {
        s.capsule({-0.6, 0, 0}, {0.6, 0, 0}, 0.25);
        s.capsule({0, 0.1, 0}, {0, 0.85, 0}, 0.07);
    } else if (name == "slab") {
        s.box({0, 0, 0}, {0.6, 0.4, 0.08});
    } else if (name == "box-tubes") {
        s.box({0, 0, 0}, {0.32, 0.26, 0.22}, 0.08);
        s.cylinder({0.2, 0, 0}, {0.75, 0, 0}, 0.08);
        s.cylinder({0, 0.15, 0}, {0, 0.7, 0}, 0.08);
        s.cylinder({-0.1, 0, 0.1}, {-0.1, 0, 0.65}, 0.08);
    } else if (name == "torus-limb") {
        s.torus({0, 0, 0}, {0, 0, 1}, 0.42, 0.13);
        s.capsule({0.5, 0, 0}, {1.05, 0, 0}, 0.06);
    } else if (name == "figure") {
        if (pose < 0 || pose > 2) throw UsageError("figure pose must be 0, 1 or 2");
        // Limb angles (degrees from straight down) per pose: arms, legs.
        const double arm[3][2] = {{60, -60}, {100, -35}, {25, -140}};
        const double leg[3][2] = {{15, -15}, {35, -5}, {5, -40}};
        s.ellipsoid({0, 0, 0}, {0.22, 0.15, 0.35});   // body
        s.capsule({0, 0, 0.3}, {0, 0, 0.47}, 0.055);  // neck
        s.sphere({0, 0, 0.6}, 0.14);                  // head
        for (int side = 0; side < 2; ++side) {
            const double sign = side == 0 ? 1.0 : -1.0;
            const Vec shoulder = {sign * 0.14, 0, 0.2};
            const double a = arm[pose][side] * M_PI / 180.0;
            const Vec hand = add(shoulder, {std::sin(a) * 0.55, 0, -std::cos(a) * 0.55});
            s.capsule(shoulder, hand, 0.055);
            const Vec hip = {sign * 0.1, 0, -0.25};
            const double l = leg[pose][side] * M_PI / 180.0;
            const Vec foot = add(hip, {std::sin(l) * 0.6, 0, -std::cos(l) * 0.6});
            s.capsule(hip, foot, 0.07);
        }
    } else if (name == "capsule-chain") {
        // Three capsules end to end; where two meet, their end spheres
        // overlap and leave a waist of about 0.66 times their radius.
        const double r = 0.12, gap = 1.5 * r;
        const double ends[3][2] = {{-0.85, -0.85 + 0.5}, {-0.35 + gap, 0.35 - gap}, {0.35, 0.85}};
        for (const auto& e : ends)
            s.capsule(orient({e[0], 0, 0}, pose), orient({e[1], 0, 0}, pose), r);
    } else if (name == "bent-capsule-chain") {
        // The capsule chain flexed by 45 degrees at both waists, in a zigzag
        // in one plane, as a knee and an ankle flex: each capsule turns about
        // the centre of the end sphere it meets, so the two spheres of a
        // waist stay 1.5 r apart and the waist keeps its 0.66 r.
        const double r = 0.12, gap = 1.5 * r;
        const Vec straight = {1.0, 0.0, 0.0}, flexed = rotateZ(straight, 45.0);
        const Vec first = {-0.35, 0.0, 0.0}, second = add(first, scale(flexed, gap + 0.34));
        s.capsule(orient(add(first, scale(straight, -0.5)), pose), orient(first, pose), r);
        s.capsule(orient(add(first, scale(flexed, gap)), pose), orient(second, pose), r);
        s.capsule(orient(add(second, scale(straight, gap)), pose),
                  orient(add(second, scale(straight, gap + 0.5)), pose), r);
    } else if (name == "bent-tube") {
        // A uniform tube with one 90 degree bend in its middle.
        const double r = 0.1;
        const Vec corner = orient({0.0, 0.0, 0.0}, pose);
        s.capsule(orient({-0.7, 0.0, 0.0}, pose), corner, r);
        s.capsule(corner, orient({0.0, 0.7, 0.0}, pose), r);
    } else if (name == "capsule") {
        s.capsule({-0.6, 0, 0}, {0.6, 0, 0}, 0.15);
    } else if (name == "cylinder") {
        s.cylinder({-0.6, 0, 0}, {0.6, 0, 0}, 0.15);
    } else if (name == "sphere") {
        s.sphere({0, 0, 0}, 0.5);
    } else if (name == "box") {
        s.box({0, 0, 0}, {0.5, 0.35, 0.25});
    } else if (name == "torus") {
        s.torus({0, 0, 0}, {0, 0, 1}, 0.4, 0.12);
    } else {
        std::string list;
        for (const auto& n : shapeNames()) list += (list.empty() ? "" : ", ") + n;
        throw UsageError("unknown shape '" + name + "' (known: " + list + ")");
    }
    return s;
}

void addBoundaryNoise(MaskVolume& mask, double fraction, std::uint64_t seed) {
    // splitmix64: a tiny, fully specified generator, so the noise is the same
    // on every platform and standard library.
    auto next = [&seed]() {
        std::uint64_t z = (seed += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    };
    const MaskVolume boundary = boundaryVoxels(mask);
    const Dims d = mask.dims();
    std::vector<std::size_t> inner, outer;
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) {
                const std::size_t v = mask.index(x, y, z);
                if (boundary[v]) {
                    inner.push_back(v);
                    continue;
                }
                if (mask[v] || x == 0 || y == 0 || z == 0 || x == d.x - 1 || y == d.y - 1 ||
                    z == d.z - 1)
                    continue;
                const bool touches = mask(x - 1, y, z) || mask(x + 1, y, z) || mask(x, y - 1, z) ||
                                     mask(x, y + 1, z) || mask(x, y, z - 1) || mask(x, y, z + 1);
                if (touches) outer.push_back(v);
            }
    const std::size_t flips = std::size_t(double(inner.size()) * fraction);
    for (std::size_t i = 0; i < flips; ++i) {
        // Half the flips remove a boundary voxel, half add one outside.
        auto& pool = (i % 2 == 0) ? inner : outer;
        if (pool.empty()) continue;
        const std::size_t k = std::size_t(next() % pool.size());
        mask[pool[k]] = (&pool == &inner) ? 0 : 1;
        pool[k] = pool.back();
        pool.pop_back();
    }
}

}  // namespace skelseg
