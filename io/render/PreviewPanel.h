// skelseg: one view of preview.png, rasterised (internal to io/render/).
//
// prepareScene() computes what the three views share (normals, framing
// points, extent, the labels present); makeViews() picks the front, side and
// 3/4 cameras; renderPanel() z-buffers the surface at kSupersample times the
// panel's resolution, shades it, outlines silhouettes and segment boundaries
// and draws the skeleton and the cut loops over it. PreviewRenderer.h
// describes the picture.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "io/render/PreviewCanvas.h"
#include "io/render/PreviewRenderer.h"

namespace skelseg::preview {

/// A camera: caption, and the rotation whose rows are the camera's right, up
/// and viewing direction (towards the scene) in world coordinates.
struct View {
    std::string caption;
    Eigen::Matrix3d worldToCamera = Eigen::Matrix3d::Identity();
};

/// What every view shares: validated input, normals, extent.
struct PreparedScene {
    const PreviewScene* scene = nullptr;
    std::vector<std::array<float, 3>> faceNormals;    // unit, from the winding; zero if degenerate
    std::vector<std::array<float, 3>> vertexNormals;  // unit, area-weighted face normals
    std::vector<Eigen::Vector3d> framingPoints;       // every finite point the scene shows
    Eigen::Vector3d centre{0.0, 0.0, 0.0};
    Eigen::Vector3d extent{0.0, 0.0, 0.0};  // bounding box size
    double diagonal = 1.0;
    std::vector<std::uint32_t> labels;  // distinct nonzero triangle labels, increasing
};

/// Normals, framing points, extent and labels of a validated scene. The
/// scene must outlive the result. threaded: face normals on TBB (same values).
PreparedScene prepareScene(const PreviewScene& scene, bool threaded);

/// Front, side and 3/4-above views (see PreviewOptions::upAxis). `extent`:
/// size of the scene's bounding box, used by the automatic choice.
std::array<View, 3> makeViews(int upAxis, const Eigen::Vector3d& extent);

/// One view rendered at kSupersample times panelWidth x panelHeight, framed
/// above a caption line of captionSpace pixels; lineScale widens skeleton and
/// cut lines. threaded: TBB over bands of rows (same bytes as serial).
Canvas renderPanel(const PreparedScene& prepared, const View& view, int panelWidth, int panelHeight,
                   int captionSpace, double lineScale, bool threaded);

}  // namespace skelseg::preview
