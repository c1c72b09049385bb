// skelseg: the few 3-vector operations the mesh kernels need on the
// std::array<double, 3> points that TriangleMesh stores (ContactSeparation,
// ThinPartFill), so that they work on the mesh's own storage without a copy
// into another vector type.
#pragma once

#include <array>

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

}  // namespace skelseg::vec3
