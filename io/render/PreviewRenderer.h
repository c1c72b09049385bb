// skelseg: preview.png, the picture people look at first.
//
// A software rasteriser (no GPU, no GL) that draws the segmented surface from
// three orthographic views side by side -- front, side, and a 3/4 view from
// above -- each framed to fit the scene, under a title bar holding the title
// text and one colour swatch per segment.
//
//  - Surfaces: z-buffered, coloured per triangle by segmentColour(label),
//    Lambert-shaded (ambient + a light just above-left of the camera + a small
//    highlight) with per-corner normals: a vertex's averaged normal where the
//    surface is smooth there, the face normal across creases (> 45 deg), so
//    voxel surfaces look smooth and CAD edges stay sharp. Two-sided, so open
//    or inconsistently oriented meshes render too. Silhouettes and depth
//    jumps get a dark outline, segment boundaries a lighter one.
//  - Skeleton: thin dark lines drawn over the surface; the parts hidden
//    inside the shape at partial opacity, so the whole skeleton shows.
//  - Cut loops: thick yellow lines with a black outline, depth-tested
//    against the surface with a small bias: only the visible part is drawn.
//  - Rendering is 2x2 supersampled (anti-aliased edges and lines); text is
//    stb_easy_font at an integer scale.
// The picture is deterministic: `threaded` (TBB over views and bands of rows)
// gives the same bytes as a serial run.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace skelseg {

/// What to draw; any part may be empty (an empty scene gives the title bar
/// and empty panels).
struct PreviewScene {
    /// Surface: V world positions and T triangles (0-based vertex indices).
    std::vector<std::array<double, 3>> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    /// T segment labels in the label-volume convention (1..K; 0 = unlabelled,
    /// drawn grey), or empty for an all-grey surface. Callers holding 0-based
    /// segment indices (mesh face labels) pass index + 1.
    std::vector<std::uint32_t> triangleLabels;
    /// Curve skeleton: points (world) and edges between them. A point on no
    /// edge is drawn as a dot.
    std::vector<std::array<double, 3>> skeletonPoints;
    std::vector<std::array<std::uint32_t, 2>> skeletonEdges;
    /// Cut loops: closed polylines (world), the last point joins the first.
    std::vector<std::vector<std::array<double, 3>>> cutLoops;
    /// One line of text for the title bar, e.g. "figure.nrrd  parts: 6  tau: 3%".
    /// Printable ASCII; anything else is shown as '?'.
    std::string title;
};

struct PreviewOptions {
    /// Picture size in pixels; width in [256, 16384], height in [128, 16384].
    int width = 1536;
    int height = 640;
    /// TBB over views and row bands; false renders serially (same bytes).
    bool threaded = true;
    /// World axis drawn pointing up: -1 (automatic), 0 = x, 1 = y, 2 = z.
    /// Automatic puts the longest side of the scene's bounding box up (the
    /// panels are taller than wide) and looks along the shortest one in the
    /// front view (the broadest outline), because input files disagree on
    /// which axis is up. With a fixed axis the front view looks from +z (up = x
    /// or y) or +y (up = z), the side view from +x (up = y or z) or +y (up = x).
    /// The 3/4 view looks from between the front and side cameras, 30 degrees
    /// above. Each panel's caption names its direction and the up axis.
    int upAxis = -1;
};

/// An 8-bit RGB raster, rows top to bottom, 3 bytes per pixel.
struct Image {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;
};

/// Renders the scene into a raster of options.width x options.height.
/// @throw Error if the options are out of range, a triangle or edge refers to
///        a missing vertex, or triangleLabels has a size other than 0 or T.
Image renderPreview(const PreviewScene& scene, const PreviewOptions& options = {});

/// The most renderPreviewPng() holds at once while it renders and encodes a
/// scene of `triangles` triangles and `vertices` vertices with `options`,
/// bytes (the scene itself is the caller's and not counted): the picture,
/// the scene's normals, and per panel rendered at once (up to 3, one per
/// thread of `threads`) its supersampled depth, triangle, colour and line
/// layers. What --max-memory's estimate counts for preview.png; a test holds
/// it to the allocations it measures.
std::uint64_t previewMemoryBytes(const PreviewOptions& options, std::uint64_t triangles,
                                 std::uint64_t vertices, int threads);

/// PNG encoding of an image (8-bit RGB, no metadata, deterministic bytes).
std::string encodePng(const Image& image);

/// renderPreview() + encodePng(), written atomically to `file`.
/// @throw OutputError naming `file` if it cannot be written; Error as above.
void renderPreviewPng(const std::filesystem::path& file, const PreviewScene& scene,
                      const PreviewOptions& options = {});

}  // namespace skelseg
