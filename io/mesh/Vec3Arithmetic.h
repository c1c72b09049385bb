// skelseg: the few 3-vector operations the mesh kernels need on the
// std::array<double, 3> points that TriangleMesh stores (ContactSeparation,
// ContactPatchSeams, ThinPartFill), so that they work on the mesh's own
// storage without a copy into another vector type; and the point of a
// triangle nearest to a point.
#pragma once

#include <array>
#include <cmath>

namespace skelseg::vec3 {

using Vec3 = std::array<double, 3>;

inline Vec3 sub(const Vec3& a, const Vec3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}

inline double dot(const Vec3& a, const Vec3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

inline double distance(const Vec3& a, const Vec3& b) {
    return std::sqrt(dot(sub(a, b), sub(a, b)));
}

inline Vec3 along(const Vec3& a, const Vec3& d, double t) {
    return {a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]};
}

/// Point of triangle (a, b, c) nearest to p (Ericson, Real-Time Collision
/// Detection, 5.1.5: the Voronoi region of p decides vertex, edge or face).
inline Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const Vec3 bp = sub(p, b);
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return along(a, ab, d1 / (d1 - d3));
    const Vec3 cp = sub(p, c);
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return along(a, ac, d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return along(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const double denominator = va + vb + vc;
    if (!(denominator > 0)) return a;  // degenerate triangle
    const double v = vb / denominator, w = vc / denominator;
    return {a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w,
            a[2] + ab[2] * v + ac[2] * w};
}

}  // namespace skelseg::vec3
