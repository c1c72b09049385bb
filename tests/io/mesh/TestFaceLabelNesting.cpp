#include "io/mesh/FaceLabelNesting.h"

#include <gtest/gtest.h>

#include "kernels/base/Error.h"

namespace skelseg {
namespace {

/// A strip of `cells` unit squares along x, two triangles (faces) per cell:
/// faces 2c and 2c + 1 are cell c, neighbours share edges along the strip.
TriangleMesh strip(std::uint32_t cells) {
    TriangleMesh mesh;
    for (std::uint32_t i = 0; i <= cells; ++i) {
        mesh.vertices.push_back({double(i), 0.0, 0.0});
        mesh.vertices.push_back({double(i), 1.0, 0.0});
    }
    for (std::uint32_t c = 0; c < cells; ++c) {
        const std::uint32_t a = 2 * c, b = 2 * c + 1, d = 2 * c + 2, e = 2 * c + 3;
        mesh.triangles.push_back({a, d, e});
        mesh.triangles.push_back({a, e, b});
        mesh.triangleFace.push_back(2 * c);
        mesh.triangleFace.push_back(2 * c + 1);
    }
    mesh.faceCount = 2 * cells;
    return mesh;
}

/// Per face a label from a per-cell list.
std::vector<std::uint32_t> byCell(const std::vector<std::uint32_t>& cells) {
    std::vector<std::uint32_t> faces;
    for (std::uint32_t label : cells) faces.insert(faces.end(), {label, label});
    return faces;
}

TEST(FaceLabelNesting, NestedLabelsAreLeftAlone) {
    const TriangleMesh mesh = strip(6);
    std::vector<std::uint32_t> fine = byCell({1, 1, 2, 2, 3, 3});
    const std::vector<std::uint32_t> coarse = byCell({1, 1, 1, 1, 2, 2});
    const std::vector<std::uint32_t> before = fine;
    EXPECT_EQ(nestFaceLabels(mesh, fine, coarse, {1, 1, 2}, {1, 3}), 0u);
    EXPECT_EQ(fine, before);
}

TEST(FaceLabelNesting, StrayFacesTakeANeighbourInsideTheirCoarseSegment) {
    // Cells 5 and 6 voted fine 2 (parent 1) but lie in coarse 2: they take
    // fine 3 (parent 2) from cell 7 inwards, round by round.
    const TriangleMesh mesh = strip(10);
    std::vector<std::uint32_t> fine = byCell({1, 1, 1, 2, 2, 2, 2, 3, 3, 3});
    const std::vector<std::uint32_t> coarse = byCell({1, 1, 1, 1, 1, 2, 2, 2, 2, 2});
    const std::vector<std::uint16_t> parent = {1, 1, 2};
    EXPECT_EQ(nestFaceLabels(mesh, fine, coarse, parent, {1, 3}), 4u);
    EXPECT_EQ(fine, byCell({1, 1, 1, 2, 2, 3, 3, 3, 3, 3}));
    for (std::size_t f = 0; f < fine.size(); ++f) EXPECT_EQ(parent[fine[f] - 1], coarse[f]);
}

TEST(FaceLabelNesting, AnIsolatedStrayFaceTakesTheFallbackChild) {
    // Coarse 3 holds only cell 0, which no face of a child of 3 touches.
    const TriangleMesh mesh = strip(4);
    std::vector<std::uint32_t> fine = byCell({1, 1, 2, 2});
    const std::vector<std::uint32_t> coarse = byCell({3, 1, 2, 2});
    const std::vector<std::uint16_t> parent = {1, 2, 3};
    EXPECT_EQ(nestFaceLabels(mesh, fine, coarse, parent, {1, 2, 3}), 2u);
    EXPECT_EQ(fine, byCell({3, 1, 2, 2}));
}

TEST(FaceLabelNesting, BadInputIsRefused) {
    const TriangleMesh mesh = strip(2);
    std::vector<std::uint32_t> fine = byCell({1, 2});
    EXPECT_THROW(nestFaceLabels(mesh, fine, byCell({1}), {1, 1}, {1}), UsageError);
    EXPECT_THROW(nestFaceLabels(mesh, fine, byCell({1, 1}), {1}, {1}), UsageError);
}

TEST(FaceLabelNesting, RenumberingFollowsSegFileOrder) {
    EXPECT_EQ(renumberFaceLabels({5, 2, 5, 9}), (std::vector<std::uint32_t>{1, 0, 1, 2}));
}

}  // namespace
}  // namespace skelseg
