#include "io/render/SegmentSurfaces.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <map>
#include <set>

#include "tests/support/Pi.h"

namespace skelseg {
namespace {

using Vec3 = std::array<double, 3>;
using test::kPi;

struct Box {
    int lo[3], hi[3];  // inclusive voxel ranges
};

LabelVolume twoTouchingBoxes() {
    LabelVolume volume(Dims{20, 14, 12}, 0);
    // Box 1: x 2..9, box 2: x 10..15 -- they share the wall at x = 9.5.
    for (int z = 3; z <= 8; ++z)
        for (int y = 2; y <= 10; ++y) {
            for (int x = 2; x <= 9; ++x) volume(x, y, z) = 1;
            for (int x = 10; x <= 15; ++x)
                if (y >= 4 && y <= 8) volume(x, y, z) = 2;
        }
    return volume;
}
const Box kBox1{{2, 2, 3}, {9, 10, 8}};
const Box kBox2{{10, 4, 3}, {15, 8, 8}};

/// A rotation about z by 30 degrees, voxel size 0.5 (x, y) and 0.75 (z),
/// shifted origin: the surfaces must come out in this frame.
VolumeGeometry skewedGeometry() {
    VolumeGeometry geometry;
    const double c = std::cos(kPi / 6.0), s = std::sin(kPi / 6.0);
    geometry.origin = {10.0, -5.0, 3.0};
    geometry.directions = {{{0.5 * c, 0.5 * s, 0.0}, {-0.5 * s, 0.5 * c, 0.0}, {0.0, 0.0, 0.75}}};
    return geometry;
}

/// Inverse of skewedGeometry(): world -> continuous voxel index.
Vec3 worldToIndex(const Vec3& world) {
    const double c = std::cos(kPi / 6.0), s = std::sin(kPi / 6.0);
    const double x = world[0] - 10.0, y = world[1] + 5.0, z = world[2] - 3.0;
    return {(c * x + s * y) / 0.5, (-s * x + c * y) / 0.5, z / 0.75};
}

/// Distance (in voxels, per axis max norm) from p to the surface of the box
/// covered by the voxels, whose faces are half a voxel beyond the centres.
double distanceToBoxSurface(const Vec3& p, const Box& box) {
    double outside = 0.0, inside = 1e9;
    for (int a = 0; a < 3; ++a) {
        const double lo = box.lo[a] - 0.5, hi = box.hi[a] + 0.5;
        outside = std::max({outside, lo - p[a], p[a] - hi});
        inside = std::min({inside, p[a] - lo, hi - p[a]});
    }
    return outside > 0.0 ? outside : inside;
}

/// Each directed edge of label L's triangles must appear once and its reverse
/// once: closed, manifold along edges and consistently oriented.
void expectClosedAndOriented(const LabelledSurface& surface) {
    std::map<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>, int>
        directed;  // (label, from, to)
    for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
        const auto& tri = surface.triangles[t];
        for (int k = 0; k < 3; ++k)
            ++directed[{surface.triangleLabels[t], tri[k], tri[(k + 1) % 3]}];
    }
    std::size_t problems = 0;
    for (const auto& [key, count] : directed) {
        const auto& [label, from, to] = key;
        const auto reverse = directed.find({label, to, from});
        if (count != 1 || reverse == directed.end() || reverse->second != 1) ++problems;
    }
    EXPECT_EQ(problems, 0u) << "directed edges not matched by exactly one reverse edge";
}

/// Signed volume per label (divergence theorem): positive when the normals
/// point outwards.
std::map<std::uint32_t, double> signedVolumes(const LabelledSurface& surface) {
    std::map<std::uint32_t, double> volumes;
    for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
        const Vec3& a = surface.vertices[surface.triangles[t][0]];
        const Vec3& b = surface.vertices[surface.triangles[t][1]];
        const Vec3& c = surface.vertices[surface.triangles[t][2]];
        volumes[surface.triangleLabels[t]] +=
            (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
             a[2] * (b[0] * c[1] - b[1] * c[0])) /
            6.0;
    }
    return volumes;
}

