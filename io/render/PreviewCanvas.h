// skelseg: the float canvas preview.png is composited on (internal to
// io/render/): colours, rectangles, text, downsampling and the final 8-bit
// raster. PreviewPanel draws the views into canvases, PreviewRenderer lays
// them out under the title bar.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "io/render/PreviewRenderer.h"

namespace skelseg::preview {

using Colour = std::array<float, 3>;  // 0..255 per channel while compositing

inline Colour mix(const Colour& a, const Colour& b, float t) {
    return {a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t};
}
inline Colour toColour(const std::array<std::uint8_t, 3>& rgb) {
    return {float(rgb[0]), float(rgb[1]), float(rgb[2])};
}

constexpr int kSupersample = 2;  // 2x2 samples per output pixel

inline const Colour kTitleBackground = {255.0f, 255.0f, 255.0f};
inline const Colour kPanelTop = {250.0f, 250.0f, 251.0f};
inline const Colour kPanelBottom = {228.0f, 230.0f, 235.0f};
inline const Colour kSeparator = {205.0f, 207.0f, 212.0f};
inline const Colour kTextColour = {35.0f, 35.0f, 40.0f};
inline const Colour kCaptionColour = {110.0f, 112.0f, 120.0f};
inline const Colour kOutlineColour = {25.0f, 25.0f, 30.0f};

/// Float RGB canvas used while compositing (both for the supersampled panels
/// and the final picture), so blends do not round at every step.
struct Canvas {
    int width = 0, height = 0;
    std::vector<Colour> pixels;
    Canvas(int w, int h, Colour fill)
        : width(w), height(h), pixels(std::size_t(w) * std::size_t(h), fill) {}
    Colour& at(int x, int y) {
        return pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)];
    }
};

/// Blends `colour` at `opacity` into the pixels [x0, x1) x [y0, y1), clipped
/// to the canvas.
void fillRectangle(Canvas& canvas, int x0, int y0, int x1, int y1, const Colour& colour,
                   float opacity = 1.0f);

/// Width in pixels of `text` at integer `scale`.
int textWidth(const std::string& text, int scale);

/// Draws one line of text with its top-left corner at (x, y). stb_easy_font
/// gives axis-aligned unit quads; at an integer scale they fill whole pixels,
/// which keeps the text crisp without anti-aliasing. Pixels right of
/// `clipRight` are left alone. Bytes outside printable ASCII show as '?'.
void drawText(Canvas& canvas, int x, int y, const std::string& text, int scale,
              const Colour& colour, int clipRight = std::numeric_limits<int>::max());

/// Averages each kSupersample^2 block of `panel` into `target` at (left, top).
void downsampleInto(const Canvas& panel, Canvas& target, int left, int top);

/// The canvas rounded to 8-bit RGB.
Image toImage(const Canvas& canvas);

}  // namespace skelseg::preview
