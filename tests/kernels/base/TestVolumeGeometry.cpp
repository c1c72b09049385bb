// VolumeGeometry::problemOver: the geometry a reader may hand on is one whose
// voxels have a size, a volume and distinct world positions in doubles.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <string>

#include "kernels/base/Volume.h"

namespace skelseg {
namespace {

const Dims kDims{8, 4, 2};

/// problemOver() of `geometry`, which must contain `phrase`.
void expectProblem(const VolumeGeometry& geometry, const Dims& dims, const std::string& phrase) {
    const std::string problem = geometry.problemOver(dims);
    EXPECT_NE(problem.find(phrase), std::string::npos) << "problem: '" << problem << "'";
    EXPECT_EQ(problem.find('\n'), std::string::npos) << problem;
}

TEST(VolumeGeometry, OrdinaryGridsAreRepresentable) {
    EXPECT_EQ(VolumeGeometry().problemOver(kDims), "");
    EXPECT_EQ(VolumeGeometry::uniform(0.5, {-10, 3, 1e3}).problemOver(kDims), "");
    VolumeGeometry oblique;
    oblique.origin = {-12.5, 3.25, 100.125};
    oblique.directions = {{{0.5, 0.1, 0.0}, {-0.1, 0.75, 0.0}, {0.0, 0.0, -1.2}}};
    EXPECT_EQ(oblique.problemOver(kDims), "");
    // Tiny and huge voxels whose volume a double still holds; 1 um voxels at
    // a million units from the origin (a step of 1e-12 of the coordinates).
    EXPECT_EQ(VolumeGeometry::uniform(1e-100, {0, 0, 0}).problemOver(kDims), "");
    EXPECT_EQ(VolumeGeometry::uniform(1e100, {0, 0, 0}).problemOver(kDims), "");
    EXPECT_EQ(VolumeGeometry::uniform(1e-6, {1e6, 0, 0}).problemOver(kDims), "");
}

TEST(VolumeGeometry, VoxelsWithoutSizeOrVolumeAreRefused) {
    VolumeGeometry zero;
    zero.directions[1] = {0, 0, 0};
    expectProblem(zero, kDims, "the voxel step along axis 1 is zero: the voxels have no volume");
    VolumeGeometry subnormal;
    subnormal.directions[2] = {0, 0, 5e-324};
    expectProblem(subnormal, kDims,
                  "the voxel step along axis 2 (4.94066e-324) is a subnormal number");
    VolumeGeometry infinite;
    infinite.directions[0] = {INFINITY, 0, 0};
    expectProblem(infinite, kDims, "the voxel step along axis 0 is not finite");
    VolumeGeometry parallel;
    parallel.directions = {{{1, 2, 3}, {3, 6, 9}, {0, 0, 1}}};
    expectProblem(parallel, kDims, "the voxel steps are parallel or nearly so");
    // Every step a normal number, the volume not.
    expectProblem(VolumeGeometry::uniform(1e-110, {0, 0, 0}), kDims,
                  "the voxel volume (1e-110 x 1e-110 x 1e-110) is outside the range of doubles");
    expectProblem(VolumeGeometry::uniform(1e110, {0, 0, 0}), kDims,
                  "is outside the range of doubles");
}

TEST(VolumeGeometry, WorldCoordinatesMustStayFiniteAndApart) {
    VolumeGeometry overflowing;
    overflowing.origin = {1e308, 0, 0};
    overflowing.directions[0] = {1e305, 0, 0};
    expectProblem(overflowing, Dims{8192, 1, 1},
                  "world coordinates overflow: voxel (8191, 0, 0) lies at a non-finite position");
    expectProblem(VolumeGeometry::uniform(1.0, {1e15, 0, 0}), kDims,
                  "world coordinates reach 1e+15, where the voxel step along axis 0 (1) is below "
                  "2^-40 of them");
    // The bound itself: a unit step at 2^40 is kept, one ulp further is not.
    const double bound = std::ldexp(1.0, 40);
    EXPECT_EQ(VolumeGeometry::uniform(1.0, {0, -bound, 0}).problemOver(Dims{1, 1, 1}), "");
    expectProblem(VolumeGeometry::uniform(1.0, {0, -std::nextafter(bound, 2 * bound), 0}),
                  Dims{1, 1, 1}, "is below 2^-40 of them");
    // The far corner counts, not only the origin.
    expectProblem(VolumeGeometry::uniform(1.0, {bound, 0, 0}), Dims{2, 1, 1},
                  "world coordinates reach 1.09951e+12");
}

}  // namespace
}  // namespace skelseg