TEST(SegmentSurfaces, TwoBoxesGiveTwoClosedSurfacesInWorldCoordinates) {
    LabelVolume volume = twoTouchingBoxes();
    volume.geometry = skewedGeometry();
    const LabelledSurface surface = extractSegmentSurfaces(volume);

    ASSERT_FALSE(surface.triangles.empty());
    ASSERT_EQ(surface.triangles.size(), surface.triangleLabels.size());
    EXPECT_EQ(std::set<std::uint32_t>(surface.triangleLabels.begin(), surface.triangleLabels.end()),
              (std::set<std::uint32_t>{1, 2}));
    // Labels come in increasing order.
    EXPECT_TRUE(std::is_sorted(surface.triangleLabels.begin(), surface.triangleLabels.end()));

    // Every vertex lies within one voxel of its box's surface, once mapped
    // back through the geometry: proves both the meshing and the mapping.
    std::vector<std::uint32_t> vertexLabel(surface.vertices.size(), 0);
    for (std::size_t t = 0; t < surface.triangles.size(); ++t)
        for (auto v : surface.triangles[t]) vertexLabel[v] = surface.triangleLabels[t];
    double worst = 0.0;
    for (std::size_t v = 0; v < surface.vertices.size(); ++v) {
        ASSERT_NE(vertexLabel[v], 0u) << "vertex " << v << " on no triangle";
        const Box& box = vertexLabel[v] == 1 ? kBox1 : kBox2;
        worst = std::max(worst, distanceToBoxSurface(worldToIndex(surface.vertices[v]), box));
    }
    EXPECT_LT(worst, 1.0);

    expectClosedAndOriented(surface);
    // Outward normals, and the enclosed volume is close to the voxel volume
    // (bevelled edges cut a little off).
    const double voxelVolume = 0.5 * 0.5 * 0.75;
    const auto volumes = signedVolumes(surface);
    const double box1 = 8 * 9 * 6 * voxelVolume, box2 = 6 * 5 * 6 * voxelVolume;
    EXPECT_GT(volumes.at(1), 0.8 * box1);
    EXPECT_LE(volumes.at(1), 1.0001 * box1);
    EXPECT_GT(volumes.at(2), 0.75 * box2);
    EXPECT_LE(volumes.at(2), 1.0001 * box2);
}

