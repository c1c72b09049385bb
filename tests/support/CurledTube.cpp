#include "tests/support/CurledTube.h"

#include <algorithm>
#include <cmath>

#include "tests/support/Pi.h"

namespace skelseg::test {
namespace {

/// Closed UV-parametrised surface: rings 1..rings-1 between two poles;
/// point(u, v) with u in [0, pi] from pole to pole and v in [0, 2 pi).
template <typename Point>
TriangleMesh uvSurface(int rings, int around, const Point& point) {
    TriangleMesh mesh;
    mesh.vertices.push_back(point(0.0, 0.0));
    for (int i = 1; i < rings; ++i)
        for (int j = 0; j < around; ++j)
            mesh.vertices.push_back(point(kPi * i / rings, 2.0 * kPi * j / around));
    mesh.vertices.push_back(point(kPi, 0.0));
    const auto ring = [&](int i, int j) {
        return std::uint32_t(1 + (i - 1) * around + (j % around));
    };
    const std::uint32_t last = std::uint32_t(mesh.vertices.size() - 1);
    for (int j = 0; j < around; ++j) {
        mesh.triangles.push_back({0, ring(1, j + 1), ring(1, j)});
        for (int i = 1; i + 1 < rings; ++i) {
            mesh.triangles.push_back({ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)});
            mesh.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
        }
        mesh.triangles.push_back({last, ring(rings - 1, j), ring(rings - 1, j + 1)});
    }
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) mesh.triangleFace.push_back(t);
    mesh.faceCount = mesh.triangles.size();
    return mesh;
}

}  // namespace

double CurledTube::profile(double x) const {
    const double length = bendRadius * (2.0 * kPi + extraAngle);
    x = std::clamp(x, 0.0, length);
    // Quarter-ellipse tips: 0 at both ends, 1 from tipLength inwards.
    const double fromEnd = std::min(x, length - x);
    const double t = std::max(0.0, 1.0 - fromEnd / tipLength);
    return (startRadius + (endRadius - startRadius) * x / length) * std::sqrt(1.0 - t * t);
}

double CurledTube::radiusAt(double angle) const {
    return profile(angle * bendRadius);
}

TriangleMesh CurledTube::mesh() const {
    const double length = bendRadius * (2.0 * kPi + extraAngle);
    return uvSurface(alongAxis, around, [&](double u, double v) {
        const double x = 0.5 * length * (1.0 - std::cos(u));
        const double r = profile(x);
        const double y = r * std::cos(v), z = r * std::sin(v);
        const double angle = x / bendRadius;
        return std::array<double, 3>{(bendRadius + y) * std::cos(angle),
                                     (bendRadius + y) * std::sin(angle), z};
    });
}

bool CurledTube::insideAt(const std::array<double, 3>& point, double angle, double slack) const {
    const double fromAxis = std::hypot(std::hypot(point[0], point[1]) - bendRadius, point[2]);
    return fromAxis < radiusAt(angle) + slack;
}

TriangleMesh sphereMesh(const std::array<double, 3>& centre, double radius, int rings, int around) {
    return uvSurface(rings, around, [&](double u, double v) {
        return std::array<double, 3>{centre[0] + radius * std::sin(u) * std::cos(v),
                                     centre[1] + radius * std::sin(u) * std::sin(v),
                                     centre[2] + radius * std::cos(u)};
    });
}

}  // namespace skelseg::test
