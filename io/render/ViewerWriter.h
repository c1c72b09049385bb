// skelseg: viewer.html, the result in one self-contained web page.
//
// The page shows the coloured segments, the curve skeleton (coloured by
// sigma or by rho_C, switchable), the cut loops, orbit and zoom with the
// mouse, a slider over the levels of a hierarchy, and a click on a segment
// names its id, size and parent. It needs no network and no server: the
// script (io/render/viewer/viewer.js, WebGL 1, written for this page) and
// the data are inlined; the page's Content-Security-Policy forbids every
// fetch. The template is compiled into the binary (CMake turns
// io/render/viewer/ into a generated header), so the executable stays
// self-contained.
//
// Data: one JSON block, arrays as base64 of little-endian float32/uint32.
// The surface is simplified for display (meshoptimizer, per segment, see
// MeshSimplification.h) to at most ViewerOptions::maxTriangles triangles, so
// a 400^3 run stays a few MB. Text from the input (the title: a file name;
// the facts: a grid name) reaches the page only as JSON strings: every
// non-ASCII character and `<`, `>`, `&` are written as \u escapes, so
// nothing in them can close the script element, and the script puts them
// on the page with textContent only.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "io/render/PlyWriter.h"

namespace skelseg {

struct ViewerSegment {
    /// Label at its level (1..K).
    std::uint32_t label = 0;
    /// Size in voxels.
    std::uint64_t voxels = 0;
    /// Label of the segment at the next coarser level that contains it; 0 at
    /// the coarsest level.
    std::uint32_t parent = 0;
};

/// One level of detail.
struct ViewerLevel {
    /// The tau of the level, as the user gave it ("3%").
    std::string tau;
    /// T labels of the scene's surface triangles at this level (1..K).
    std::vector<std::uint32_t> triangleLabels;
    std::vector<ViewerSegment> segments;
    /// Cut loops (world), closed polylines as in cuts.ply.
    std::vector<std::vector<std::array<double, 3>>> cutLoops;
};

struct ViewerScene {
    /// Heading and page title (usually the input's file name); any text.
    std::string title;
    /// Short facts shown under the title ("grid 120 x 80 x 60"); any text.
    std::vector<std::string> facts;
    /// Surface: V world positions and T triangles (0-based vertex indices).
    std::vector<std::array<double, 3>> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    /// Curve skeleton (its rho_c and sigma colour the lines) and its edges.
    std::vector<SkeletonPointRecord> skeletonPoints;
    std::vector<std::array<std::uint32_t, 2>> skeletonEdges;
    /// Finest level first; at least one. Levels must nest: triangles with the
    /// same label at level 0 share their label at every level.
    std::vector<ViewerLevel> levels;
    /// The level the page opens at (past the last: the coarsest).
    std::size_t openLevel = std::size_t(-1);
};

struct ViewerOptions {
    /// The surface is simplified to at most about this many triangles.
    std::size_t maxTriangles = 100000;
};

/// The bytes of viewer.html for `scene`.
/// @throw UsageError if there is no level, a level's triangleLabels has a size
///        other than T, an index is out of range, or the levels do not nest.
std::string viewerHtml(const ViewerScene& scene, const ViewerOptions& options = {});

/// viewerHtml() written atomically to `file`.
/// @throw OutputError naming `file` if it cannot be written; as above.
void writeViewerHtml(const std::filesystem::path& file, const ViewerScene& scene,
                     const ViewerOptions& options = {});

/// JSON text made safe inside an HTML <script> element: `<`, `>` and `&`
/// become \u003c, \u003e, \u0026 (they can only occur inside strings, where
/// the escapes mean the same characters). `json` must be ASCII (dumped with
/// ensure_ascii), which also covers U+2028 and U+2029.
std::string jsonForScriptElement(const std::string& json);

/// Standard base64 (RFC 4648, with padding) of `size` bytes.
std::string base64(const void* data, std::size_t size);

}  // namespace skelseg
