// Geodesicness sigma on digital tubes: a straight or gently bent tube must
// read sigma near 1 whatever its radius (2 voxels and up) and its angle to
// the grid, and clearly less next to a T junction (issue 12; docs/algorithm.md
// "Geodesicness on digital surfaces").
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

#include "io/mesh/Vec3Arithmetic.h"
#include "kernels/Geodesicness.h"
#include "kernels/SkeletonMeasures.h"
#include "tests/kernels/KernelTestSupport.h"

namespace skelseg {
namespace {

using Vec3 = std::array<double, 3>;
using vec3::dot;

Vec3 add(Vec3 a, Vec3 b, double s = 1.0) {
    return {a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]};
}

/// Distance from p to the segment [a, b] and the segment parameter in [0, 1].
std::pair<double, double> segmentDistance(Vec3 p, Vec3 a, Vec3 b) {
    const Vec3 ab = add(b, a, -1.0), ap = add(p, a, -1.0);
    const double t = std::clamp(dot(ap, ab) / dot(ab, ab), 0.0, 1.0);
    const Vec3 q = add(a, ab, t);
    const Vec3 d = add(p, q, -1.0);
    return {std::sqrt(dot(d, d)), t};
}

/// A union of capsules (segments with a radius) rasterised by voxel centres.
struct Capsule {
    Vec3 from, to;
    double radius;
};

MaskVolume rasteriseCapsules(const std::vector<Capsule>& capsules, int margin = 2) {
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const Capsule& c : capsules)
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min({lo[k], c.from[k] - c.radius, c.to[k] - c.radius});
            hi[k] = std::max({hi[k], c.from[k] + c.radius, c.to[k] + c.radius});
        }
    Dims dims;
    int* extent[3] = {&dims.x, &dims.y, &dims.z};
    for (int k = 0; k < 3; ++k) *extent[k] = int(std::ceil(hi[k] - lo[k])) + 2 * margin + 1;
    MaskVolume mask(dims, 0);
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x) {
                const Vec3 p{x + lo[0] - margin, y + lo[1] - margin, z + lo[2] - margin};
                for (const Capsule& c : capsules)
                    if (segmentDistance(p, c.from, c.to).first <= c.radius) {
                        mask(x, y, z) = 1;
                        break;
                    }
            }
    return mask;
}

/// The skeleton of a mask as the engine measures it (tau 1% of the boundary).
struct MeasuredSkeleton {
    MaskVolume mask;
    BoundaryGraph graph;
    std::vector<SkeletonPoint> points;
    Vec3 offset;  // voxel (0,0,0) in capsule coordinates

    explicit MeasuredSkeleton(MaskVolume m, Vec3 origin = {0, 0, 0})
        : mask(std::move(m)), offset(origin) {
        test::OnePercentSkeleton measured = test::measureSkeletonAtOnePercent(mask);
        graph = std::move(measured.graph);
        points = std::move(measured.points);
    }
    Vec3 position(const SkeletonPoint& p) const {
        const Dims d = mask.dims();
        const std::uint32_t v = p.voxel;
        return {double(v % std::uint32_t(d.x)) + offset[0],
                double((v / std::uint32_t(d.x)) % std::uint32_t(d.y)) + offset[1],
                double(v / (std::uint32_t(d.x) * std::uint32_t(d.y))) + offset[2]};
    }
};

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Median sigma of the skeleton points of C_tau whose projection on the
/// segment [from, to] falls in its middle third (0 where none).
double middleThirdSigma(double radius, double azimuth, double elevation) {
    const double length = std::max(12.0 * radius, 48.0);
    const Vec3 from{0, 0, 0}, to = add(from, test::unitDirection(azimuth, elevation), length);
    const int margin = 2;
    const MaskVolume mask = rasteriseCapsules({{from, to, radius}}, margin);
    Vec3 lo;
    for (int k = 0; k < 3; ++k) lo[k] = std::min(from[k], to[k]) - radius - margin;
    const MeasuredSkeleton skeleton(mask, lo);
    std::vector<double> sigmas;
    for (const SkeletonPoint& p : skeleton.points) {
        if (p.sigma < 0.0f) continue;
        const auto [distance, t] = segmentDistance(skeleton.position(p), from, to);
        if (t >= 1.0 / 3.0 && t <= 2.0 / 3.0 && distance < 0.5 * radius) sigmas.push_back(p.sigma);
    }
    return median(sigmas);
}

struct TubeCase {
    double radius, azimuth, elevation;
};

class GeodesicnessOnTubes : public ::testing::TestWithParam<TubeCase> {};

TEST_P(GeodesicnessOnTubes, MiddleOfAStraightTubeIsAGeodesic) {
    const TubeCase c = GetParam();
    const double sigma = middleThirdSigma(c.radius, c.azimuth, c.elevation);
    std::printf("radius %.1f azimuth %.0f elevation %.0f: median sigma %.3f\n", c.radius, c.azimuth,
                c.elevation, sigma);
    EXPECT_GE(sigma, c.radius < 3.0 ? 0.85 : 0.9);
}

