#include "io/render/PreviewCanvas.h"

#include <stb_easy_font.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace skelseg::preview {

void fillRectangle(Canvas& canvas, int x0, int y0, int x1, int y1, const Colour& colour,
                   float opacity) {
    x0 = std::max(x0, 0), y0 = std::max(y0, 0);
    x1 = std::min(x1, canvas.width), y1 = std::min(y1, canvas.height);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) canvas.at(x, y) = mix(canvas.at(x, y), colour, opacity);
}

namespace {

std::string printable(const std::string& text) {
    std::string result = text;
    // stb_easy_font indexes a table by (char - 32) for chars 32..126 only.
    for (char& c : result)
        if (c < 32 || c > 126) c = '?';
    return result;
}

}  // namespace

int textWidth(const std::string& text, int scale) {
    std::string copy = printable(text);
    return stb_easy_font_width(copy.data()) * scale;
}

void drawText(Canvas& canvas, int x, int y, const std::string& text, int scale,
              const Colour& colour, int clipRight) {
    std::string copy = printable(text);
    // Up to 11 quads of 64 bytes per character (the "X"); stb truncates silently.
    std::vector<char> vertexBuffer(copy.size() * 12 * 64 + 64);
    const int quads = stb_easy_font_print(0.0f, 0.0f, copy.data(), nullptr, vertexBuffer.data(),
                                          int(vertexBuffer.size()));
    constexpr std::size_t kVertexBytes = 16;  // x, y, z float + 4 colour bytes
    for (int q = 0; q < quads; ++q) {
        float minX = std::numeric_limits<float>::max(), minY = minX;
        float maxX = std::numeric_limits<float>::lowest(), maxY = maxX;
        for (int v = 0; v < 4; ++v) {
            float xy[2];
            std::memcpy(xy,
                        vertexBuffer.data() + (std::size_t(q) * 4 + std::size_t(v)) * kVertexBytes,
                        sizeof(xy));
            minX = std::min(minX, xy[0]), maxX = std::max(maxX, xy[0]);
            minY = std::min(minY, xy[1]), maxY = std::max(maxY, xy[1]);
        }
        const int x0 = x + int(std::lround(minX * float(scale))),
                  x1 = x + int(std::lround(maxX * float(scale)));
        const int y0 = y + int(std::lround(minY * float(scale))),
                  y1 = y + int(std::lround(maxY * float(scale)));
        fillRectangle(canvas, x0, y0, std::min(x1, clipRight), y1, colour);
    }
}

void downsampleInto(const Canvas& panel, Canvas& target, int left, int top) {
    const int width = panel.width / kSupersample, height = panel.height / kSupersample;
    const float weight = 1.0f / float(kSupersample * kSupersample);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            Colour sum{0.0f, 0.0f, 0.0f};
            for (int sy = 0; sy < kSupersample; ++sy)
                for (int sx = 0; sx < kSupersample; ++sx) {
                    const Colour& c =
                        panel.pixels[std::size_t(y * kSupersample + sy) * std::size_t(panel.width) +
                                     std::size_t(x * kSupersample + sx)];
                    sum = {sum[0] + c[0], sum[1] + c[1], sum[2] + c[2]};
                }
            target.at(left + x, top + y) = {sum[0] * weight, sum[1] * weight, sum[2] * weight};
        }
}

Image toImage(const Canvas& canvas) {
    Image image;
    image.width = canvas.width;
    image.height = canvas.height;
    image.rgb.resize(canvas.pixels.size() * 3);
    for (std::size_t i = 0; i < canvas.pixels.size(); ++i)
        for (std::size_t c = 0; c < 3; ++c)
            image.rgb[3 * i + c] =
                std::uint8_t(std::clamp(canvas.pixels[i][c], 0.0f, 255.0f) + 0.5f);
    return image;
}

}  // namespace skelseg::preview
