#include "tests/support/BoxMeshes.h"

#include <cmath>

namespace skelseg::test {

Rotation rotation(std::array<double, 3> axis, double degrees) {
    constexpr double kPi = 3.14159265358979323846;
    const double length = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    for (double& a : axis) a /= length;
    const double c = std::cos(degrees * kPi / 180), s = std::sin(degrees * kPi / 180);
    const double x = axis[0], y = axis[1], z = axis[2];
    return {{{c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s},
             {y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s},
             {z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)}}};
}

void addBox(TriangleMesh& mesh, const std::array<double, 3>& size, const Rotation& r,
            const std::array<double, 3>& centre) {
    const auto first = std::uint32_t(mesh.vertices.size());
    for (int corner = 0; corner < 8; ++corner) {
        const double p[3] = {(corner & 1 ? 0.5 : -0.5) * size[0],
                             (corner & 2 ? 0.5 : -0.5) * size[1],
                             (corner & 4 ? 0.5 : -0.5) * size[2]};
        std::array<double, 3> q{};
        for (std::size_t i = 0; i < 3; ++i)
            q[i] = centre[i] + r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2];
        mesh.vertices.push_back(q);
    }
    const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                       {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        mesh.triangles.push_back({first + q[0], first + q[1], first + q[2]});
        mesh.triangles.push_back({first + q[0], first + q[2], first + q[3]});
    }
    mesh.triangleFace.resize(mesh.triangles.size());
    mesh.faceCount = mesh.triangles.size();
}

TriangleMesh unitCubes(const std::vector<std::array<double, 3>>& corners) {
    TriangleMesh mesh;
    for (const auto& c : corners)
        addBox(mesh, {1, 1, 1}, rotation({0, 0, 1}, 0), {c[0] + 0.5, c[1] + 0.5, c[2] + 0.5});
    return mesh;
}

TriangleMesh ringOfUnitCubes(bool crossOneSharedFace) {
    std::vector<std::array<double, 3>> corners;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (i != 1 || j != 1) corners.push_back({double(i), double(j), 0});
    TriangleMesh mesh = unitCubes(corners);
    if (crossOneSharedFace) {
        // The first cube's +x face: addBox's triangles 10 and 11, (1, 3, 7)
        // and (1, 7, 5); split along 3-5 instead, wound the same way.
        const auto a = mesh.triangles[10], b = mesh.triangles[11];
        mesh.triangles[10] = {a[1], a[2], b[2]};
        mesh.triangles[11] = {a[1], b[2], a[0]};
    }
    return mesh;
}

}  // namespace skelseg::test