// Along an axis, and at 30 and 45 degrees leaning 20 degrees out of the xy
// plane (the tubes of the table); then flat in the xy plane, along a
// space diagonal, and axis-aligned tubes whose axis is off the voxel centres.
INSTANTIATE_TEST_SUITE_P(
    RadiusAndAngle, GeodesicnessOnTubes,
    ::testing::Values(TubeCase{2, 0, 0}, TubeCase{2, 30, 20}, TubeCase{2, 45, 20},
                      TubeCase{3, 0, 0}, TubeCase{3, 30, 20}, TubeCase{3, 45, 20},
                      TubeCase{5, 0, 0}, TubeCase{5, 30, 20}, TubeCase{5, 45, 20},
                      TubeCase{8, 0, 0}, TubeCase{8, 30, 20}, TubeCase{8, 45, 20},
                      TubeCase{2, 45, 0}, TubeCase{3, 30, 0}, TubeCase{5, 45, 45},
                      TubeCase{2.5, 0, 0}, TubeCase{3.5, 0, 0}, TubeCase{4.3, 0, 0}));

/// Median sigma in the middle third of a tube of `radius` bent along a
/// quarter circle of radius `bend` (in the xy plane, leaning 20 degrees out
/// of it), drawn as a chain of capsules.
double bentTubeSigma(double radius, double bend) {
    const int pieces = 24;
    const double lean = 20.0 * test::kPi / 180.0;
    std::vector<Capsule> capsules;
    std::vector<Vec3> centre;
    for (int i = 0; i <= pieces; ++i) {
        const double angle = 0.5 * test::kPi * i / pieces;
        const Vec3 flat{bend * std::cos(angle), bend * std::sin(angle), 0.0};
        centre.push_back({flat[0], flat[1] * std::cos(lean), flat[1] * std::sin(lean)});
    }
    for (int i = 0; i < pieces; ++i) capsules.push_back({centre[i], centre[i + 1], radius});
    const int margin = 2;
    const MaskVolume mask = rasteriseCapsules(capsules, margin);
    Vec3 lo{1e300, 1e300, 1e300};
    for (const Vec3& c : centre)
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], c[k] - radius - margin);
    const MeasuredSkeleton skeleton(mask, lo);
    std::vector<double> sigmas;
    for (const SkeletonPoint& p : skeleton.points) {
        if (p.sigma < 0.0f) continue;
        const Vec3 q = skeleton.position(p);
        for (int i = pieces / 3; i < 2 * pieces / 3; ++i)
            if (segmentDistance(q, centre[i], centre[i + 1]).first < 0.5 * radius) {
                sigmas.push_back(p.sigma);
                break;
            }
    }
    return median(sigmas);
}

TEST(GeodesicnessOnBentTubes, MiddleOfAGentlyBentTubeIsAGeodesic) {
    for (double radius : {2.0, 3.0, 5.0}) {
        const double sigma = bentTubeSigma(radius, 12.0 * radius);
        std::printf("bent tube radius %.0f: median sigma %.3f\n", radius, sigma);
        EXPECT_GE(sigma, radius < 3.0 ? 0.85 : 0.9) << "radius " << radius;
    }
}

/// A limb of `limbRadius` standing on a body tube of radius 9 (a T). sigma
/// along the limb's skeleton, by distance from the junction at the body's
/// axis: next to the junction the loop wraps around where the limb meets
/// the body and is far from a geodesic.
TEST(GeodesicnessNearAJunction, IsClearlyLowerThanInTheLimb) {
    for (double limbRadius : {2.0, 3.0, 5.0}) {
        const double bodyRadius = 9.0, limbLength = 40.0;
        const Vec3 junction{36, 0, 0}, tip{36, limbLength, 0};
        const int margin = 2;
        const MaskVolume mask = rasteriseCapsules(
            {{{0, 0, 0}, {72, 0, 0}, bodyRadius}, {junction, tip, limbRadius}}, margin);
        const double lo = -bodyRadius - margin;
        const MeasuredSkeleton skeleton(mask, {lo, lo, lo});
        std::vector<double> nearJunction, inLimb;
        for (const SkeletonPoint& p : skeleton.points) {
            if (p.sigma < 0.0f) continue;
            const Vec3 q = skeleton.position(p);
            const auto [distance, t] = segmentDistance(q, junction, tip);
            if (distance >= 1.5) continue;
            const double height = t * limbLength;
            if (height >= 0.5 && height <= 1.5) nearJunction.push_back(p.sigma);
            const double outside = height - bodyRadius;  // along the limb, out of the body
            if (outside >= (limbLength - bodyRadius) / 3.0 &&
                outside <= 2.0 * (limbLength - bodyRadius) / 3.0)
                inLimb.push_back(p.sigma);
        }
        ASSERT_FALSE(nearJunction.empty()) << "limb radius " << limbRadius;
        ASSERT_FALSE(inLimb.empty()) << "limb radius " << limbRadius;
        const double junctionSigma = median(nearJunction), limbSigma = median(inLimb);
        std::printf("limb radius %.0f: sigma next to the junction %.3f, in the limb %.3f\n",
                    limbRadius, junctionSigma, limbSigma);
        EXPECT_GE(limbSigma, limbRadius < 3.0 ? 0.85 : 0.9) << "limb radius " << limbRadius;
        EXPECT_LT(junctionSigma, limbSigma - 0.3) << "limb radius " << limbRadius;
    }
}

}  // namespace
}  // namespace skelseg