TEST(SegmentSurfaces, MirroringGeometryKeepsNormalsOutward) {
    LabelVolume volume = twoTouchingBoxes();
    volume.geometry.directions = {{{-1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};  // x flipped
    const auto surface = extractSegmentSurfaces(volume);
    for (const auto& [label, signedVolume] : signedVolumes(surface))
        EXPECT_GT(signedVolume, 0.0) << label;
    expectClosedAndOriented(surface);
}

TEST(SegmentSurfaces, SerialAndParallelAreIdentical) {
    LabelVolume volume(Dims{40, 36, 30}, 0);
    // Seven blobs (balls of different radii), some touching, one on the border.
    for (int z = 0; z < 30; ++z)
        for (int y = 0; y < 36; ++y)
            for (int x = 0; x < 40; ++x)
                for (int label = 1; label <= 7; ++label) {
                    const double cx = 5.0 * label, cy = 18.0 + 3.0 * (label % 3),
                                 cz = label == 7 ? 0.0 : 15.0;
                    const double r = 3.0 + label % 4;
                    if ((x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz) <= r * r)
                        volume(x, y, z) = std::uint16_t(label);
                }
    volume.geometry = skewedGeometry();
    const auto parallel = extractSegmentSurfaces(volume, SegmentSurfaceOptions{true});
    const auto serial = extractSegmentSurfaces(volume, SegmentSurfaceOptions{false});
    EXPECT_EQ(parallel.vertices, serial.vertices);
    EXPECT_EQ(parallel.triangles, serial.triangles);
    EXPECT_EQ(parallel.triangleLabels, serial.triangleLabels);
    EXPECT_EQ(
        std::set<std::uint32_t>(parallel.triangleLabels.begin(), parallel.triangleLabels.end())
            .size(),
        7u);
    expectClosedAndOriented(parallel);  // the ball cut by the volume border is closed too
}

TEST(SegmentSurfaces, SmoothingKeepsSurfacesClosedAndNearTheVoxels) {
    LabelVolume volume = twoTouchingBoxes();
    volume.geometry = skewedGeometry();
    SegmentSurfaceOptions options;
    options.smoothingIterations = 10;
    const auto smooth = extractSegmentSurfaces(volume, options);
    const auto exact = extractSegmentSurfaces(volume);
    ASSERT_EQ(smooth.triangles, exact.triangles);  // same connectivity, moved vertices
    EXPECT_NE(smooth.vertices, exact.vertices);
    expectClosedAndOriented(smooth);
    std::vector<std::uint32_t> vertexLabel(smooth.vertices.size(), 0);
    for (std::size_t t = 0; t < smooth.triangles.size(); ++t)
        for (auto v : smooth.triangles[t]) vertexLabel[v] = smooth.triangleLabels[t];
    for (std::size_t v = 0; v < smooth.vertices.size(); ++v) {
        const Box& box = vertexLabel[v] == 1 ? kBox1 : kBox2;
        EXPECT_LT(distanceToBoxSurface(worldToIndex(smooth.vertices[v]), box), 1.5)
            << "vertex " << v;
    }
    // Taubin smoothing roughly keeps the volume (plain Laplacian would shrink it).
    const auto before = signedVolumes(exact), after = signedVolumes(smooth);
    for (std::uint32_t label : {1u, 2u})
        EXPECT_NEAR(after.at(label), before.at(label), 0.15 * before.at(label));
    options.threaded = false;
    const auto serial = extractSegmentSurfaces(volume, options);
    EXPECT_EQ(serial.vertices, smooth.vertices);
}

TEST(SegmentSurfaces, ObjectSurfaceHasNoInnerWallAndLabelsBothBoxes) {
    const LabelVolume volume = twoTouchingBoxes();  // identity geometry: index == world
    const auto surface = extractObjectSurface(volume);
    EXPECT_EQ(std::set<std::uint32_t>(surface.triangleLabels.begin(), surface.triangleLabels.end()),
              (std::set<std::uint32_t>{1, 2}));
    // One closed surface: check with a single label.
    LabelledSurface single = surface;
    std::fill(single.triangleLabels.begin(), single.triangleLabels.end(), 1u);
    expectClosedAndOriented(single);
    // The shared wall at x = 9.5 is inside the object where the boxes overlap
    // in y and z: no triangle may sit there.
    for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
        Vec3 centroid{0, 0, 0};
        for (auto v : surface.triangles[t])
            for (int a = 0; a < 3; ++a) centroid[a] += surface.vertices[v][a] / 3.0;
        const bool onInnerWall = std::fabs(centroid[0] - 9.5) < 0.3 && centroid[1] > 4.5 &&
                                 centroid[1] < 7.5 && centroid[2] > 3.5 && centroid[2] < 7.5;
        EXPECT_FALSE(onInnerWall) << "triangle " << t;
        // Tag: the box whose voxels the triangle bounds.
        if (centroid[0] < 9.0) EXPECT_EQ(surface.triangleLabels[t], 1u) << "triangle " << t;
        if (centroid[0] > 10.0) EXPECT_EQ(surface.triangleLabels[t], 2u) << "triangle " << t;
    }
    // Mask overload: same surface, all labelled 1.
    MaskVolume mask(volume.dims(), 0);
    for (std::size_t i = 0; i < volume.size(); ++i) mask[i] = volume[i] != 0;
    const auto maskSurface = extractObjectSurface(mask);
    EXPECT_EQ(maskSurface.vertices, surface.vertices);
    EXPECT_EQ(maskSurface.triangles, surface.triangles);
    EXPECT_EQ(std::set<std::uint32_t>(maskSurface.triangleLabels.begin(),
                                      maskSurface.triangleLabels.end()),
              (std::set<std::uint32_t>{1}));
}

TEST(SegmentSurfaces, EmptyVolumeGivesEmptySurface) {
    const LabelVolume volume(Dims{5, 5, 5}, 0);
    const auto surface = extractSegmentSurfaces(volume);
    EXPECT_TRUE(surface.vertices.empty());
    EXPECT_TRUE(surface.triangles.empty());
    EXPECT_TRUE(extractObjectSurface(volume).triangles.empty());
}

TEST(SegmentSurfaces, SingleVoxelIsAClosedSurface) {
    LabelVolume volume(Dims{1, 1, 1}, 3);  // touches the border on every side
    const auto surface = extractSegmentSurfaces(volume);
    ASSERT_FALSE(surface.triangles.empty());
    EXPECT_EQ(std::set<std::uint32_t>(surface.triangleLabels.begin(), surface.triangleLabels.end()),
              (std::set<std::uint32_t>{3}));
    expectClosedAndOriented(surface);
    for (const auto& v : surface.vertices)
        for (double c : v) EXPECT_LE(std::fabs(c), 0.5 + 1e-6);
}

class CountingInterrupter : public Interrupter {
public:
    explicit CountingInterrupter(int allowedPolls) : mAllowed(allowedPolls) {}
    bool wasInterrupted(double) override { return mPolls.fetch_add(1) >= mAllowed; }
    void start(const char*) override { ++starts; }
    void end() override { ++ends; }
    int starts = 0, ends = 0;

private:
    std::atomic<int> mPolls{0};
    int mAllowed;
};

TEST(SegmentSurfaces, InterruptionThrowsAndEndsTheStage) {
    const LabelVolume volume = twoTouchingBoxes();
    CountingInterrupter interrupter(3);
    EXPECT_THROW(extractSegmentSurfaces(volume, interrupter), InterruptedError);
    EXPECT_EQ(interrupter.starts, 1);
    EXPECT_EQ(interrupter.ends, 1);
}

}  // namespace
}  // namespace skelseg
